// SPDX-License-Identifier: GPL-3.0-or-later
// Neighbour-mean colours coded by the payload itself instead of Draco (payload 1.5,
// spec/FORMAT.md 8.8): L, C1, C2 of the decorrelated colours as indices on the grids of
// neighbour-mean colours (8.2), each predicted by the mean of the vertex's earlier neighbours
// and the residual binarised with adaptive models of the tag stream's range coder, after the
// positions (8.7). A grey image's one component (payload 1.6, 8.9) is coded the same way.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "range_coder.h"
#include "sdvi/status.h"
#include "tag_stream.h"

namespace sdvi::codec_internal {

// The largest size of a decoded colour index (here and in the Draco mesh's neighbour-mean
// colours, spec/FORMAT.md 8.2): larger is corrupt.
constexpr int64_t kMaxColorIndex = int64_t{1} << 40;

// What the colour stream codes: the grid (component k of a vertex is origin[k] + q[k] step)
// and every vertex's indices in the decoded vertex numbering. With components = 1 (a grey
// image, payload 1.6) only component 0 is coded: the grey value R = G = B, origin[0] its
// origin; origin[1], origin[2] and q[.][1], q[.][2] are 0.
struct ColorStream {
  int components = 3;              // 3: L, C1, C2 (payload 1.5); 1: grey (payload 1.6)
  double step = 1;                 // > 0, finite
  std::array<float, 3> origin{};  // L, C1, C2 (grey: the grey value's); finite
  std::vector<std::array<int64_t, 3>> q;
};

// The prediction residuals of every index (MeanPrediction over EarlierNeighbours of edges
// in the vertex order) must each be below 2^31 in size.
void EncodeColors(RangeEncoder& rc, const ColorStream& stream, const std::vector<MeshEdge>& edges);
// Decodes vertex_count vertices' indices of out->components (1 or 3, set by the caller); kCorrupt (what) for a grid that is not finite and
// positive, a residual that does not end, or an index beyond 2^40 in size.
Status DecodeColors(RangeDecoder& rc, size_t vertex_count, const std::vector<MeshEdge>& edges,
                    const std::string& what, ColorStream* out);

}  // namespace sdvi::codec_internal
