// SPDX-License-Identifier: GPL-3.0-or-later
// The one validation of every reader and writer (format.h ValidateImage; spec/FORMAT.md
// section 9, checks 19-24), and the bounded Draco quantization (codec.h).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <span>
#include <limits>
#include <string>

#include "sdvi/codec.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"

namespace {

using sdvi::Image;
using sdvi::StatusCode;

// A 2 x 2 grid of cells on a 64 x 64 image, counter-clockwise (in y-down pixels,
// "positive" orientation of the cross product), colours inside 0..255.
Image Square() {
  Image image;
  image.width = image.height = 64;
  for (int y = 0; y <= 2; ++y)
    for (int x = 0; x <= 2; ++x)
      image.vertices.push_back({32.f * x, 32.f * y, 10.f * x, 20.f * y, 128.f});
  auto id = [](uint32_t x, uint32_t y) { return y * 3 + x; };
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 2; ++x) {
      image.triangles.push_back({{id(x, y), id(x + 1, y), id(x + 1, y + 1)}});
      image.triangles.push_back({{id(x, y), id(x + 1, y + 1), id(x, y + 1)}});
    }
  return image;
}

// The code ValidateImage, the raw writer, the Draco writer and the JSON reader give.
// (JSON cannot spell NaN or infinity: those are a syntax error there, json_code.)
void RequireEverywhere(const Image& image, StatusCode code, StatusCode json_code = StatusCode::kOk) {
  CHECK(sdvi::ValidateImage(image, "t").code() == code);
  CHECK(sdvi::EncodeSdvi(image).status().code() == code);
  sdvi::CompressOptions options;
  CHECK(sdvi::EncodeImage(image, &options, "t").status().code() == code);
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == code);
  CHECK(sdvi::ParseMeshJson(sdvi::FormatMeshJson(image), "t.json").status().code() ==
        (json_code == StatusCode::kOk ? code : json_code));
}

}  // namespace

TEST_CASE("a valid mesh passes, and its Draco round trip too") {
  const Image image = Square();
  REQUIRE(sdvi::ValidateImage(image, "t").ok());
  sdvi::CompressOptions options;
  auto bytes = sdvi::EncodeImage(image, &options, "t");
  REQUIRE(bytes.ok());
  REQUIRE(sdvi::DecodeImage(*bytes, "t").ok());
}

TEST_CASE("issue 16.5: a width or height over 2^18 is refused by every writer (convert wrote 4294967295)") {
  Image image = Square();
  image.width = 4294967295u;
  RequireEverywhere(image, StatusCode::kLimitExceeded);
  image.width = sdvi::kMaxImageSide + 1;
  RequireEverywhere(image, StatusCode::kLimitExceeded);
  image.width = sdvi::kMaxImageSide;
  CHECK(sdvi::ValidateImage(image, "t").ok());
}

TEST_CASE("issue 16.1: a colour of -1.7e38 is kValueOutOfRange, never reaches Draco") {
  Image image = Square();
  image.vertices[4].g = -1.7e38f;
  RequireEverywhere(image, StatusCode::kValueOutOfRange);
  const sdvi::Status status = sdvi::ValidateImage(image, "in.sdvi");
  CHECK(status.message().find("in.sdvi: vertex 4") == 0);
}

TEST_CASE("colours at the documented bounds pass, beyond them fail") {
  Image image = Square();
  image.vertices[1].r = sdvi::kMinColor;
  image.vertices[2].b = sdvi::kMaxColor;
  CHECK(sdvi::ValidateImage(image, "t").ok());
  image.vertices[2].b = std::nextafter(sdvi::kMaxColor, 1e9f);
  RequireEverywhere(image, StatusCode::kValueOutOfRange);
}

TEST_CASE("issue 16.1: a vertex at x = 1e7 is kValueOutOfRange (the 16 GB Draco runaway)") {
  Image image = Square();
  image.vertices[8].x = 1e7f;
  RequireEverywhere(image, StatusCode::kValueOutOfRange);
  // One image size outside is the limit on each side.
  image.vertices[8].x = 128.f;   // width + max(width, height)
  image.vertices[0].y = -64.f;
  CHECK(sdvi::ValidateImage(image, "t").ok());
  image.vertices[0].y = -64.01f;
  CHECK(sdvi::ValidateImage(image, "t").code() == StatusCode::kValueOutOfRange);
}

TEST_CASE("NaN and infinity stay kNonFinite") {
  Image image = Square();
  image.vertices[3].x = std::numeric_limits<float>::quiet_NaN();
  RequireEverywhere(image, StatusCode::kNonFinite, StatusCode::kDecodeFailed);
  image = Square();
  image.vertices[3].b = std::numeric_limits<float>::infinity();
  RequireEverywhere(image, StatusCode::kNonFinite, StatusCode::kDecodeFailed);
}

TEST_CASE("issue 16.5: duplicate triangles are kDuplicateTriangle in every writer") {
  Image image = Square();
  image.triangles.push_back({{image.triangles[0].v[1], image.triangles[0].v[2], image.triangles[0].v[0]}});
  RequireEverywhere(image, StatusCode::kDuplicateTriangle);
  image = Square();
  image.triangles.push_back({{image.triangles[0].v[0], image.triangles[0].v[2], image.triangles[0].v[1]}});
  RequireEverywhere(image, StatusCode::kDuplicateTriangle);
}

TEST_CASE("issue 16.5: an edge in three triangles is kNonManifoldEdge in every writer") {
  Image image = Square();
  // A fin on the diagonal (0, 4) of the first cell: a new vertex above the image.
  image.vertices.push_back({40.f, -8.f, 0.f, 0.f, 0.f});
  image.triangles.push_back({{0, 9, 4}});
  RequireEverywhere(image, StatusCode::kNonManifoldEdge);
}

TEST_CASE("an inconsistent orientation is kInvalidMesh") {
  Image image = Square();
  std::swap(image.triangles[1].v[1], image.triangles[1].v[2]);
  RequireEverywhere(image, StatusCode::kInvalidMesh);
}

TEST_CASE("issue 16.5: a folded triangle is kFoldedTriangle in every writer") {
  Image image = Square();
  image.vertices[4].x = 70.f;  // the centre vertex dragged past the right column: folds
  RequireEverywhere(image, StatusCode::kFoldedTriangle);
  // Moved, not folded: fine.
  image.vertices[4].x = 40.f;
  CHECK(sdvi::ValidateImage(image, "t").ok());
}

TEST_CASE("zero-area triangles (coincident feature pairs) are not folds") {
  Image image = Square();
  image.vertices[4] = image.vertices[3];  // the centre on the left edge's midpoint
  image.vertices[4].x = 0.f;
  // Triangles (0,4,3) and (3,4,6)... touch; validation sees zero areas only.
  CHECK(sdvi::ValidateImage(image, "t").code() != StatusCode::kFoldedTriangle);
}

TEST_CASE("the reader refuses what the writer refuses (out-of-range colour patched into a file)") {
  Image image = Square();
  auto bytes = sdvi::EncodeSdvi(image);
  REQUIRE(bytes.ok());
  // Find vertex 4's green (128 + ... no: 20.f) and replace it by -1.7e38, fixing the CRC.
  Image copy = image;
  copy.vertices[4].g = -1.7e38f;
  auto decoded = sdvi::DecodeSdvi(*bytes, "t");
  REQUIRE(decoded.ok());
  std::vector<uint8_t> patched = *bytes;
  const float green = image.vertices[4].g, bad = -1.7e38f;
  size_t hits = 0;
  for (size_t i = 0; i + 4 <= patched.size(); i += 4)
    if (std::memcmp(&patched[i], &image.vertices[4].x, 4) == 0 &&
        std::memcmp(&patched[i + 12], &green, 4) == 0) {
      std::memcpy(&patched[i + 12], &bad, 4);
      ++hits;
    }
  REQUIRE(hits == 1);
  auto result = sdvi::DecodeSdvi(patched, "bad.sdvi");
  // The CRC catches it first in a release build; the value check is behind it.
  CHECK(!result.ok());
}

TEST_CASE("positions or colours spanning a subnormal float are kEncodeFailed, never reach Draco") {
  // Found by fuzz_compress: every vertex within 7e-39 px of the origin (valid: no triangle
  // folds in double) made Draco's float quantiser divide 2^12 - 1 by a subnormal span and
  // then read out of bounds (sdvi compress: segmentation fault).
  Image image = Square();
  for (sdvi::Vertex& v : image.vertices) {
    v.x *= 2e-40f;
    v.y *= 2e-40f;
  }
  REQUIRE(sdvi::ValidateImage(image, "t").ok());
  sdvi::CompressOptions options;
  for (int speed : {0, 5}) {
    options.speed = speed;
    const sdvi::Status status = sdvi::EncodeImage(image, &options, "t").status();
    CHECK(status.code() == StatusCode::kEncodeFailed);
    CHECK(status.message().find("positions span") != std::string::npos);
  }
  options.position_bits = 6;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kEncodeFailed);
  // Colours: a span of 1e-40 levels.
  image = Square();
  for (sdvi::Vertex& v : image.vertices) v.r = v.g = v.b = 0.f;
  image.vertices[4].g = 1e-40f;
  options = {};
  const sdvi::Status colours = sdvi::EncodeDracoPayload(image, options).status();
  CHECK(colours.code() == StatusCode::kEncodeFailed);
  CHECK(colours.message().find("colours span") != std::string::npos);
  // The smallest span that passes at 12 bits, 2^-114, quantises and decodes.
  image = Square();
  for (sdvi::Vertex& v : image.vertices) {
    v.x = std::ldexp(v.x / 64.f, -114);
    v.y = std::ldexp(v.y / 64.f, -114);
  }
  options.position_bits = 12;
  auto bytes = sdvi::EncodeImage(image, &options, "t");
  REQUIRE(bytes.ok());
  CHECK(sdvi::DecodeImage(*bytes, "t").ok());
}

TEST_CASE("Draco quantization is bounded at kMaxQuantizationBits") {
  Image image = Square();
  sdvi::CompressOptions options;
  options.position_bits = sdvi::kMaxQuantizationBits + 1;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kInvalidArgument);
  options.position_bits = 30;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kInvalidArgument);
  options.position_bits = 0;
  options.color_bits = 30;
  CHECK(sdvi::EncodeDracoPayload(image, options).status().code() == StatusCode::kInvalidArgument);
  // The defaults never exceed it, even for the largest image with vertices at its margins.
  image.width = image.height = sdvi::kMaxImageSide;
  image.vertices[0].x = -float(sdvi::kMaxImageSide);
  image.vertices[8].x = 2.f * float(sdvi::kMaxImageSide);
  REQUIRE(sdvi::ValidateImage(image, "t").ok());
  CHECK(sdvi::DefaultPositionBits(image) == sdvi::kMaxQuantizationBits);
  CHECK(sdvi::DefaultColorBits(image) <= sdvi::kMaxQuantizationBits);
  options.color_bits = sdvi::kMaxQuantizationBits;
  options.position_bits = sdvi::kMaxQuantizationBits;
  auto payload = sdvi::EncodeDracoPayload(image, options);
  REQUIRE(payload.ok());
  Image out;
  out.width = out.height = 64;
  REQUIRE(sdvi::DecodeDracoPayload(*payload, "t", &out).ok());
  // A payload header claiming more bits is refused before Draco runs.
  std::vector<uint8_t> bad = *payload;
  bad[7] = 30;
  // Its CRC-32 (spec/FORMAT.md 8.1): bytes 0..35 and 40..end.
  uint32_t crc = sdvi::Crc32(std::span<const uint8_t>(bad.data(), 36));
  crc = sdvi::Crc32(std::span<const uint8_t>(bad.data() + 40, bad.size() - 40), crc);
  for (int i = 0; i < 4; ++i) bad[36 + i] = uint8_t(crc >> (8 * i));
  Image ignored;
  CHECK(sdvi::DecodeDracoPayload(bad, "t", &ignored).code() == StatusCode::kLimitExceeded);
}
