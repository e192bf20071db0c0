// SPDX-License-Identifier: GPL-3.0-or-later
// The neighbour-mean prediction of grid indices and the adaptive binarisation of its residuals,
// one definition for every use: the neighbour-mean colours of the Draco mesh (payload 1.3,
// spec/FORMAT.md 8.2), the positions (payload 1.4, 8.7) and the colours (payload 1.5, 8.8) in
// the tag stream.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "range_coder.h"
#include "tag_stream.h"

namespace sdvi::codec_internal {

// Per vertex, its *earlier neighbours*: the other ends of its mesh edges (edges as
// CollectMeshEdges returns them: unique, sorted by (a, b)) with a smaller index, ascending,
// each once. An edge of a vertex to itself (only in a damaged mesh) is no neighbour.
inline std::vector<std::vector<uint32_t>> EarlierNeighbours(size_t vertex_count, const std::vector<MeshEdge>& edges) {
  std::vector<std::vector<uint32_t>> out(vertex_count);
  for (const MeshEdge& e : edges)
    if (e.a != e.b) out[e.b].push_back(e.a);
  return out;
}

// The prediction of component k of vertex v from the indices q of the vertices before it: the
// mean of q over v's earlier neighbours rounded half up, floor((2 sum + c) / (2 c)) for c of
// them, in integer arithmetic; without any, q of vertex v - 1 (0 for vertex 0). The sum is
// taken in 128 bits: a decoded colour index is up to 2^40 in size and a damaged mesh can give
// one vertex millions of neighbours, so 64 bits could overflow. The mean lies within the
// neighbours' range, so it fits 64 bits.
template <typename T, size_t N>
int64_t MeanPrediction(const std::vector<uint32_t>& earlier, const std::vector<std::array<T, N>>& q, size_t v, int k) {
  if (earlier.empty()) return v > 0 ? int64_t{q[v - 1][k]} : 0;
  __int128 sum = 0;
  for (uint32_t j : earlier) sum += q[j][k];
  const __int128 c = static_cast<__int128>(earlier.size());
  const __int128 a = 2 * sum + c, b = 2 * c;
  return static_cast<int64_t>(a >= 0 ? a / b : -((-a + b - 1) / b));
}

// The adaptive models of one component's residuals, all starting at one half: zero, sign, and
// per length e (0 .. Lengths - 1) a length model and a top-bit model. A residual of size below
// 2^Lengths is coded: zero (1: r = 0), else sign (1: negative), then e one bits with length
// models 0 .. e - 1 and a zero bit with length model e (|r| in [2^e, 2^(e+1))), then for
// e >= 1 the bit 2^(e-1) with top-bit model e and for e >= 2 the lower e - 1 bits direct.
template <int Lengths>
struct ResidualModels {
  static_assert(Lengths >= 1 && Lengths <= 32);
  BitModel zero, sign;
  std::array<BitModel, Lengths> length{}, top{};
};

// r must be below 2^Lengths in size.
template <int Lengths>
void EncodeResidual(RangeEncoder& rc, ResidualModels<Lengths>& m, int64_t r) {
  rc.Encode(m.zero, r == 0);
  if (r == 0) return;
  rc.Encode(m.sign, r < 0);
  const uint32_t a = static_cast<uint32_t>(r < 0 ? -r : r);
  const int e = std::bit_width(a) - 1;  // a in [2^e, 2^(e+1))
  for (int j = 0; j <= e; ++j) rc.Encode(m.length[j], j < e);
  if (e >= 1) {
    rc.Encode(m.top[e], (a >> (e - 1)) & 1);
    if (e >= 2) rc.EncodeDirect(a & ((uint32_t{1} << (e - 1)) - 1), e - 1);
  }
}

// False when Lengths length bits in a row are 1 (the residual does not end: corrupt).
template <int Lengths>
bool DecodeResidual(RangeDecoder& rc, ResidualModels<Lengths>& m, int64_t* r) {
  *r = 0;
  if (rc.Decode(m.zero)) return true;
  const bool negative = rc.Decode(m.sign);
  int e = 0;
  while (rc.Decode(m.length[e]))
    if (++e == Lengths) return false;
  int64_t a = int64_t{1} << e;
  if (e >= 1) {
    a |= int64_t{rc.Decode(m.top[e])} << (e - 1);
    if (e >= 2) a |= rc.DecodeDirect(e - 1);
  }
  *r = negative ? -a : a;
  return true;
}

}  // namespace sdvi::codec_internal
