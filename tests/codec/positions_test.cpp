// SPDX-License-Identifier: GPL-3.0-or-later
// Positions in the tag stream (payload 1.4, spec/FORMAT.md 8.7): the x, y indices on Draco's
// own grid, each predicted by the mean of the neighbours decoded before it. The smallest colour
// coding tries them and keeps them where the payload is smaller; they decode to exactly the
// image of the payload without them; the header rules; damaged bytes are errors, never crashes.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "sdvi/codec.h"
#include "synthetic_mesh.h"

using sdvi::ColorCoding;
using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;
using sdvi::testing::MustEncode;
using sdvi::testing::SameBits;

namespace {

// The synthetic grid (its interior vertices jittered: a vectorizer's irregular samples, which
// no parallelogram predicts) of cols x cols vertices with noisy colours.
Image IrregularImage(uint32_t seed, uint32_t cols = 30) {
  Image image = sdvi::testing::SyntheticGridImage(256, 256, cols, cols, seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> colour(0.f, 255.f);
  for (auto& v : image.vertices) {
    v.r = colour(rng);
    v.g = colour(rng);
    v.b = colour(rng);
  }
  return image;
}

}  // namespace

TEST_CASE("positions in the tag stream: smaller on irregular samples, exactly the image of the payload without them",
          "[codec][positions]") {
  const Image image = IrregularImage(5);
  for (int position_bits : {10, 12}) {
    INFO("position bits " << position_bits);
    CompressOptions options;
    options.position_bits = position_bits;
    options.color_bits = 7;
    options.color_coding = ColorCoding::kSmallest;
    options.stream_colors = false;  // the positions alone (colours too: color_stream_test.cpp)
    const std::vector<uint8_t> streamed = MustEncode(image, options);
    options.stream_positions = false;
    const std::vector<uint8_t> in_draco = MustEncode(image, options);
    options.stream_positions = true;
    REQUIRE(streamed.size() > 40);
    CHECK(streamed[5] == 4);           // payload 1.4
    CHECK(streamed[10] == 1);          // positions in the tag stream
    CHECK((streamed[6] & 1) == 0);     // no vertex ids
    CHECK(in_draco[5] < 4);
    CHECK(in_draco[10] == 0);
    CHECK(streamed.size() < in_draco.size());
    CHECK(MustEncode(image, options) == streamed);  // deterministic
    auto info = sdvi::InspectDracoPayload(streamed, "streamed");
    REQUIRE(info.ok());
    CHECK(info->stream_positions);
    CHECK(info->position_bits == position_bits);
    // Lossless given Draco's grid: the same vertices bit for bit, in the same order, and the
    // same tags and feature layer.
    const Image a = sdvi::testing::MustDecode(in_draco);
    const Image b = sdvi::testing::MustDecode(streamed);
    CHECK(SameBits(a, b));
    // Through the container (at 12 bits: at 10 some of these jittered triangles fold, which the
    // file writer refuses): what a reader of the file gets is the same image.
    if (position_bits < 12) continue;
    CHECK(sdvi::testing::MustReadBack(image, options).vertices.size() == b.vertices.size());
  }
}

TEST_CASE("positions in the tag stream are not taken where Draco's are smaller, nor with vertex ids",
          "[codec][positions]") {
  // A regular grid: Draco's parallelogram predicts every interior vertex exactly.
  Image grid = sdvi::testing::SyntheticGridImage(256, 256, 30, 30, 2);
  for (auto& v : grid.vertices) {
    v.x = std::round(v.x * 29 / 256) * 256 / 29;
    v.y = std::round(v.y * 29 / 256) * 256 / 29;
  }
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  options.position_bits = 12;
  const std::vector<uint8_t> smallest = MustEncode(grid, options);
  CHECK(smallest[5] < 4);
  CHECK(smallest[10] == 0);
  // Vertex ids (the vertex order kept): never.
  options.keep_vertex_order = true;
  const std::vector<uint8_t> with_ids = MustEncode(IrregularImage(6), options);
  CHECK((with_ids[6] & 1) == 1);
  CHECK(with_ids[10] == 0);
}

TEST_CASE("positions in the tag stream: header rules and damaged bytes", "[codec][positions][corrupt]") {
  // 16 x 16 vertices: every third byte of the stream is damaged below, each a whole decode, and
  // the sweep also runs under the sanitizers.
  const Image image = IrregularImage(7, 16);
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  options.position_bits = 10;
  options.stream_colors = false;  // payload 1.4 (1.5: color_stream_test.cpp)
  const std::vector<uint8_t> good = MustEncode(image, options);
  REQUIRE(good[10] == 1);
  Image out;
  // The flag with vertex ids, an unknown bit of the second flag byte, a non-zero byte 11: corrupt.
  sdvi::testing::CheckRefused(good,
                              {{6, static_cast<uint8_t>(good[6] ^ 1)},
                               {10, static_cast<uint8_t>(good[10] ^ 2)},
                               {11, static_cast<uint8_t>(good[11] ^ 1)}},
                              "streamed.sdvi");
  // The flag cleared: the Draco mesh's positions are all (0, 0) and the tag stream starts with
  // the positions, so it does not decode as tags; a 1.4 reader without the positions would be
  // wrong, never silently right.
  {
    std::vector<uint8_t> bad = good;
    bad[10] = 0;
    sdvi::testing::FixPayloadChecksum(&bad);
    Image decoded;
    const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "cleared.sdvi", &decoded);
    if (status.ok()) CHECK(decoded.vertices != sdvi::testing::MustDecode(good).vertices);
  }
  // Damaged bytes behind a valid checksum, in the Draco mesh and in the tag stream (positions
  // first): errors or images, never a crash; a position off its grid is an error.
  int tried = 0;
  const int errors = sdvi::testing::DamagedPayloadErrors(good, 7, 3, &tried);
  CHECK(errors > tried / 4);
  // Truncated: the header's sizes no longer match.
  std::vector<uint8_t> truncated(good.begin(), good.end() - 1);
  CHECK(sdvi::DecodeDracoPayload(truncated, "short.sdvi", &out).code() == StatusCode::kTruncated);
}

TEST_CASE("the golden payload 1.4 file reads (kept forever)", "[codec][positions]") {
  // The built-in sample (`sdvi sample`) vectorized by `sdvi vectorize s.png -o s.sdvi --compress
  // --compression-ratio 600`: positions in the tag stream at 10 bits, RGB colours, features first.
  sdvi::testing::CheckGoldenFile("golden_draco_v1_4");
}
