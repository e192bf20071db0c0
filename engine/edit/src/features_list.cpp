// SPDX-License-Identifier: GPL-3.0-or-later
// The feature table of `sdvi info --features` and the edge facts shared by the edit phases.
#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "edit_internal.h"
#include "sdvi/edit.h"

namespace sdvi {
namespace edit_internal {

std::vector<Edge> BoundaryEdges(const Image& image) {
  std::vector<Edge> edges;
  edges.reserve(image.triangles.size() * 3);
  for (const Triangle& t : image.triangles)
    for (int k = 0; k < 3; ++k) edges.push_back(Edge::Of(t.v[k], t.v[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  std::vector<Edge> boundary;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) boundary.push_back(edges[i]);
    i = j;
  }
  return boundary;
}

std::vector<Edge> AllCreaseEdges(const Image& image) {
  std::vector<Edge> edges = BoundaryEdges(image);
  edges.insert(edges.end(), image.crease_edges.begin(), image.crease_edges.end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

double SignedArea2(const Image& image, const Triangle& t) {
  const Vertex& a = image.vertices[t.v[0]];
  const Vertex& b = image.vertices[t.v[1]];
  const Vertex& c = image.vertices[t.v[2]];
  return (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
}

}  // namespace edit_internal

namespace {

// Bounding box of the points of the given vertex lists (all zero when they are empty).
FeatureBox BoxOf(const Image& image, std::initializer_list<const std::vector<uint32_t>*> lists) {
  FeatureBox box;
  bool empty = true;
  for (const std::vector<uint32_t>* list : lists)
    for (uint32_t v : *list) {
      const double x = image.vertices[v].x, y = image.vertices[v].y;
      if (empty) box = {x, y, x, y};
      empty = false;
      box = {std::min(box.min_x, x), std::min(box.min_y, y), std::max(box.max_x, x), std::max(box.max_y, y)};
    }
  return box;
}

double PolygonLength(const std::vector<Point2>& p, bool closed) {
  double len = 0;
  for (size_t i = 1; i < p.size(); ++i) len += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
  if (closed && p.size() > 2) len += std::hypot(p.front().x - p.back().x, p.front().y - p.back().y);
  return len;
}

std::vector<Point2> PointsOf(const Image& image, const FeaturePolyline& l) {
  std::vector<Point2> out;
  for (uint32_t v : l.vertices) out.push_back({image.vertices[v].x, image.vertices[v].y});
  return out;
}

}  // namespace

const char* FeatureKindName(FeatureKind kind) {
  switch (kind) {
    case FeatureKind::kPair: return "pair";
    case FeatureKind::kBoundary: return "boundary";
    case FeatureKind::kPairSide: return "pair_side";
    case FeatureKind::kPolyline: return "polyline";
  }
  return "polyline";
}

std::vector<FeatureInfo> ListFeatures(const Image& image) {
  std::vector<FeatureInfo> out;
  std::vector<int64_t> pair_of(image.polylines.size(), -1);
  for (size_t p = 0; p < image.pairs.size(); ++p) {
    const FeaturePair& pair = image.pairs[p];
    if (pair.first >= image.polylines.size() || pair.second >= image.polylines.size()) continue;
    pair_of[pair.first] = pair_of[pair.second] = int64_t(p);
    const FeaturePolyline& a = image.polylines[pair.first];
    const FeaturePolyline& b = image.polylines[pair.second];
    FeatureInfo info;
    info.kind = FeatureKind::kPair;
    info.id = uint32_t(p);
    info.first = pair.first;
    info.second = pair.second;
    info.closed = a.closed && b.closed;
    info.sharpness = pair.sharpness;
    info.vertex_count = uint32_t(a.vertices.size() + b.vertices.size());
    info.box = BoxOf(image, {&a.vertices, &b.vertices});
    std::vector<Point2> pa = PointsOf(image, a), pb = PointsOf(image, b);
    if (pa.size() == pb.size()) {
      for (size_t i = 0; i < pa.size(); ++i) pa[i] = {(pa[i].x + pb[i].x) / 2, (pa[i].y + pb[i].y) / 2};
      info.length = PolygonLength(pa, info.closed);
    } else {
      info.length = (PolygonLength(pa, a.closed) + PolygonLength(pb, b.closed)) / 2;
    }
    out.push_back(info);
  }
  const std::vector<Edge> boundary = edit_internal::BoundaryEdges(image);
  for (size_t k = 0; k < image.polylines.size(); ++k) {
    const FeaturePolyline& l = image.polylines[k];
    FeatureInfo info;
    info.id = uint32_t(k);
    info.closed = l.closed;
    info.vertex_count = uint32_t(l.vertices.size());
    info.box = BoxOf(image, {&l.vertices});
    info.length = PolygonLength(PointsOf(image, l), l.closed);
    if (pair_of[k] >= 0) {
      info.kind = FeatureKind::kPairSide;
      info.pair = pair_of[k];
      info.sharpness = image.pairs[size_t(pair_of[k])].sharpness;
    } else {
      const size_t m = l.vertices.size();
      const size_t segs = l.closed ? m : (m ? m - 1 : 0);
      bool on_boundary = segs > 0;
      for (size_t i = 0; i < segs && on_boundary; ++i)
        on_boundary = std::binary_search(boundary.begin(), boundary.end(),
                                         Edge::Of(l.vertices[i], l.vertices[(i + 1) % m]));
      info.kind = on_boundary ? FeatureKind::kBoundary : FeatureKind::kPolyline;
    }
    out.push_back(info);
  }
  return out;
}

}  // namespace sdvi
