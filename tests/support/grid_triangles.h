// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by tests and benchmarks: the triangles of a regular grid of quads, each split
// along alternating diagonals so that interior vertices have valence 4 and 8 in turn.
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/image.h"

namespace sdvi::testing {

// Appends 2 * cols * rows triangles for the quads of a (cols + 1) x (rows + 1) vertex grid,
// row by row; vertex_id(i, j) gives the index of grid vertex (column i, row j).
template <typename VertexId>
void AppendGridTriangles(int cols, int rows, VertexId vertex_id, std::vector<Triangle>* triangles) {
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      const uint32_t a = vertex_id(i, j), b = vertex_id(i + 1, j), c = vertex_id(i + 1, j + 1),
                     d = vertex_id(i, j + 1);
      if ((i + j) % 2 == 0) {
        triangles->push_back({{a, b, c}});
        triangles->push_back({{a, c, d}});
      } else {
        triangles->push_back({{a, b, d}});
        triangles->push_back({{b, c, d}});
      }
    }
  }
}

}  // namespace sdvi::testing
