// SPDX-License-Identifier: GPL-3.0-or-later
// Control meshes generated in code for the engine tests, and small helpers that apply
// mask matrices in double precision.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <cstdint>
#include <vector>

#include "grid_triangles.h"
#include "sdvi/image.h"
#include "sdvi/tagged_mesh.h"

namespace sdvi::test {

// Deterministic pseudo-random value in [-1, 1] for (seed, i).
inline double Noise(uint32_t seed, uint32_t i) {
  uint64_t z = (uint64_t{seed} << 32) ^ (i * 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) / static_cast<double>(1ull << 52) - 1.0;
}

inline Vertex MakeVertex(double x, double y, uint32_t seed, uint32_t i) {
  return Vertex{static_cast<float>(x), static_cast<float>(y), static_cast<float>(128 + 100 * Noise(seed, 3 * i)),
                static_cast<float>(128 + 100 * Noise(seed, 3 * i + 1)),
                static_cast<float>(128 + 100 * Noise(seed, 3 * i + 2))};
}

// A grid of nx x ny quads (spacing 10 px), each split into two triangles with
// alternating diagonals; x jittered by up to jitter px (rows stay straight lines).
inline uint32_t GridIndex(int nx, int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); }
inline Image GridImage(int nx, int ny, double jitter, uint32_t seed) {
  Image image;
  image.width = static_cast<uint32_t>(10 * nx);
  image.height = static_cast<uint32_t>(10 * ny);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const uint32_t id = GridIndex(nx, i, j);
      const bool inner = i > 0 && i < nx;
      image.vertices.push_back(MakeVertex(10.0 * i + (inner ? jitter * Noise(seed + 7, id) : 0), 10.0 * j, seed, id));
    }
  testing::AppendGridTriangles(nx, ny, [nx](int i, int j) { return GridIndex(nx, i, j); },
                               &image.triangles);
  return image;
}

// A strip around an open feature polyline P0..Pn (a wavy curve): rows of vertices 8 px
// above and below, so that the polyline is interior except for its two ends, which lie
// on the boundary and are corners (crease-degree 3).
struct Strip {
  Image image;
  std::vector<uint32_t> polyline;  // P0 .. Pn
};
inline Strip StripImage(int n, uint32_t seed) {
  Strip s;
  auto p = [&](int i) { return std::pair<double, double>(12.0 * i, 40 + 9 * std::sin(0.9 * i) + 3 * Noise(seed, i)); };
  for (int i = 0; i <= n; ++i) {
    const auto [x, y] = p(i);
    s.polyline.push_back(static_cast<uint32_t>(s.image.vertices.size()));
    s.image.vertices.push_back(MakeVertex(x, y, seed, 3 * i));
    s.image.vertices.push_back(MakeVertex(x + 2 * Noise(seed + 1, i), y - 8, seed, 3 * i + 1));
    s.image.vertices.push_back(MakeVertex(x + 2 * Noise(seed + 2, i), y + 8, seed, 3 * i + 2));
  }
  for (uint32_t i = 0; i < static_cast<uint32_t>(n); ++i) {
    const uint32_t p0 = 3 * i, a0 = 3 * i + 1, b0 = 3 * i + 2, p1 = 3 * i + 3, a1 = 3 * i + 4, b1 = 3 * i + 5;
    s.image.triangles.push_back({{p0, p1, a1}});
    s.image.triangles.push_back({{p0, a1, a0}});
    s.image.triangles.push_back({{p0, b0, b1}});
    s.image.triangles.push_back({{p0, b1, p1}});
    s.image.crease_edges.push_back(Edge::Of(p0, p1));
  }
  s.image.width = static_cast<uint32_t>(12 * n + 1);
  s.image.height = 80;
  return s;
}

// An annulus of three rings of m vertices (radii 20, 30, 40 around (50, 50)); the middle
// ring is a closed feature polyline without corners (a periodic B-spline), the inner and
// outer rings are boundary loops.
struct Annulus {
  Image image;
  std::vector<uint32_t> polyline;  // the middle ring, in order
};
inline Annulus AnnulusImage(int m, uint32_t seed) {
  Annulus a;
  const double radii[3] = {20, 30, 40};
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i < m; ++i) {
      const double t = 2 * std::numbers::pi * (i + 0.5 * r) / m;
      const double rad = radii[r] + 2.5 * Noise(seed + r, i);
      a.image.vertices.push_back(MakeVertex(50 + rad * std::cos(t), 50 + rad * std::sin(t), seed, r * m + i));
    }
  auto id = [m](int r, int i) { return static_cast<uint32_t>(r * m + (i % m)); };
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < m; ++i) {
      a.image.triangles.push_back({{id(r, i), id(r, i + 1), id(r + 1, i)}});
      a.image.triangles.push_back({{id(r, i + 1), id(r + 1, i + 1), id(r + 1, i)}});
    }
  for (int i = 0; i < m; ++i) {
    a.polyline.push_back(id(1, i));
    a.image.crease_edges.push_back(Edge::Of(id(1, i), id(1, i + 1)));
  }
  std::sort(a.image.crease_edges.begin(), a.image.crease_edges.end());
  a.image.width = a.image.height = 100;
  return a;
}

// A fan: centre vertex 0 with n ring vertices (random radii); the centre is smooth of valence n.
inline Image FanImage(int n, uint32_t seed) {
  Image image;
  image.vertices.push_back(MakeVertex(50 + Noise(seed, 99), 50 + Noise(seed, 98), seed, 0));
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * (i + 0.3 * Noise(seed, 200 + i)) / n;
    const double r = 20 + 5 * Noise(seed, 300 + i);
    image.vertices.push_back(MakeVertex(50 + r * std::cos(t), 50 + r * std::sin(t), seed, i + 1));
  }
  for (int i = 0; i < n; ++i)
    image.triangles.push_back({{0, static_cast<uint32_t>(1 + i), static_cast<uint32_t>(1 + (i + 1) % n)}});
  image.width = image.height = 100;
  return image;
}

// Values of the image's vertices, 5 doubles a vertex.
inline std::vector<double> Values(const Image& image) {
  std::vector<double> out;
  for (const Vertex& v : image.vertices) out.insert(out.end(), {v.x, v.y, v.r, v.g, v.b});
  return out;
}

// rows x values (5 doubles a vertex).
inline std::vector<double> ApplyRows(const SparseRows& rows, const std::vector<double>& values) {
  std::vector<double> out(5 * rows.rows(), 0.0);
  for (size_t i = 0; i < rows.rows(); ++i)
    for (uint32_t k = rows.offsets[i]; k < rows.offsets[i + 1]; ++k)
      for (int c = 0; c < 5; ++c) out[5 * i + c] += rows.weights[k] * values[5 * rows.indices[k] + c];
  return out;
}

// The edge index of (u, w) in mesh, or kNoIndex.
inline uint32_t FindEdge(const TaggedMesh& mesh, uint32_t u, uint32_t w) {
  auto n = mesh.neighbours(u);
  auto e = mesh.neighbour_edges(u);
  for (size_t i = 0; i < n.size(); ++i)
    if (n[i] == w) return e[i];
  return kNoIndex;
}

// A polyline (vertex chain) of mesh, refined once: edge points inserted (tagged_mesh.h numbering).
inline std::vector<uint32_t> RefinePolyline(const TaggedMesh& mesh, const std::vector<uint32_t>& chain, bool closed) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < chain.size(); ++i) {
    out.push_back(chain[i]);
    if (i + 1 < chain.size() || closed)
      out.push_back(mesh.num_vertices() + FindEdge(mesh, chain[i], chain[(i + 1) % chain.size()]));
  }
  return out;
}

}  // namespace sdvi::test
