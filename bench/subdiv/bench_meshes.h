// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmark control meshes: a jittered grid of about N vertices with feature polylines
// (horizontal crease runs with tagged corners, vertical runs that meet them in junctions,
// closed loops), so that every vertex type and rule is exercised.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "grid_triangles.h"
#include "sdvi/image.h"

namespace sdvi::bench {

inline double Hash01(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) / static_cast<double>(1ull << 53);
}

inline Image FeatureGridImage(int target_vertices) {
  const int n = std::max(4, static_cast<int>(std::lround(std::sqrt(static_cast<double>(target_vertices)))) - 1);
  Image image;
  image.width = image.height = static_cast<uint32_t>(8 * n);
  auto id = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const uint64_t h = id(i, j);
      const bool inner = i > 0 && i < n && j > 0 && j < n;
      const float jx = inner ? static_cast<float>(2.5 * (Hash01(3 * h) - 0.5)) : 0.f;
      const float jy = inner ? static_cast<float>(2.5 * (Hash01(3 * h + 1) - 0.5)) : 0.f;
      image.vertices.push_back(Vertex{8.f * i + jx, 8.f * j + jy, static_cast<float>(255 * Hash01(5 * h)),
                                      static_cast<float>(255 * Hash01(5 * h + 1)),
                                      static_cast<float>(255 * Hash01(5 * h + 2))});
    }
  testing::AppendGridTriangles(n, n, id, &image.triangles);
  // Feature polylines: every 6th row from column 2 to n-2 (open, corners at both ends and
  // a tagged corner in the middle), every 9th column crossing them (junctions), and a
  // closed square loop in every 12 x 12 block.
  for (int j = 3; j < n; j += 6) {
    for (int i = 2; i < n - 2; ++i) image.crease_edges.push_back(Edge::Of(id(i, j), id(i + 1, j)));
    image.corners.push_back(id(n / 2, j));
  }
  for (int i = 5; i < n; i += 9)
    for (int j = 1; j < n - 1; ++j) image.crease_edges.push_back(Edge::Of(id(i, j), id(i, j + 1)));
  for (int bj = 0; bj + 12 <= n; bj += 12)
    for (int bi = 0; bi + 12 <= n; bi += 12) {
      const int x0 = bi + 7, y0 = bj + 7, s = 3;
      for (int k = 0; k < s; ++k) {
        image.crease_edges.push_back(Edge::Of(id(x0 + k, y0 + 1), id(x0 + k + 1, y0 + 1)));
        image.crease_edges.push_back(Edge::Of(id(x0 + k, y0 + s + 1), id(x0 + k + 1, y0 + s + 1)));
        image.crease_edges.push_back(Edge::Of(id(x0, y0 + 1 + k), id(x0, y0 + 2 + k)));
        image.crease_edges.push_back(Edge::Of(id(x0 + s, y0 + 1 + k), id(x0 + s, y0 + 2 + k)));
      }
    }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                           image.crease_edges.end());
  std::sort(image.corners.begin(), image.corners.end());
  return image;
}

}  // namespace sdvi::bench
