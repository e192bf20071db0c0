// SPDX-License-Identifier: GPL-3.0-or-later
// Tagged triangle-mesh topology of the extended Loop scheme (spec/SUBDIVISION.md section 1):
// connectivity tables (structure of arrays) plus crease tags on edges and
// smooth / crease / corner tags on vertices. Refinement produces the next level's
// topology with inherited tags; the masks that move values live in subdiv_rules.h and
// are gathered per level by RefinementMasks / LimitMasks below.
//
// Invariants of a TaggedMesh:
//  - every edge has one or two triangles (more is kNonManifoldEdge); an edge with one
//    triangle is on the mesh boundary and is always crease;
//  - a vertex with crease-degree 1 (endpoint) or >= 3 (junction), or tagged corner
//    explicitly, is a corner; crease-degree 2 is crease; 0 is smooth. A vertex in no
//    triangle is a corner (it never moves);
//  - refinement numbering: vertex v of level k is vertex v of level k+1; edge e of level
//    k gives vertex num_vertices + e; triangle t = (a, b, c) gives triangles 4t .. 4t+3 =
//    (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca), all oriented like t. So a
//    level-r triangle f descends from control triangle f >> 2r, and the first
//    num_vertices of every level are the control vertices.
//  - edge e = (a, b) of level k gives edges 2e = (a, m) and 2e+1 = (m, b) of level k+1,
//    which inherit its crease tag; the three edges inside triangle t are smooth.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sdvi/default_init_allocator.h"
#include "sdvi/image.h"
#include "sdvi/status.h"
#include "sdvi/subdiv.h"

namespace sdvi {

inline constexpr uint32_t kNoIndex = 0xffffffffu;

class TaggedMesh {
 public:
  TaggedMesh() = default;

  // Validates the control mesh of image and tags it: kEmptyInput (no vertices or no
  // triangles), kIndexOutOfRange, kDegenerateTriangle, kDuplicateTriangle,
  // kNonManifoldEdge, kCreaseNotAnEdge; every message names the element.
  static StatusOr<TaggedMesh> FromImage(const Image& image);
  // The same from the parts (num_vertices, triangles, crease edges, explicit corners).
  static StatusOr<TaggedMesh> Build(uint32_t num_vertices, std::span<const Triangle> triangles,
                                    std::span<const Edge> crease_edges,
                                    std::span<const uint32_t> corners);

  // The sub-mesh made of the given triangles of this mesh, keeping this mesh's tags
  // (a cut edge stays smooth, a vertex keeps its tag). vertex_map receives, for each
  // sub-mesh vertex, its vertex in this mesh. Values near the cut are not those of this
  // mesh; BuildLimitSurface keeps a margin of rings around a region for that reason.
  TaggedMesh Submesh(std::span<const uint32_t> triangles, std::vector<uint32_t>* vertex_map) const;

  // The next level's topology (numbering in the header comment). threads: workers for a
  // large mesh (0 = the hardware's, at most 8); the result does not depend on it.
  TaggedMesh Refine(int threads = 1) const;
  // Parts of Refine() for callers that need only these: the next level's triangles,
  // vertex tags and sorted crease edges.
  std::vector<Triangle> RefinedTriangles(int threads = 1) const;
  std::vector<VertexTag> RefinedVertexTags() const;
  std::vector<Edge> RefinedCreaseEdges() const;

  uint32_t num_vertices() const { return num_vertices_; }
  size_t num_triangles() const { return triangles_.size(); }
  size_t num_edges() const { return edges_.size(); }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  const std::vector<Edge>& edges() const { return edges_; }
  // Edge k of triangle t joins v[k] and v[(k+1) % 3].
  const std::array<uint32_t, 3>& triangle_edges(size_t t) const { return triangle_edges_[t]; }
  // The triangles of edge e; the second is kNoIndex on the boundary.
  const std::array<uint32_t, 2>& edge_triangles(size_t e) const { return edge_triangles_[e]; }
  bool is_crease(size_t e) const { return edge_crease_[e] != 0; }
  VertexTag tag(uint32_t v) const { return vertex_tags_[v]; }
  bool is_corner(uint32_t v) const { return vertex_tags_[v] == VertexTag::kCorner; }
  const std::vector<VertexTag>& vertex_tags() const { return vertex_tags_; }
  // Neighbours of v (the other ends of its edges) and the edges to them, same order.
  std::span<const uint32_t> neighbours(uint32_t v) const {
    return {neighbour_vertices_.data() + neighbour_offsets_[v],
            neighbour_vertices_.data() + neighbour_offsets_[v + 1]};
  }
  std::span<const uint32_t> neighbour_edges(uint32_t v) const {
    return {neighbour_edges_.data() + neighbour_offsets_[v],
            neighbour_edges_.data() + neighbour_offsets_[v + 1]};
  }
  // The crease edges, sorted.
  std::vector<Edge> CreaseEdges() const;

 private:
  // Edges, triangle_edges, edge_triangles from triangles_ (sorting); kNonManifoldEdge.
  Status BuildEdges();
  // Neighbour tables from edges_.
  void BuildNeighbours();
  // Vertex tags from edge tags, crease degrees and explicit corners.
  void TagVertices(std::span<const uint32_t> corners);

  // Tables not exposed as vectors leave resize's new elements unwritten (Refine fills them
  // from several threads, each writing its own part).
  template <typename T>
  using Table = std::vector<T, DefaultInitAllocator<T>>;

  uint32_t num_vertices_ = 0;
  std::vector<Triangle> triangles_;
  Table<std::array<uint32_t, 3>> triangle_edges_;
  std::vector<Edge> edges_;
  Table<std::array<uint32_t, 2>> edge_triangles_;
  Table<uint8_t> edge_crease_;
  std::vector<VertexTag> vertex_tags_;
  Table<uint32_t> neighbour_offsets_;
  Table<uint32_t> neighbour_vertices_;
  Table<uint32_t> neighbour_edges_;
};

// A sparse matrix in CSR form with double weights: row i = sum_k weights[k] * x[indices[k]].
struct SparseRows {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;
  std::vector<double> weights;
  size_t rows() const { return offsets.size() - 1; }
};

// One refinement step as a matrix: row i is child vertex i of mesh.Refine() as a
// combination of mesh's vertices (masks of subdiv_rules.h).
SparseRows RefinementMasks(const TaggedMesh& mesh);
// Row v is the limit position of vertex v of mesh as a combination of mesh's vertices.
SparseRows LimitMasks(const TaggedMesh& mesh);

// Rows [begin, end) of RefinementMasks(mesh) (of LimitMasks(mesh): vertex rows only) applied
// to values (5 doubles a vertex of mesh) into out (5 doubles a row, row begin first), without
// building the masks: each row's terms are summed from zero in the masks' order, so the
// result is bit for bit that of applying the built rows that way.
void ApplyRefinementRows(const TaggedMesh& mesh, const double* values, size_t begin, size_t end, double* out);
void ApplyLimitRows(const TaggedMesh& mesh, const double* values, uint32_t begin, uint32_t end, double* out);

// Row `row` of RefinementMasks(mesh), each weight times scale, and row v of LimitMasks(mesh),
// appended to (indices, weights) without building the masks: the same entries in the same
// order as the built rows (BuildLimitSurface composes rows this way, so that no level's
// masks are held in memory).
void AppendRefinementRow(const TaggedMesh& mesh, size_t row, std::vector<uint32_t>& indices,
                         std::vector<double>& weights, double scale = 1.0);
void AppendLimitRow(const TaggedMesh& mesh, uint32_t v, std::vector<uint32_t>& indices, std::vector<double>& weights);

// The limit position of the child of edge e (vertex num_vertices + e of mesh.Refine()) as
// a combination of mesh's vertices, without building the next level: the limit mask of
// the child's one-ring there (EdgeChildLimitRing), each ring vertex taken through its
// refinement row (AppendRefinementRow, times its ring weight). Entries are appended to
// (indices, weights) and may repeat an index. (A vertex child's limit is the limit of its
// parent: AppendLimitRow.)
void AppendEdgeChildLimitMask(const TaggedMesh& mesh, uint32_t e, std::vector<uint32_t>& indices,
                              std::vector<double>& weights);
// The same mask with repeated indices merged: each index once, where it first appears, its
// weight 0.0 + its first entry + its later ones in order (what summing the entries into a
// dense accumulator cleared to 0 gives, bit for bit). BuildLimitSurface's edge-child rows.
void AppendMergedEdgeChildLimitMask(const TaggedMesh& mesh, uint32_t e, std::vector<uint32_t>& indices,
                                    std::vector<double>& weights);

// The same limit as a combination of the next level's vertices (the child's one-ring
// there, numbered as in mesh.Refine(): vertex children first, then edge children): at most
// 7 entries written to children / weights, their count returned.
int EdgeChildLimitRing(const TaggedMesh& mesh, uint32_t e, uint32_t children[7], double weights[7]);

}  // namespace sdvi
