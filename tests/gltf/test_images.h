// SPDX-License-Identifier: GPL-3.0-or-later
// Small sdvi images built in code for the glTF tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sdvi/image.h"

namespace sdvi::gltf_test {

// A width x height image as a grid of control vertices (cols x rows cells, two triangles
// each). A colour discontinuity crosses it horizontally: two crease rows 2 px apart
// (a feature pair, spec/METHOD.md section 2) with warm colours above and cool colours below. The four
// image corners are tagged corner. reverse_winding flips every triangle's vertex order.
inline Image GradientWithCrease(uint32_t width, uint32_t height, int cols = 8, int rows = 6,
                                bool reverse_winding = false) {
  Image image;
  image.width = width;
  image.height = height;
  // Row y values: `rows` cells above the pair and `rows` below, the pair at mid +- 1.
  const float mid = height / 2.0f;
  std::vector<float> ys;
  for (int j = 0; j <= rows; ++j) ys.push_back((mid - 1) * j / rows);
  for (int j = 0; j <= rows; ++j) ys.push_back(mid + 1 + (height - mid - 1) * j / rows);
  const int n_rows = int(ys.size());
  const int n_cols = cols + 1;
  for (int j = 0; j < n_rows; ++j) {
    const bool above = j <= rows;
    for (int i = 0; i < n_cols; ++i) {
      const float x = float(width) * i / cols;
      const float y = ys[j];
      const float u = x / width, v = y / height;
      Vertex vx{x, y, 0, 0, 0};
      if (above) {
        vx.r = 40 + 200 * u;
        vx.g = 30 + 150 * v;
        vx.b = 20 + 40 * u * v;
      } else {
        vx.r = 20 + 60 * u;
        vx.g = 60 + 120 * (1 - u);
        vx.b = 120 + 130 * v;
      }
      image.vertices.push_back(vx);
    }
  }
  auto id = [n_cols](int i, int j) { return uint32_t(j * n_cols + i); };
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    image.triangles.push_back(reverse_winding ? Triangle{{a, c, b}} : Triangle{{a, b, c}});
  };
  for (int j = 0; j + 1 < n_rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      add(id(i, j), id(i, j + 1), id(i + 1, j));
      add(id(i + 1, j), id(i, j + 1), id(i + 1, j + 1));
    }
  }
  for (int pair_row : {rows, rows + 1}) {
    for (int i = 0; i < cols; ++i) image.crease_edges.push_back(Edge::Of(id(i, pair_row), id(i + 1, pair_row)));
  }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.corners = {id(0, 0), id(cols, 0), id(0, n_rows - 1), id(cols, n_rows - 1)};
  std::sort(image.corners.begin(), image.corners.end());
  image.metadata = {{"title", "gradient with a crease pair"}};
  return image;
}

// An object image: a convex octagon-like polygon (k boundary vertices, all corners) in a
// width x height frame, fanned from a centre vertex, with a second ring so the interior is
// smooth. The domain is the polygon; the rest of the frame is empty.
inline Image ConvexObject(uint32_t width, uint32_t height, int k = 10) {
  Image image;
  image.width = width;
  image.height = height;
  const float cx = width * 0.5f, cy = height * 0.5f;
  const float rx = width * 0.35f, ry = height * 0.3f;
  image.vertices.push_back({cx, cy, 250, 240, 200});
  for (int ring = 1; ring <= 2; ++ring) {
    for (int i = 0; i < k; ++i) {
      const double a = 2 * M_PI * i / k;
      const float s = ring / 2.0f;
      image.vertices.push_back({float(cx + s * rx * std::cos(a)), float(cy + s * ry * std::sin(a)),
                                float(120 + 100 * std::cos(a)), float(90 + 80 * std::sin(a)),
                                float(ring == 2 ? 40 : 140)});
    }
  }
  auto ring1 = [k](int i) { return uint32_t(1 + (i % k)); };
  auto ring2 = [k](int i) { return uint32_t(1 + k + (i % k)); };
  for (int i = 0; i < k; ++i) {
    image.triangles.push_back({{0, ring1(i), ring1(i + 1)}});
    image.triangles.push_back({{ring1(i), ring2(i), ring2(i + 1)}});
    image.triangles.push_back({{ring1(i), ring2(i + 1), ring1(i + 1)}});
  }
  for (int i = 0; i < k; ++i) image.corners.push_back(ring2(i));
  std::sort(image.corners.begin(), image.corners.end());
  return image;
}

}  // namespace sdvi::gltf_test
