// SPDX-License-Identifier: GPL-3.0-or-later
// The mesh JSON form: bit-exact round trips with .sdvi, and its errors.
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>
#include <random>

#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"
#include "test_util.h"

namespace sdvi {
namespace {

using test::BitEqual;

// A mesh with open and closed feature polylines, interior corners, a pair, and colours
// drawn from all bit patterns of the colour range ValidateImage allows (denormals, -0,
// the range's ends and tiny values included).
Image AwkwardMesh() {
  Image image = test::Grid(5);  // 36 vertices
  std::mt19937 rng(20140801);
  for (Vertex& v : image.vertices) {
    float* c = &v.x;
    for (int k = 2; k < 5; ++k) {  // colours: random finite bit patterns
      float f;
      do {
        const uint32_t bits = rng();
        std::memcpy(&f, &bits, sizeof f);
      } while (!(f >= sdvi::kMinColor && f <= sdvi::kMaxColor));
      c[k] = f;
    }
  }
  image.vertices[0].r = -0.f;
  image.vertices[1].g = std::numeric_limits<float>::denorm_min();
  image.vertices[2].b = sdvi::kMaxColor;
  image.vertices[3].r = 0.1f;
  image.vertices[4].g = sdvi::kMinColor;
  auto id = [](uint32_t x, uint32_t y) { return y * 6 + x; };
  FeaturePolyline open{{id(1, 1), id(2, 1), id(3, 1)}, false};
  FeaturePolyline open2{{id(1, 2), id(2, 2), id(3, 2)}, false};
  FeaturePolyline closed{{}, true};  // the boundary loop (tagged crease by Grid)
  for (uint32_t x = 0; x < 5; ++x) closed.vertices.push_back(id(x, 0));
  for (uint32_t y = 0; y < 5; ++y) closed.vertices.push_back(id(5, y));
  for (uint32_t x = 5; x > 0; --x) closed.vertices.push_back(id(x, 5));
  for (uint32_t y = 5; y > 0; --y) closed.vertices.push_back(id(0, y));
  for (const auto* p : {&open, &open2})
    for (size_t i = 0; i + 1 < p->vertices.size(); ++i)
      image.crease_edges.push_back(Edge::Of(p->vertices[i], p->vertices[i + 1]));
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.corners = {id(0, 0), id(2, 1), id(5, 5)};
  image.polylines = {open, open2, closed};
  image.pairs = {{0, 1, 0.3f}};
  image.metadata = {{"note", "quotes \" and \\ and unicode \xc3\xa9"}, {"empty", ""}};
  return image;
}

StatusCode ParseCode(const std::string& text) {
  return ParseMeshJson(text, "t.json").status().code();
}

TEST_CASE("JSON -> sdvi -> JSON is exact: every vertex bit, every tag") {
  const Image image = AwkwardMesh();
  const std::string json = FormatMeshJson(image);
  auto parsed = ParseMeshJson(json, "mem.json");
  REQUIRE(parsed.ok());
  CHECK(BitEqual(parsed->vertices, image.vertices));
  CHECK(*parsed == image);
  auto bytes = EncodeSdvi(*parsed);
  REQUIRE(bytes.ok());
  auto file = DecodeSdvi(*bytes, "mem.sdvi");
  REQUIRE(file.ok());
  auto back = ParseMeshJson(FormatMeshJson(file->image), "back.json");
  REQUIRE(back.ok());
  CHECK(BitEqual(back->vertices, image.vertices));
  CHECK(back->crease_edges == image.crease_edges);
  CHECK(back->corners == image.corners);
  CHECK(*back == CanonicalizeImage(image));
  // In canonical form the text itself survives.
  const std::string canonical_json = FormatMeshJson(CanonicalizeImage(image));
  CHECK(FormatMeshJson(file->image) == canonical_json);
}

TEST_CASE("sdvi -> JSON -> sdvi is byte-identical") {
  auto bytes = EncodeSdvi(AwkwardMesh());
  REQUIRE(bytes.ok());
  auto file = DecodeSdvi(*bytes, "mem.sdvi");
  REQUIRE(file.ok());
  auto parsed = ParseMeshJson(FormatMeshJson(file->image), "mem.json");
  REQUIRE(parsed.ok());
  auto again = EncodeSdvi(*parsed);
  REQUIRE(again.ok());
  CHECK(*again == *bytes);
}

TEST_CASE("the golden JSON converts to the golden .sdvi and back to the same text") {
  auto json = ReadFileBytes(std::string(SDVI_TEST_DATA_DIR) + "/golden_v1_0.json");
  auto sdvi = ReadFileBytes(std::string(SDVI_TEST_DATA_DIR) + "/golden_v1_0.sdvi");
  REQUIRE(json.ok());
  REQUIRE(sdvi.ok());
  const std::string text(json->begin(), json->end());
  auto image = ParseMeshJson(text, "golden_v1_0.json");
  REQUIRE(image.ok());
  auto bytes = EncodeSdvi(*image);
  REQUIRE(bytes.ok());
  CHECK(*bytes == *sdvi);
  CHECK(FormatMeshJson(*image) == text);
}

TEST_CASE("crease edges and corners are read as sets") {
  const std::string text = R"({"width": 2, "height": 2,
    "vertices": [[0,0,0,0,0],[2,0,0,0,0],[0,2,0,0,0]], "triangles": [[0,1,2]],
    "crease_edges": [[2,1],[1,0],[1,2]], "corners": [2,0,2]})";
  auto image = ParseMeshJson(text, "t.json");
  REQUIRE(image.ok());
  CHECK(image->crease_edges == std::vector<Edge>{{0, 1}, {1, 2}});
  CHECK(image->corners == std::vector<uint32_t>{0, 2});
}

TEST_CASE("malformed mesh JSON gives specific codes") {
  const std::string head = R"({"width": 2, "height": 2, "vertices": [[0,0,0,0,0],[2,0,0,0,0],[0,2,0,0,0]], )";
  CHECK(ParseCode("{\"width\": 2,") == StatusCode::kDecodeFailed);
  CHECK(ParseCode("[1, 2]") == StatusCode::kCorrupt);
  CHECK(ParseCode(R"({"width": 2, "height": 2, "vertices": []})") == StatusCode::kCorrupt);
  CHECK(ParseCode(head + R"("triangles": [[0,1]]})") == StatusCode::kCorrupt);
  CHECK(ParseCode(head + R"("triangles": [[0,1,"2"]]})") == StatusCode::kCorrupt);
  CHECK(ParseCode(head + R"("triangles": [[0,1,2.5]]})") == StatusCode::kCorrupt);
  CHECK(ParseCode(head + R"("triangles": [[0,1,-2]]})") == StatusCode::kIndexOutOfRange);
  CHECK(ParseCode(head + R"("triangles": [[0,1,3]]})") == StatusCode::kIndexOutOfRange);
  CHECK(ParseCode(head + R"("triangles": [[0,1,1]]})") == StatusCode::kDegenerateTriangle);
  CHECK(ParseCode(head + R"("triangles": [[0,1,2]], "colour": 1})") == StatusCode::kInvalidArgument);
  CHECK(ParseCode(head + R"("triangles": [[0,1,2]], "version": 2})") ==
        StatusCode::kUnsupportedVersion);
  CHECK(ParseCode(head + R"("triangles": [[0,1,2]], "crease_edges": [[0,1],[0,4]]})") ==
        StatusCode::kIndexOutOfRange);
  CHECK(ParseCode(R"({"width": 4, "height": 4, "vertices": [[0,0,0,0,0],[2,0,0,0,0],[0,2,0,0,0],[2,2,0,0,0]],
      "triangles": [[0,1,2],[1,3,2]], "crease_edges": [[0,3]]})") == StatusCode::kCreaseNotAnEdge);
  // JSON has no NaN or infinity; a number beyond float range is a syntax-level error.
  CHECK(ParseCode(R"({"width": 2, "height": 2, "vertices": [[0,0,0,0,1e999]], "triangles": []})") ==
        StatusCode::kDecodeFailed);
  CHECK(ParseCode(head + R"("triangles": [[0,1,2]], "pairs": [{"first": 0, "second": 1}]})") ==
        StatusCode::kIndexOutOfRange);
  auto r = ParseMeshJson(head + R"("triangles": [[0,1,2]], "corners": [0, "x"]})", "shape.json");
  CHECK(r.status().code() == StatusCode::kCorrupt);
  CHECK(r.status().message() == "shape.json: corners[1] must be a non-negative integer");
}

}  // namespace
}  // namespace sdvi
