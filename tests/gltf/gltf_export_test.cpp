// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the glTF exporter (converters/gltf, spec/GLTF.md). Files are read back with an
// independent GLB parser (nlohmann_json + the BIN chunk) and Draco's decoder; the Khronos
// validator and the three.js viewer run as separate ctest tests (tests/gltf/*.sh).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <unistd.h>

#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>

#include "sdvi/file_util.h"
#include "sdvi/gltf.h"
#include "sdvi/subdiv.h"
#include "test_images.h"

namespace {

using json = nlohmann::json;
using sdvi::GltfExportOptions;
using sdvi::Image;
using sdvi::StatusCode;

struct Glb {
  json doc;
  std::vector<uint8_t> bin;
};

uint32_t ReadU32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// Parses a GLB container (header, JSON chunk, optional BIN chunk), checking its framing.
Glb ParseGlb(const std::vector<uint8_t>& bytes) {
  REQUIRE(bytes.size() >= 20);
  REQUIRE(std::memcmp(bytes.data(), "glTF", 4) == 0);
  REQUIRE(ReadU32(bytes, 4) == 2);
  REQUIRE(ReadU32(bytes, 8) == bytes.size());
  const uint32_t json_length = ReadU32(bytes, 12);
  REQUIRE(ReadU32(bytes, 16) == 0x4E4F534Au);  // "JSON"
  REQUIRE(json_length % 4 == 0);
  Glb glb;
  glb.doc = json::parse(bytes.begin() + 20, bytes.begin() + 20 + json_length);
  const size_t bin_at = 20 + json_length;
  if (bin_at < bytes.size()) {
    const uint32_t bin_length = ReadU32(bytes, bin_at);
    REQUIRE(ReadU32(bytes, bin_at + 4) == 0x004E4942u);  // "BIN\0"
    REQUIRE(bin_at + 8 + bin_length == bytes.size());
    glb.bin.assign(bytes.begin() + bin_at + 8, bytes.end());
  }
  return glb;
}

// The bytes of buffer view `view`.
std::vector<uint8_t> ViewBytes(const Glb& glb, int view) {
  const json& v = glb.doc["bufferViews"][view];
  const size_t offset = v.value("byteOffset", 0);
  const size_t length = v["byteLength"];
  REQUIRE(offset + length <= glb.bin.size());
  return {glb.bin.begin() + offset, glb.bin.begin() + offset + length};
}

// A float VEC3 accessor's values.
std::vector<float> ReadVec3(const Glb& glb, int accessor) {
  const json& a = glb.doc["accessors"][accessor];
  REQUIRE(a["componentType"] == 5126);
  REQUIRE(a["type"] == "VEC3");
  const size_t count = a["count"];
  const std::vector<uint8_t> bytes = ViewBytes(glb, a["bufferView"]);
  REQUIRE(bytes.size() >= count * 12);
  std::vector<float> out(count * 3);
  std::memcpy(out.data(), bytes.data() + a.value("byteOffset", 0), count * 12);
  return out;
}

// An index accessor's values (unsigned short or unsigned int).
std::vector<uint32_t> ReadIndices(const Glb& glb, int accessor) {
  const json& a = glb.doc["accessors"][accessor];
  REQUIRE(a["type"] == "SCALAR");
  const size_t count = a["count"];
  const std::vector<uint8_t> bytes = ViewBytes(glb, a["bufferView"]);
  std::vector<uint32_t> out(count);
  if (a["componentType"] == 5123) {
    for (size_t i = 0; i < count; ++i) {
      uint16_t v;
      std::memcpy(&v, bytes.data() + 2 * i, 2);
      out[i] = v;
    }
  } else {
    REQUIRE(a["componentType"] == 5125);
    std::memcpy(out.data(), bytes.data(), count * 4);
  }
  return out;
}

Glb Export(const Image& image, const GltfExportOptions& options) {
  auto exported = sdvi::EncodeGltf(image, options);
  INFO(exported.status().ToString());
  REQUIRE(exported.ok());
  return ParseGlb(exported->bytes);
}

GltfExportOptions Levels(int r) {
  GltfExportOptions options;
  options.levels = r;
  return options;
}

// Twice the signed area seen from +Z of triangle (a, b, c) of a POSITION array.
double SignedArea2(const std::vector<float>& p, uint32_t a, uint32_t b, uint32_t c) {
  return (double(p[3 * b]) - p[3 * a]) * (double(p[3 * c + 1]) - p[3 * a + 1]) -
         (double(p[3 * b + 1]) - p[3 * a + 1]) * (double(p[3 * c]) - p[3 * a]);
}

}  // namespace

TEST_CASE("gltf SrgbToLinear decodes the sRGB transfer function and clamps") {
  CHECK(sdvi::SrgbToLinear(0.0f) == 0.0f);
  CHECK(sdvi::SrgbToLinear(1.0f) == Approx(1.0f));
  CHECK(sdvi::SrgbToLinear(0.5f) == Approx(0.214041f).epsilon(1e-5));
  CHECK(sdvi::SrgbToLinear(0.04f) == Approx(0.04f / 12.92f));
  CHECK(sdvi::SrgbToLinear(-3.0f) == 0.0f);
  CHECK(sdvi::SrgbToLinear(2.0f) == Approx(1.0f));
  CHECK(sdvi::SrgbToLinear(std::nanf("")) == 0.0f);
}

TEST_CASE("gltf default level makes fine triangles of about 1-2 source pixels within caps") {
  // 64x48 with 8 x 13 cells of 2 triangles: mean area 14.8 px^2; r = 1 leaves 3.7 px^2,
  // r = 2 gives 0.92 px^2.
  CHECK(sdvi::DefaultGltfLevels(sdvi::gltf_test::GradientWithCrease(64, 48, 8, 6)) == 2);
  // 4 x 4 times the area: 236 px^2; r = 3 leaves 3.7 px^2, r = 4 gives 0.92 px^2.
  CHECK(sdvi::DefaultGltfLevels(sdvi::gltf_test::GradientWithCrease(256, 192, 8, 6)) == 4);
  // 6384 triangles of 2628 px^2 would want r = 6: the level cap makes it 5, and the 2^21
  // fine-triangle cap 4 (6384 * 4^5 > 2^21 >= 6384 * 4^4).
  CHECK(sdvi::DefaultGltfLevels(sdvi::gltf_test::GradientWithCrease(4096, 4096, 56, 28)) == 4);
  // Huge triangles: capped at level 5.
  CHECK(sdvi::DefaultGltfLevels(sdvi::gltf_test::GradientWithCrease(4096, 4096, 2, 1)) == 5);
  CHECK(sdvi::DefaultGltfLevels(Image{}) == 0);
}

TEST_CASE("gltf surface is one indexed mesh in source pixels with y flipped and exact min and max") {
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  const Glb glb = Export(image, Levels(2));
  const json& doc = glb.doc;
  REQUIRE(doc["meshes"].size() == 1);
  REQUIRE(doc["meshes"][0]["primitives"].size() == 1);
  const json& prim = doc["meshes"][0]["primitives"][0];
  CHECK(prim.value("mode", 4) == 4);
  const std::vector<float> pos = ReadVec3(glb, prim["attributes"]["POSITION"]);
  const std::vector<uint32_t> idx = ReadIndices(glb, prim["indices"]);
  CHECK(idx.size() == image.triangles.size() * 16 * 3);

  // The same fine vertices as the engine's limit surface, mapped (x, H - y, 0).
  sdvi::LimitSurfaceOptions so;
  so.levels = 2;
  auto surface = sdvi::BuildLimitSurface(image, so);
  REQUIRE(surface.ok());
  const std::vector<sdvi::Vertex> fine = sdvi::EvaluateSurface(*surface, image.vertices);
  REQUIRE(pos.size() == fine.size() * 3);
  for (size_t i = 0; i < fine.size(); ++i) {
    REQUIRE(pos[3 * i] == fine[i].x);
    REQUIRE(pos[3 * i + 1] == 48.0f - fine[i].y);
    REQUIRE(pos[3 * i + 2] == 0.0f);
  }
  // min/max equal the data (the validator checks them exactly too).
  const json& acc = doc["accessors"][int(prim["attributes"]["POSITION"])];
  std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
  for (size_t i = 0; i < pos.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], pos[i]);
    hi[i % 3] = std::max(hi[i % 3], pos[i]);
  }
  for (int c = 0; c < 3; ++c) {
    CHECK(float(acc["min"][c].get<double>()) == lo[c]);
    CHECK(float(acc["max"][c].get<double>()) == hi[c]);
  }
  // Corners are fixed by the limit rules: the image frame is exactly [0,64] x [0,48].
  CHECK(lo[0] == 0.0f);
  CHECK(lo[1] == 0.0f);
  CHECK(hi[0] == 64.0f);
  CHECK(hi[1] == 48.0f);
}

TEST_CASE("gltf triangles are counter-clockwise seen from +Z whatever the input winding") {
  for (bool reverse : {false, true}) {
    const Image image = sdvi::gltf_test::GradientWithCrease(64, 48, 8, 6, reverse);
    const Glb glb = Export(image, Levels(2));
    const json& prim = glb.doc["meshes"][0]["primitives"][0];
    const std::vector<float> pos = ReadVec3(glb, prim["attributes"]["POSITION"]);
    const std::vector<uint32_t> idx = ReadIndices(glb, prim["indices"]);
    size_t clockwise = 0;
    double area = 0;
    for (size_t t = 0; t < idx.size(); t += 3) {
      const double a = SignedArea2(pos, idx[t], idx[t + 1], idx[t + 2]);
      clockwise += a <= 0;
      area += a / 2;
    }
    INFO("reverse winding " << reverse);
    CHECK(clockwise == 0);
    // No overlap, no gap: the triangles tile the 64 x 48 frame.
    CHECK(area == Approx(64.0 * 48.0).epsilon(1e-4));
  }
}

TEST_CASE("gltf COLOR_0 is the limit colour decoded from sRGB to linear light") {
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  const Glb glb = Export(image, Levels(1));
  const json& prim = glb.doc["meshes"][0]["primitives"][0];
  const std::vector<float> col = ReadVec3(glb, prim["attributes"]["COLOR_0"]);
  sdvi::LimitSurfaceOptions so;
  so.levels = 1;
  auto surface = sdvi::BuildLimitSurface(image, so);
  REQUIRE(surface.ok());
  const std::vector<sdvi::Vertex> fine = sdvi::EvaluateSurface(*surface, image.vertices);
  REQUIRE(col.size() == fine.size() * 3);
  for (size_t i = 0; i < fine.size(); ++i) {
    REQUIRE(col[3 * i] == Approx(sdvi::SrgbToLinear(fine[i].r / 255.0f)));
    REQUIRE(col[3 * i + 1] == Approx(sdvi::SrgbToLinear(fine[i].g / 255.0f)));
    REQUIRE(col[3 * i + 2] == Approx(sdvi::SrgbToLinear(fine[i].b / 255.0f)));
  }
  // Linear light is darker than the sRGB code value for mid tones.
  const float r = fine[0].r / 255.0f;
  if (r > 0.05f && r < 0.95f) CHECK(col[0] < r);
}

TEST_CASE("gltf out-of-range control colours are clamped to 0..1 in COLOR_0") {
  Image image = sdvi::gltf_test::GradientWithCrease(32, 32, 2, 1);
  image.vertices[0].r = 400;
  image.vertices[1].g = -80;
  const Glb glb = Export(image, Levels(1));
  const json& acc = glb.doc["accessors"][int(glb.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"])];
  for (int c = 0; c < 3; ++c) {
    CHECK(acc["min"][c].get<double>() >= 0.0);
    CHECK(acc["max"][c].get<double>() <= 1.0);
  }
}

TEST_CASE("gltf asset and unlit material and extras follow spec GLTF.md") {
  Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  image.metadata.push_back({"copyright", "CC0, the sdvi tests"});
  const Glb glb = Export(image, Levels(1));
  const json& doc = glb.doc;
  CHECK(doc["asset"]["version"] == "2.0");
  CHECK(doc["asset"]["generator"].get<std::string>().rfind("sdvi ", 0) == 0);
  CHECK(doc["asset"]["copyright"] == "CC0, the sdvi tests");
  CHECK(doc["asset"]["extras"]["sdvi"]["source_width"] == 64);
  CHECK(doc["asset"]["extras"]["sdvi"]["source_height"] == 48);
  CHECK(doc["asset"]["extras"]["sdvi"]["levels"] == 1);
  const json& material = doc["materials"][int(doc["meshes"][0]["primitives"][0]["material"])];
  CHECK(material["extensions"].contains("KHR_materials_unlit"));
  CHECK(doc["extensionsUsed"].size() == 1);
  CHECK(doc["extensionsUsed"][0] == "KHR_materials_unlit");
  CHECK_FALSE(doc.contains("extensionsRequired"));
  CHECK(doc["scenes"][0]["nodes"].size() == 1);

  GltfExportOptions options = Levels(1);
  options.copyright = "given on the command line";
  CHECK(Export(image, options).doc["asset"]["copyright"] == "given on the command line");
  CHECK(Export(sdvi::gltf_test::GradientWithCrease(8, 8, 1, 1), Levels(0))
            .doc["asset"]["copyright"] == "unspecified");
  // JSON needs UTF-8: bytes that are not (Latin-1 here) become U+FFFD; valid text stays.
  options.copyright = "\xA9 1972 Playboy, \xC2\xA9 ok, \xED\xA0\x80, \xF0\x9F\x98\x80";
  CHECK(Export(image, options).doc["asset"]["copyright"] ==
        "\xEF\xBF\xBD 1972 Playboy, \xC2\xA9 ok, \xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD, \xF0\x9F\x98\x80");
}

TEST_CASE("gltf object image has no triangles outside its domain") {
  const Image image = sdvi::gltf_test::ConvexObject(80, 60);
  const Glb glb = Export(image, Levels(3));
  const json& prim = glb.doc["meshes"][0]["primitives"][0];
  const std::vector<float> pos = ReadVec3(glb, prim["attributes"]["POSITION"]);
  const std::vector<uint32_t> idx = ReadIndices(glb, prim["indices"]);
  // The domain is the convex control polygon (boundary vertices are corners): every
  // vertex lies inside it (in glTF coordinates, y flipped), and the area does not exceed it.
  std::vector<std::pair<double, double>> polygon;
  for (size_t i = 11; i < image.vertices.size(); ++i) {
    polygon.push_back({image.vertices[i].x, 60.0 - image.vertices[i].y});
  }
  double polygon_area = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const auto& [x0, y0] = polygon[i];
    const auto& [x1, y1] = polygon[(i + 1) % polygon.size()];
    polygon_area += (x0 * y1 - x1 * y0) / 2;
  }
  const double orientation = polygon_area > 0 ? 1 : -1;
  for (size_t v = 0; v < pos.size() / 3; ++v) {
    for (size_t i = 0; i < polygon.size(); ++i) {
      const auto& [x0, y0] = polygon[i];
      const auto& [x1, y1] = polygon[(i + 1) % polygon.size()];
      const double side = (x1 - x0) * (pos[3 * v + 1] - y0) - (y1 - y0) * (pos[3 * v] - x0);
      REQUIRE(orientation * side >= -1e-3);
    }
  }
  double area = 0;
  for (size_t t = 0; t < idx.size(); t += 3) area += SignedArea2(pos, idx[t], idx[t + 1], idx[t + 2]) / 2;
  CHECK(area > 0);
  CHECK(area <= std::abs(polygon_area) * (1 + 1e-6));
}

TEST_CASE("gltf draco option writes KHR_draco_mesh_compression that decodes to the same mesh") {
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  const Glb plain = Export(image, Levels(2));
  GltfExportOptions options = Levels(2);
  options.draco = true;
  auto exported = sdvi::EncodeGltf(image, options);
  REQUIRE(exported.ok());
  const Glb glb = ParseGlb(exported->bytes);
  const json& doc = glb.doc;
  CHECK(std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(),
                  "KHR_draco_mesh_compression") != doc["extensionsUsed"].end());
  CHECK(doc["extensionsRequired"] == json::array({"KHR_draco_mesh_compression"}));
  const json& prim = doc["meshes"][0]["primitives"][0];
  const json& ext = prim["extensions"]["KHR_draco_mesh_compression"];
  const std::vector<uint8_t> bytes = ViewBytes(glb, ext["bufferView"]);
  CHECK(bytes.size() == exported->draco_bytes);

  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  REQUIRE(decoded.ok());
  const draco::Mesh& mesh = *decoded.value();
  const json& pos_acc = doc["accessors"][int(prim["attributes"]["POSITION"])];
  const json& col_acc = doc["accessors"][int(prim["attributes"]["COLOR_0"])];
  const json& idx_acc = doc["accessors"][int(prim["indices"])];
  CHECK_FALSE(pos_acc.contains("bufferView"));
  CHECK(pos_acc["count"] == mesh.num_points());
  CHECK(col_acc["count"] == mesh.num_points());
  CHECK(idx_acc["count"] == mesh.num_faces() * 3);
  CHECK(mesh.num_faces() == image.triangles.size() * 16);
  // Attribute ids in the extension are the Draco unique ids.
  const draco::PointAttribute* pos = mesh.GetAttributeByUniqueId(ext["attributes"]["POSITION"]);
  const draco::PointAttribute* col = mesh.GetAttributeByUniqueId(ext["attributes"]["COLOR_0"]);
  REQUIRE(pos != nullptr);
  REQUIRE(col != nullptr);
  CHECK(pos->attribute_type() == draco::GeometryAttribute::POSITION);
  CHECK(col->attribute_type() == draco::GeometryAttribute::COLOR);

  // Quantized positions stay within 14-bit steps of the plain export's bounding box.
  const json& plain_acc = plain.doc["accessors"][int(plain.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"])];
  for (int c = 0; c < 2; ++c) {
    CHECK(pos_acc["min"][c].get<double>() == Approx(plain_acc["min"][c].get<double>()).margin(64.0 / 8192));
    CHECK(pos_acc["max"][c].get<double>() == Approx(plain_acc["max"][c].get<double>()).margin(64.0 / 8192));
  }
  // Every decoded triangle is still counter-clockwise seen from +Z.
  size_t clockwise = 0;
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    std::array<std::array<float, 3>, 3> p;
    for (int k = 0; k < 3; ++k) pos->GetMappedValue(mesh.face(f)[k], p[k].data());
    const double a = (double(p[1][0]) - p[0][0]) * (double(p[2][1]) - p[0][1]) -
                     (double(p[1][1]) - p[0][1]) * (double(p[2][0]) - p[0][0]);
    clockwise += a <= 0;
  }
  CHECK(clockwise == 0);
  CHECK(exported->bytes.size() < plain.bin.size());
}

TEST_CASE("gltf Draco quantization bits are configurable and validated") {
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  GltfExportOptions coarse = Levels(2), fine = Levels(2);
  coarse.draco = fine.draco = true;
  coarse.position_bits = 10;
  coarse.color_bits = 6;
  fine.position_bits = 18;
  fine.color_bits = 14;
  auto a = sdvi::EncodeGltf(image, coarse);
  auto b = sdvi::EncodeGltf(image, fine);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a->draco_bytes < b->draco_bytes);
  for (int bits : {0, 31, -2}) {
    GltfExportOptions bad = coarse;
    bad.position_bits = bits;
    CHECK(sdvi::EncodeGltf(image, bad).status().code() == StatusCode::kInvalidArgument);
    bad = coarse;
    bad.color_bits = bits;
    CHECK(sdvi::EncodeGltf(image, bad).status().code() == StatusCode::kInvalidArgument);
  }
}

TEST_CASE("gltf control mesh option adds a node with the control triangles and crease LINES") {
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48, 4, 3);
  GltfExportOptions options = Levels(1);
  options.control_mesh = true;
  for (bool draco : {false, true}) {
    options.draco = draco;
    const Glb glb = Export(image, options);
    const json& doc = glb.doc;
    REQUIRE(doc["scenes"][0]["nodes"].size() == 2);
    const json& node = doc["nodes"][int(doc["scenes"][0]["nodes"][1])];
    CHECK(node["translation"][0].get<double>() > 64.0);  // beside the surface
    const json& mesh = doc["meshes"][int(node["mesh"])];
    REQUIRE(mesh["primitives"].size() == 2);
    const json& tris = mesh["primitives"][0];
    const json& lines = mesh["primitives"][1];
    CHECK(tris.value("mode", 4) == 4);
    CHECK(lines["mode"] == 1);
    CHECK(ReadIndices(glb, tris["indices"]).size() == image.triangles.size() * 3);
    CHECK(ReadVec3(glb, tris["attributes"]["POSITION"]).size() == image.vertices.size() * 3);
    // Crease edges: the 2 x 4 listed pair edges plus the boundary: 2 x 4 horizontal
    // edges and 2 x 7 vertical ones (rows 0..3 and 4..7 on each side).
    const std::vector<uint32_t> line_idx = ReadIndices(glb, lines["indices"]);
    CHECK(line_idx.size() == 2 * (8 + 8 + 14));
    // Control triangles are counter-clockwise from +Z too.
    const std::vector<float> pos = ReadVec3(glb, tris["attributes"]["POSITION"]);
    const std::vector<uint32_t> idx = ReadIndices(glb, tris["indices"]);
    for (size_t t = 0; t < idx.size(); t += 3) CHECK(SignedArea2(pos, idx[t], idx[t + 1], idx[t + 2]) > 0);
  }
}

TEST_CASE("gltf text file embeds the same buffer as a data URI") {
  const Image image = sdvi::gltf_test::GradientWithCrease(32, 24, 2, 1);
  GltfExportOptions options = Levels(1);
  options.container = sdvi::GltfContainer::kText;
  auto text = sdvi::EncodeGltf(image, options);
  REQUIRE(text.ok());
  const json doc = json::parse(text->bytes.begin(), text->bytes.end());
  const std::string uri = doc["buffers"][0]["uri"];
  CHECK(uri.rfind("data:application/octet-stream;base64,", 0) == 0);
  options.container = sdvi::GltfContainer::kBinary;
  auto binary = sdvi::EncodeGltf(image, options);
  REQUIRE(binary.ok());
  CHECK(doc["buffers"][0]["byteLength"] == ParseGlb(binary->bytes).bin.size());
}

TEST_CASE("gltf export is deterministic") {
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  GltfExportOptions options = Levels(2);
  options.control_mesh = true;
  for (bool draco : {false, true}) {
    options.draco = draco;
    auto a = sdvi::EncodeGltf(image, options);
    auto b = sdvi::EncodeGltf(image, options);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a->bytes == b->bytes);
  }
}

TEST_CASE("gltf bad inputs and options fail with specific codes") {
  CHECK(sdvi::EncodeGltf(Image{}, {}).status().code() == StatusCode::kEmptyInput);
  const Image image = sdvi::gltf_test::GradientWithCrease(64, 48);
  CHECK(sdvi::EncodeGltf(image, Levels(-2)).status().code() == StatusCode::kInvalidArgument);
  CHECK(sdvi::EncodeGltf(image, Levels(sdvi::kMaxGltfLevels + 1)).status().code() ==
        StatusCode::kInvalidArgument);
  // 1024 control triangles at level 8 would be 67M fine triangles, over the 2^25 budget.
  const Image big = sdvi::gltf_test::GradientWithCrease(4096, 4096, 16, 16);
  CHECK(sdvi::EncodeGltf(big, Levels(8)).status().code() == StatusCode::kLimitExceeded);
  GltfExportOptions speed = Levels(1);
  speed.draco = true;
  speed.draco_speed = 11;
  CHECK(sdvi::EncodeGltf(image, speed).status().code() == StatusCode::kInvalidArgument);
  Image nan = image;
  nan.vertices[3].g = std::nanf("");
  CHECK(sdvi::EncodeGltf(nan, Levels(1)).status().code() == StatusCode::kNonFinite);
  nan.vertices[3].g = 0;
  nan.vertices[5].x = INFINITY;
  CHECK(sdvi::EncodeGltf(nan, Levels(1)).status().code() == StatusCode::kNonFinite);
  // Topology the engine refuses (an index out of range) keeps the engine's code.
  Image broken = image;
  broken.triangles[0].v[1] = 100000;
  for (int levels : {1, -1}) {  // -1: the default level is computed before the engine checks
    auto status = sdvi::EncodeGltf(broken, Levels(levels)).status();
    CHECK_FALSE(status.ok());
    CHECK(status.code() == StatusCode::kIndexOutOfRange);
  }
  CHECK(sdvi::GltfContainerForPath("a.GLB").ok());
  CHECK(sdvi::GltfContainerForPath("a.png").status().code() == StatusCode::kInvalidArgument);
}

TEST_CASE("gltf WriteGltf writes atomically and leaves nothing behind on failure") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sdvi_gltf_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Image image = sdvi::gltf_test::GradientWithCrease(32, 24, 2, 1);
  const std::string glb = (dir / "out.glb").string();
  auto written = sdvi::WriteGltf(glb, image, Levels(1));
  REQUIRE(written.ok());
  auto bytes = sdvi::ReadFileBytes(glb);
  REQUIRE(bytes.ok());
  CHECK(*bytes == written->bytes);
  // The extension decides the container.
  auto text = sdvi::WriteGltf((dir / "out.gltf").string(), image, Levels(1));
  REQUIRE(text.ok());
  CHECK(text->bytes.front() == '{');
  // Failures: wrong extension, missing directory, bad image: no file appears.
  CHECK(sdvi::WriteGltf((dir / "out.png").string(), image, Levels(1)).status().code() ==
        StatusCode::kInvalidArgument);
  CHECK_FALSE(sdvi::WriteGltf((dir / "missing" / "x.glb").string(), image, Levels(1)).ok());
  CHECK(sdvi::WriteGltf((dir / "empty.glb").string(), Image{}, Levels(1)).status().code() ==
        StatusCode::kEmptyInput);
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  CHECK(files == 3);  // out.glb, out.gltf and the out.bin beside it
  fs::remove_all(dir);
}

TEST_CASE("gltf text file gets its buffer in a .bin beside it, or embedded with embed") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sdvi_gltf_bin_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Image image = sdvi::gltf_test::GradientWithCrease(32, 24, 2, 1);
  auto glb = sdvi::EncodeGltf(image, Levels(1));
  REQUIRE(glb.ok());
  const std::vector<uint8_t> bin_chunk = ParseGlb(glb->bytes).bin;
  const std::string gltf = (dir / "my scene.gltf").string();
  auto text = sdvi::WriteGltf(gltf, image, Levels(1));
  REQUIRE(text.ok());
  CHECK(sdvi::GltfBinPath(gltf) == (dir / "my scene.bin").string());
  const json doc = json::parse(text->bytes.begin(), text->bytes.end());
  CHECK(doc["buffers"].size() == 1);
  CHECK(doc["buffers"][0]["uri"] == "my%20scene.bin");
  CHECK(doc["buffers"][0]["byteLength"] == bin_chunk.size());
  auto bin = sdvi::ReadFileBytes((dir / "my scene.bin").string());
  REQUIRE(bin.ok());
  CHECK(*bin == bin_chunk);  // the same bytes a .glb carries in its BIN chunk
  CHECK(text->bin == bin_chunk);
  // --embed: one file, the buffer as a data: URI.
  GltfExportOptions embed = Levels(1);
  embed.embed = true;
  const std::string single = (dir / "single.gltf").string();
  auto embedded = sdvi::WriteGltf(single, image, embed);
  REQUIRE(embedded.ok());
  CHECK(embedded->bin.empty());
  CHECK_FALSE(fs::exists(dir / "single.bin"));
  const json doc2 = json::parse(embedded->bytes.begin(), embedded->bytes.end());
  CHECK(std::string(doc2["buffers"][0]["uri"]).rfind("data:application/octet-stream;base64,", 0) == 0);
  // A failed write of the .gltf leaves no .bin behind either.
  CHECK_FALSE(sdvi::WriteGltf((dir / "missing" / "x.gltf").string(), image, Levels(1)).ok());
  CHECK_FALSE(fs::exists(dir / "missing"));
  fs::remove_all(dir);
}
