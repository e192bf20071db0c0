// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include "sdvi/codec.h"
#include "synthetic_mesh.h"

using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;

namespace {

// Checks decoded against original renumbered by new_index: topology and tags exactly,
// positions and colours within the stated error bound.
void RequireRoundTrip(const Image& original, const Image& decoded,
                      const std::vector<uint32_t>& new_index, int position_bits, int color_bits) {
  Image expected = original;
  REQUIRE(sdvi::RenumberVertices(new_index, &expected).ok());
  sdvi::CanonicalizeTriangles(&expected.triangles);
  REQUIRE(decoded.vertices.size() == expected.vertices.size());
  CHECK(decoded.triangles == expected.triangles);
  CHECK(decoded.crease_edges == expected.crease_edges);
  CHECK(decoded.corners == expected.corners);
  const sdvi::ErrorBound bound = sdvi::CompressionErrorBound(original, position_bits, color_bits);
  double worst_position = 0, worst_color = 0;
  for (size_t i = 0; i < expected.vertices.size(); ++i) {
    const auto& a = decoded.vertices[i];
    const auto& b = expected.vertices[i];
    worst_position = std::max({worst_position, double(std::abs(a.x - b.x)), double(std::abs(a.y - b.y))});
    worst_color = std::max({worst_color, double(std::abs(a.r - b.r)), double(std::abs(a.g - b.g)),
                            double(std::abs(a.b - b.b))});
  }
  CHECK(worst_position <= bound.position);
  CHECK(worst_color <= bound.color);
  CHECK(worst_position > 0);  // quantization happened: the bound is what is tested
}

struct Encoded {
  std::vector<uint8_t> payload;
  std::vector<uint32_t> new_index;
};

// The payload and the encoder's new vertex order.
Encoded MustEncodeIndexed(const Image& image, const CompressOptions& options = {}) {
  Encoded e;
  e.payload = sdvi::testing::MustEncode(image, options, &e.new_index);
  return e;
}

}  // namespace

TEST_CASE("default round trip keeps topology and tags exactly, values within the bound",
          "[codec]") {
  for (bool shuffle : {false, true}) {
    const Image image = sdvi::testing::SyntheticGridImage(512, 384, 40, 30, 11, shuffle);
    const Encoded e = MustEncodeIndexed(image);
    const Image decoded = sdvi::testing::MustDecode(e.payload);
    RequireRoundTrip(image, decoded, e.new_index, sdvi::DefaultPositionBits(image),
                     sdvi::DefaultColorBits(image));
  }
}

TEST_CASE("explicit quantization bits bound the error as stated", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(300, 200, 25, 17, 5);
  for (int bits : {8, 11, 14, 20}) {
    CompressOptions options;
    options.position_bits = bits;
    options.color_bits = bits - 2;
    const Encoded e = MustEncodeIndexed(image, options);
    RequireRoundTrip(image, sdvi::testing::MustDecode(e.payload), e.new_index, bits, bits - 2);
  }
}

TEST_CASE("keep_vertex_order decodes vertices in their original order", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(256, 256, 20, 20, 3, /*shuffle=*/true);
  CompressOptions options;
  options.keep_vertex_order = true;
  const Encoded e = MustEncodeIndexed(image, options);
  std::vector<uint32_t> identity(image.vertices.size());
  std::iota(identity.begin(), identity.end(), 0u);
  CHECK(e.new_index == identity);
  RequireRoundTrip(image, sdvi::testing::MustDecode(e.payload), e.new_index, sdvi::DefaultPositionBits(image),
                   sdvi::DefaultColorBits(image));
  // Without ids the payload is smaller (the shuffled numbering is expensive to keep).
  const Encoded plain = MustEncodeIndexed(image);
  CHECK(plain.payload.size() < e.payload.size());
}

TEST_CASE("the feature layer renumbered by the encoder points at the same vertices", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(200, 200, 15, 15, 9, true);
  const Encoded e = MustEncodeIndexed(image);
  Image moved = image;
  REQUIRE(sdvi::RenumberVertices(e.new_index, &moved).ok());
  const Image decoded = sdvi::testing::MustDecode(e.payload);
  const auto& before = image.polylines.at(0).vertices;
  const auto& after = moved.polylines.at(0).vertices;
  REQUIRE(before.size() == after.size());
  const double tolerance = sdvi::CompressionErrorBound(image, sdvi::DefaultPositionBits(image),
                                                       sdvi::DefaultColorBits(image)).position;
  for (size_t k = 0; k < before.size(); ++k) {
    CHECK(std::abs(decoded.vertices[after[k]].x - image.vertices[before[k]].x) <= tolerance);
    CHECK(std::abs(decoded.vertices[after[k]].y - image.vertices[before[k]].y) <= tolerance);
  }
}

TEST_CASE("encoding is deterministic", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(512, 512, 50, 50, 21, true);
  for (int speed : {0, 5, 10}) {
    CompressOptions options;
    options.speed = speed;
    CHECK(MustEncodeIndexed(image, options).payload == MustEncodeIndexed(image, options).payload);
  }
}

TEST_CASE("every speed round trips, speed 10 through sequential encoding", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(128, 96, 12, 9, 4, true);
  for (int speed : {0, 3, 7, 10}) {
    CompressOptions options;
    options.speed = speed;
    const Encoded e = MustEncodeIndexed(image, options);
    RequireRoundTrip(image, sdvi::testing::MustDecode(e.payload), e.new_index, sdvi::DefaultPositionBits(image),
                     sdvi::DefaultColorBits(image));
    auto info = sdvi::InspectDracoPayload(e.payload, "x");
    REQUIRE(info.ok());
    CHECK(info->speed == speed);
    if (speed == 10) CHECK(info->has_vertex_ids);
  }
}

TEST_CASE("meshes edgebreaker cannot carry still round trip (isolated vertex); non-manifold is refused",
          "[codec]") {
  Image image = sdvi::testing::SyntheticGridImage(64, 64, 6, 6, 2);
  SECTION("non-manifold edge") {
    // The renderer refuses it, so the writers do too (ValidateImage, issue 16).
    image.vertices.push_back({30.f, 30.f, 100, 100, 100});
    const uint32_t extra = static_cast<uint32_t>(image.vertices.size() - 1);
    const auto t = image.triangles[20].v;
    image.triangles.push_back({{t[0], t[1], extra}});
    CHECK(sdvi::EncodeDracoPayload(image, {}).status().code() == StatusCode::kNonManifoldEdge);
    return;
  }
  image.vertices.push_back({10.5f, 20.25f, 1, 2, 3});  // isolated
  const Encoded e = MustEncodeIndexed(image);
  RequireRoundTrip(image, sdvi::testing::MustDecode(e.payload), e.new_index, sdvi::DefaultPositionBits(image),
                   sdvi::DefaultColorBits(image));
}

TEST_CASE("default quantization is chosen from the image size", "[codec]") {
  Image small = sdvi::testing::SyntheticGridImage(64, 64, 5, 5);
  Image large = sdvi::testing::SyntheticGridImage(4096, 2048, 5, 5);
  CHECK(sdvi::DefaultPositionBits(small) == 14);  // 64 * 128 steps need 2^14 - 1 >= 8192
  CHECK(sdvi::DefaultPositionBits(large) == 20);
  CHECK(sdvi::DefaultColorBits(small) >= 8);
  const auto bound = sdvi::CompressionErrorBound(large, sdvi::DefaultPositionBits(large),
                                                 sdvi::DefaultColorBits(large));
  CHECK(bound.position <= 1.0 / 256 + 0.004);  // half a step + float rounding at 4096
  CHECK(bound.color <= 0.0625 + 1e-3);
}

TEST_CASE("Draco payload is at most a quarter of the paper's raw size", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(512, 512, 100, 100, 8);
  const Encoded e = MustEncodeIndexed(image);
  const size_t raw = image.vertices.size() * 20 + image.triangles.size() * 6 + 8;
  INFO("raw " << raw << " draco " << e.payload.size());
  CHECK(e.payload.size() * 4 <= raw);
}

TEST_CASE("truncated payloads are errors, never crashes", "[codec][corrupt]") {
  const Image image = sdvi::testing::SyntheticGridImage(100, 80, 10, 8, 6);
  const Encoded e = MustEncodeIndexed(image);
  for (size_t n = 0; n < e.payload.size(); n += (n < 64 ? 1 : 7)) {
    std::vector<uint8_t> cut(e.payload.begin(), e.payload.begin() + n);
    Image out;
    const sdvi::Status status = sdvi::DecodeDracoPayload(cut, "cut.sdvi", &out);
    REQUIRE_FALSE(status.ok());
    CHECK(status.code() == StatusCode::kTruncated);
    CHECK(status.message().find("cut.sdvi") != std::string::npos);
    CHECK(out.vertices.empty());
  }
}

TEST_CASE("flipped bytes are caught by the checksum", "[codec][corrupt]") {
  const Image image = sdvi::testing::SyntheticGridImage(100, 80, 10, 8, 6);
  const Encoded e = MustEncodeIndexed(image);
  for (size_t i = 0; i < e.payload.size(); ++i) {
    std::vector<uint8_t> bad = e.payload;
    bad[i] ^= 0x10;
    Image out;
    const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "bad.sdvi", &out);
    REQUIRE_FALSE(status.ok());
    CHECK((status.code() == StatusCode::kCorrupt || status.code() == StatusCode::kTruncated ||
           status.code() == StatusCode::kUnsupportedVersion));
  }
}

TEST_CASE("damaged Draco bytes behind a valid checksum give errors or data, never crashes",
          "[codec][corrupt]") {
  const Image image = sdvi::testing::SyntheticGridImage(100, 80, 10, 8, 6);
  const Encoded e = MustEncodeIndexed(image);
  auto info = sdvi::InspectDracoPayload(e.payload, "x");
  REQUIRE(info.ok());
  std::mt19937 rng(99);
  int failures = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<uint8_t> bad = e.payload;
    const size_t at = 40 + rng() % (info->draco_bytes + info->tag_bytes);
    bad[at] = static_cast<uint8_t>(rng());
    sdvi::testing::FixPayloadChecksum(&bad);
    Image out;
    const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "fuzz.sdvi", &out);
    if (!status.ok()) {
      ++failures;
      CHECK((status.code() == StatusCode::kCorrupt || status.code() == StatusCode::kDecodeFailed ||
             status.code() == StatusCode::kNonFinite || status.code() == StatusCode::kLimitExceeded));
    } else {
      for (const auto& t : out.triangles)
        for (uint32_t v : t.v) CHECK(v < out.vertices.size());
    }
  }
  CHECK(failures > 0);
}

TEST_CASE("a Draco face count beyond the payload header's is refused before Draco allocates for it",
          "[codec][corrupt]") {
  // Found by fuzzing: Draco reserves memory for the faces its connectivity header declares
  // (a 266-byte payload asked for 2.9 GB). Here a valid payload's face count (bitstream 2.2,
  // edgebreaker: after the 11-byte Draco header, the traversal type, the encoded vertices'
  // varint, the faces' varint) becomes 2^28 - 1.
  const Image image = sdvi::testing::SyntheticGridImage(50, 50, 6, 6);
  const Encoded e = MustEncodeIndexed(image);
  constexpr size_t kDraco = 40;  // the payload header's size (spec/FORMAT.md section 8)
  REQUIRE(std::string(e.payload.begin() + kDraco, e.payload.begin() + kDraco + 5) == "DRACO");
  REQUIRE(e.payload[kDraco + 8] == 1);                                     // edgebreaker
  REQUIRE((e.payload[kDraco + 9] | e.payload[kDraco + 10] << 8) == 0);  // no metadata
  size_t at = kDraco + 12;
  while (e.payload[at] & 0x80) ++at;  // the encoded vertices
  const size_t faces_at = ++at;
  while (e.payload[at] & 0x80) ++at;
  const size_t faces_end = at + 1;
  std::vector<uint8_t> bad(e.payload.begin(), e.payload.begin() + faces_at);
  for (uint8_t b : {0xff, 0xff, 0xff, 0x7f}) bad.push_back(b);  // 2^28 - 1
  bad.insert(bad.end(), e.payload.begin() + faces_end, e.payload.end());
  const uint32_t draco_size = uint32_t(e.payload[28] | e.payload[29] << 8 | e.payload[30] << 16) +
                              uint32_t(4 - (faces_end - faces_at));
  for (int i = 0; i < 4; ++i) bad[28 + i] = uint8_t(draco_size >> (8 * i));
  sdvi::testing::FixPayloadChecksum(&bad);
  Image out;
  const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "faces.sdvi", &out);
  INFO(status.ToString());
  CHECK(status.code() == StatusCode::kCorrupt);
  CHECK(status.message() == "faces.sdvi: Draco mesh declares 268435455 faces, the payload header " +
                                std::to_string(image.triangles.size()) + " triangles");
  CHECK(out.vertices.empty());
}

TEST_CASE("header problems have specific codes", "[codec][corrupt]") {
  const Image image = sdvi::testing::SyntheticGridImage(50, 50, 6, 6);
  const Encoded e = MustEncodeIndexed(image);
  Image out;
  std::vector<uint8_t> bad = e.payload;
  bad[0] = 'X';
  CHECK(sdvi::DecodeDracoPayload(bad, "m", &out).code() == StatusCode::kCorrupt);
  bad = e.payload;
  bad[4] = 2;  // a future major version
  CHECK(sdvi::DecodeDracoPayload(bad, "v", &out).code() == StatusCode::kUnsupportedVersion);
  bad = e.payload;
  bad.push_back(0);
  CHECK(sdvi::DecodeDracoPayload(bad, "long", &out).code() == StatusCode::kCorrupt);
  CHECK(sdvi::DecodeDracoPayload(e.payload, "limit", &out, 10).code() == StatusCode::kLimitExceeded);
  // A wrong checksum: kCorrupt, unless the caller asks not to verify it (the fuzz targets).
  bad = e.payload;
  bad[36] ^= 0x01;  // the CRC-32 field
  CHECK(sdvi::DecodeDracoPayload(bad, "crc", &out).code() == StatusCode::kCorrupt);
  CHECK(sdvi::DecodeDracoPayload(bad, "crc", &out, uint64_t{1} << 26, /*verify_checksum=*/false).ok());
  CHECK(out.vertices.size() == image.vertices.size());
}

TEST_CASE("images that cannot be encoded and bad options are rejected", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(50, 50, 6, 6);
  CompressOptions options;
  options.position_bits = 31;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kInvalidArgument);
  options = {};
  options.speed = 11;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kInvalidArgument);
  CHECK(sdvi::EncodeDracoPayload(Image{}, {}).status().code() == StatusCode::kEmptyInput);
  Image bad = image;
  bad.crease_edges.push_back(sdvi::Edge::Of(0, 35));  // opposite grid corners
  CHECK(sdvi::EncodeDracoPayload(bad, {}).status().code() == StatusCode::kCreaseNotAnEdge);
  bad = image;
  bad.triangles[0].v[1] = 1000;
  CHECK(sdvi::EncodeDracoPayload(bad, {}).status().code() == StatusCode::kIndexOutOfRange);
  bad = image;
  bad.vertices[3].g = std::nanf("");
  CHECK(sdvi::EncodeDracoPayload(bad, {}).status().code() == StatusCode::kNonFinite);
}

TEST_CASE("the feature layer travels exactly in the payload", "[codec][features]") {
  Image image = sdvi::testing::SyntheticGridImage(256, 200, 20, 16, 31, /*shuffle=*/true);
  // A closed loop along the boundary (crease walks), a polyline with non-crease steps
  // (escapes), a single vertex, an empty one; pairs with odd sharpness values.
  sdvi::FeaturePolyline boundary;
  boundary.closed = true;
  {
    // Walk the crease boundary from the lowest corner using the crease edges.
    std::vector<std::vector<uint32_t>> adj(image.vertices.size());
    for (const auto& e : image.crease_edges) {
      adj[e.a].push_back(e.b);
      adj[e.b].push_back(e.a);
    }
    uint32_t start = image.corners[0], prev = UINT32_MAX, cur = start;
    for (int steps = 0; steps < 200; ++steps) {
      boundary.vertices.push_back(cur);
      uint32_t next = UINT32_MAX;
      for (uint32_t n : adj[cur])
        if (n != prev && (next == UINT32_MAX || n < next)) next = n;
      if (next == UINT32_MAX || next == start) break;
      prev = cur;
      cur = next;
    }
  }
  image.polylines.push_back(boundary);
  image.polylines.push_back({{5, 17, 3, 200, 4}, false});
  image.polylines.push_back({{42}, false});
  image.polylines.push_back({{}, false});
  image.pairs = {{0, 1, 0.3f}, {2, 4, 1.0f}, {3, 3, 0.0f}};
  const Encoded e = MustEncodeIndexed(image);
  const Image decoded = sdvi::testing::MustDecode(e.payload);
  Image expected = image;
  REQUIRE(sdvi::RenumberVertices(e.new_index, &expected).ok());
  CHECK(decoded.polylines == expected.polylines);
  CHECK(decoded.pairs == expected.pairs);

  // Without the feature layer in the payload, decoding leaves the caller's untouched.
  CompressOptions options;
  options.feature_layer = false;
  const Encoded bare = MustEncodeIndexed(image, options);
  CHECK(bare.payload.size() < e.payload.size());
  Image out;
  out.polylines.push_back({{1, 2}, false});
  REQUIRE(sdvi::DecodeDracoPayload(bare.payload, "bare", &out).ok());
  CHECK(out.polylines.size() == 1);
  CHECK(out.pairs.empty());
}

TEST_CASE("a feature layer naming missing vertices or polylines is rejected", "[codec][features]") {
  Image image = sdvi::testing::SyntheticGridImage(50, 50, 6, 6);
  image.polylines.push_back({{1, 99}, false});
  CHECK(sdvi::EncodeDracoPayload(image, {}).status().code() == StatusCode::kIndexOutOfRange);
  image.polylines.pop_back();
  image.pairs.push_back({0, 7, 0.5f});
  CHECK(sdvi::EncodeDracoPayload(image, {}).status().code() == StatusCode::kIndexOutOfRange);
  CompressOptions options;
  options.feature_layer = false;
  CHECK(sdvi::EncodeDracoPayload(image, options).ok());
}

TEST_CASE("a reference MSE coarsens the default quantization within its limits", "[codec]") {
  const Image image = sdvi::testing::SyntheticGridImage(512, 512, 10, 10);
  const int p0 = sdvi::DefaultPositionBits(image), c0 = sdvi::DefaultColorBits(image);
  CHECK(sdvi::DefaultPositionBits(image, 1e-6) == 19);  // 1/512 px: 2^19 - 1 >= 512 * 512
  CHECK(sdvi::DefaultColorBits(image, 1e-6) > c0);
  CHECK(sdvi::DefaultPositionBits(image, 100) < p0);    // a 28 dB fit tolerates coarser steps
  CHECK(sdvi::DefaultColorBits(image, 100) < c0);
  CHECK(sdvi::DefaultPositionBits(image, 1e9) == 12);   // at most 1/4 px: 2048 steps over 512
  CompressOptions options;
  options.reference_mse = 100;
  const Encoded e = MustEncodeIndexed(image, options);
  auto info = sdvi::InspectDracoPayload(e.payload, "x");
  REQUIRE(info.ok());
  CHECK(info->position_bits == sdvi::DefaultPositionBits(image, 100));
  CHECK(info->color_bits == sdvi::DefaultColorBits(image, 100));
  options.reference_mse = -1;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kInvalidArgument);
}

TEST_CASE("grey images code one colour component and decode R = G = B", "[codec]") {
  Image image = sdvi::testing::SyntheticGridImage(256, 256, 24, 24, 41);
  for (auto& v : image.vertices) v.g = v.b = v.r;
  const Encoded grey = MustEncodeIndexed(image);
  auto info = sdvi::InspectDracoPayload(grey.payload, "g");
  REQUIRE(info.ok());
  CHECK(info->grey);
  const Image decoded = sdvi::testing::MustDecode(grey.payload);
  for (const auto& v : decoded.vertices) {
    CHECK(v.g == v.r);
    CHECK(v.b == v.r);
  }
  RequireRoundTrip(image, decoded, grey.new_index, sdvi::DefaultPositionBits(image),
                   sdvi::DefaultColorBits(image));
  Image almost = image;
  almost.vertices[7].b += 0.5f;  // one vertex not grey: three components
  const Encoded colour = MustEncodeIndexed(almost);
  CHECK_FALSE(sdvi::InspectDracoPayload(colour.payload, "c")->grey);
  CHECK(grey.payload.size() < colour.payload.size());
}
