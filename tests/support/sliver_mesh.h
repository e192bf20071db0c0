// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the codec and rate tests: a small mesh with one sliver triangle, for the fold
// mend of spec/RATE.md section 3.
#pragma once

#include <optional>

#include "sdvi/image.h"

namespace sdvi::testing {

// A 64 x 64 square: a long edge A-B across the middle (A = (8, ay), B = (56, by)), below it
// one triangle, above it a sliver (A, B, P) with P p_above pixels above the edge's midpoint;
// the rest fans to the corners. Triangles counter-clockwise in (x, y); colours vary with
// position (r = 2x, g = 2y, b = 60) so that a file of it has something to measure.
inline Image SliverImage(float ay, float by, float p_above) {
  Image image;
  image.width = image.height = 64;
  const float xy[7][2] = {{0, 0}, {64, 0}, {64, 64}, {0, 64}, {8, ay}, {56, by}, {32, 0.5f * (ay + by) + p_above}};
  for (const auto& p : xy) {
    Vertex v;
    v.x = p[0];
    v.y = p[1];
    v.r = 2 * p[0];
    v.g = 2 * p[1];
    v.b = 60;
    image.vertices.push_back(v);
  }
  image.triangles = {{{0, 1, 5}}, {{0, 5, 4}}, {{0, 4, 3}}, {{1, 2, 5}},
                     {{4, 5, 6}}, {{4, 6, 3}}, {{6, 5, 2}}, {{6, 2, 3}}};
  return image;
}

// The first sliver, in a fixed scan of A's and B's heights near y = 30 in fortieths of a
// grid step (P a tenth of a step above A-B), for which folds(image) holds: a deterministic
// search for one whose edge ends round one way and apex the other at the codec's grid.
template <typename Folds>
std::optional<Image> FindFoldingSliver(float step, Folds folds) {
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      Image candidate = SliverImage(30 + 0.025f * float(i) * step, 30 + 0.025f * float(j) * step, 0.1f * step);
      if (folds(candidate)) return candidate;
    }
  return std::nullopt;
}

}  // namespace sdvi::testing
