// SPDX-License-Identifier: GPL-3.0-or-later
#include "tag_stream.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "color_stream.h"
#include "position_stream.h"
#include "range_coder.h"

namespace sdvi::codec_internal {
namespace {

constexpr int kEdgeContexts = 18;
constexpr int kCornerContexts = 4;

int EdgeContext(const MeshEdge& e, const std::vector<uint32_t>& degree) {
  const int boundary = e.triangles == 1 ? 1 : 0;
  return boundary * 9 + static_cast<int>(std::min<uint32_t>(degree[e.a], 2)) * 3 +
         static_cast<int>(std::min<uint32_t>(degree[e.b], 2));
}

// The edge model: a polyline segment (features first) by boundary, else EdgeContext.
int EdgeModel(const MeshEdge& e, const std::vector<uint32_t>& degree, const std::vector<Edge>& segments) {
  if (!segments.empty() && std::binary_search(segments.begin(), segments.end(), Edge{e.a, e.b}))
    return kEdgeContexts + (e.triangles == 1 ? 1 : 0);
  return EdgeContext(e, degree);
}

int CornerContext(uint32_t v, const std::vector<uint32_t>& degree) {
  return static_cast<int>(std::min<uint32_t>(degree[v], 3));
}

// Bits needed to write any index below count (at least 1).
int IndexBits(uint64_t count) {
  return count <= 2 ? 1 : static_cast<int>(std::bit_width(count - 1));
}

// The models of the feature layer.
struct FeatureModels {
  std::array<BitModel, 32> count_prefix{};  // Exp-Golomb prefix of counts
  BitModel closed;
  std::array<BitModel, 8> stop{};           // closed x vertex class
  std::array<BitModel, 3> choice{};         // candidate position min(j, 2)
  // Compact pairs (payload 1.1): first as expected, second = first + 1, sharpness as the
  // j-th entry of the recent values min(j, 3).
  BitModel pair_first, pair_second;
  std::array<BitModel, 4> sharpness{};
  // Ranked starts (payload 1.1, flag bit 5): near the previous start, or among the unused.
  BitModel start_near, start_unused;
  // Features first (payload 1.2, flag bit 6): the stop bit by closed x partner state, the
  // next vertex as the j-th of the ordered mesh neighbours: beside the partner x min(j, 3).
  std::array<BitModel, 6> step_stop{};
  std::array<BitModel, 8> step_choice{};
};

// Edge models: 18 by crease degree and boundary, then (features first) 2 for the segments of
// the polylines by boundary.
constexpr int kSegmentContexts = 2;

// The crease vertices (features first: all vertices) on no polyline coded so far, by rank
// (ranked starts): a Fenwick tree of 0/1 over the vertex indices.
class UnusedCreaseVertices {
 public:
  // Members: the vertices with a non-empty neighbour list.
  explicit UnusedCreaseVertices(const std::vector<std::vector<uint32_t>>& neighbours)
      : tree_(neighbours.size() + 1, 0) {
    for (size_t v = 0; v < neighbours.size(); ++v)
      if (!neighbours[v].empty()) Add(v, 1);
  }
  uint32_t size() const { return size_; }
  bool Contains(uint32_t v) const { return Rank(v + 1) - Rank(v) == 1; }
  uint32_t Rank(uint32_t v) const {  // members below v
    uint32_t sum = 0;
    for (size_t i = v; i > 0; i -= i & (~i + 1)) sum += tree_[i];
    return sum;
  }
  uint32_t Select(uint32_t rank) const {  // the member with `rank` members below it (rank < size())
    size_t at = 0;
    for (size_t step = std::bit_floor(tree_.size() - 1); step > 0; step >>= 1)
      if (at + step < tree_.size() && tree_[at + step] <= rank) {
        at += step;
        rank -= tree_[at];
      }
    return static_cast<uint32_t>(at);
  }
  void Remove(uint32_t v) {
    if (v < tree_.size() - 1 && Contains(v)) Add(v, -1);
  }

 private:
  void Add(size_t v, int delta) {
    for (size_t i = v + 1; i < tree_.size(); i += i & (~i + 1)) tree_[i] += static_cast<uint32_t>(delta);
    size_ += static_cast<uint32_t>(delta);
  }
  std::vector<uint32_t> tree_;
  uint32_t size_ = 0;
};
constexpr uint32_t kNearStart = 4;  // a start within 4 indices of the previous one is "near"

// The sharpness values of compact pairs seen so far, most recently used first (at most
// kRecentSharpness): a pair's sharpness is one of them (its position, unary) or new (its 32
// bits), and moves to the front.
constexpr size_t kRecentSharpness = 8;
class RecentSharpness {
 public:
  // Position of bits in the list, or size() when absent.
  size_t Find(uint32_t bits) const {
    return static_cast<size_t>(std::find(values_.begin(), values_.end(), bits) - values_.begin());
  }
  size_t size() const { return values_.size(); }
  uint32_t operator[](size_t j) const { return values_[j]; }
  void Use(size_t j, uint32_t bits) {  // j = position, or size() for a new value
    if (j < values_.size()) values_.erase(values_.begin() + static_cast<std::ptrdiff_t>(j));
    values_.insert(values_.begin(), bits);
    if (values_.size() > kRecentSharpness) values_.pop_back();
  }

 private:
  std::vector<uint32_t> values_;
};

// Vertex class for the stop bit: 0 = crease degree 0 or 1, 1 = degree 2, 2 = degree 2
// and an explicit corner, 3 = degree >= 3.
int VertexClass(uint32_t degree, bool corner) {
  if (degree <= 1) return 0;
  if (degree >= 3) return 3;
  return corner ? 2 : 1;
}

// Exp-Golomb with adaptive prefix: x = value + 1 has k bits (1..32); k - 1 one bits and
// a zero bit with models count_prefix[0..k-1], then the low k - 1 bits of x directly.
void EncodeCount(RangeEncoder& rc, FeatureModels& m, uint32_t value) {
  const uint64_t x = uint64_t{value} + 1;
  const int k = static_cast<int>(std::bit_width(x));
  for (int i = 0; i < k - 1; ++i) rc.Encode(m.count_prefix[i], true);
  rc.Encode(m.count_prefix[k - 1], false);
  rc.EncodeDirect(static_cast<uint32_t>(x), k - 1);
}

// The count, or UINT64_MAX when the prefix runs past 32 bits (a damaged stream).
uint64_t DecodeCount(RangeDecoder& rc, FeatureModels& m) {
  int k = 1;
  while (rc.Decode(m.count_prefix[k - 1]))
    if (++k > 32) return UINT64_MAX;
  const uint64_t x = (uint64_t{1} << (k - 1)) | rc.DecodeDirect(k - 1);
  return x - 1;
}

// Neighbours of every vertex along the given edges (crease edges or mesh edges: anything
// with endpoints a and b), ascending.
template <typename EdgeT>
std::vector<std::vector<uint32_t>> Neighbours(uint32_t vertex_count, const std::vector<EdgeT>& edges) {
  std::vector<std::vector<uint32_t>> out(vertex_count);
  for (const EdgeT& e : edges) {
    out[e.a].push_back(e.b);
    out[e.b].push_back(e.a);
  }
  for (auto& n : out) std::sort(n.begin(), n.end());
  return out;
}

std::vector<uint32_t> Candidates(const std::vector<uint32_t>& neighbours, int64_t previous) {
  std::vector<uint32_t> out;
  for (uint32_t n : neighbours)
    if (int64_t{n} != previous) out.push_back(n);
  return out;
}

bool Adjacent(const std::vector<std::vector<uint32_t>>& neighbours, uint32_t a, uint32_t b) {
  return std::binary_search(neighbours[a].begin(), neighbours[a].end(), b);
}

// Features first: the partner of polyline k is the `first` of the first pair whose `second`
// is k and whose `first` is below k (coded before it); -1 for none.
std::vector<int64_t> Partners(size_t polyline_count, const std::vector<FeaturePair>& pairs) {
  std::vector<int64_t> out(polyline_count, -1);
  for (const FeaturePair& pair : pairs)
    if (pair.first < pair.second && pair.second < polyline_count && out[pair.second] < 0)
      out[pair.second] = pair.first;
  return out;
}

// Features first: the stop model of a polyline with `length` vertices so far: closed x
// (no partner, the partner goes on, the partner has ended).
int StopModel(bool closed, const std::vector<uint32_t>* partner, size_t length) {
  const int state = !partner ? 0 : length < partner->size() ? 1 : 2;
  return (closed ? 3 : 0) + state;
}

// Features first: whether the step after the line's vertex i goes beside the partner (it
// has a vertex i + 1).
bool Beside(const std::vector<uint32_t>* partner, size_t i) { return partner && i + 1 < partner->size(); }

// Features first: the candidates for the vertex after the last of `line` (its vertex i),
// best first: the last vertex's mesh neighbours without the previous vertex, ordered by (on
// a polyline already, not a mesh neighbour of the partner's vertex i + 1 when Beside, squared
// distance from the predicted step, index). The predicted step: beside the partner its step
// from vertex i to i + 1, else the line's last step (none for i = 0: distance 0). Doubles,
// no fused multiply-add (tag_stream.cpp is built with -ffp-contract=off): every reader
// orders them the same.
std::vector<uint32_t> OrderedSteps(const std::vector<std::vector<uint32_t>>& neighbours,
                                   const std::vector<uint32_t>& line, const std::vector<char>& on_polyline,
                                   const std::vector<uint32_t>* partner, Positions positions) {
  const size_t i = line.size() - 1;
  const uint32_t v = line[i];
  const int64_t previous = i > 0 ? int64_t{line[i - 1]} : -1;
  const bool beside = Beside(partner, i);
  struct Key {
    int used, apart;
    double distance;
    uint32_t vertex;
  };
  double step_x = 0, step_y = 0;
  const bool predicted = beside || i > 0;
  const uint32_t from = beside ? (*partner)[i] : i > 0 ? line[i - 1] : v;
  const uint32_t to = beside ? (*partner)[i + 1] : v;
  if (predicted) {
    step_x = double(positions[to].x) - double(positions[from].x);
    step_y = double(positions[to].y) - double(positions[from].y);
  }
  std::vector<Key> keys;
  keys.reserve(neighbours[v].size());
  for (uint32_t c : neighbours[v]) {
    if (int64_t{c} == previous) continue;
    Key key{on_polyline[c] ? 1 : 0, beside && !Adjacent(neighbours, (*partner)[i + 1], c) ? 1 : 0, 0.0, c};
    if (predicted) {
      const double ex = (double(positions[c].x) - double(positions[v].x)) - step_x;
      const double ey = (double(positions[c].y) - double(positions[v].y)) - step_y;
      key.distance = ex * ex + ey * ey;
    }
    keys.push_back(key);
  }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    if (a.used != b.used) return a.used < b.used;
    if (a.apart != b.apart) return a.apart < b.apart;
    if (a.distance != b.distance) return a.distance < b.distance;
    return a.vertex < b.vertex;
  });
  std::vector<uint32_t> out(keys.size());
  for (size_t k = 0; k < keys.size(); ++k) out[k] = keys[k].vertex;
  return out;
}

// The segments of the polylines (consecutive vertices, and last to first when closed) as
// sorted undirected edges.
std::vector<Edge> PolylineSegments(const std::vector<FeaturePolyline>& polylines) {
  std::vector<Edge> out;
  for (const FeaturePolyline& line : polylines) {
    const auto& vs = line.vertices;
    for (size_t i = 0; i + 1 < vs.size(); ++i)
      if (vs[i] != vs[i + 1]) out.push_back(Edge::Of(vs[i], vs[i + 1]));
    if (line.closed && vs.size() > 2 && vs.back() != vs.front()) out.push_back(Edge::Of(vs.back(), vs.front()));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// A polyline's first vertex (vertex_count: an empty polyline), written out or, ranked, near
// the previous start or by its rank among the unused vertices.
void EncodeStart(RangeEncoder& rc, FeatureModels& m, bool ranked, const std::vector<uint32_t>& vs,
                 uint32_t vertex_count, const UnusedCreaseVertices& unused, int64_t* previous_start) {
  const uint32_t start = vs.empty() ? vertex_count : vs[0];
  bool coded = false;
  if (ranked && *previous_start >= 0) {
    const int64_t delta = int64_t{start} - *previous_start;
    const bool near = !vs.empty() && delta != 0 && std::abs(delta) <= kNearStart;
    rc.Encode(m.start_near, near);
    if (near) {
      rc.EncodeDirect(delta < 0 ? 1 : 0, 1);
      rc.EncodeDirect(static_cast<uint32_t>(std::abs(delta) - 1), 2);
      coded = true;
    }
  }
  if (ranked && !coded) {
    const bool is_unused = !vs.empty() && unused.Contains(start);
    rc.Encode(m.start_unused, is_unused);
    if (is_unused) {
      rc.EncodeDirect(unused.Rank(start), IndexBits(unused.size()));
      coded = true;
    }
  }
  if (!coded) rc.EncodeDirect(start, IndexBits(uint64_t{vertex_count} + 1));
  if (!vs.empty()) *previous_start = start;
}

// The first vertex EncodeStart coded, or -1 for an empty polyline; kCorrupt for a vertex or
// rank out of range.
StatusOr<int64_t> DecodeStart(RangeDecoder& rc, FeatureModels& m, bool ranked, uint32_t vertex_count,
                              const UnusedCreaseVertices& unused, int64_t* previous_start, const std::string& what) {
  int64_t first = -1;
  if (ranked && *previous_start >= 0 && rc.Decode(m.start_near)) {
    const bool negative = rc.DecodeDirect(1) != 0;
    const int64_t magnitude = int64_t{rc.DecodeDirect(2)} + 1;
    first = *previous_start + (negative ? -magnitude : magnitude);
    if (first < 0 || first >= int64_t{vertex_count})
      return Status(StatusCode::kCorrupt, what + ": a feature polyline starts at vertex " + std::to_string(first) +
                                              " of " + std::to_string(vertex_count));
  } else if (ranked && rc.Decode(m.start_unused)) {
    const uint32_t rank = rc.DecodeDirect(IndexBits(unused.size()));
    if (rank >= unused.size())
      return Status(StatusCode::kCorrupt, what + ": a feature polyline starts at the unused vertex " +
                                              std::to_string(rank) + " of " + std::to_string(unused.size()));
    first = unused.Select(rank);
  } else {
    first = rc.DecodeDirect(IndexBits(uint64_t{vertex_count} + 1));
    if (first == vertex_count) return int64_t{-1};  // empty polyline
    if (first > vertex_count)
      return Status(StatusCode::kCorrupt, what + ": a feature polyline starts at vertex " + std::to_string(first) +
                                              " of " + std::to_string(vertex_count));
  }
  *previous_start = first;
  return first;
}

// The pairs: written out (48 bits each) or compact (payload 1.1).
void EncodePairs(RangeEncoder& rc, FeatureModels& m, const std::vector<FeaturePair>& pairs, size_t polyline_count,
                 bool compact) {
  EncodeCount(rc, m, static_cast<uint32_t>(pairs.size()));
  const int polyline_bits = IndexBits(polyline_count);
  uint32_t expected_first = 0;
  RecentSharpness recent;
  for (const FeaturePair& pair : pairs) {
    uint32_t sharpness_bits;
    std::memcpy(&sharpness_bits, &pair.sharpness, 4);
    if (!compact) {
      rc.EncodeDirect(pair.first, polyline_bits);
      rc.EncodeDirect(pair.second, polyline_bits);
      rc.EncodeDirect(sharpness_bits, 32);
      continue;
    }
    rc.Encode(m.pair_first, pair.first == expected_first);
    if (pair.first != expected_first) rc.EncodeDirect(pair.first, polyline_bits);
    rc.Encode(m.pair_second, pair.second == pair.first + 1);
    if (pair.second != pair.first + 1) rc.EncodeDirect(pair.second, polyline_bits);
    expected_first = pair.second + 1;
    const size_t at = recent.Find(sharpness_bits);
    for (size_t j = 0; j < recent.size() && j <= at; ++j)
      rc.Encode(m.sharpness[std::min<size_t>(j, 3)], j == at);
    if (at == recent.size()) rc.EncodeDirect(sharpness_bits, 32);
    recent.Use(at, sharpness_bits);
  }
}

Status DecodePairs(RangeDecoder& rc, FeatureModels& m, uint64_t count, bool compact, const std::string& what,
                   std::vector<FeaturePair>* pairs) {
  const uint64_t pair_count = DecodeCount(rc, m);
  if (pair_count > 4 * count + 16 || rc.overrun())
    return Status(StatusCode::kCorrupt, what + " counts " + std::to_string(pair_count) + " feature pairs for " +
                                            std::to_string(count) + " polylines");
  const int polyline_bits = IndexBits(count);
  pairs->resize(pair_count);
  uint64_t expected_first = 0;
  RecentSharpness recent;
  for (FeaturePair& pair : *pairs) {
    uint32_t sharpness_bits = 0;
    if (!compact) {
      pair.first = rc.DecodeDirect(polyline_bits);
      pair.second = rc.DecodeDirect(polyline_bits);
      sharpness_bits = rc.DecodeDirect(32);
    } else {
      const uint64_t first = rc.Decode(m.pair_first) ? expected_first : rc.DecodeDirect(polyline_bits);
      const uint64_t second = rc.Decode(m.pair_second) ? first + 1 : rc.DecodeDirect(polyline_bits);
      if (first >= count || second >= count)
        return Status(StatusCode::kCorrupt, what + ": a feature pair names polyline " +
                                                std::to_string(std::max(first, second)) + " of " +
                                                std::to_string(count));
      pair.first = static_cast<uint32_t>(first);
      pair.second = static_cast<uint32_t>(second);
      expected_first = second + 1;
      size_t at = 0;
      while (at < recent.size() && !rc.Decode(m.sharpness[std::min<size_t>(at, 3)])) ++at;
      sharpness_bits = at < recent.size() ? recent[at] : rc.DecodeDirect(32);
      recent.Use(at, sharpness_bits);
    }
    std::memcpy(&pair.sharpness, &sharpness_bits, 4);
    if (pair.first >= count || pair.second >= count)
      return Status(StatusCode::kCorrupt, what + ": a feature pair names polyline " +
                                              std::to_string(std::max(pair.first, pair.second)) + " of " +
                                              std::to_string(count));
  }
  return Status::Ok();
}

// Features first (payload 1.2): polyline count, pairs, then the polylines along mesh edges.
void EncodeFeaturesFirst(RangeEncoder& rc, FeatureModels& m, uint32_t vertex_count,
                         const std::vector<std::vector<uint32_t>>& neighbours, const Tags& tags,
                         Positions positions) {
  const auto& polylines = tags.polylines;
  EncodeCount(rc, m, static_cast<uint32_t>(polylines.size()));
  EncodePairs(rc, m, tags.pairs, polylines.size(), true);
  const std::vector<int64_t> partners = Partners(polylines.size(), tags.pairs);
  const int vertex_bits = IndexBits(vertex_count);
  UnusedCreaseVertices unused(neighbours);
  std::vector<char> on_polyline(vertex_count, 0);
  int64_t previous_start = -1;
  std::vector<uint32_t> line;
  for (size_t k = 0; k < polylines.size(); ++k) {
    const auto& vs = polylines[k].vertices;
    rc.Encode(m.closed, polylines[k].closed);
    EncodeStart(rc, m, true, vs, vertex_count, unused, &previous_start);
    const std::vector<uint32_t>* partner = partners[k] >= 0 ? &polylines[partners[k]].vertices : nullptr;
    line.clear();
    for (size_t i = 0; i < vs.size(); ++i) {
      line.push_back(vs[i]);
      on_polyline[vs[i]] = 1;
      const bool stop = i + 1 == vs.size();
      rc.Encode(m.step_stop[StopModel(polylines[k].closed, partner, line.size())], stop);
      if (stop) break;
      const auto candidates = OrderedSteps(neighbours, line, on_polyline, partner, positions);
      bool found = false;
      for (size_t j = 0; j < candidates.size() && !found; ++j) {
        found = candidates[j] == vs[i + 1];
        rc.Encode(m.step_choice[(Beside(partner, i) ? 4 : 0) + std::min<size_t>(j, 3)], found);
      }
      if (!found) rc.EncodeDirect(vs[i + 1], vertex_bits);
    }
    for (uint32_t v : vs) unused.Remove(v);
  }
}

Status DecodeFeaturesFirst(RangeDecoder& rc, FeatureModels& m, uint32_t vertex_count, uint64_t max_polylines,
                           uint64_t max_polyline_vertices, const std::vector<std::vector<uint32_t>>& neighbours,
                           Positions positions, const std::string& what, Tags* out) {
  const uint64_t count = DecodeCount(rc, m);
  if (count > max_polylines || rc.overrun())
    return Status(StatusCode::kCorrupt,
                  what + " counts " + std::to_string(count) + " feature polylines, more than the mesh can hold");
  SDVI_RETURN_IF_ERROR(DecodePairs(rc, m, count, true, what, &out->pairs));
  const std::vector<int64_t> partners = Partners(count, out->pairs);
  const int vertex_bits = IndexBits(vertex_count);
  UnusedCreaseVertices unused(neighbours);
  std::vector<char> on_polyline(vertex_count, 0);
  int64_t previous_start = -1;
  uint64_t total = 0;
  out->polylines.resize(count);
  for (size_t k = 0; k < count; ++k) {
    FeaturePolyline& line = out->polylines[k];
    line.closed = rc.Decode(m.closed);
    SDVI_ASSIGN_OR_RETURN(const int64_t first,
                          DecodeStart(rc, m, true, vertex_count, unused, &previous_start, what));
    if (first < 0) continue;
    const std::vector<uint32_t>* partner = partners[k] >= 0 ? &out->polylines[partners[k]].vertices : nullptr;
    line.vertices.push_back(static_cast<uint32_t>(first));
    on_polyline[first] = 1;
    while (true) {
      if (++total > max_polyline_vertices || rc.overrun())
        return Status(StatusCode::kCorrupt, what + ": the feature polylines do not end");
      if (rc.Decode(m.step_stop[StopModel(line.closed, partner, line.vertices.size())])) break;
      const auto candidates = OrderedSteps(neighbours, line.vertices, on_polyline, partner, positions);
      int64_t next = -1;
      for (size_t j = 0; j < candidates.size() && next < 0; ++j)
        if (rc.Decode(m.step_choice[(Beside(partner, line.vertices.size() - 1) ? 4 : 0) + std::min<size_t>(j, 3)]))
          next = candidates[j];
      if (next < 0) next = rc.DecodeDirect(vertex_bits);
      if (next >= int64_t{vertex_count})
        return Status(StatusCode::kCorrupt, what + ": a feature polyline names vertex " + std::to_string(next) +
                                                " of " + std::to_string(vertex_count));
      line.vertices.push_back(static_cast<uint32_t>(next));
      on_polyline[next] = 1;
    }
    for (uint32_t v : line.vertices) unused.Remove(v);
  }
  return Status::Ok();
}

}  // namespace

std::vector<MeshEdge> CollectMeshEdges(const std::vector<Triangle>& triangles) {
  std::vector<MeshEdge> all;
  all.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const Edge e = Edge::Of(t.v[k], t.v[(k + 1) % 3]);
      all.push_back({e.a, e.b, 1});
    }
  }
  std::sort(all.begin(), all.end(), [](const MeshEdge& x, const MeshEdge& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  std::vector<MeshEdge> edges;
  edges.reserve(all.size() / 2 + 1);
  for (const MeshEdge& e : all) {
    if (!edges.empty() && edges.back().a == e.a && edges.back().b == e.b)
      ++edges.back().triangles;
    else
      edges.push_back(e);
  }
  return edges;
}

std::vector<uint8_t> EncodeTags(uint32_t vertex_count, const std::vector<MeshEdge>& edges, const Tags& tags,
                                Positions positions, size_t* feature_bytes, size_t* position_bytes) {
  RangeEncoder rc;
  FeatureModels m;
  if (position_bytes) *position_bytes = 0;
  if (tags.positions) {
    EncodePositions(rc, *tags.positions, edges);
    if (position_bytes) *position_bytes = rc.bytes_so_far();
    if (tags.colors) EncodeColors(rc, *tags.colors, edges);
  }
  const bool features_first = tags.has_feature_layer && tags.features_first;
  if (feature_bytes) *feature_bytes = 0;
  std::vector<Edge> segments;
  if (features_first) {
    EncodeFeaturesFirst(rc, m, vertex_count, Neighbours(vertex_count, edges), tags, positions);
    if (feature_bytes) *feature_bytes = rc.bytes_so_far();
    segments = PolylineSegments(tags.polylines);
  }
  std::array<BitModel, kEdgeContexts + kSegmentContexts> edge_models{};
  std::array<BitModel, kCornerContexts> corner_models{};
  std::vector<uint32_t> degree(vertex_count, 0);
  size_t next_crease = 0;  // crease_edges and edges are both sorted by (a, b)
  for (const MeshEdge& e : edges) {
    const auto& creases = tags.crease_edges;
    while (next_crease < creases.size() && creases[next_crease] < Edge{e.a, e.b}) ++next_crease;
    const bool crease = next_crease < creases.size() && creases[next_crease].a == e.a &&
                        creases[next_crease].b == e.b;
    rc.Encode(edge_models[EdgeModel(e, degree, segments)], crease);
    if (crease) {
      ++degree[e.a];
      ++degree[e.b];
    }
  }
  std::vector<char> is_corner(vertex_count, 0);
  for (uint32_t c : tags.corners) is_corner[c] = 1;
  for (uint32_t v = 0; v < vertex_count; ++v)
    rc.Encode(corner_models[CornerContext(v, degree)], is_corner[v] != 0);

  if (tags.has_feature_layer && !features_first) {
    const auto neighbours = Neighbours(vertex_count, tags.crease_edges);
    const int vertex_bits = IndexBits(vertex_count);
    EncodeCount(rc, m, static_cast<uint32_t>(tags.polylines.size()));
    UnusedCreaseVertices unused(neighbours);
    int64_t previous_start = -1;
    for (const FeaturePolyline& line : tags.polylines) {
      rc.Encode(m.closed, line.closed);
      const auto& vs = line.vertices;
      EncodeStart(rc, m, tags.ranked_starts, vs, vertex_count, unused, &previous_start);
      if (vs.empty()) continue;
      for (uint32_t v : vs) unused.Remove(v);
      for (size_t i = 0; i < vs.size(); ++i) {
        const uint32_t v = vs[i];
        const bool stop = i + 1 == vs.size();
        const int cls = VertexClass(static_cast<uint32_t>(neighbours[v].size()), is_corner[v] != 0);
        rc.Encode(m.stop[(line.closed ? 4 : 0) + cls], stop);
        if (stop) break;
        const auto candidates = Candidates(neighbours[v], i > 0 ? int64_t{vs[i - 1]} : -1);
        const uint32_t next = vs[i + 1];
        bool found = false;
        for (size_t j = 0; j < candidates.size() && !found; ++j) {
          found = candidates[j] == next;
          rc.Encode(m.choice[std::min<size_t>(j, 2)], found);
        }
        if (!found) rc.EncodeDirect(next, vertex_bits);
      }
    }
    EncodePairs(rc, m, tags.pairs, tags.polylines.size(), tags.compact_pairs);
  }
  return rc.Finish();
}

Status DecodeTags(std::span<const uint8_t> bytes, uint32_t vertex_count,
                  const std::vector<MeshEdge>& edges, uint32_t expected_crease_edges,
                  uint32_t expected_corners, bool has_feature_layer, bool compact_pairs,
                  bool ranked_starts, const std::string& source_name, Tags* tags, bool features_first,
                  Positions positions, int position_bits, std::vector<Vertex>* decoded_positions,
                  ColorStream* decoded_colors) {
  const std::string what = source_name + ": Draco payload tag stream";
  RangeDecoder rc(bytes);
  if (decoded_positions) {
    if (decoded_positions->size() != vertex_count)
      return Status(StatusCode::kInternal, what + ": the vertices to decode positions into are missing");
    SDVI_RETURN_IF_ERROR(DecodePositions(rc, position_bits, edges, what, decoded_positions));
    positions = *decoded_positions;
    if (decoded_colors) SDVI_RETURN_IF_ERROR(DecodeColors(rc, vertex_count, edges, what, decoded_colors));
  }
  FeatureModels m;
  Tags out;
  out.has_feature_layer = has_feature_layer;
  // Bounds against damaged streams: no more polylines than vertices plus crease edges (features
  // first: plus mesh edges), no more polyline vertices in all than twice that.
  const uint64_t max_lines_edges = uint64_t{vertex_count} + std::max<uint64_t>(expected_crease_edges, edges.size());
  const uint64_t max_polylines = max_lines_edges + 16;
  const uint64_t max_polyline_vertices = 2 * max_lines_edges + 16;
  features_first = features_first && has_feature_layer;
  std::vector<Edge> segments;
  if (features_first) {
    if (positions.size() != vertex_count)
      return Status(StatusCode::kInternal, what + ": the positions of the vertices are missing");
    SDVI_RETURN_IF_ERROR(DecodeFeaturesFirst(rc, m, vertex_count, max_polylines, max_polyline_vertices,
                                             Neighbours(vertex_count, edges), positions, what, &out));
    segments = PolylineSegments(out.polylines);
  }
  std::array<BitModel, kEdgeContexts + kSegmentContexts> edge_models{};
  std::array<BitModel, kCornerContexts> corner_models{};
  std::vector<uint32_t> degree(vertex_count, 0);
  for (const MeshEdge& e : edges) {
    if (rc.Decode(edge_models[EdgeModel(e, degree, segments)])) {
      out.crease_edges.push_back({e.a, e.b});
      ++degree[e.a];
      ++degree[e.b];
      if (out.crease_edges.size() > expected_crease_edges) break;
    }
  }
  if (out.crease_edges.size() != expected_crease_edges)
    return Status(StatusCode::kCorrupt,
                  what + " holds " + (out.crease_edges.size() > expected_crease_edges ? "more than " : "") +
                      std::to_string(out.crease_edges.size()) + " crease edges, header says " +
                      std::to_string(expected_crease_edges));
  std::vector<char> is_corner(vertex_count, 0);
  for (uint32_t v = 0; v < vertex_count; ++v) {
    if (rc.Decode(corner_models[CornerContext(v, degree)])) {
      out.corners.push_back(v);
      is_corner[v] = 1;
      if (out.corners.size() > expected_corners) break;
    }
  }
  if (out.corners.size() != expected_corners)
    return Status(StatusCode::kCorrupt,
                  what + " holds " + (out.corners.size() > expected_corners ? "more than " : "") +
                      std::to_string(out.corners.size()) + " corners, header says " +
                      std::to_string(expected_corners));

  if (has_feature_layer && !features_first) {
    const auto neighbours = Neighbours(vertex_count, out.crease_edges);
    const int vertex_bits = IndexBits(vertex_count);
    const uint64_t count = DecodeCount(rc, m);
    if (count > max_polylines || rc.overrun())
      return Status(StatusCode::kCorrupt, what + " counts " + std::to_string(count) +
                                              " feature polylines, more than the mesh can hold");
    uint64_t total = 0;
    out.polylines.resize(count);
    UnusedCreaseVertices unused(neighbours);
    int64_t previous_start = -1;
    for (FeaturePolyline& line : out.polylines) {
      line.closed = rc.Decode(m.closed);
      SDVI_ASSIGN_OR_RETURN(const int64_t first,
                            DecodeStart(rc, m, ranked_starts, vertex_count, unused, &previous_start, what));
      if (first < 0) continue;
      line.vertices.push_back(static_cast<uint32_t>(first));
      while (true) {
        if (++total > max_polyline_vertices || rc.overrun())
          return Status(StatusCode::kCorrupt, what + ": the feature polylines do not end");
        const uint32_t v = line.vertices.back();
        const int cls = VertexClass(static_cast<uint32_t>(neighbours[v].size()), is_corner[v] != 0);
        if (rc.Decode(m.stop[(line.closed ? 4 : 0) + cls])) break;
        const size_t n = line.vertices.size();
        const auto candidates = Candidates(neighbours[v], n > 1 ? int64_t{line.vertices[n - 2]} : -1);
        int64_t next = -1;
        for (size_t j = 0; j < candidates.size() && next < 0; ++j)
          if (rc.Decode(m.choice[std::min<size_t>(j, 2)])) next = candidates[j];
        if (next < 0) next = rc.DecodeDirect(vertex_bits);
        if (next >= int64_t{vertex_count})
          return Status(StatusCode::kCorrupt, what + ": a feature polyline names vertex " +
                                                  std::to_string(next) + " of " + std::to_string(vertex_count));
        line.vertices.push_back(static_cast<uint32_t>(next));
      }
      for (uint32_t v : line.vertices) unused.Remove(v);
    }
    SDVI_RETURN_IF_ERROR(DecodePairs(rc, m, count, compact_pairs, what, &out.pairs));
  }
  if (rc.overrun())
    return Status(StatusCode::kCorrupt,
                  what + " (" + std::to_string(bytes.size()) +
                      " bytes) ends before its last bit or does not start with a zero byte");
  *tags = std::move(out);
  return Status::Ok();
}

}  // namespace sdvi::codec_internal
