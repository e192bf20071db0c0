// SPDX-License-Identifier: GPL-3.0-or-later
// Images the edit tests start from, generated in code.
#pragma once

#include <cmath>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/image.h"
#include "sdvi/vectorize.h"

namespace sdvi::edit_test {

// A width x height control mesh with one vertical feature pair at x = width / 2 (sharpness
// s), coloured 40 left of it and 200 right of it (grey).
inline Image StraightEdge(int width, int height, float s) {
  FeatureCurve c;
  for (int k = 0; k <= 8; ++k) c.points.push_back({width / 2.0, 2.0 + (height - 4.0) * k / 8});
  c.sharpness = s;
  std::vector<Point2> samples;
  for (int y = 3; y < height; y += 6)
    for (int x = 3 + (y / 6) % 2; x < width; x += 6) samples.push_back({x + 0.25, y + 0.1});
  Image image = BuildControlMesh(width, height, {c}, samples, ControlMeshOptions{}).value();
  for (Vertex& v : image.vertices) v.r = v.g = v.b = v.x < width / 2.0 ? 40.f : 200.f;
  return image;
}

// An arc of a circle (centre (cx, cy), radius r, angles a0..a1 in radians) as a feature.
inline FeatureCurve Arc(double cx, double cy, double r, double a0, double a1, int n, float s) {
  FeatureCurve c;
  for (int k = 0; k <= n; ++k) {
    const double a = a0 + (a1 - a0) * k / n;
    c.points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  c.sharpness = s;
  return c;
}

// The built-in sample image (sharp and blurred curved edges, gradients), vectorized.
inline Image VectorizedSample(int width = 96, int height = 64) {
  VectorizeOptions options;
  options.compression_ratio = 24;
  options.iterations = 2;
  return Vectorize(MakeSampleImage(width, height), nullptr, options).value().image;
}

// Twice the signed area of triangle t.
inline double Area2(const Image& m, const Triangle& t) {
  const Vertex &a = m.vertices[t.v[0]], &b = m.vertices[t.v[1]], &c = m.vertices[t.v[2]];
  return (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
}

}  // namespace sdvi::edit_test
