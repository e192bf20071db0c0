// SPDX-License-Identifier: GPL-3.0-or-later
// Decorrelated colours in the Draco payload (spec/FORMAT.md 8.2, payload 1.1): the transform's
// error bound, the choice of the smaller coding, grey images, the header rules, and the golden
// compressed files of both payload versions.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "sdvi/codec.h"
#include "sdvi/mesh_json.h"
#include "synthetic_mesh.h"

using sdvi::ColorCoding;
using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;
using sdvi::testing::MustEncode;

namespace {

std::vector<uint8_t> ReadData(const std::string& name) {
  std::ifstream in(std::string(SDVI_TEST_DATA_DIR) + "/" + name, std::ios::binary);
  REQUIRE(in);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The synthetic grid with colours like a photo's: a random luminance per vertex and small
// random tints (R, G, B strongly correlated), overshooting 0..255 as fitted colours do.
Image PhotoLikeImage(uint32_t seed) {
  Image image = sdvi::testing::SyntheticGridImage(256, 256, 30, 30, seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> luminance(-40.f, 300.f), tint(-12.f, 12.f);
  for (auto& v : image.vertices) {
    const float y = luminance(rng);
    v.r = y + tint(rng);
    v.g = y + tint(rng);
    v.b = y + tint(rng);
  }
  return image;
}

sdvi::DracoPayloadInfo MustInspect(const std::vector<uint8_t>& payload) {
  auto info = sdvi::InspectDracoPayload(payload, "test");
  INFO(info.status().ToString());
  REQUIRE(info.ok());
  return *info;
}

// The forward transform of spec/FORMAT.md 8.2, computed independently (long double).
std::array<long double, 3> Opponent(long double r, long double g, long double b) {
  return {(r + g + b) / std::sqrt(3.0L), (r - b) / std::sqrt(2.0L), (r - 2 * g + b) / std::sqrt(6.0L)};
}

}  // namespace

TEST_CASE("decorrelated colours: each of L, C1, C2 within half a step, R, G, B within the stated bound",
          "[codec][colors]") {
  const Image image = PhotoLikeImage(5);
  for (int color_bits : {5, 8, 12}) {
    CompressOptions options;
    options.position_bits = 14;
    options.color_bits = color_bits;
    options.color_coding = ColorCoding::kDecorrelated;
    std::vector<uint32_t> new_index;
    const std::vector<uint8_t> payload = MustEncode(image, options, &new_index);
    const sdvi::DracoPayloadInfo info = MustInspect(payload);
    CHECK(info.decorrelated);
    CHECK_FALSE(info.grey);
    CHECK(info.version_major == 1);
    CHECK(info.version_minor == 2);  // features first (payload 1.2)
    CHECK(info.color_bits == color_bits);
    const Image decoded = sdvi::testing::MustDecode(payload);
    Image expected = image;
    REQUIRE(sdvi::RenumberVertices(new_index, &expected).ok());
    sdvi::CanonicalizeTriangles(&expected.triangles);
    CHECK(decoded.triangles == expected.triangles);
    CHECK(decoded.crease_edges == expected.crease_edges);
    CHECK(decoded.polylines == expected.polylines);

    // The step: the R, G, B extent over 2^bits - 1 (as for RGB coding).
    float extent = 0;
    for (int k = 0; k < 3; ++k) {
      float a = 1e30f, b = -1e30f;
      for (const auto& v : image.vertices) {
        const float c = k == 0 ? v.r : k == 1 ? v.g : v.b;
        a = std::min(a, c);
        b = std::max(b, c);
      }
      extent = std::max(extent, b - a);
    }
    const long double step = extent / ((1u << color_bits) - 1.0L);
    const double bound = sdvi::CompressionErrorBound(image, 14, color_bits, true).color;
    CHECK(bound >= double(sdvi::kDecorrelatedErrorFactor * 0.5L * step));
    CHECK(bound <= double(1.05L * sdvi::kDecorrelatedErrorFactor * 0.5L * step));
    long double worst_opponent = 0, worst_rgb = 0, squared_rgb = 0;
    for (size_t i = 0; i < expected.vertices.size(); ++i) {
      const auto& d = decoded.vertices[i];
      const auto& o = expected.vertices[i];
      const auto a = Opponent(d.r, d.g, d.b), b = Opponent(o.r, o.g, o.b);
      for (int k = 0; k < 3; ++k) worst_opponent = std::max(worst_opponent, std::abs(a[k] - b[k]));
      for (long double e : {d.r - o.r, d.g - o.g, d.b - o.b}) {
        worst_rgb = std::max(worst_rgb, std::abs(e));
        squared_rgb += e * e;
      }
    }
    CHECK(worst_opponent <= 0.5L * step * (1 + 1e-4L) + 1e-3L);
    CHECK(worst_rgb <= bound);
    CHECK(worst_rgb > 0.5L * step);  // the bound is looser than RGB coding's, and needed
    // Orthonormal: the mean squared error is that of uniform rounding on the step, step^2 / 12
    // (a 2,700-sample mean; its spread at 5 bits is ~2%).
    if (color_bits <= 8)
      CHECK(double(squared_rgb / (3.0L * expected.vertices.size())) ==
            Approx(double(step * step / 12)).epsilon(0.08));
  }
}

TEST_CASE("decorrelated colours code correlated colours in fewer bytes; smallest keeps the smaller",
          "[codec][colors]") {
  const Image image = PhotoLikeImage(11);
  CompressOptions options;
  options.position_bits = 12;
  options.color_bits = 6;
  options.stream_positions = false;  // the colour codings alone (positions: positions_test.cpp)
  const std::vector<uint8_t> rgb = MustEncode(image, options);
  options.color_coding = ColorCoding::kDecorrelated;
  const std::vector<uint8_t> decorrelated = MustEncode(image, options);
  options.color_coding = ColorCoding::kSmallest;
  const std::vector<uint8_t> smallest = MustEncode(image, options);
  CHECK(decorrelated.size() < 0.95 * rgb.size());
  CHECK(smallest == decorrelated);
  CHECK_FALSE(MustInspect(rgb).decorrelated);
  CHECK(MustInspect(rgb).version_minor == 2);

  // A linear colour gradient: RGB's parallelogram prediction is exact, so RGB is smaller and
  // smallest keeps it (byte-identical to the RGB file).
  const Image gradient = sdvi::testing::SyntheticGridImage(256, 256, 30, 30, 11);
  options.color_coding = ColorCoding::kRgb;
  const std::vector<uint8_t> gradient_rgb = MustEncode(gradient, options);
  options.color_coding = ColorCoding::kDecorrelated;
  const std::vector<uint8_t> gradient_decorrelated = MustEncode(gradient, options);
  options.color_coding = ColorCoding::kSmallest;
  const std::vector<uint8_t> gradient_smallest = MustEncode(gradient, options);
  CHECK(gradient_smallest ==
        (gradient_decorrelated.size() < gradient_rgb.size() ? gradient_decorrelated : gradient_rgb));
  CHECK(gradient_smallest.size() == std::min(gradient_rgb.size(), gradient_decorrelated.size()));
  // Deterministic.
  CHECK(MustEncode(image, options) == smallest);
}

TEST_CASE("grey images stay one grey component whatever the colour coding", "[codec][colors]") {
  Image image = PhotoLikeImage(3);
  for (auto& v : image.vertices) v.g = v.b = v.r;
  CompressOptions options;
  options.stream_positions = false;  // the colour codings alone
  const std::vector<uint8_t> rgb = MustEncode(image, options);
  for (ColorCoding coding : {ColorCoding::kDecorrelated, ColorCoding::kSmallest}) {
    options.color_coding = coding;
    const std::vector<uint8_t> payload = MustEncode(image, options);
    CHECK(payload == rgb);
    CHECK(MustInspect(payload).grey);
    CHECK_FALSE(MustInspect(payload).decorrelated);
  }
}

TEST_CASE("decorrelated payload header rules", "[codec][colors][corrupt]") {
  const Image image = PhotoLikeImage(7);
  CompressOptions options;
  options.color_coding = ColorCoding::kDecorrelated;
  const std::vector<uint8_t> good = MustEncode(image, options);
  Image out;
  // Grey and decorrelated together.
  std::vector<uint8_t> bad = good;
  bad[6] |= 4;
  sdvi::testing::FixPayloadChecksum(&bad);
  sdvi::Status status = sdvi::DecodeDracoPayload(bad, "both.sdvi", &out);
  CHECK(status.code() == StatusCode::kCorrupt);
  CHECK(status.message().find("both.sdvi") != std::string::npos);
  // The flag cleared: the Draco mesh's 1-component COLOR reads as grey, which the header
  // does not flag.
  bad = good;
  bad[6] &= static_cast<uint8_t>(~8);
  sdvi::testing::FixPayloadChecksum(&bad);
  CHECK(sdvi::DecodeDracoPayload(bad, "cleared.sdvi", &out).code() == StatusCode::kCorrupt);
  // The flag set on an RGB payload: its attributes are not the decorrelated ones.
  options.color_coding = ColorCoding::kRgb;
  bad = MustEncode(image, options);
  bad[6] |= 8;
  sdvi::testing::FixPayloadChecksum(&bad);
  status = sdvi::DecodeDracoPayload(bad, "rgb.sdvi", &out);
  CHECK(status.code() == StatusCode::kCorrupt);
  CHECK(status.message().find("decorrelated") != std::string::npos);
  // A later minor version: unsupported (its stream may mean something else); an unknown
  // flag, or the decorrelated flag in a 1.0 payload: corrupt.
  bad = good;
  bad[5] = 7;
  sdvi::testing::FixPayloadChecksum(&bad);
  status = sdvi::DecodeDracoPayload(bad, "later.sdvi", &out);
  CHECK(status.code() == StatusCode::kUnsupportedVersion);
  CHECK(status.message().find("1.7") != std::string::npos);
  bad = good;
  bad[6] |= 128;
  sdvi::testing::FixPayloadChecksum(&bad);
  CHECK(sdvi::DecodeDracoPayload(bad, "flag.sdvi", &out).code() == StatusCode::kCorrupt);
  options.color_coding = ColorCoding::kDecorrelated;
  options.features_first = false;
  bad = MustEncode(image, options);  // payload 1.1
  REQUIRE(bad[5] == 1);
  bad[5] = 0;
  sdvi::testing::FixPayloadChecksum(&bad);
  CHECK(sdvi::DecodeDracoPayload(bad, "old.sdvi", &out).code() == StatusCode::kCorrupt);
  CHECK(out.vertices.empty());
}

TEST_CASE("golden compressed files of payload 1.0 (RGB), 1.1 (decorrelated) and 1.2 (features first) read "
          "(kept forever)",
          "[codec][colors]") {
  const Image source = [] {
    auto image = sdvi::DecodeImage(ReadData("golden_v1_0.sdvi"), "golden_v1_0.sdvi");
    REQUIRE(image.ok());
    return std::move(image).value();
  }();
  for (const char* version : {"1_0", "1_1", "1_2"}) {
    const std::string name = std::string("golden_draco_v") + version;
    INFO(name);
    const std::vector<uint8_t> bytes = ReadData(name + ".sdvi");
    auto decoded = sdvi::DecodeImage(bytes, name + ".sdvi");
    INFO(decoded.status().ToString());
    REQUIRE(decoded.ok());
    // Exactly the values its JSON (written by `sdvi convert` when the file was made) holds.
    const std::vector<uint8_t> json = ReadData(name + ".json");
    auto expected = sdvi::ParseMeshJson(std::string_view(reinterpret_cast<const char*>(json.data()), json.size()),
                                        name + ".json");
    REQUIRE(expected.ok());
    CHECK(expected->vertices == decoded->vertices);
    CHECK(expected->triangles == decoded->triangles);
    CHECK(expected->crease_edges == decoded->crease_edges);
    CHECK(expected->polylines == decoded->polylines);
    CHECK(expected->pairs == decoded->pairs);
    // The 1.2 file is what this writer makes of the raw golden file (`sdvi compress
    // --colors decorrelated`), the 1.1 file the same without features first; the 1.0 file was
    // made by the 1.0 writer (`sdvi compress`, RGB).
    if (version != std::string("1_0")) {
      CompressOptions options;
      options.color_coding = ColorCoding::kDecorrelated;
      options.features_first = version == std::string("1_2");
      auto again = sdvi::EncodeImage(source, &options);
      REQUIRE(again.ok());
      CHECK(*again == bytes);
    }
  }
}
