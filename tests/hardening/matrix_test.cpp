// SPDX-License-Identifier: GPL-3.0-or-later
// The bad-input matrix at the library level: every truncation and every single-byte flip
// of a small real file (raw and Draco payload) through DecodeImage, the reader every
// command that takes an .sdvi file uses; huge declared sizes; NaN, infinity and huge
// numbers in mesh JSON. Each must give a specific code and a message naming the file.
#include <catch2/catch.hpp>

#include <set>
#include <string>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"

using sdvi::StatusCode;

namespace {

std::vector<uint8_t> Golden() {
  auto bytes = sdvi::ReadFileBytes(std::string(SDVI_TEST_DATA_DIR) + "/golden_v1_0.sdvi");
  REQUIRE(bytes.ok());
  return *bytes;
}

std::vector<uint8_t> GoldenCompressed() {
  auto image = sdvi::DecodeImage(Golden(), "golden");
  REQUIRE(image.ok());
  sdvi::CompressOptions options;
  auto bytes = sdvi::EncodeImage(*image, &options, "golden");
  REQUIRE(bytes.ok());
  return *bytes;
}

// A refusal names the file and has a code a reader gives for damaged input.
void CheckRefused(const std::vector<uint8_t>& bytes, const std::string& name) {
  static const std::set<StatusCode> kExpected = {
      StatusCode::kEmptyInput,      StatusCode::kTruncated,        StatusCode::kCorrupt,
      StatusCode::kWrongIdentifier, StatusCode::kUnsupportedVersion, StatusCode::kCountMismatch,
      StatusCode::kLimitExceeded,   StatusCode::kIndexOutOfRange,  StatusCode::kUnsupportedFormat};
  auto image = sdvi::DecodeImage(bytes, name);
  INFO(name);
  REQUIRE(!image.ok());
  CHECK(kExpected.count(image.status().code()) == 1);
  CHECK(image.status().message().rfind(name, 0) == 0);
}

}  // namespace

TEST_CASE("matrix: every truncation of a raw and a Draco file is refused, naming the file") {
  for (const auto& whole : {Golden(), GoldenCompressed()}) {
    for (size_t keep = 0; keep < whole.size(); ++keep)
      CheckRefused(std::vector<uint8_t>(whole.begin(), whole.begin() + long(keep)),
                   "cut" + std::to_string(keep) + ".sdvi");
  }
}

TEST_CASE("matrix: every single-byte flip of a raw and a Draco file is refused, naming the file") {
  for (const auto& whole : {Golden(), GoldenCompressed()}) {
    for (size_t at = 0; at < whole.size(); ++at)
      for (uint8_t mask : {uint8_t{0xff}, uint8_t{0x01}}) {
        std::vector<uint8_t> bad = whole;
        bad[at] ^= mask;
        CheckRefused(bad, "flip" + std::to_string(at) + ".sdvi");
      }
  }
}

TEST_CASE("matrix: huge declared sizes are kLimitExceeded before allocation") {
  const std::vector<uint8_t> whole = Golden();
  sdvi::ReadOptions tight;
  tight.max_vertices = 10;
  CHECK(sdvi::DecodeImage(whole, "v.sdvi", tight).status().code() == StatusCode::kLimitExceeded);
  tight = {};
  tight.max_triangles = 10;
  CHECK(sdvi::DecodeImage(whole, "t.sdvi", tight).status().code() == StatusCode::kLimitExceeded);
  tight = {};
  tight.max_file_bytes = 100;
  CHECK(sdvi::DecodeImage(whole, "f.sdvi", tight).status().code() == StatusCode::kLimitExceeded);
  tight = {};
  tight.max_width = 4;
  CHECK(sdvi::DecodeImage(whole, "w.sdvi", tight).status().code() == StatusCode::kLimitExceeded);
  const std::vector<uint8_t> compressed = GoldenCompressed();
  tight = {};
  tight.max_vertices = 10;
  CHECK(sdvi::DecodeImage(compressed, "c.sdvi", tight).status().code() == StatusCode::kLimitExceeded);
}

TEST_CASE("matrix: NaN, infinity and huge numbers in mesh JSON give specific codes") {
  const std::string head = R"({"format": "sdvi-mesh", "version": 1, "width": 8, "height": 8, )";
  auto code = [&](const std::string& vertices, const std::string& rest = "") {
    return sdvi::ParseMeshJson(head + R"("vertices": )" + vertices + R"(, "triangles": [[0,1,2]])" + rest + "}",
                               "m.json")
        .status()
        .code();
  };
  const std::string ok = "[[0,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]]";
  REQUIRE(code(ok) == StatusCode::kOk);
  // NaN and Infinity are not JSON: a syntax error.
  CHECK(code("[[NaN,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]]") == StatusCode::kDecodeFailed);
  CHECK(code("[[Infinity,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]]") == StatusCode::kDecodeFailed);
  // Numbers beyond float: not a finite float32.
  const StatusCode huge = code("[[1e39,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]]");
  CHECK((huge == StatusCode::kNonFinite || huge == StatusCode::kDecodeFailed));
  // Finite but no image has them.
  CHECK(code("[[1e7,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]]") == StatusCode::kValueOutOfRange);
  CHECK(code("[[0,0,-1.7e38,0,0],[8,0,1,2,3],[0,8,4,5,6]]") == StatusCode::kValueOutOfRange);
  // Huge sizes.
  CHECK(sdvi::ParseMeshJson(R"({"format": "sdvi-mesh", "version": 1, "width": 4294967295, "height": 8, "vertices": )" +
                                ok + R"(, "triangles": [[0,1,2]]})",
                            "w.json")
            .status()
            .code() == StatusCode::kLimitExceeded);
  CHECK(sdvi::ParseMeshJson(R"({"format": "sdvi-mesh", "version": 1, "width": 4294967296, "height": 8, "vertices": )" +
                                ok + R"(, "triangles": [[0,1,2]]})",
                            "w.json")
            .status()
            .code() != StatusCode::kOk);
  CHECK(code(ok, R"(, "corners": [4294967295])") == StatusCode::kIndexOutOfRange);
}
