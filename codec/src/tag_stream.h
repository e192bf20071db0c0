// SPDX-License-Identifier: GPL-3.0-or-later
// The tag stream of the Draco payload (spec/FORMAT.md, "Tag stream"): which mesh edges
// are crease edges, which vertices are explicit corners and, optionally, the feature
// layer, as adaptive-binary-range-coded bits in an order both sides derive from the
// decoded mesh alone.
//
// 1. Edge bits: the undirected mesh edges (a, b), a < b, sorted by (a, b); one bit each,
//    1 = crease. Context: boundary (edge of exactly one triangle) x min(crease degree of
//    a so far, 2) x min(crease degree of b so far, 2): 18 models.
// 2. Corner bits: vertex 0..V-1, 1 = explicit corner; context min(crease degree, 3).
// 3. Feature layer (when present): polyline count; per polyline a closed bit, the first
//    vertex (written out, or in payload 1.1 ranked: within 4 indices of the previous
//    polyline's first, or its rank among the crease vertices on no polyline yet), then per vertex a stop bit and, unless stopping, the next vertex as the
//    choice among the current vertex's crease neighbours (ascending, the previous vertex
//    left out) or an escape with the index written out. Then the pairs: their polyline
//    indices and sharpness written out (payload 1.0) or, compact (payload 1.1), the first
//    polyline as expected (the previous pair's second + 1) or written out, the second as
//    first + 1 or written out, the sharpness as one of the 8 most recently used values or
//    written out.
//    Features first (payload 1.2): the feature layer comes before the edge bits; the pairs
//    before the polylines, and each polyline's next vertex is a choice among the current
//    vertex's mesh neighbours, ordered by how well they continue the polyline (off earlier
//    polylines, beside the paired polyline's next vertex, nearest to the straight
//    continuation of the last step in the decoded positions). The edge bits then take
//    polyline segments from two models of their own, so crease edges along polylines cost
//    almost nothing.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi::codec_internal {

struct PositionStream;  // position_stream.h
struct ColorStream;     // color_stream.h

// One undirected mesh edge and the number of triangles that have it.
struct MeshEdge {
  uint32_t a = 0, b = 0;  // a < b
  uint32_t triangles = 0;
};

// Every edge of triangles, sorted by (a, b).
std::vector<MeshEdge> CollectMeshEdges(const std::vector<Triangle>& triangles);

// What the tag stream carries.
struct Tags {
  std::vector<Edge> crease_edges;       // sorted, unique, each a mesh edge
  std::vector<uint32_t> corners;        // sorted, unique, each < vertex count
  bool has_feature_layer = false;
  std::vector<FeaturePolyline> polylines;  // vertex indices < vertex count
  std::vector<FeaturePair> pairs;          // polyline indices < polylines.size()
  bool compact_pairs = true;               // the pairs coded compactly (payload 1.1)
  bool ranked_starts = true;               // polyline starts coded by rank (payload 1.1)
  bool features_first = false;             // the feature layer before the edge bits (payload 1.2)
  // The vertex positions, coded first (payload 1.4, position_stream.h); null: in the Draco mesh.
  const PositionStream* positions = nullptr;
  // The colours, coded after the positions (payload 1.5, color_stream.h; only with positions);
  // null: in the Draco mesh.
  const ColorStream* colors = nullptr;
};

// The decoded positions of the vertices (their x, y; features_first orders a polyline's
// next vertex by them), in the tag stream's vertex numbering.
using Positions = std::span<const Vertex>;

// Codes tags of a mesh with vertex_count vertices and the given edges. With
// tags.features_first and a feature layer, positions must hold vertex_count vertices as the
// reader decodes them; *feature_bytes (when given) receives the bytes of the stream up to the end of its feature layer
// (features first only; else 0), *position_bytes those up to the end of the positions (0 without them).
std::vector<uint8_t> EncodeTags(uint32_t vertex_count, const std::vector<MeshEdge>& edges,
                                const Tags& tags, Positions positions = {}, size_t* feature_bytes = nullptr,
                                size_t* position_bytes = nullptr);

// Decodes tags (the feature layer when has_feature_layer); kCorrupt (naming source_name)
// when the stream overruns, names a vertex or polyline that does not exist, or its counts
// differ from the header's. With decoded_positions (vertex_count vertices) the stream starts with
// the positions on a grid of position_bits (payload 1.4): their x, y are decoded into it and
// the feature layer is ordered by them (positions is then ignored); with decoded_colors too, the
// colours follow them (payload 1.5) and are decoded into it.
Status DecodeTags(std::span<const uint8_t> bytes, uint32_t vertex_count,
                  const std::vector<MeshEdge>& edges, uint32_t expected_crease_edges,
                  uint32_t expected_corners, bool has_feature_layer, bool compact_pairs,
                  bool ranked_starts, const std::string& source_name, Tags* tags,
                  bool features_first = false, Positions positions = {}, int position_bits = 0,
                  std::vector<Vertex>* decoded_positions = nullptr, ColorStream* decoded_colors = nullptr);

// The parts of a Draco payload (PartBytes in sdvi/codec.h; container = its 40-byte header);
// defined in draco_payload.cpp.
StatusOr<PartBytes> MeasureDracoParts(std::span<const uint8_t> payload, const std::string& source_name);

}  // namespace sdvi::codec_internal
