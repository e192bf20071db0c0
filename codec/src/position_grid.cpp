// SPDX-License-Identifier: GPL-3.0-or-later
// Positions on the codec's grid with folds mended locally (SnapPositionsToGrid in
// sdvi/codec.h; the rule and its figures: spec/RATE.md section 3).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/format.h"
#include "position_stream.h"

namespace sdvi {
namespace {

constexpr int kMendRounds = 4;

// Draco's position grid (the payload's position stream codes on it too).
using PositionGrid = codec_internal::DracoPositionGrid;

// An edge of the mesh with its one or two triangles' opposite vertices (second = -1 on
// the boundary).
struct MeshEdge2 {
  uint32_t a = 0, b = 0;
  int64_t apex[2] = {-1, -1};
};

// The defects of positions on a grid: edges that fold (ValidateImage's rule) and triangles
// that collapse (zero or reversed area where the unquantised mesh has a positive one).
class Mender {
 public:
  Mender(const Image& original, Image* snapped) : image_(*snapped), tolerance_(FoldTolerance(original)) {
    const auto& tris = image_.triangles;
    double total = 0;
    for (const Triangle& t : tris) total += Area(original, t);
    orientation_ = total < 0 ? -1 : 1;
    proper_.resize(tris.size());
    for (size_t t = 0; t < tris.size(); ++t) proper_[t] = orientation_ * Area(original, tris[t]) > 0;
    struct Record {
      uint32_t a, b, t, apex;
      bool operator<(const Record& o) const { return std::tie(a, b, t) < std::tie(o.a, o.b, o.t); }
    };
    std::vector<Record> records;
    records.reserve(3 * tris.size());
    for (size_t t = 0; t < tris.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Edge e = Edge::Of(tris[t].v[k], tris[t].v[(k + 1) % 3]);
        records.push_back({e.a, e.b, static_cast<uint32_t>(t), tris[t].v[(k + 2) % 3]});
      }
    std::sort(records.begin(), records.end());
    triangle_edges_.assign(tris.size(), {0, 0, 0});
    std::vector<int> filled(tris.size(), 0);
    for (size_t i = 0; i < records.size();) {
      size_t j = i;
      MeshEdge2 edge{records[i].a, records[i].b, {-1, -1}};
      for (; j < records.size() && records[j].a == records[i].a && records[j].b == records[i].b; ++j) {
        if (j - i < 2) edge.apex[j - i] = records[j].apex;
        triangle_edges_[records[j].t][filled[records[j].t]++] = static_cast<uint32_t>(edges_.size());
      }
      edges_.push_back(edge);
      i = j;
    }
    // Triangles around each vertex (CSR).
    const size_t n = image_.vertices.size();
    start_.assign(n + 1, 0);
    for (const Triangle& t : tris)
      for (uint32_t v : t.v) ++start_[v + 1];
    for (size_t v = 0; v < n; ++v) start_[v + 1] += start_[v];
    around_.resize(start_[n]);
    std::vector<uint32_t> next(start_.begin(), start_.end() - 1);
    for (size_t t = 0; t < tris.size(); ++t)
      for (uint32_t v : tris[t].v) around_[next[v]++] = static_cast<uint32_t>(t);
  }

  // The defects: folded edges and collapsed triangles, each with the vertices whose moves
  // can mend it (in a fixed order).
  std::vector<std::vector<uint32_t>> Defects() const {
    std::vector<std::vector<uint32_t>> out;
    for (uint32_t e = 0; e < edges_.size(); ++e)
      if (Folds(e))
        out.push_back({edges_[e].a, edges_[e].b, static_cast<uint32_t>(edges_[e].apex[0]),
                       static_cast<uint32_t>(edges_[e].apex[1])});
    for (uint32_t t = 0; t < image_.triangles.size(); ++t)
      if (Collapsed(t)) {
        const auto& v = image_.triangles[t].v;
        out.push_back({v[0], v[1], v[2]});
      }
    return out;
  }

  // The defects whose test involves vertex v: the edges and triangles around it.
  int DefectsAround(uint32_t v) const {
    std::vector<uint32_t> edges;
    int count = 0;
    for (uint32_t i = start_[v]; i < start_[v + 1]; ++i) {
      count += Collapsed(around_[i]);
      for (uint32_t e : triangle_edges_[around_[i]]) edges.push_back(e);
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (uint32_t e : edges) count += Folds(e);
    return count;
  }

 private:
  static double Side(const Vertex& a, const Vertex& b, const Vertex& p) {
    return (double(b.x) - a.x) * (double(p.y) - a.y) - (double(b.y) - a.y) * (double(p.x) - a.x);
  }
  static double Area(const Image& image, const Triangle& t) {
    return Side(image.vertices[t.v[0]], image.vertices[t.v[1]], image.vertices[t.v[2]]);
  }

  // ValidateImage's fold rule (format/src/validate.cpp).
  bool Folds(uint32_t e) const {
    const MeshEdge2& edge = edges_[e];
    if (edge.apex[1] < 0) return false;
    const Vertex& a = image_.vertices[edge.a];
    const Vertex& b = image_.vertices[edge.b];
    const double length = std::hypot(double(b.x) - a.x, double(b.y) - a.y);
    const double d0 = Side(a, b, image_.vertices[edge.apex[0]]);
    const double d1 = Side(a, b, image_.vertices[edge.apex[1]]);
    return d0 * d1 > 0 && std::min(std::abs(d0), std::abs(d1)) > tolerance_ * length;
  }
  bool Collapsed(uint32_t t) const { return proper_[t] && !(orientation_ * Area(image_, image_.triangles[t]) > 0); }

  Image& image_;
  double tolerance_ = 0;
  int orientation_ = 1;
  std::vector<char> proper_;
  std::vector<MeshEdge2> edges_;
  std::vector<std::array<uint32_t, 3>> triangle_edges_;
  std::vector<uint32_t> start_, around_;
};

}  // namespace

StatusOr<Image> SnapPositionsToGrid(const Image& image, int position_bits, int* moved) {
  if (position_bits < 1 || position_bits > kMaxQuantizationBits)
    return Status(StatusCode::kInvalidArgument, "position bits " + std::to_string(position_bits) + " not in 1.." +
                                                    std::to_string(kMaxQuantizationBits));
  if (image.vertices.empty() || image.triangles.empty())
    return Status(StatusCode::kEmptyInput, "image to snap has no vertices or no triangles");
  const size_t n = image.vertices.size();
  for (size_t t = 0; t < image.triangles.size(); ++t)
    for (uint32_t v : image.triangles[t].v)
      if (v >= n)
        return Status(StatusCode::kIndexOutOfRange, "image to snap: triangle " + std::to_string(t) +
                                                        " names vertex " + std::to_string(v) + " of " +
                                                        std::to_string(n));
  const PositionGrid grid(image, position_bits);
  Image out = image;
  std::vector<std::array<int32_t, 2>> q(n), nearest(n);
  int32_t lo[2] = {std::numeric_limits<int32_t>::max(), std::numeric_limits<int32_t>::max()};
  int32_t hi[2] = {std::numeric_limits<int32_t>::min(), std::numeric_limits<int32_t>::min()};
  for (size_t i = 0; i < n; ++i) {
    nearest[i] = {grid.Quantize(image.vertices[i].x, 0), grid.Quantize(image.vertices[i].y, 1)};
    q[i] = nearest[i];
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], q[i][k]);
      hi[k] = std::max(hi[k], q[i][k]);
    }
    out.vertices[i].x = grid.Position(q[i][0], 0);
    out.vertices[i].y = grid.Position(q[i][1], 1);
  }

  Mender mender(image, &out);
  std::vector<std::vector<uint32_t>> defects = mender.Defects();
  for (int round = 0; round < kMendRounds && !defects.empty(); ++round) {
    bool progress = false;
    for (const std::vector<uint32_t>& vertices : defects) {
      // The best single move of one of the defect's vertices: most defects removed around
      // it, then nearest to its unquantised position.
      int best_gain = 0;
      double best_distance = std::numeric_limits<double>::infinity();
      uint32_t best_vertex = 0;
      std::array<int32_t, 2> best_q{};
      for (uint32_t v : vertices) {
        const int before = mender.DefectsAround(v);
        if (before == 0) continue;  // mended by an earlier move
        Vertex& p = out.vertices[v];
        const Vertex kept = p;
        const std::array<int32_t, 2>& home = nearest[v];
        const bool fixed[2] = {home[0] == lo[0] || home[0] == hi[0], home[1] == lo[1] || home[1] == hi[1]};
        for (int dy = -kMendRadius; dy <= kMendRadius; ++dy)
          for (int dx = -kMendRadius; dx <= kMendRadius; ++dx) {
            const std::array<int32_t, 2> c = {home[0] + dx, home[1] + dy};
            if (c == q[v] || (fixed[0] && dx != 0) || (fixed[1] && dy != 0)) continue;
            if (c[0] < lo[0] || c[0] > hi[0] || c[1] < lo[1] || c[1] > hi[1]) continue;
            p.x = grid.Position(c[0], 0);
            p.y = grid.Position(c[1], 1);
            const int gain = before - mender.DefectsAround(v);
            const double distance =
                std::hypot(double(p.x) - image.vertices[v].x, double(p.y) - image.vertices[v].y);
            if (gain > best_gain || (gain == best_gain && gain > 0 && distance < best_distance)) {
              best_gain = gain;
              best_distance = distance;
              best_vertex = v;
              best_q = c;
            }
          }
        p = kept;
      }
      if (best_gain <= 0) continue;
      q[best_vertex] = best_q;
      out.vertices[best_vertex].x = grid.Position(best_q[0], 0);
      out.vertices[best_vertex].y = grid.Position(best_q[1], 1);
      progress = true;
    }
    defects = mender.Defects();
    if (!progress) break;
  }
  if (!defects.empty())
    return Status(StatusCode::kFoldedTriangle,
                  std::to_string(defects.size()) + " folded edges or collapsed triangles remain on the " +
                      std::to_string(position_bits) + "-bit position grid after moving vertices up to " +
                      std::to_string(kMendRadius) + " steps (first at vertex " +
                      std::to_string(defects.front().front()) + ")");
  if (moved) {
    *moved = 0;
    for (size_t i = 0; i < n; ++i) *moved += q[i] != nearest[i];
  }
  return out;
}

}  // namespace sdvi
