// SPDX-License-Identifier: GPL-3.0-or-later
// Neighbour-mean colours (payload 1.3, flag bit 7, spec/FORMAT.md 8.2): L, C1, C2 on grids, each
// predicted by the mean of the neighbours decoded before it. The smallest colour coding takes
// them where they are smaller; they decode to the decorrelated file's positions and vertex order
// with colours within the decorrelated bound; the header rules; damaged bytes are errors.
#include <catch2/catch.hpp>

#include <cmath>

#include "sdvi/codec.h"
#include "synthetic_mesh.h"

using sdvi::ColorCoding;
using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;
using sdvi::testing::MustEncode;

TEST_CASE("neighbour-mean colours: smaller than decorrelated, the same positions and order, colours within its bound",
          "[codec][colors]") {
  const Image image = sdvi::testing::PhotoLikeGridImage(3);
  for (int color_bits : {6, 8}) {
    INFO("colour bits " << color_bits);
    CompressOptions options;
    options.position_bits = 12;
    options.color_bits = color_bits;
    options.color_coding = ColorCoding::kDecorrelated;
    const std::vector<uint8_t> decorrelated = MustEncode(image, options);
    options.color_coding = ColorCoding::kSmallest;
    options.stream_positions = false;  // the colour codings alone (positions: positions_test.cpp)
    const std::vector<uint8_t> smallest = MustEncode(image, options);
    REQUIRE(smallest.size() > 40);
    CHECK(smallest[5] == 3);                 // payload 1.3
    CHECK((smallest[6] & (128 | 8)) == (128 | 8));  // neighbour mean, decorrelated
    CHECK((smallest[6] & 1) == 0);           // no vertex ids
    CHECK(smallest.size() < decorrelated.size());
    CHECK(MustEncode(image, options) == smallest);  // deterministic
    options.neighbour_mean = false;  // payload 1.2's choice: not among the candidates
    const std::vector<uint8_t> without = MustEncode(image, options);
    CHECK(without[5] == 2);
    CHECK((without[6] & 128) == 0);
    CHECK(without.size() > smallest.size());
    options.neighbour_mean = true;

    const Image a = sdvi::testing::MustDecode(decorrelated);
    const Image b = sdvi::testing::MustDecode(smallest);
    REQUIRE(a.vertices.size() == b.vertices.size());
    CHECK(a.triangles == b.triangles);
    CHECK(a.crease_edges == b.crease_edges);
    CHECK(a.polylines == b.polylines);
    // The same grid as decorrelated coding (origin = minimum, the same step): each colour
    // component of the two files within float rounding of each other, and of the original
    // within the decorrelated bound.
    const double bound = sdvi::CompressionErrorBound(image, 12, color_bits, true).color;
    double worst_between = 0;
    for (size_t i = 0; i < a.vertices.size(); ++i) {
      CHECK(a.vertices[i].x == b.vertices[i].x);
      CHECK(a.vertices[i].y == b.vertices[i].y);
      worst_between = std::max({worst_between, double(std::abs(a.vertices[i].r - b.vertices[i].r)),
                                 double(std::abs(a.vertices[i].g - b.vertices[i].g)),
                                 double(std::abs(a.vertices[i].b - b.vertices[i].b))});
    }
    CHECK(worst_between < 1e-3);
    std::vector<uint32_t> new_index;
    REQUIRE(sdvi::EncodeDracoPayload(image, options, &new_index).ok());
    Image expected = image;
    REQUIRE(sdvi::RenumberVertices(new_index, &expected).ok());
    for (size_t i = 0; i < b.vertices.size(); ++i) {
      CHECK(std::abs(b.vertices[i].r - expected.vertices[i].r) <= bound);
      CHECK(std::abs(b.vertices[i].g - expected.vertices[i].g) <= bound);
      CHECK(std::abs(b.vertices[i].b - expected.vertices[i].b) <= bound);
    }
  }
}

TEST_CASE("neighbour-mean colours are not taken where differences are smaller (a linear gradient)",
          "[codec][colors]") {
  // A gradient with a jump: Draco's own prediction codes it in fewer bytes; smallest keeps
  // that file (payload 1.2, no flag bit 7).
  const Image gradient = sdvi::testing::SyntheticGridImage(256, 256, 30, 30, 11);
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  options.stream_positions = false;
  const std::vector<uint8_t> smallest = MustEncode(gradient, options);
  CHECK(smallest[5] == 2);
  CHECK((smallest[6] & 128) == 0);
}

TEST_CASE("neighbour-mean header rules and damaged bytes", "[codec][colors][corrupt]") {
  const Image image = sdvi::testing::PhotoLikeGridImage(4);
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  const std::vector<uint8_t> good = MustEncode(image, options);
  REQUIRE((good[6] & 128) != 0);
  Image out;
  // Flag bit 7 in a 1.2 payload, without decorrelated colours, or with vertex ids: corrupt.
  for (const auto& [minor, flip] : std::vector<std::pair<uint8_t, uint8_t>>{{2, 0}, {3, 8}, {3, 1}}) {
    std::vector<uint8_t> bad = good;
    bad[5] = minor;
    bad[6] ^= flip;
    sdvi::testing::FixPayloadChecksum(&bad);
    const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "mean.sdvi", &out);
    CHECK(status.code() == StatusCode::kCorrupt);
    CHECK(status.message().find("mean.sdvi") != std::string::npos);
  }
  // The flag cleared: the int32 attributes are not the float ones of decorrelated colours.
  std::vector<uint8_t> bad = good;
  bad[5] = 2;
  bad[6] &= static_cast<uint8_t>(~128);
  sdvi::testing::FixPayloadChecksum(&bad);
  CHECK(sdvi::DecodeDracoPayload(bad, "cleared.sdvi", &out).code() == StatusCode::kCorrupt);
  // Damaged Draco bytes behind a valid checksum: errors or images, never a crash.
  const uint32_t draco_size = uint32_t(good[28]) | uint32_t(good[29]) << 8 | uint32_t(good[30]) << 16 |
                              uint32_t(good[31]) << 24;
  int errors = 0;
  for (size_t at = 40; at < 40 + draco_size; at += 7) {
    std::vector<uint8_t> damaged = good;
    damaged[at] ^= 0x5A;
    sdvi::testing::FixPayloadChecksum(&damaged);
    Image decoded;
    if (!sdvi::DecodeDracoPayload(damaged, "damaged.sdvi", &decoded).ok()) ++errors;
  }
  CHECK(errors > 0);
}
