#include "tag_stream.h"

#include <algorithm>
#include <array>

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

int CornerContext(uint32_t v, const std::vector<uint32_t>& degree) {
  return static_cast<int>(std::min<uint32_t>(degree[v], 3));
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

std::vector<uint8_t> EncodeTags(uint32_t vertex_count, const std::vector<MeshEdge>& edges,
                                const std::vector<Edge>& crease_edges,
                                const std::vector<uint32_t>& corners) {
  RangeEncoder encoder;
  std::array<BitModel, kEdgeContexts> edge_models{};
  std::array<BitModel, kCornerContexts> corner_models{};
  std::vector<uint32_t> degree(vertex_count, 0);
  size_t next_crease = 0;  // crease_edges and edges are both sorted by (a, b)
  for (const MeshEdge& e : edges) {
    while (next_crease < crease_edges.size() && crease_edges[next_crease] < Edge{e.a, e.b})
      ++next_crease;
    const bool crease = next_crease < crease_edges.size() &&
                        crease_edges[next_crease].a == e.a && crease_edges[next_crease].b == e.b;
    encoder.Encode(edge_models[EdgeContext(e, degree)], crease);
    if (crease) {
      ++degree[e.a];
      ++degree[e.b];
    }
  }
  size_t next_corner = 0;
  for (uint32_t v = 0; v < vertex_count; ++v) {
    const bool corner = next_corner < corners.size() && corners[next_corner] == v;
    if (corner) ++next_corner;
    encoder.Encode(corner_models[CornerContext(v, degree)], corner);
  }
  return encoder.Finish();
}

Status DecodeTags(std::span<const uint8_t> bytes, uint32_t vertex_count,
                  const std::vector<MeshEdge>& edges, uint32_t expected_crease_edges,
                  uint32_t expected_corners, const std::string& source_name,
                  std::vector<Edge>* crease_edges, std::vector<uint32_t>* corners) {
  RangeDecoder decoder(bytes);
  std::array<BitModel, kEdgeContexts> edge_models{};
  std::array<BitModel, kCornerContexts> corner_models{};
  std::vector<uint32_t> degree(vertex_count, 0);
  std::vector<Edge> creases;
  std::vector<uint32_t> tagged_corners;
  for (const MeshEdge& e : edges) {
    if (decoder.Decode(edge_models[EdgeContext(e, degree)])) {
      creases.push_back({e.a, e.b});
      ++degree[e.a];
      ++degree[e.b];
      if (creases.size() > expected_crease_edges) break;
    }
  }
  if (creases.size() != expected_crease_edges)
    return Status(StatusCode::kCorrupt,
                  source_name + ": Draco payload tag stream holds " +
                      (creases.size() > expected_crease_edges ? "more than " : "") +
                      std::to_string(creases.size()) + " crease edges, header says " +
                      std::to_string(expected_crease_edges));
  for (uint32_t v = 0; v < vertex_count; ++v) {
    if (decoder.Decode(corner_models[CornerContext(v, degree)])) {
      tagged_corners.push_back(v);
      if (tagged_corners.size() > expected_corners) break;
    }
  }
  if (tagged_corners.size() != expected_corners)
    return Status(StatusCode::kCorrupt,
                  source_name + ": Draco payload tag stream holds " +
                      (tagged_corners.size() > expected_corners ? "more than " : "") +
                      std::to_string(tagged_corners.size()) + " corners, header says " +
                      std::to_string(expected_corners));
  if (decoder.overrun())
    return Status(StatusCode::kCorrupt,
                  source_name + ": Draco payload tag stream (" + std::to_string(bytes.size()) +
                      " bytes) ends before its last bit or does not start with a zero byte");
  *crease_edges = std::move(creases);
  *corners = std::move(tagged_corners);
  return Status::Ok();
}

}  // namespace sdvi::codec_internal
