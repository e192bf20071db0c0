// SPDX-License-Identifier: GPL-3.0-or-later
// Colours in the tag stream (payload 1.5, spec/FORMAT.md 8.8; grey, payload 1.6, 8.9).
#include "color_stream.h"

#include <bit>
#include <cmath>
#include <cstdlib>

#include "neighbour_mean.h"

namespace sdvi::codec_internal {
namespace {

constexpr int kColorLengths = 32;  // a residual is below 2^31 in size

// One set of residual models per component (L, C1, C2).
using ColorModels = std::array<ResidualModels<kColorLengths>, 3>;

}  // namespace

void EncodeColors(RangeEncoder& rc, const ColorStream& stream, const std::vector<MeshEdge>& edges) {
  const uint64_t step = std::bit_cast<uint64_t>(stream.step);
  rc.EncodeDirect(static_cast<uint32_t>(step >> 32), 32);
  rc.EncodeDirect(static_cast<uint32_t>(step), 32);
  const int components = stream.components == 1 ? 1 : 3;
  for (int k = 0; k < components; ++k) rc.EncodeDirect(std::bit_cast<uint32_t>(stream.origin[k]), 32);
  const auto earlier = EarlierNeighbours(stream.q.size(), edges);
  ColorModels m;
  for (size_t v = 0; v < stream.q.size(); ++v)
    for (int k = 0; k < components; ++k) EncodeResidual(rc, m[k], stream.q[v][k] - MeanPrediction(earlier[v], stream.q, v, k));
}

Status DecodeColors(RangeDecoder& rc, size_t vertex_count, const std::vector<MeshEdge>& edges,
                    const std::string& what, ColorStream* out) {
  const uint64_t high = rc.DecodeDirect(32);
  out->step = std::bit_cast<double>(high << 32 | rc.DecodeDirect(32));
  const int components = out->components == 1 ? 1 : 3;
  out->origin.fill(0.f);
  for (int k = 0; k < components; ++k) out->origin[k] = std::bit_cast<float>(rc.DecodeDirect(32));
  if (!std::isfinite(out->step) || !(out->step > 0) || !std::isfinite(out->origin[0]) ||
      !std::isfinite(out->origin[1]) || !std::isfinite(out->origin[2]))
    return Status(StatusCode::kCorrupt, what + ": the colour grid is not finite with a positive step");
  const auto earlier = EarlierNeighbours(vertex_count, edges);
  out->q.assign(vertex_count, {0, 0, 0});
  ColorModels m;
  for (size_t v = 0; v < vertex_count; ++v)
    for (int k = 0; k < components; ++k) {
      int64_t r = 0;
      if (!DecodeResidual(rc, m[k], &r)) return Status(StatusCode::kCorrupt, what + ": a colour residual does not end");
      const int64_t value = MeanPrediction(earlier[v], out->q, v, k) + r;
      if (std::abs(value) > kMaxColorIndex || rc.overrun())
        return Status(StatusCode::kCorrupt, what + ": vertex " + std::to_string(v) + "'s colour lies off its grid");
      out->q[v][k] = value;
    }
  return Status::Ok();
}

}  // namespace sdvi::codec_internal
