// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <random>
#include <vector>

#include "range_coder.h"

using namespace sdvi::codec_internal;

TEST_CASE("range coder round trips skewed and balanced bit sequences", "[codec][range]") {
  for (double p_one : {0.0, 0.01, 0.2, 0.5, 0.93, 1.0}) {
    std::mt19937 rng(7);
    std::bernoulli_distribution bit(p_one);
    std::vector<bool> bits(20000);
    for (size_t i = 0; i < bits.size(); ++i) bits[i] = bit(rng);
    RangeEncoder encoder;
    BitModel models[2];
    for (size_t i = 0; i < bits.size(); ++i) encoder.Encode(models[i % 2], bits[i]);
    const std::vector<uint8_t> bytes = encoder.Finish();
    RangeDecoder decoder(bytes);
    BitModel decode_models[2];
    for (size_t i = 0; i < bits.size(); ++i) REQUIRE(decoder.Decode(decode_models[i % 2]) == bits[i]);
    CHECK_FALSE(decoder.overrun());
    if (p_one == 0.0 || p_one == 1.0) CHECK(bytes.size() < 100);  // adaptive: nearly free
  }
}

TEST_CASE("range decoder reports a truncated stream as overrun", "[codec][range]") {
  std::mt19937 rng(3);
  RangeEncoder encoder;
  BitModel model;
  for (int i = 0; i < 5000; ++i) encoder.Encode(model, rng() & 1);
  std::vector<uint8_t> bytes = encoder.Finish();
  bytes.resize(bytes.size() / 2);
  RangeDecoder decoder(bytes);
  BitModel decode_model;
  for (int i = 0; i < 5000; ++i) (void)decoder.Decode(decode_model);
  CHECK(decoder.overrun());
}

TEST_CASE("range coder mixes direct bits and modelled bits", "[codec][range]") {
  std::mt19937 rng(5);
  std::vector<uint32_t> values;
  std::vector<int> widths;
  RangeEncoder encoder;
  BitModel model;
  for (int i = 0; i < 3000; ++i) {
    const int width = static_cast<int>(rng() % 33);
    const uint32_t value = width == 32 ? static_cast<uint32_t>(rng()) : static_cast<uint32_t>(rng() & ((1u << width) - 1));
    values.push_back(value);
    widths.push_back(width);
    encoder.EncodeDirect(value, width);
    encoder.Encode(model, (i % 3) == 0);
  }
  const std::vector<uint8_t> bytes = encoder.Finish();
  RangeDecoder decoder(bytes);
  BitModel decode_model;
  for (size_t i = 0; i < values.size(); ++i) {
    REQUIRE(decoder.DecodeDirect(widths[i]) == values[i]);
    REQUIRE(decoder.Decode(decode_model) == ((i % 3) == 0));
  }
  CHECK_FALSE(decoder.overrun());
}
