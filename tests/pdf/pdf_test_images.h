// SPDX-License-Identifier: GPL-3.0-or-later
// Small sdvi images built in code for the PDF tests and their script fixture.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "grid_triangles.h"
#include "sdvi/image.h"

namespace sdvi::pdf_test {

// A full-frame width x height image: a (cols + 1) x (rows + 1) grid of control vertices
// with smooth colour gradients, and a crease polyline along the middle row (a sharp
// colour step: the rows above and below carry different colours at the crease).
inline Image Gradient(uint32_t width, uint32_t height, int cols = 8, int rows = 6) {
  Image image;
  image.width = width;
  image.height = height;
  auto id = [cols](int i, int j) { return uint32_t(j * (cols + 1) + i); };
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i <= cols; ++i) {
      const float u = float(i) / cols, v = float(j) / rows;
      const bool upper = j <= rows / 2;
      image.vertices.push_back({float(width) * u, float(height) * v,
                                upper ? 40 + 200 * u : 230 - 150 * u,
                                upper ? 30 + 150 * v : 60 + 120 * (1 - u),
                                upper ? 20 + 60 * u * v : 120 + 130 * v});
    }
  }
  testing::AppendGridTriangles(cols, rows, id, &image.triangles);
  for (int i = 0; i < cols; ++i) image.crease_edges.push_back(Edge::Of(id(i, rows / 2), id(i + 1, rows / 2)));
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.corners = {id(0, 0), id(cols, 0), id(0, rows), id(cols, rows)};
  std::sort(image.corners.begin(), image.corners.end());
  image.metadata = {{"title", "gradient with a crease"}};
  return image;
}

// An object image: an annulus (a disc with a hole) centred in a width x height frame, as
// `rings` rings of `k` control vertices; the outside and the hole are not in the domain.
inline Image Annulus(uint32_t width, uint32_t height, int k = 16, int rings = 3) {
  Image image;
  image.width = width;
  image.height = height;
  const double cx = width * 0.5, cy = height * 0.5;
  const double outer = std::min(width, height) * 0.42, inner = outer * 0.4;
  for (int r = 0; r < rings; ++r) {
    const double radius = inner + (outer - inner) * r / (rings - 1);
    for (int i = 0; i < k; ++i) {
      const double a = 2 * M_PI * i / k;
      image.vertices.push_back({float(cx + radius * std::cos(a)), float(cy + radius * std::sin(a)),
                                float(128 + 100 * std::cos(a)), float(128 + 100 * std::sin(a)),
                                float(60 + 150.0 * r / (rings - 1))});
    }
  }
  auto id = [k](int i, int r) { return uint32_t(r * k + (i % k)); };
  testing::AppendGridTriangles(k, rings - 1, id, &image.triangles);
  image.metadata = {{"title", "annulus"}};
  return image;
}

}  // namespace sdvi::pdf_test
