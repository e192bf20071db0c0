// SPDX-License-Identifier: GPL-3.0-or-later
// Positions in the tag stream (payload 1.4, spec/FORMAT.md 8.7).
#include "position_stream.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "neighbour_mean.h"

namespace sdvi::codec_internal {
namespace {

constexpr int kPositionLengths = 25;  // a residual is below 2^24 in size: lengths 0..24

// One set of residual models per coordinate (x, y).
using PositionModels = std::array<ResidualModels<kPositionLengths>, 2>;

uint32_t FloatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
float BitsFloat(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

}  // namespace

DracoPositionGrid::DracoPositionGrid(const Image& image, int bits) {
  const Vertex& first = image.vertices.front();
  float lo[2] = {first.x, first.y}, hi[2] = {first.x, first.y};
  for (const Vertex& v : image.vertices) {
    const float c[2] = {v.x, v.y};
    for (int k = 0; k < 2; ++k) {
      if (lo[k] > c[k]) lo[k] = c[k];
      if (hi[k] < c[k]) hi[k] = c[k];
    }
  }
  float range = 0.f;
  for (int k = 0; k < 2; ++k) {
    min_[k] = lo[k];
    range = std::max(range, hi[k] - lo[k]);
  }
  range_ = range == 0.f ? 1.f : range;
  Init(bits);
}

DracoPositionGrid::DracoPositionGrid(float min_x, float min_y, float range, int bits) {
  min_[0] = min_x;
  min_[1] = min_y;
  range_ = range;
  Init(bits);
}

void DracoPositionGrid::Init(int bits) {
  const auto max_quantized = static_cast<int32_t>((uint32_t{1} << bits) - 1);
  quantizer_.Init(range_, max_quantized);
  dequantizer_.Init(range_, max_quantized);
}

void EncodePositions(RangeEncoder& rc, const PositionStream& stream, const std::vector<MeshEdge>& edges) {
  rc.EncodeDirect(FloatBits(stream.min_x), 32);
  rc.EncodeDirect(FloatBits(stream.min_y), 32);
  rc.EncodeDirect(FloatBits(stream.range), 32);
  const auto earlier = EarlierNeighbours(stream.q.size(), edges);
  PositionModels m;
  for (size_t v = 0; v < stream.q.size(); ++v)
    for (int k = 0; k < 2; ++k) EncodeResidual(rc, m[k], stream.q[v][k] - MeanPrediction(earlier[v], stream.q, v, k));
}

Status DecodePositions(RangeDecoder& rc, int bits, const std::vector<MeshEdge>& edges, const std::string& what,
                       std::vector<Vertex>* vertices) {
  if (bits < 1 || bits > 24)
    return Status(StatusCode::kCorrupt, what + ": the position grid has " + std::to_string(bits) + " bits");
  const float min_x = BitsFloat(rc.DecodeDirect(32)), min_y = BitsFloat(rc.DecodeDirect(32));
  const float range = BitsFloat(rc.DecodeDirect(32));
  if (!std::isfinite(min_x) || !std::isfinite(min_y) || !std::isfinite(range) || !(range > 0))
    return Status(StatusCode::kCorrupt, what + ": the position grid is not finite and positive");
  const DracoPositionGrid grid(min_x, min_y, range, bits);
  const int64_t top = (int64_t{1} << bits) - 1;
  const size_t n = vertices->size();
  const auto earlier = EarlierNeighbours(n, edges);
  std::vector<std::array<int32_t, 2>> q(n);
  PositionModels m;
  for (size_t v = 0; v < n; ++v) {
    for (int k = 0; k < 2; ++k) {
      int64_t r = 0;
      if (!DecodeResidual(rc, m[k], &r)) return Status(StatusCode::kCorrupt, what + ": a position residual does not end");
      const int64_t value = MeanPrediction(earlier[v], q, v, k) + r;
      if (value < 0 || value > top || rc.overrun())
        return Status(StatusCode::kCorrupt, what + ": vertex " + std::to_string(v) + "'s position lies off its grid");
      q[v][k] = static_cast<int32_t>(value);
    }
    (*vertices)[v].x = grid.Position(q[v][0], 0);
    (*vertices)[v].y = grid.Position(q[v][1], 1);
  }
  return Status::Ok();
}

}  // namespace sdvi::codec_internal
