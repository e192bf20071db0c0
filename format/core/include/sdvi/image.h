// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi::Image: the representation of spec/METHOD.md section 2, independent of any file format.
//
// Units: positions in pixels of the source image, (0,0) = top-left corner of the
// top-left pixel, x to the right, y down; pixel (i,j) covers [i,i+1) x [j,j+1) and its
// centre is (i+0.5, j+0.5). Colours are the source's 8-bit sRGB scale (0..255) as floats
// (values outside 0..255 are legal in the control mesh; renderers clamp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sdvi {

// A control vertex in R^5. 20 bytes, no padding (the file stores exactly this).
struct Vertex {
  float x = 0, y = 0;
  float r = 0, g = 0, b = 0;
  friend bool operator==(const Vertex&, const Vertex&) = default;
};
static_assert(sizeof(Vertex) == 20);

struct Triangle {
  std::array<uint32_t, 3> v{};
  friend bool operator==(const Triangle&, const Triangle&) = default;
};

// An undirected mesh edge; invariant a < b.
struct Edge {
  uint32_t a = 0, b = 0;
  static Edge Of(uint32_t p, uint32_t q) { return p < q ? Edge{p, q} : Edge{q, p}; }
  friend auto operator<=>(const Edge&, const Edge&) = default;
};

// A feature polyline: consecutive crease edges (vertex indices in order). Closed
// polylines do not repeat their first vertex.
struct FeaturePolyline {
  std::vector<uint32_t> vertices;
  bool closed = false;
  friend bool operator==(const FeaturePolyline&, const FeaturePolyline&) = default;
};

// Two feature polylines that together model one colour discontinuity (spec/METHOD.md section 2):
// their distance is rho * (1 - sharpness). Indices into Image::polylines.
struct FeaturePair {
  uint32_t first = 0, second = 0;
  float sharpness = 1.0f;  // in [0, 1]
  friend bool operator==(const FeaturePair&, const FeaturePair&) = default;
};

struct Image {
  uint32_t width = 0, height = 0;      // source image size in pixels (the domain's frame)
  std::vector<Vertex> vertices;        // control vertices
  std::vector<Triangle> triangles;     // control triangles (any orientation, consistent)
  std::vector<Edge> crease_edges;      // tagged crease edges, sorted, unique; the mesh
                                       // boundary is crease whether listed or not
  std::vector<uint32_t> corners;       // vertices tagged corner explicitly, sorted, unique;
                                       // endpoints and junctions are corners implicitly
  std::vector<FeaturePolyline> polylines;  // feature layer (optional, for editing)
  std::vector<FeaturePair> pairs;          // feature layer (optional, for editing)
  std::vector<std::pair<std::string, std::string>> metadata;  // key/value, in order
  friend bool operator==(const Image&, const Image&) = default;
};

}  // namespace sdvi
