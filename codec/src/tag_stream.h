// The tag stream of the Draco payload (spec/FORMAT.md, "Tag stream"): which mesh edges
// are crease edges and which vertices are explicit corners, as adaptive-binary-range-
// coded bits in an order both sides derive from the decoded mesh alone.
//
// Edge bits: the undirected mesh edges (a, b), a < b, sorted by (a, b); one bit each,
// 1 = crease. Context: boundary (edge of exactly one triangle) x min(crease degree of a
// so far, 2) x min(crease degree of b so far, 2): 18 models. Then corner bits: vertex 0..
// V-1, 1 = explicit corner, context min(crease degree, 3): 4 models.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi::codec_internal {

// One undirected mesh edge and the number of triangles that have it.
struct MeshEdge {
  uint32_t a = 0, b = 0;  // a < b
  uint32_t triangles = 0;
};

// Every edge of triangles, sorted by (a, b).
std::vector<MeshEdge> CollectMeshEdges(const std::vector<Triangle>& triangles);

// Codes crease_edges (sorted, unique, each a mesh edge) and corners (sorted, unique,
// each < vertex_count) of a mesh with the given edges.
std::vector<uint8_t> EncodeTags(uint32_t vertex_count, const std::vector<MeshEdge>& edges,
                                const std::vector<Edge>& crease_edges,
                                const std::vector<uint32_t>& corners);

// Decodes the tags; kCorrupt (naming source_name) when the stream overruns or the
// counts differ from the header's.
Status DecodeTags(std::span<const uint8_t> bytes, uint32_t vertex_count,
                  const std::vector<MeshEdge>& edges, uint32_t expected_crease_edges,
                  uint32_t expected_corners, const std::string& source_name,
                  std::vector<Edge>* crease_edges, std::vector<uint32_t>* corners);

}  // namespace sdvi::codec_internal
