// SPDX-License-Identifier: GPL-3.0-or-later
// Positions in the tag stream (payload 1.4, spec/FORMAT.md 8.7).
#include "position_stream.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

namespace sdvi::codec_internal {
namespace {

constexpr int kLengths = 25;  // a residual is below 2^24 in size: lengths 0..24

struct PositionModels {
  std::array<BitModel, 2> zero{}, sign{};
  std::array<std::array<BitModel, kLengths>, 2> length{}, top{};
};

// Per vertex, the other ends of its mesh edges with a smaller index.
std::vector<std::vector<uint32_t>> EarlierNeighbours(size_t vertex_count, const std::vector<MeshEdge>& edges) {
  std::vector<std::vector<uint32_t>> out(vertex_count);
  for (const MeshEdge& e : edges) out[e.b].push_back(e.a);
  return out;
}

// The mean of the earlier neighbours' index k rounded half up, floor((2 sum + c) / (2 c));
// none: the previous vertex's (0 for vertex 0). Indices are below 2^24, so sums of up to
// 2^38 neighbours fit 64 bits.
int64_t Prediction(const std::vector<uint32_t>& earlier, const std::vector<std::array<int32_t, 2>>& q, size_t v,
                   int k) {
  if (earlier.empty()) return v > 0 ? q[v - 1][k] : 0;
  int64_t sum = 0;
  for (uint32_t j : earlier) sum += q[j][k];
  const int64_t c = static_cast<int64_t>(earlier.size());
  const int64_t a = 2 * sum + c, b = 2 * c;  // a >= 0: indices are not negative
  return a / b;
}

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
    for (int k = 0; k < 2; ++k) {
      const int64_t r = stream.q[v][k] - Prediction(earlier[v], stream.q, v, k);
      rc.Encode(m.zero[k], r == 0);
      if (r == 0) continue;
      rc.Encode(m.sign[k], r < 0);
      const uint32_t a = static_cast<uint32_t>(r < 0 ? -r : r);
      const int e = std::bit_width(a) - 1;  // a in [2^e, 2^(e+1))
      for (int j = 0; j <= e; ++j) rc.Encode(m.length[k][j], j < e);
      if (e >= 1) {
        rc.Encode(m.top[k][e], (a >> (e - 1)) & 1);
        if (e >= 2) rc.EncodeDirect(a & ((uint32_t{1} << (e - 1)) - 1), e - 1);
      }
    }
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
      if (!rc.Decode(m.zero[k])) {
        const bool negative = rc.Decode(m.sign[k]);
        int e = 0;
        while (rc.Decode(m.length[k][e]))
          if (++e == kLengths) return Status(StatusCode::kCorrupt, what + ": a position residual does not end");
        int64_t a = int64_t{1} << e;
        if (e >= 1) {
          a |= int64_t{rc.Decode(m.top[k][e])} << (e - 1);
          if (e >= 2) a |= rc.DecodeDirect(e - 1);
        }
        r = negative ? -a : a;
      }
      const int64_t value = Prediction(earlier[v], q, v, k) + r;
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
