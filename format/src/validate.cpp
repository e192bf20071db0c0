// SPDX-License-Identifier: GPL-3.0-or-later
// Topology checks of ValidateImage (format.h; spec/FORMAT.md section 9, checks 22-24):
// what a real image has, beyond what the structure allows. Checks 19-21, the values, are
// CheckImageValues (sdvi/mesh_rules.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "format_internal.h"
#include "sdvi/format.h"
#include "sdvi/mesh_rules.h"

namespace sdvi::format_internal {
namespace {

std::string TriangleText(size_t t, const Triangle& tri) {
  return "triangle " + std::to_string(t) + " (" + std::to_string(tri.v[0]) + ", " +
         std::to_string(tri.v[1]) + ", " + std::to_string(tri.v[2]) + ")";
}

// Twice the signed area of (a, b, p): > 0 when p is left of a->b.
double Side(const Vertex& a, const Vertex& b, const Vertex& p) {
  return (double(b.x) - a.x) * (double(p.y) - a.y) - (double(b.y) - a.y) * (double(p.x) - a.x);
}

}  // namespace

}  // namespace sdvi::format_internal

namespace sdvi {

double FoldTolerance(const Image& image) {
  return format_internal::kFoldTolerance + std::ldexp(double(std::max(image.width, image.height)), -22);
}

}  // namespace sdvi

namespace sdvi::format_internal {

Status ValidateTopology(const Image& image, const std::string& source) {
  const std::vector<Triangle>& tris = image.triangles;
  // The same vertex set twice, in any order or orientation.
  if (const auto twice = FindDuplicateTriangle(tris))
    return Status(StatusCode::kDuplicateTriangle, source + ": " + TriangleText(twice->first, tris[twice->first]) +
                                                      " has the same vertices as triangle " +
                                                      std::to_string(twice->second));
  // Edges as (smaller, larger, triangle, position of the edge in the triangle).
  struct Record {
    uint32_t a, b, t, k;
    bool operator<(const Record& o) const { return std::tie(a, b, t) < std::tie(o.a, o.b, o.t); }
  };
  std::vector<Record> records(3 * tris.size());
  for (size_t t = 0; t < tris.size(); ++t)
    for (uint32_t k = 0; k < 3; ++k) {
      const Edge e = Edge::Of(tris[t].v[k], tris[t].v[(k + 1) % 3]);
      records[3 * t + k] = {e.a, e.b, static_cast<uint32_t>(t), k};
    }
  std::sort(records.begin(), records.end());
  // Float coordinates of a fitted mesh: a vertex may sit a rounding error across an edge.
  const double tolerance = FoldTolerance(image);
  for (size_t i = 0; i < records.size();) {
    size_t j = i;
    while (j < records.size() && records[j].a == records[i].a && records[j].b == records[i].b) ++j;
    // Named for an error message only, not for each edge of a valid file.
    auto edge = [&] { return "edge " + EdgeText(Edge{records[i].a, records[i].b}); };
    if (j - i > 2)
      return Status(StatusCode::kNonManifoldEdge,
                    source + ": " + edge() + " is shared by " + std::to_string(j - i) +
                        " triangles (" + std::to_string(records[i].t) + ", " +
                        std::to_string(records[i + 1].t) + ", " + std::to_string(records[i + 2].t) +
                        (j - i > 3 ? ", ..." : "") + "); at most two are allowed");
    if (j - i == 2) {
      const Record& r0 = records[i];
      const Record& r1 = records[i + 1];
      const Triangle& t0 = tris[r0.t];
      const Triangle& t1 = tris[r1.t];
      if (t0.v[r0.k] == t1.v[r1.k])
        return Status(StatusCode::kInvalidMesh,
                      source + ": triangles " + std::to_string(r0.t) + " and " + std::to_string(r1.t) +
                          " traverse " + edge() +
                          " in the same direction (the orientation is not consistent)");
      const Vertex& a = image.vertices[r0.a];
      const Vertex& b = image.vertices[r0.b];
      const double length = std::hypot(double(b.x) - a.x, double(b.y) - a.y);
      const double d0 = Side(a, b, image.vertices[t0.v[(r0.k + 2) % 3]]);
      const double d1 = Side(a, b, image.vertices[t1.v[(r1.k + 2) % 3]]);
      if (d0 * d1 > 0 && std::min(std::abs(d0), std::abs(d1)) > tolerance * length)
        return Status(StatusCode::kFoldedTriangle,
                      source + ": " + TriangleText(r0.t, t0) + " and " + TriangleText(r1.t, t1) +
                          " lie on the same side of their shared " + edge() +
                          " (the mesh folds over itself)");
    }
    i = j;
  }
  return Status::Ok();
}

}  // namespace sdvi::format_internal
