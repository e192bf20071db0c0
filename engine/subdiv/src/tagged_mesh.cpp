// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/tagged_mesh.h"

#include <algorithm>
#include <string>
#include <utility>

#include "row_blocks.h"
#include "sdvi/large_buffers.h"
#include "sdvi/mesh_rules.h"
#include "sdvi/subdiv_rules.h"

namespace sdvi {
namespace {

std::string TriangleName(size_t t, const Triangle& tri) {
  return "triangle " + std::to_string(t) + " (" + std::to_string(tri.v[0]) + ", " +
         std::to_string(tri.v[1]) + ", " + std::to_string(tri.v[2]) + ")";
}

std::string EdgeName(const Edge& e) {
  return "edge (" + std::to_string(e.a) + ", " + std::to_string(e.b) + ")";
}

using subdiv_internal::ForRowBlocks;

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t{a} << 32) | b;
}

// Appends one weighted entry to the row being built (weights of exactly 0 are dropped).
void Push(SparseRows& rows, uint32_t index, double weight) {
  if (weight == 0) return;
  rows.indices.push_back(index);
  rows.weights.push_back(weight);
}
void EndRow(SparseRows& rows) { rows.offsets.push_back(static_cast<uint32_t>(rows.indices.size())); }

// The two crease neighbours of v, or false when v has not exactly two (only possible at
// the cut of a sub-mesh, where values are not used).
bool CreaseNeighbours(const TaggedMesh& mesh, uint32_t v, uint32_t* c0, uint32_t* c1) {
  auto nbrs = mesh.neighbours(v);
  auto edges = mesh.neighbour_edges(v);
  int found = 0;
  for (size_t i = 0; i < nbrs.size(); ++i) {
    if (!mesh.is_crease(edges[i])) continue;
    if (found == 0) *c0 = nbrs[i];
    if (found == 1) *c1 = nbrs[i];
    ++found;
  }
  return found == 2;
}

// Mask rows are produced through a sink: sink.Add(index, weight) for each non-zero term in
// order, sink.EndRow() after each row. MaskRows builds SparseRows; ValueRows applies the
// rows to values as they come, without building them, with the same terms in the same order.
struct MaskRows {
  SparseRows& rows;
  void Add(uint32_t index, double weight) { Push(rows, index, weight); }
  void EndRow() { sdvi::EndRow(rows); }
};
struct ValueRows {
  const double* values;  // 5 a vertex
  double* out;           // 5 a row, from the first row given
  double sum[5] = {0, 0, 0, 0, 0};
  void Add(uint32_t index, double weight) {
    if (weight == 0) return;
    const double* src = values + 5 * size_t{index};
    for (int c = 0; c < 5; ++c) sum[c] += weight * src[c];
  }
  void EndRow() {
    for (int c = 0; c < 5; ++c) *out++ = sum[c], sum[c] = 0;
  }
};

// Vertex rows [begin, end) of mesh under the given vertex rules.
template <typename SmoothRule, typename CreaseRule, typename Sink>
void VertexRows(const TaggedMesh& mesh, uint32_t begin, uint32_t end, SmoothRule smooth_rule, CreaseRule crease_rule,
                Sink& sink) {
  for (uint32_t v = begin; v < end; ++v) {
    const VertexTag tag = mesh.tag(v);
    uint32_t c0 = 0, c1 = 0;
    auto nbrs = mesh.neighbours(v);
    if (tag == VertexTag::kCrease && CreaseNeighbours(mesh, v, &c0, &c1)) {
      const rules::CreaseVertexMask m = crease_rule(mesh.is_corner(c0), mesh.is_corner(c1));
      sink.Add(c0, m.c0);
      sink.Add(v, m.self);
      sink.Add(c1, m.c1);
    } else if (tag == VertexTag::kSmooth && nbrs.size() >= 3) {
      const rules::SmoothVertexMask m = smooth_rule(static_cast<int>(nbrs.size()));
      sink.Add(v, m.self);
      for (uint32_t n : nbrs) sink.Add(n, m.neighbour);
    } else {
      sink.Add(v, rules::kCornerVertexWeight);
    }
    sink.EndRow();
  }
}

template <typename SmoothRule, typename CreaseRule>
void VertexMasks(const TaggedMesh& mesh, SparseRows& rows, SmoothRule smooth_rule,
                 CreaseRule crease_rule) {
  MaskRows sink{rows};
  VertexRows(mesh, 0, mesh.num_vertices(), smooth_rule, crease_rule, sink);
}

uint32_t OppositeVertex(const Triangle& tri, const Edge& e) {
  for (uint32_t v : tri.v)
    if (v != e.a && v != e.b) return v;
  return e.a;
}

}  // namespace

StatusOr<TaggedMesh> TaggedMesh::FromImage(const Image& image) {
  return Build(static_cast<uint32_t>(image.vertices.size()), image.triangles, image.crease_edges,
               image.corners);
}

StatusOr<TaggedMesh> TaggedMesh::Build(uint32_t num_vertices, std::span<const Triangle> triangles,
                                       std::span<const Edge> crease_edges,
                                       std::span<const uint32_t> corners) {
  if (num_vertices == 0) return Status(StatusCode::kEmptyInput, "control mesh has no vertices");
  if (triangles.empty()) return Status(StatusCode::kEmptyInput, "control mesh has no triangles");
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    for (uint32_t v : tri.v)
      if (v >= num_vertices)
        return Status(StatusCode::kIndexOutOfRange,
                      TriangleName(t, tri) + " refers to vertex " + std::to_string(v) +
                          " but the mesh has " + std::to_string(num_vertices) + " vertices");
    if (tri.v[0] == tri.v[1] || tri.v[1] == tri.v[2] || tri.v[2] == tri.v[0])
      return Status(StatusCode::kDegenerateTriangle, TriangleName(t, tri) + " repeats a vertex");
  }
  // Duplicate triangles: the same vertex set in any order or orientation.
  if (const auto twice = FindDuplicateTriangle(triangles))
    return Status(StatusCode::kDuplicateTriangle, TriangleName(twice->first, triangles[twice->first]) +
                                                      " has the same vertices as triangle " +
                                                      std::to_string(twice->second));
  for (uint32_t c : corners)
    if (c >= num_vertices)
      return Status(StatusCode::kIndexOutOfRange,
                    "corner " + std::to_string(c) + " is not a vertex (the mesh has " +
                        std::to_string(num_vertices) + ")");

  TaggedMesh mesh;
  mesh.num_vertices_ = num_vertices;
  mesh.triangles_.assign(triangles.begin(), triangles.end());
  SDVI_RETURN_IF_ERROR(mesh.BuildEdges());
  mesh.edge_crease_.assign(mesh.edges_.size(), 0);
  for (const Edge& given : crease_edges) {
    if (given.a >= num_vertices || given.b >= num_vertices)
      return Status(StatusCode::kIndexOutOfRange,
                    "crease " + EdgeName(given) + " refers to a vertex >= " +
                        std::to_string(num_vertices));
    const Edge e = Edge::Of(given.a, given.b);
    auto it = std::lower_bound(mesh.edges_.begin(), mesh.edges_.end(), e);
    if (e.a == e.b || it == mesh.edges_.end() || *it != e)
      return Status(StatusCode::kCreaseNotAnEdge,
                    "crease " + EdgeName(given) + " is not an edge of any triangle");
    mesh.edge_crease_[it - mesh.edges_.begin()] = 1;
  }
  for (size_t e = 0; e < mesh.edges_.size(); ++e)
    if (mesh.edge_triangles_[e][1] == kNoIndex) mesh.edge_crease_[e] = 1;  // boundary
  mesh.BuildNeighbours();
  mesh.TagVertices(corners);
  return mesh;
}

Status TaggedMesh::BuildEdges() {
  const size_t num_tris = triangles_.size();
  std::vector<std::pair<uint64_t, uint32_t>> records(3 * num_tris);
  for (size_t t = 0; t < num_tris; ++t)
    for (int k = 0; k < 3; ++k)
      records[3 * t + k] = {EdgeKey(triangles_[t].v[k], triangles_[t].v[(k + 1) % 3]),
                            static_cast<uint32_t>(3 * t + k)};
  std::sort(records.begin(), records.end());
  edges_.clear();
  edge_triangles_.clear();
  triangle_edges_.assign(num_tris, {kNoIndex, kNoIndex, kNoIndex});
  for (size_t i = 0; i < records.size();) {
    size_t j = i;
    while (j < records.size() && records[j].first == records[i].first) ++j;
    const Edge e{static_cast<uint32_t>(records[i].first >> 32),
                 static_cast<uint32_t>(records[i].first & 0xffffffffu)};
    if (j - i > 2) {
      std::string tris;
      for (size_t k = i; k < j; ++k) tris += (k > i ? ", " : "") + std::to_string(records[k].second / 3);
      return Status(StatusCode::kNonManifoldEdge,
                    EdgeName(e) + " is shared by " + std::to_string(j - i) + " triangles (" + tris +
                        "); at most two are allowed");
    }
    const uint32_t index = static_cast<uint32_t>(edges_.size());
    edges_.push_back(e);
    std::array<uint32_t, 2> tris{kNoIndex, kNoIndex};
    for (size_t k = i; k < j; ++k) {
      tris[k - i] = records[k].second / 3;
      triangle_edges_[records[k].second / 3][records[k].second % 3] = index;
    }
    edge_triangles_.push_back(tris);
    i = j;
  }
  return Status::Ok();
}

void TaggedMesh::BuildNeighbours() {
  neighbour_offsets_.assign(size_t{num_vertices_} + 1, 0);
  for (const Edge& e : edges_) {
    ++neighbour_offsets_[e.a + 1];
    ++neighbour_offsets_[e.b + 1];
  }
  for (uint32_t v = 0; v < num_vertices_; ++v) neighbour_offsets_[v + 1] += neighbour_offsets_[v];
  internal::ReserveLarge(neighbour_vertices_, 2 * edges_.size());
  internal::ReserveLarge(neighbour_edges_, 2 * edges_.size());
  neighbour_vertices_.resize(2 * edges_.size());
  neighbour_edges_.resize(2 * edges_.size());
  std::vector<uint32_t> fill(neighbour_offsets_.begin(), neighbour_offsets_.end() - 1);
  for (uint32_t i = 0; i < edges_.size(); ++i) {
    const Edge& e = edges_[i];
    neighbour_vertices_[fill[e.a]] = e.b;
    neighbour_edges_[fill[e.a]++] = i;
    neighbour_vertices_[fill[e.b]] = e.a;
    neighbour_edges_[fill[e.b]++] = i;
  }
}

void TaggedMesh::TagVertices(std::span<const uint32_t> corners) {
  vertex_tags_.assign(num_vertices_, VertexTag::kSmooth);
  for (uint32_t v = 0; v < num_vertices_; ++v) {
    int crease_degree = 0;
    for (uint32_t e : neighbour_edges(v)) crease_degree += edge_crease_[e];
    if (neighbours(v).empty() || crease_degree == 1 || crease_degree >= 3)
      vertex_tags_[v] = VertexTag::kCorner;
    else if (crease_degree == 2)
      vertex_tags_[v] = VertexTag::kCrease;
  }
  for (uint32_t c : corners) vertex_tags_[c] = VertexTag::kCorner;
}

TaggedMesh TaggedMesh::Submesh(std::span<const uint32_t> triangles,
                               std::vector<uint32_t>* vertex_map) const {
  std::vector<uint32_t> globals;
  globals.reserve(3 * triangles.size());
  for (uint32_t t : triangles)
    for (uint32_t v : triangles_[t].v) globals.push_back(v);
  std::sort(globals.begin(), globals.end());
  globals.erase(std::unique(globals.begin(), globals.end()), globals.end());
  std::vector<uint32_t> local(num_vertices_, kNoIndex);
  for (uint32_t i = 0; i < globals.size(); ++i) local[globals[i]] = i;

  TaggedMesh sub;
  sub.num_vertices_ = static_cast<uint32_t>(globals.size());
  sub.triangles_.reserve(triangles.size());
  for (uint32_t t : triangles) {
    const Triangle& tri = triangles_[t];
    sub.triangles_.push_back(Triangle{{local[tri.v[0]], local[tri.v[1]], local[tri.v[2]]}});
  }
  // A subset of a valid mesh's triangles is valid: BuildEdges cannot fail here.
  (void)sub.BuildEdges();
  sub.edge_crease_.resize(sub.edges_.size());
  for (size_t e = 0; e < sub.edges_.size(); ++e) {
    const uint32_t ga = globals[sub.edges_[e].a], gb = globals[sub.edges_[e].b];
    auto nbrs = neighbours(ga);
    auto edges = neighbour_edges(ga);
    uint8_t crease = 0;
    for (size_t i = 0; i < nbrs.size(); ++i)
      if (nbrs[i] == gb) crease = edge_crease_[edges[i]];
    sub.edge_crease_[e] = crease;
  }
  sub.BuildNeighbours();
  sub.vertex_tags_.resize(globals.size());
  for (uint32_t i = 0; i < globals.size(); ++i) sub.vertex_tags_[i] = vertex_tags_[globals[i]];
  if (vertex_map) *vertex_map = std::move(globals);
  return sub;
}

TaggedMesh TaggedMesh::Refine(int threads) const {
  // Every table of the child is written once, each part of it by one thread (the tables
  // not exposed as std::vector are not zero-filled first): on a virtual machine first-touch
  // memory is most of the cost of a level, and the threads share it.
  const uint32_t nv = num_vertices_;
  const size_t ne = edges_.size(), nt = triangles_.size();
  const size_t child_edges = 2 * ne + 3 * nt;
  TaggedMesh child;
  child.num_vertices_ = static_cast<uint32_t>(nv + ne);
  child.triangles_ = RefinedTriangles(threads);
  child.vertex_tags_ = RefinedVertexTags();
  // Half of parent edge e on the side of its end x.
  auto half = [&](uint32_t e, uint32_t x) { return static_cast<uint32_t>(edges_[e].a == x ? 2 * e : 2 * e + 1); };
  auto inner = [&](size_t t) { return static_cast<uint32_t>(2 * ne + 3 * t); };  // (m0,m1), (m1,m2), (m2,m0)

  internal::ReserveLarge(child.triangle_edges_, 4 * nt);
  child.triangle_edges_.resize(4 * nt);
  // Edges, their crease tags and their triangles (in increasing order): a half edge lies
  // in the corner children of its parent edge's triangles; an inner edge in a corner child
  // and the middle child.
  internal::ReserveLarge(child.edges_, child_edges);
  internal::ReserveLarge(child.edge_triangles_, child_edges);
  internal::ReserveLarge(child.edge_crease_, child_edges);
  child.edges_.resize(child_edges);
  child.edge_triangles_.resize(child_edges);
  child.edge_crease_.resize(child_edges);
  ForRowBlocks(nt, threads, [&](size_t t0, size_t t1) {
    for (size_t t = t0; t < t1; ++t) {
      const auto [a, b, c] = triangles_[t].v;
      const auto [e0, e1, e2] = triangle_edges_[t];
      const uint32_t i0 = inner(t);
      child.triangle_edges_[4 * t] = {half(e0, a), i0 + 2, half(e2, a)};
      child.triangle_edges_[4 * t + 1] = {half(e0, b), half(e1, b), i0};
      child.triangle_edges_[4 * t + 2] = {i0 + 1, half(e1, c), half(e2, c)};
      child.triangle_edges_[4 * t + 3] = {i0, i0 + 1, i0 + 2};
      const uint32_t m0 = nv + e0, m1 = nv + e1, m2 = nv + e2, f = static_cast<uint32_t>(4 * t);
      const size_t k = i0;
      child.edges_[k] = Edge::Of(m0, m1);
      child.edges_[k + 1] = Edge::Of(m1, m2);
      child.edges_[k + 2] = Edge::Of(m2, m0);
      child.edge_triangles_[k] = {f + 1, f + 3};
      child.edge_triangles_[k + 1] = {f + 2, f + 3};
      child.edge_triangles_[k + 2] = {f, f + 3};
      child.edge_crease_[k] = child.edge_crease_[k + 1] = child.edge_crease_[k + 2] = 0;
    }
  });
  ForRowBlocks(ne, threads, [&](size_t e0, size_t e1) {
    for (size_t e = e0; e < e1; ++e) {
      const uint32_t m = nv + static_cast<uint32_t>(e);
      for (int side = 0; side < 2; ++side) {
        const uint32_t end = side == 0 ? edges_[e].a : edges_[e].b;
        child.edges_[2 * e + side] = Edge{end, m};
        child.edge_crease_[2 * e + side] = edge_crease_[e];
        std::array<uint32_t, 2> tris{kNoIndex, kNoIndex};
        for (int k = 0; k < 2; ++k) {
          const uint32_t t = edge_triangles_[e][k];
          if (t == kNoIndex) continue;
          const auto& v = triangles_[t].v;
          tris[k] = 4 * t + (v[0] == end ? 0 : v[1] == end ? 1 : 2);
        }
        child.edge_triangles_[2 * e + side] = tris;
      }
    }
  });

  // Neighbours. A vertex point's are the edge points of its edges (same order: its offsets
  // are its parent's); an edge point's are the vertex points of its ends, then for each of
  // its triangles the edge points of the triangle's two other edges.
  internal::ReserveLarge(child.neighbour_offsets_, size_t{child.num_vertices_} + 1);
  internal::ReserveLarge(child.neighbour_vertices_, 2 * child_edges);
  internal::ReserveLarge(child.neighbour_edges_, 2 * child_edges);
  child.neighbour_offsets_.resize(size_t{child.num_vertices_} + 1);
  child.neighbour_vertices_.resize(2 * child_edges);
  child.neighbour_edges_.resize(2 * child_edges);
  std::copy(neighbour_offsets_.begin(), neighbour_offsets_.end(), child.neighbour_offsets_.begin());
  for (size_t e = 0; e < ne; ++e) {
    const auto& et = edge_triangles_[e];
    child.neighbour_offsets_[nv + e + 1] =
        child.neighbour_offsets_[nv + e] + 2 + 2 * ((et[0] != kNoIndex) + (et[1] != kNoIndex));
  }
  ForRowBlocks(nv, threads, [&](size_t v0, size_t v1) {
    for (size_t v = v0; v < v1; ++v) {
      uint32_t at = child.neighbour_offsets_[v];
      for (uint32_t e : neighbour_edges(static_cast<uint32_t>(v))) {
        child.neighbour_vertices_[at] = nv + e;
        child.neighbour_edges_[at++] = half(e, static_cast<uint32_t>(v));
      }
    }
  });
  ForRowBlocks(ne, threads, [&](size_t e0, size_t e1) {
    for (size_t e = e0; e < e1; ++e) {
      uint32_t at = child.neighbour_offsets_[nv + e];
      auto link = [&](uint32_t vertex, uint32_t edge) {
        child.neighbour_vertices_[at] = vertex;
        child.neighbour_edges_[at++] = edge;
      };
      link(edges_[e].a, static_cast<uint32_t>(2 * e));
      link(edges_[e].b, static_cast<uint32_t>(2 * e + 1));
      for (uint32_t t : edge_triangles_[e]) {
        if (t == kNoIndex) continue;
        const auto& te = triangle_edges_[t];
        const uint32_t i0 = inner(t);
        if (te[0] == e) {
          link(nv + te[1], i0);
          link(nv + te[2], i0 + 2);
        } else if (te[1] == e) {
          link(nv + te[0], i0);
          link(nv + te[2], i0 + 1);
        } else {
          link(nv + te[1], i0 + 1);
          link(nv + te[0], i0 + 2);
        }
      }
    }
  });
  return child;
}

std::vector<Triangle> TaggedMesh::RefinedTriangles(int threads) const {
  const uint32_t nv = num_vertices_;
  std::vector<Triangle> out;
  internal::ReserveLarge(out, 4 * triangles_.size());
  out.resize(4 * triangles_.size());
  ForRowBlocks(triangles_.size(), threads, [&](size_t t0, size_t t1) {
    for (size_t t = t0; t < t1; ++t) {
      const auto [a, b, c] = triangles_[t].v;
      const auto [e0, e1, e2] = triangle_edges_[t];
      const uint32_t m0 = nv + e0, m1 = nv + e1, m2 = nv + e2;
      out[4 * t] = Triangle{{a, m0, m2}};
      out[4 * t + 1] = Triangle{{m0, b, m1}};
      out[4 * t + 2] = Triangle{{m2, m1, c}};
      out[4 * t + 3] = Triangle{{m0, m1, m2}};
    }
  });
  return out;
}

std::vector<VertexTag> TaggedMesh::RefinedVertexTags() const {
  std::vector<VertexTag> out(size_t{num_vertices_} + edges_.size());
  std::copy(vertex_tags_.begin(), vertex_tags_.end(), out.begin());
  for (size_t e = 0; e < edges_.size(); ++e)
    out[num_vertices_ + e] = edge_crease_[e] ? VertexTag::kCrease : VertexTag::kSmooth;
  return out;
}

std::vector<Edge> TaggedMesh::RefinedCreaseEdges() const {
  std::vector<Edge> out;
  for (size_t e = 0; e < edges_.size(); ++e)
    if (edge_crease_[e]) {
      const uint32_t m = num_vertices_ + static_cast<uint32_t>(e);
      out.push_back(Edge{edges_[e].a, m});
      out.push_back(Edge{edges_[e].b, m});
    }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Edge> TaggedMesh::CreaseEdges() const {
  std::vector<Edge> out;
  for (size_t e = 0; e < edges_.size(); ++e)
    if (edge_crease_[e]) out.push_back(edges_[e]);
  std::sort(out.begin(), out.end());
  return out;
}

namespace {

// Edge rows [begin, end) of RefinementMasks(mesh) (edge e is row num_vertices + e).
template <typename Sink>
void EdgeRows(const TaggedMesh& mesh, size_t begin, size_t end, Sink& sink) {
  for (size_t e = begin; e < end; ++e) {
    const Edge& edge = mesh.edges()[e];
    const auto& tris = mesh.edge_triangles(e);
    if (mesh.is_crease(e) || tris[1] == kNoIndex) {
      // (A smooth edge with one triangle exists only at a sub-mesh cut: its value is unused.)
      const rules::EdgeMask m = mesh.is_crease(e)
                                    ? rules::CreaseEdgeRule(mesh.is_corner(edge.a), mesh.is_corner(edge.b))
                                    : rules::EdgeMask{};
      sink.Add(edge.a, m.end0);
      sink.Add(edge.b, m.end1);
    } else {
      const rules::EdgeMask m = rules::SmoothEdgeRule();
      sink.Add(edge.a, m.end0);
      sink.Add(edge.b, m.end1);
      sink.Add(OppositeVertex(mesh.triangles()[tris[0]], edge), m.opposite);
      sink.Add(OppositeVertex(mesh.triangles()[tris[1]], edge), m.opposite);
    }
    sink.EndRow();
  }
}

}  // namespace

SparseRows RefinementMasks(const TaggedMesh& mesh) {
  SparseRows rows;
  // Vertex rows hold at most 1 + valence entries, edge rows at most 4.
  const size_t n = mesh.num_vertices() + mesh.num_edges();
  const size_t entries = mesh.num_vertices() + 6 * mesh.num_edges();
  internal::ReserveLarge(rows.offsets, n + 1);
  internal::ReserveLarge(rows.indices, entries);
  internal::ReserveLarge(rows.weights, entries);
  VertexMasks(mesh, rows, rules::SmoothVertexRule, rules::CreaseVertexRule);
  MaskRows sink{rows};
  EdgeRows(mesh, 0, mesh.num_edges(), sink);
  return rows;
}

void ApplyRefinementRows(const TaggedMesh& mesh, const double* values, size_t begin, size_t end, double* out) {
  ValueRows sink{values, out};
  const size_t nv = mesh.num_vertices();
  if (begin < nv)
    VertexRows(mesh, static_cast<uint32_t>(begin), static_cast<uint32_t>(std::min(end, nv)), rules::SmoothVertexRule,
               rules::CreaseVertexRule, sink);
  if (end > nv) EdgeRows(mesh, std::max(begin, nv) - nv, end - nv, sink);
}

void ApplyLimitRows(const TaggedMesh& mesh, const double* values, uint32_t begin, uint32_t end, double* out) {
  ValueRows sink{values, out};
  VertexRows(mesh, begin, end, rules::SmoothLimitRule, rules::CreaseLimitRule, sink);
}

SparseRows LimitMasks(const TaggedMesh& mesh) {
  SparseRows rows;
  const size_t entries = mesh.num_vertices() + 2 * mesh.num_edges();
  internal::ReserveLarge(rows.offsets, size_t{mesh.num_vertices()} + 1);
  internal::ReserveLarge(rows.indices, entries);
  internal::ReserveLarge(rows.weights, entries);
  VertexMasks(mesh, rows, rules::SmoothLimitRule, rules::CreaseLimitRule);
  return rows;
}

int EdgeChildLimitRing(const TaggedMesh& mesh, uint32_t e, uint32_t children[7], double weights[7]) {
  const uint32_t nv = mesh.num_vertices();
  const Edge& edge = mesh.edges()[e];
  if (mesh.is_crease(e)) {
    // The child is a crease vertex whose crease neighbours are the children of a and b.
    const rules::CreaseVertexMask m = rules::CreaseLimitRule(mesh.is_corner(edge.a), mesh.is_corner(edge.b));
    children[0] = edge.a, weights[0] = m.c0;
    children[1] = nv + e, weights[1] = m.self;
    children[2] = edge.b, weights[2] = m.c1;
    return 3;
  }
  children[0] = nv + e;
  // A smooth child: its ring is the children of a and b and of the other edges of the
  // triangles of e (valence 6 inside the mesh).
  int n = 1;
  children[n++] = edge.a;
  children[n++] = edge.b;
  for (uint32_t t : mesh.edge_triangles(e)) {
    if (t == kNoIndex) continue;
    for (uint32_t other : mesh.triangle_edges(t))
      if (other != e) children[n++] = nv + other;
  }
  if (n < 4) {  // only at a sub-mesh cut, where values are unused
    weights[0] = 1.0;
    return 1;
  }
  const rules::SmoothVertexMask m = rules::SmoothLimitRule(n - 1);
  weights[0] = m.self;
  for (int i = 1; i < n; ++i) weights[i] = m.neighbour;
  return n;
}

namespace {

// Appends a row's terms, each times scale, to (indices, weights): the terms RefinementMasks
// or LimitMasks store, in their order (weights of exactly 0 are dropped, as Push does).
struct AppendRows {
  std::vector<uint32_t>& indices;
  std::vector<double>& weights;
  double scale = 1.0;
  void Add(uint32_t index, double weight) {
    if (weight == 0) return;
    indices.push_back(index);
    weights.push_back(scale * weight);
  }
  void EndRow() {}
};

}  // namespace

void AppendRefinementRow(const TaggedMesh& mesh, size_t row, std::vector<uint32_t>& indices,
                         std::vector<double>& weights, double scale) {
  AppendRows sink{indices, weights, scale};
  const uint32_t nv = mesh.num_vertices();
  if (row < nv) {
    VertexRows(mesh, static_cast<uint32_t>(row), static_cast<uint32_t>(row) + 1, rules::SmoothVertexRule,
               rules::CreaseVertexRule, sink);
  } else {
    EdgeRows(mesh, row - nv, row - nv + 1, sink);
  }
}

void AppendLimitRow(const TaggedMesh& mesh, uint32_t v, std::vector<uint32_t>& indices, std::vector<double>& weights) {
  AppendRows sink{indices, weights};
  VertexRows(mesh, v, v + 1, rules::SmoothLimitRule, rules::CreaseLimitRule, sink);
}

void AppendEdgeChildLimitMask(const TaggedMesh& mesh, uint32_t e, std::vector<uint32_t>& indices,
                              std::vector<double>& weights) {
  uint32_t children[7];
  double lambda[7];
  const int n = EdgeChildLimitRing(mesh, e, children, lambda);
  for (int k = 0; k < n; ++k) {
    if (lambda[k] == 0) continue;
    AppendRefinementRow(mesh, children[k], indices, weights, lambda[k]);
  }
}

namespace {

// Appends a row's terms, each times scale, to a merged row in a buffer sized for them: a
// term whose index is already there is added to its sum, in order; a new index is appended
// with 0.0 + the term (what a dense accumulator cleared to 0 gives). Weights of exactly 0
// are dropped, as Push does. A row has a few dozen terms, so searching the merged indices
// is cheaper than a dense accumulator over the level's vertices, which misses the caches.
struct MergedRows {
  uint32_t* indices;
  double* weights;
  size_t size = 0;
  double scale = 1.0;
  void Add(uint32_t index, double weight) {
    if (weight == 0) return;
    const double term = scale * weight;
    size_t j = 0;
    while (j < size && indices[j] != index) ++j;
    if (j == size) {
      indices[size] = index;
      weights[size++] = 0.0 + term;
    } else {
      weights[j] += term;
    }
  }
  void EndRow() {}
};

}  // namespace

void AppendMergedEdgeChildLimitMask(const TaggedMesh& mesh, uint32_t e, std::vector<uint32_t>& indices,
                                    std::vector<double>& weights) {
  uint32_t children[7];
  double lambda[7];
  const int n = EdgeChildLimitRing(mesh, e, children, lambda);
  const uint32_t nv = mesh.num_vertices();
  // Room for every term: a vertex row has at most 1 + valence, an edge row at most 4.
  size_t room = 0;
  for (int k = 0; k < n; ++k) room += children[k] < nv ? 1 + mesh.neighbours(children[k]).size() : 4;
  const size_t first = indices.size();
  indices.resize(first + room);
  weights.resize(first + room);
  MergedRows sink{indices.data() + first, weights.data() + first};
  for (int k = 0; k < n; ++k) {
    if (lambda[k] == 0) continue;
    sink.scale = lambda[k];
    if (children[k] < nv) {
      VertexRows(mesh, children[k], children[k] + 1, rules::SmoothVertexRule, rules::CreaseVertexRule, sink);
    } else {
      EdgeRows(mesh, children[k] - nv, children[k] - nv + 1, sink);
    }
  }
  indices.resize(first + sink.size);
  weights.resize(first + sink.size);
}

}  // namespace sdvi
