// SPDX-License-Identifier: GPL-3.0-or-later
// Adaptive binary range coder for the tag stream of the Draco payload (spec/FORMAT.md,
// "Tag stream"). The LZMA-style binary coder: 32-bit range, 11-bit probabilities of a
// zero bit, adaptation shift 5, carry propagation through a cached byte, 5 flush bytes.
// Encoder and decoder must agree bit for bit, so both live here, next to each other.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace sdvi::codec_internal {

// Probability that the next bit is 0, in units of 1/2048; starts at one half.
struct BitModel {
  uint16_t p0 = 1024;
};

class RangeEncoder {
 public:
  void Encode(BitModel& model, bool bit);
  // Codes the low `bits` bits of value (0..32), most significant first, each with
  // probability one half (no model).
  void EncodeDirect(uint32_t value, int bits);
  // Flushes the coder and returns the bytes; the encoder is spent afterwards.
  std::vector<uint8_t> Finish();
  // Bytes the bits coded so far take: those written plus those held back (within a byte or
  // two of where a stream ending here would end; for measuring parts of a stream).
  uint64_t bytes_so_far() const { return out_.size() + cache_size_; }

 private:
  void ShiftLow();
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  std::vector<uint8_t> out_;
};

class RangeDecoder {
 public:
  explicit RangeDecoder(std::span<const uint8_t> bytes);
  bool Decode(BitModel& model);
  uint32_t DecodeDirect(int bits);
  // True when the decoder needed bytes past the end of its input, or the stream did not
  // start with the zero byte every encoder writes first: the stream is corrupt.
  bool overrun() const { return overrun_; }
  // Bytes consumed so far.
  size_t position() const { return pos_; }

 private:
  uint8_t NextByte();
  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t code_ = 0;
  bool overrun_ = false;
};

}  // namespace sdvi::codec_internal
