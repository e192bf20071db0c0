// SPDX-License-Identifier: GPL-3.0-or-later
// Positions coded by the payload itself instead of Draco (payload 1.4, spec/FORMAT.md 8.7):
// the x, y grid indices of Draco's own position grid, each predicted by the rounded mean of
// the vertex's mesh neighbours decoded before it and the residual binarised (zero, sign,
// length, bits) with adaptive models of the tag stream's range coder. Also the grid itself
// (Draco's AttributeQuantizationTransform for positions), which the mend of folds uses too.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <draco/core/quantization_utils.h>

#include "range_coder.h"
#include "sdvi/image.h"
#include "sdvi/status.h"
#include "tag_stream.h"

namespace sdvi::codec_internal {

// Draco's position grid at bits: the per-component minimum and the largest extent (1 when
// zero), in float, quantized to 2^bits - 1 steps; Position(q) is what its decoder returns.
class DracoPositionGrid {
 public:
  DracoPositionGrid(const Image& image, int bits);
  DracoPositionGrid(float min_x, float min_y, float range, int bits);
  int32_t Quantize(float value, int k) const { return quantizer_.QuantizeFloat(value - min_[k]); }
  float Position(int32_t q, int k) const { return dequantizer_.DequantizeFloat(q) + min_[k]; }
  float min(int k) const { return min_[k]; }
  float range() const { return range_; }

 private:
  void Init(int bits);
  float min_[2] = {0.f, 0.f};
  float range_ = 1.f;
  draco::Quantizer quantizer_;
  draco::Dequantizer dequantizer_;
};

// What the position stream codes: the grid and every vertex's indices (in the decoded
// vertex numbering, each in 0 .. 2^bits - 1).
struct PositionStream {
  float min_x = 0, min_y = 0, range = 1;
  int bits = 0;
  std::vector<std::array<int32_t, 2>> q;
};

// The stream's bits, first in the tag stream (spec/FORMAT.md 8.7).
void EncodePositions(RangeEncoder& rc, const PositionStream& stream, const std::vector<MeshEdge>& edges);
// Decodes them into (*vertices)[i].x, .y (vertices->size() = vertex count); kCorrupt (what)
// for a grid that is not finite or a index off the grid.
Status DecodePositions(RangeDecoder& rc, int bits, const std::vector<MeshEdge>& edges, const std::string& what,
                       std::vector<Vertex>* vertices);

}  // namespace sdvi::codec_internal
