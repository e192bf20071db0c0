// SPDX-License-Identifier: GPL-3.0-or-later
#include "range_coder.h"

namespace sdvi::codec_internal {
namespace {

constexpr int kProbabilityBits = 11;
constexpr uint32_t kProbabilityOne = 1u << kProbabilityBits;
constexpr int kAdaptShift = 5;
constexpr uint32_t kTopValue = 1u << 24;

}  // namespace

void RangeEncoder::Encode(BitModel& model, bool bit) {
  const uint32_t bound = (range_ >> kProbabilityBits) * model.p0;
  if (!bit) {
    range_ = bound;
    model.p0 = static_cast<uint16_t>(model.p0 + ((kProbabilityOne - model.p0) >> kAdaptShift));
  } else {
    low_ += bound;
    range_ -= bound;
    model.p0 = static_cast<uint16_t>(model.p0 - (model.p0 >> kAdaptShift));
  }
  while (range_ < kTopValue) {
    range_ <<= 8;
    ShiftLow();
  }
}

void RangeEncoder::EncodeDirect(uint32_t value, int bits) {
  for (int i = bits - 1; i >= 0; --i) {
    range_ >>= 1;
    if ((value >> i) & 1u) low_ += range_;
    while (range_ < kTopValue) {
      range_ <<= 8;
      ShiftLow();
    }
  }
}

// Emits the top byte of low, holding back 0xFF bytes until a carry is known.
void RangeEncoder::ShiftLow() {
  if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
    uint8_t pending = cache_;
    do {
      out_.push_back(static_cast<uint8_t>(pending + carry));
      pending = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<uint8_t>(low_ >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00FFFFFFu) << 8;
}

std::vector<uint8_t> RangeEncoder::Finish() {
  for (int i = 0; i < 5; ++i) ShiftLow();
  return std::move(out_);
}

RangeDecoder::RangeDecoder(std::span<const uint8_t> bytes) : bytes_(bytes) {
  if (NextByte() != 0) overrun_ = true;
  for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | NextByte();
}

uint32_t RangeDecoder::DecodeDirect(int bits) {
  uint32_t value = 0;
  for (int i = 0; i < bits; ++i) {
    range_ >>= 1;
    uint32_t bit = 0;
    if (code_ >= range_) {
      code_ -= range_;
      bit = 1;
    }
    value = (value << 1) | bit;
    while (range_ < kTopValue) {
      range_ <<= 8;
      code_ = (code_ << 8) | NextByte();
    }
  }
  return value;
}

uint8_t RangeDecoder::NextByte() {
  if (pos_ >= bytes_.size()) {
    overrun_ = true;
    return 0;
  }
  return bytes_[pos_++];
}

bool RangeDecoder::Decode(BitModel& model) {
  const uint32_t bound = (range_ >> kProbabilityBits) * model.p0;
  bool bit;
  if (code_ < bound) {
    range_ = bound;
    model.p0 = static_cast<uint16_t>(model.p0 + ((kProbabilityOne - model.p0) >> kAdaptShift));
    bit = false;
  } else {
    code_ -= bound;
    range_ -= bound;
    model.p0 = static_cast<uint16_t>(model.p0 - (model.p0 >> kAdaptShift));
    bit = true;
  }
  while (range_ < kTopValue) {
    range_ <<= 8;
    code_ = (code_ << 8) | NextByte();
  }
  return bit;
}

}  // namespace sdvi::codec_internal
