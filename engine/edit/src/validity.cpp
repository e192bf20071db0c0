// SPDX-License-Identifier: GPL-3.0-or-later
// The validity rule of an edit: no fold, no degenerate triangle, no crossing of crease
// edges, finite values within the ranges a file holds (rules in sdvi/edit.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "edit_internal.h"
#include "sdvi/edit.h"
#include "sdvi/mesh_rules.h"

namespace sdvi {
namespace {

using edit_internal::SignedArea2;

Status Refuse(const std::string& what) { return Status(StatusCode::kEditRefused, what); }

std::string TriangleName(const Image& image, size_t t) {
  const Triangle& tri = image.triangles[t];
  return "triangle " + std::to_string(t) + " (vertices " + std::to_string(tri.v[0]) + ", " +
         std::to_string(tri.v[1]) + ", " + std::to_string(tri.v[2]) + ")";
}

// "triangle 3 (vertices ...), triangle 9 (...) and 4 more".
std::string ListTriangles(const Image& image, const std::vector<size_t>& ids) {
  std::string out;
  const size_t shown = std::min<size_t>(ids.size(), 4);
  for (size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + TriangleName(image, ids[i]);
  if (ids.size() > shown) out += " and " + std::to_string(ids.size() - shown) + " more";
  return out;
}

// Smallest height of triangle t: twice its area over its longest edge.
double MinHeight(const Image& image, const Triangle& t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const Vertex& a = image.vertices[t.v[k]];
    const Vertex& b = image.vertices[t.v[(k + 1) % 3]];
    longest = std::max(longest, std::hypot(double(b.x) - a.x, double(b.y) - a.y));
  }
  return longest > 0 ? std::fabs(SignedArea2(image, t)) / longest : 0;
}

double Orient(const Vertex& o, const Vertex& a, const Vertex& b) {
  return (double(a.x) - o.x) * (double(b.y) - o.y) - (double(a.y) - o.y) * (double(b.x) - o.x);
}

// Segments (a, b) and (c, d) cross at a point inside both (no shared end assumed).
bool ProperCross(const Image& image, const Edge& e, const Edge& f) {
  const auto& v = image.vertices;
  const double d1 = Orient(v[f.a], v[f.b], v[e.a]), d2 = Orient(v[f.a], v[f.b], v[e.b]);
  const double d3 = Orient(v[e.a], v[e.b], v[f.a]), d4 = Orient(v[e.a], v[e.b], v[f.b]);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

Status CheckFinite(const Image& image) {
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const Vertex& v = image.vertices[i];
    for (float x : {v.x, v.y, v.r, v.g, v.b})
      if (!std::isfinite(x)) return Refuse("vertex " + std::to_string(i) + " would get a non-finite value");
  }
  return Status::Ok();
}

// The ranges every reader and writer holds an image to (CheckImageValues).
Status CheckInRange(const Image& image) {
  const Status values = CheckImageValues(image, "the edit would leave a value out of range");
  return values.ok() ? values : Refuse(values.message());
}

// Per triangle against its own sign before; after a repair (changed triangles) against
// the mesh's orientation before.
Status CheckOrientation(const Image& before, const Image& after) {
  const bool same_topology = before.triangles == after.triangles;
  const int orientation = edit_internal::MeshOrientation(before);
  std::vector<size_t> flipped, kept;
  for (size_t t = 0; t < after.triangles.size(); ++t) {
    const double a0 = same_topology ? SignedArea2(before, before.triangles[t]) : orientation;
    const double a1 = SignedArea2(after, after.triangles[t]);
    if (a0 == 0 || a1 == 0) continue;  // degenerate ones are the next rule's
    ((a0 > 0) == (a1 > 0) ? kept : flipped).push_back(t);
  }
  if (flipped.empty() || kept.empty()) return Status::Ok();  // nothing flips, or a mirror image
  const bool few_flip = flipped.size() <= kept.size();
  return Refuse("the edit would fold the mesh: " + ListTriangles(after, few_flip ? flipped : kept) +
                (few_flip ? " would flip orientation" : " would keep orientation while the rest flips"));
}

Status CheckDegenerate(const Image& before, const Image& after) {
  std::vector<size_t> bad;
  for (size_t t = 0; t < after.triangles.size(); ++t)
    if (MinHeight(after, after.triangles[t]) < kMinTriangleHeight &&
        (!(before.triangles[t] == after.triangles[t]) || MinHeight(before, before.triangles[t]) >= kMinTriangleHeight))
      bad.push_back(t);
  if (bad.empty()) return Status::Ok();
  return Refuse("the edit would make degenerate triangles (height under " + std::to_string(kMinTriangleHeight) +
                " px): " + ListTriangles(after, bad));
}

// Names an edge by the feature polyline holding it, or the boundary.
std::string EdgeName(const Edge& e, const std::map<Edge, uint32_t>& polyline_of) {
  std::string out = "edge (" + std::to_string(e.a) + ", " + std::to_string(e.b) + ")";
  auto it = polyline_of.find(e);
  return out + (it != polyline_of.end() ? " of polyline " + std::to_string(it->second) : " of the boundary");
}

Status CheckCrossings(const Image& before, const Image& after) {
  const size_t n = after.vertices.size();
  std::vector<uint8_t> moved(n, 0);
  bool any = false;
  for (size_t i = 0; i < n; ++i)
    if (before.vertices[i].x != after.vertices[i].x || before.vertices[i].y != after.vertices[i].y)
      moved[i] = 1, any = true;
  if (!any) return Status::Ok();
  const std::vector<Edge> edges = edit_internal::AllCreaseEdges(after);
  if (edges.empty()) return Status::Ok();
  // Uniform grid over the edges' bounding box.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300, total = 0;
  for (const Edge& e : edges) {
    const Vertex &a = after.vertices[e.a], &b = after.vertices[e.b];
    x0 = std::min({x0, double(a.x), double(b.x)});
    y0 = std::min({y0, double(a.y), double(b.y)});
    x1 = std::max({x1, double(a.x), double(b.x)});
    y1 = std::max({y1, double(a.y), double(b.y)});
    total += std::hypot(double(b.x) - a.x, double(b.y) - a.y);
  }
  const double cell = std::max({total / double(edges.size()), (x1 - x0) / 2048, (y1 - y0) / 2048, 1e-6});
  const int nx = int((x1 - x0) / cell) + 1, ny = int((y1 - y0) / cell) + 1;
  std::vector<std::vector<uint32_t>> grid(size_t(nx) * size_t(ny));
  auto cells = [&](const Edge& e, auto&& f) {
    const Vertex &a = after.vertices[e.a], &b = after.vertices[e.b];
    const int cx0 = int((std::min(a.x, b.x) - x0) / cell), cx1 = int((std::max(a.x, b.x) - x0) / cell);
    const int cy0 = int((std::min(a.y, b.y) - y0) / cell), cy1 = int((std::max(a.y, b.y) - y0) / cell);
    for (int y = std::max(cy0, 0); y <= std::min(cy1, ny - 1); ++y)
      for (int x = std::max(cx0, 0); x <= std::min(cx1, nx - 1); ++x) f(grid[size_t(y) * nx + x]);
  };
  for (size_t i = 0; i < edges.size(); ++i) cells(edges[i], [&](std::vector<uint32_t>& c) { c.push_back(uint32_t(i)); });
  std::map<Edge, uint32_t> polyline_of;
  for (size_t k = 0; k < after.polylines.size(); ++k) {
    const auto& l = after.polylines[k].vertices;
    const size_t m = l.size(), segs = after.polylines[k].closed ? m : (m ? m - 1 : 0);
    for (size_t i = 0; i < segs; ++i) polyline_of.emplace(Edge::Of(l[i], l[(i + 1) % m]), uint32_t(k));
  }
  for (size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (!moved[e.a] && !moved[e.b]) continue;
    Status found = Status::Ok();
    cells(e, [&](std::vector<uint32_t>& c) {
      for (uint32_t j : c) {
        if (!found.ok() || j == i) continue;
        const Edge& f = edges[j];
        if ((moved[f.a] || moved[f.b]) && j < i) continue;  // that pair was checked from f
        if (f.a == e.a || f.a == e.b || f.b == e.a || f.b == e.b) continue;
        if (ProperCross(after, e, f) && !ProperCross(before, e, f))
          found = Refuse("the edit would make crease edges cross: " + EdgeName(e, polyline_of) + " and " +
                         EdgeName(f, polyline_of));
      }
    });
    if (!found.ok()) return found;
  }
  return Status::Ok();
}

}  // namespace

Status CheckEditValidity(const Image& before, const Image& after) {
  if (before.vertices.size() != after.vertices.size() || before.triangles.size() != after.triangles.size())
    return Status(StatusCode::kInternal, "CheckEditValidity: the edit changed the vertex or triangle count");
  SDVI_RETURN_IF_ERROR(CheckFinite(after));
  SDVI_RETURN_IF_ERROR(CheckInRange(after));
  SDVI_RETURN_IF_ERROR(CheckOrientation(before, after));
  SDVI_RETURN_IF_ERROR(CheckDegenerate(before, after));
  return CheckCrossings(before, after);
}

}  // namespace sdvi
