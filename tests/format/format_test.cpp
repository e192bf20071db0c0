// SPDX-License-Identifier: GPL-3.0-or-later
// The .sdvi container: round trips, canonical form, size bound, every reader error.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"
#include "test_util.h"

namespace sdvi {
namespace {

using test::BitEqual;
using test::FixCrc;
using test::Grid;
using test::Poke;

// A mesh with an open pair of feature polylines, a closed polyline, interior corners and
// all four tag groups (the same shape as the golden file, made in code).
Image FeatureMesh() {
  Image image = Grid(6);  // 49 vertices, 72 triangles; boundary crease
  auto id = [](uint32_t x, uint32_t y) { return y * 7 + x; };
  FeaturePolyline open1{{id(1, 1), id(2, 1), id(3, 1), id(4, 1)}, false};
  FeaturePolyline open2{{id(1, 2), id(2, 2), id(3, 2), id(4, 2)}, false};
  FeaturePolyline ring{{id(4, 4), id(5, 4), id(6, 4), id(6, 5), id(6, 6), id(5, 6), id(4, 6),
                        id(4, 5)},
                       true};
  for (const auto* p : {&open1, &open2})
    for (size_t i = 0; i + 1 < p->vertices.size(); ++i)
      image.crease_edges.push_back(Edge::Of(p->vertices[i], p->vertices[i + 1]));
  for (size_t i = 0; i < ring.vertices.size(); ++i)
    image.crease_edges.push_back(
        Edge::Of(ring.vertices[i], ring.vertices[(i + 1) % ring.vertices.size()]));
  image.crease_edges.push_back(Edge::Of(id(5, 0), id(6, 1)));  // makes a 3-tagged triangle
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                           image.crease_edges.end());
  image.corners = {id(0, 0), id(6, 0), id(2, 2), id(5, 4)};  // ascending
  image.polylines = {open1, open2, ring};
  image.pairs = {{0, 1, 0.6f}};
  image.metadata = {{"source", "format_test"}, {"fit.levels", "2"}};
  image.vertices[10].r = std::nextafter(1.f, 2.f);
  image.vertices[11].g = std::numeric_limits<float>::denorm_min();
  image.vertices[12].b = -0.f;
  return image;
}

std::vector<uint8_t> Encode(const Image& image) {
  auto bytes = EncodeSdvi(image);
  REQUIRE(bytes.ok());
  return *bytes;
}

StatusCode DecodeCode(const std::vector<uint8_t>& bytes, const ReadOptions& options = {}) {
  return DecodeSdvi(bytes, "test.sdvi", options).status().code();
}

std::vector<uint8_t> ReadData(const std::string& name) {
  auto bytes = ReadFileBytes(std::string(SDVI_TEST_DATA_DIR) + "/" + name);
  REQUIRE(bytes.ok());
  return *bytes;
}

TEST_CASE("raw round trip keeps every vertex bit, tag, corner, polyline, pair and metadata") {
  const Image image = FeatureMesh();
  auto file = DecodeSdvi(Encode(image), "mem");
  REQUIRE(file.ok());
  CHECK(file->version_major == 1);
  CHECK(file->version_minor == 0);
  CHECK(file->payload == PayloadKind::kRaw);
  CHECK(BitEqual(file->image.vertices, image.vertices));
  CHECK(file->image.crease_edges == image.crease_edges);
  CHECK(file->image.corners == image.corners);
  CHECK(file->image.polylines == image.polylines);
  CHECK(file->image.pairs == image.pairs);
  CHECK(file->image.metadata == image.metadata);
  CHECK(file->image == CanonicalizeImage(image));
}

TEST_CASE("decoding then encoding gives identical bytes") {
  const std::vector<uint8_t> bytes = Encode(FeatureMesh());
  auto file = DecodeSdvi(bytes, "mem");
  REQUIRE(file.ok());
  CHECK(Encode(file->image) == bytes);
}

TEST_CASE("writer orders triangles 3-, 2-, 1-tagged, untagged and rotates tagged edges first") {
  // A fan of four triangles around vertex 4 inside a square; creases chosen so that
  // each group gets one triangle.
  Image image;
  image.width = image.height = 10;
  image.vertices = {{0, 0, 0, 0, 0}, {10, 0, 0, 0, 0}, {10, 10, 0, 0, 0}, {0, 10, 0, 0, 0},
                    {5, 5, 0, 0, 0}};
  image.triangles = {{{4, 0, 1}}, {{4, 1, 2}}, {{4, 2, 3}}, {{4, 3, 0}}};
  // (0,1) only: 1 tag in the first triangle; (1,2),(2,4): 2 tags in the second ...
  image.crease_edges = {Edge::Of(0, 1), Edge::Of(1, 2), Edge::Of(2, 4), Edge::Of(2, 3),
                        Edge::Of(3, 4)};
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  auto file = DecodeSdvi(Encode(image), "mem");
  REQUIRE(file.ok());
  CHECK(file->tagged3 == 1);  // (4,2,3): edges 4-2, 2-3, 3-4
  CHECK(file->tagged2 == 1);  // (4,1,2): 1-2, 2-4 tagged -> rotated to (1,2,4)
  CHECK(file->tagged1 == 2);  // (4,0,1): 0-1 -> (0,1,4); (4,3,0): 4-3 -> (4,3,0)
  const auto& t = file->image.triangles;
  REQUIRE(t.size() == 4);
  CHECK(t[0] == Triangle{{4, 2, 3}});
  CHECK(t[1] == Triangle{{1, 2, 4}});
  CHECK(t[2] == Triangle{{0, 1, 4}});
  CHECK(t[3] == Triangle{{4, 3, 0}});
  CHECK(file->image.crease_edges == image.crease_edges);
}

TEST_CASE("an edge is crease when any triangle tags it") {
  // Two triangles share edge (1,2); a foreign writer tags it in only one of them.
  flatbuffers::FlatBufferBuilder fbb;
  std::vector<fb::Vertex> v = {{0, 0, 1, 2, 3}, {1, 0, 1, 2, 3}, {0, 1, 1, 2, 3}, {1, 1, 1, 2, 3}};
  auto vertices = fbb.CreateVectorOfStructs(v);
  std::vector<fb::Triangle16> t = {{1, 2, 0}, {1, 3, 2}};  // first: 1-tagged, edge (1,2)
  auto triangles = fbb.CreateVectorOfStructs(t);
  fb::Header header(1, 0, 1, 1, 0, 0, 1, 0);
  fbb.Finish(fb::CreateImage(fbb, &header, vertices, triangles), "SDVI");
  std::vector<uint8_t> bytes(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
  FixCrc(bytes);
  auto file = DecodeSdvi(bytes, "foreign.sdvi");
  REQUIRE(file.ok());
  CHECK(file->image.crease_edges == std::vector<Edge>{Edge::Of(1, 2)});
}

TEST_CASE("raw narrow file is 20V + 6T + 68 bytes (+2 for odd T), within the paper size + 64") {
  for (uint32_t n : {1u, 2u, 7u, 30u, 100u, 180u}) {
    Image image = Grid(n);
    if (n == 7) {  // an odd triangle count: drop a corner triangle and its lone creases
      image.triangles.pop_back();
      std::erase_if(image.crease_edges, [&](const Edge& e) {
        return std::none_of(image.triangles.begin(), image.triangles.end(), [&](const Triangle& t) {
          for (int k = 0; k < 3; ++k)
            if (Edge::Of(t.v[k], t.v[(k + 1) % 3]) == e) return true;
          return false;
        });
      });
    }
    const uint64_t V = image.vertices.size(), T = image.triangles.size();
    REQUIRE(V <= kNarrowProfileMaxVertices);
    const std::vector<uint8_t> bytes = Encode(image);
    INFO("V = " << V << ", T = " << T);
    CHECK(bytes.size() == 20 * V + 6 * T + 68 + (T % 2 ? 2 : 0));
    CHECK(bytes.size() <= PaperSizeBytes(V, T) + 64);
  }
}

TEST_CASE("meshes over 65535 vertices use the wide profile and round-trip") {
  const Image image = Grid(256);  // 66049 vertices
  const std::vector<uint8_t> bytes = Encode(image);
  CHECK(bytes.size() == 20 * image.vertices.size() + 12 * image.triangles.size() + 68);
  const fb::Image* root = fb::GetImage(bytes.data());
  CHECK(root->triangles() == nullptr);
  REQUIRE(root->triangles_wide() != nullptr);
  auto file = DecodeSdvi(bytes, "wide");
  REQUIRE(file.ok());
  CHECK(file->image == CanonicalizeImage(image));
}

TEST_CASE("truncated files give kTruncated, an empty file kEmptyInput") {
  const std::vector<uint8_t> bytes = Encode(FeatureMesh());
  CHECK(DecodeCode({}) == StatusCode::kEmptyInput);
  for (size_t cut : {size_t{7}, size_t{30}, size_t{47}, bytes.size() / 2, bytes.size() - 100,
                     bytes.size() - 1}) {
    std::vector<uint8_t> part(bytes.begin(), bytes.begin() + cut);
    INFO("cut at " << cut << " of " << bytes.size());
    auto r = DecodeSdvi(part, "cut.sdvi");
    REQUIRE_FALSE(r.ok());
    CHECK(r.status().code() == StatusCode::kTruncated);
    CHECK(r.status().message().find("cut.sdvi") == 0);
  }
  // A real-sized file cut anywhere past its header is kTruncated, wherever the cut falls.
  const std::vector<uint8_t> big = Encode(FeatureMesh());
  for (size_t cut = 100; cut < big.size(); cut += 97) {
    std::vector<uint8_t> part(big.begin(), big.begin() + cut);
    INFO("cut at " << cut << " of " << big.size());
    CHECK(DecodeSdvi(part, "cut.sdvi").status().code() == StatusCode::kTruncated);
  }
  for (size_t cut = 1; cut < bytes.size(); ++cut) {  // no prefix is ever accepted
    std::vector<uint8_t> part(bytes.begin(), bytes.begin() + cut);
    REQUIRE_FALSE(DecodeSdvi(part, "cut.sdvi").ok());
  }
}

TEST_CASE("every flipped byte is refused, in the vertex data as kCorrupt") {
  const std::vector<uint8_t> bytes = Encode(FeatureMesh());
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::vector<uint8_t> damaged = bytes;
    damaged[i] ^= 0x5A;
    auto r = DecodeSdvi(damaged, "flip.sdvi");
    INFO("byte " << i);
    REQUIRE_FALSE(r.ok());
  }
  std::vector<uint8_t> damaged = bytes;
  damaged[test::VertexDataOffset(bytes) + 7] ^= 0x01;  // one mantissa bit of vertex 0
  auto r = DecodeSdvi(damaged, "flip.sdvi");
  CHECK(r.status().code() == StatusCode::kCorrupt);
  CHECK(r.status().message().find("checksum") != std::string::npos);
  // Unverified (what the fuzz targets read with), the same bytes decode, to the flipped value.
  ReadOptions unverified;
  unverified.verify_checksums = false;
  auto read = DecodeSdvi(damaged, "flip.sdvi", unverified);
  REQUIRE(read.ok());
  auto intact = DecodeSdvi(bytes, "intact.sdvi");
  REQUIRE(intact.ok());
  CHECK(read->image.vertices != intact->image.vertices);
  CHECK(read->image.triangles == intact->image.triangles);
}

TEST_CASE("a wrong identifier gives kWrongIdentifier") {
  std::vector<uint8_t> bytes = Encode(Grid(2));
  bytes[5] = 'X';
  auto r = DecodeSdvi(bytes, "x.sdvi");
  CHECK(r.status().code() == StatusCode::kWrongIdentifier);
  CHECK(r.status().message().find("'SXVI'") != std::string::npos);
  const std::string json = "{\"width\": 4, \"height\": 4}";
  CHECK(DecodeCode(std::vector<uint8_t>(json.begin(), json.end())) == StatusCode::kWrongIdentifier);
  const std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13};
  CHECK(DecodeCode(png) == StatusCode::kWrongIdentifier);
}

TEST_CASE("a major version from the future gives kUnsupportedVersion naming both versions") {
  std::vector<uint8_t> bytes = Encode(Grid(2));
  const size_t header = test::HeaderOffset(bytes);
  Poke<uint16_t>(bytes, header, 2);
  Poke<uint16_t>(bytes, header + 2, 3);
  FixCrc(bytes);
  auto r = DecodeSdvi(bytes, "future.sdvi");
  REQUIRE(r.status().code() == StatusCode::kUnsupportedVersion);
  CHECK(r.status().message().find("version 2.3") != std::string::npos);
  CHECK(r.status().message().find("reads version 1.x") != std::string::npos);
  Poke<uint16_t>(bytes, header, 0);  // major 0 was never released
  CHECK(DecodeCode(bytes) == StatusCode::kUnsupportedVersion);
}

TEST_CASE("a newer minor version with unknown fields reads fine") {
  // Version 1.7 with a field id 12 this build does not know, written by hand.
  const Image image = Grid(3);
  flatbuffers::FlatBufferBuilder fbb;
  auto unknown = fbb.CreateString("a field from the future");
  auto vertices = fbb.CreateVectorOfStructs(
      reinterpret_cast<const fb::Vertex*>(image.vertices.data()), image.vertices.size());
  auto canon = CanonicalizeImage(image);
  std::vector<fb::Triangle16> t;
  for (const Triangle& tri : canon.triangles)
    t.emplace_back(uint16_t(tri.v[0]), uint16_t(tri.v[1]), uint16_t(tri.v[2]));
  auto triangles = fbb.CreateVectorOfStructs(t);
  auto reference = DecodeSdvi(Encode(image), "ref");
  REQUIRE(reference.ok());
  fb::Header header(1, 7, image.width, image.height, reference->tagged3, reference->tagged2,
                    reference->tagged1, 0);
  const auto start = fbb.StartTable();
  fbb.AddOffset(4 + 2 * 12, unknown);
  fbb.AddOffset(fb::Image::VT_TRIANGLES, triangles);
  fbb.AddOffset(fb::Image::VT_VERTICES, vertices);
  fbb.AddStruct(fb::Image::VT_HEADER, &header);
  fbb.Finish(flatbuffers::Offset<fb::Image>(fbb.EndTable(start)), "SDVI");
  std::vector<uint8_t> bytes(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
  FixCrc(bytes);
  auto file = DecodeSdvi(bytes, "newer.sdvi");
  REQUIRE(file.ok());
  CHECK(file->version_minor == 7);
  CHECK(file->image == reference->image);
}

TEST_CASE("triangle indices out of range give kIndexOutOfRange") {
  std::vector<uint8_t> bytes = Encode(Grid(2));  // 9 vertices
  Poke<uint16_t>(bytes, test::TriangleDataOffset(bytes) + 2, 9);
  FixCrc(bytes);
  auto r = DecodeSdvi(bytes, "idx.sdvi");
  CHECK(r.status().code() == StatusCode::kIndexOutOfRange);
  CHECK(r.status().message().find("vertex 9") != std::string::npos);
}

TEST_CASE("NaN or infinite coordinates give kNonFinite") {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::vector<uint8_t> bytes = Encode(Grid(2));
    Poke<float>(bytes, test::VertexDataOffset(bytes) + 20 * 3 + 4, bad);  // vertex 3, y
    FixCrc(bytes);
    auto r = DecodeSdvi(bytes, "nan.sdvi");
    CHECK(r.status().code() == StatusCode::kNonFinite);
    CHECK(r.status().message().find("vertex 3") != std::string::npos);
  }
  Image image = Grid(2);
  image.vertices[4].g = std::numeric_limits<float>::quiet_NaN();
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kNonFinite);
}

TEST_CASE("tagged counts beyond the triangle count give kCountMismatch") {
  std::vector<uint8_t> bytes = Encode(Grid(2));  // 8 triangles
  Poke<uint32_t>(bytes, test::HeaderOffset(bytes) + 12, 5);  // tagged3
  Poke<uint32_t>(bytes, test::HeaderOffset(bytes) + 16, 4);  // tagged2
  FixCrc(bytes);
  CHECK(DecodeCode(bytes) == StatusCode::kCountMismatch);
}

TEST_CASE("sizes beyond ReadOptions give kLimitExceeded") {
  const std::vector<uint8_t> bytes = Encode(Grid(4));
  ReadOptions small;
  small.max_vertices = 10;
  CHECK(DecodeCode(bytes, small) == StatusCode::kLimitExceeded);
  small = {};
  small.max_triangles = 10;
  CHECK(DecodeCode(bytes, small) == StatusCode::kLimitExceeded);
  small = {};
  small.max_width = 8;
  CHECK(DecodeCode(bytes, small) == StatusCode::kLimitExceeded);
  small = {};
  small.max_file_bytes = 100;
  CHECK(DecodeCode(bytes, small) == StatusCode::kLimitExceeded);
}

TEST_CASE("structural damage behind a valid checksum gives kCorrupt") {
  std::vector<uint8_t> bytes = Encode(Grid(2));
  // Point the triangle list's offset at an odd, misaligned place inside the file.
  const size_t header = test::HeaderOffset(bytes);
  Poke<uint32_t>(bytes, header + 28 + 4, 3);
  FixCrc(bytes);
  CHECK(DecodeCode(bytes) == StatusCode::kCorrupt);
  // A root offset pointing nowhere.
  bytes = Encode(Grid(2));
  Poke<uint32_t>(bytes, 0, 0x7fffff00);
  CHECK(DecodeCode(bytes) == StatusCode::kCorrupt);
}

TEST_CASE("corner lists out of order or out of range are refused") {
  Image image = FeatureMesh();
  std::vector<uint8_t> bytes = Encode(image);
  const fb::Image* root = fb::GetImage(bytes.data());
  const size_t corners = reinterpret_cast<const uint8_t*>(root->corners()->Data()) - bytes.data();
  std::vector<uint8_t> swapped = bytes;
  Poke<uint32_t>(swapped, corners, image.corners[1]);
  Poke<uint32_t>(swapped, corners + 4, image.corners[0]);
  FixCrc(swapped);
  CHECK(DecodeCode(swapped) == StatusCode::kCorrupt);
  Poke<uint32_t>(bytes, corners + 4 * (image.corners.size() - 1), 1000);
  FixCrc(bytes);
  CHECK(DecodeCode(bytes) == StatusCode::kIndexOutOfRange);
}

TEST_CASE("the writer refuses invalid images with specific codes") {
  Image image = Grid(2);
  image.crease_edges.push_back(Edge::Of(0, 8));  // a diagonal no triangle has
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kCreaseNotAnEdge);
  image = Grid(2);
  image.triangles[0].v[1] = image.triangles[0].v[0];
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kDegenerateTriangle);
  image = Grid(2);
  image.triangles[3].v[2] = 99;
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kIndexOutOfRange);
  image = Grid(2);
  image.corners = {3, 42};
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kIndexOutOfRange);
  image = Grid(2);
  image.polylines = {{{0, 1}, false}};
  image.pairs = {{0, 1, 0.5f}};
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kIndexOutOfRange);
  image.polylines.push_back({{1, 2}, false});
  image.pairs[0].sharpness = 1.5f;
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kValueOutOfRange);
  image.pairs[0].sharpness = -1e-30f;  // once reported as "-0.000000"
  CHECK(EncodeSdvi(image).status().message().find("sharpness -1e-30") != std::string::npos);
  image = Grid(2);
  image.width = 0;
  CHECK(EncodeSdvi(image).status().code() == StatusCode::kEmptyInput);
}

TEST_CASE("WriteSdvi is atomic: a failed write leaves nothing and keeps the old file") {
  const auto dir = std::filesystem::temp_directory_path() / "sdvi_format_test_atomic";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "out.sdvi").string();
  REQUIRE(WriteSdvi(path, Grid(2)).ok());
  const auto before = ReadFileBytes(path);
  REQUIRE(before.ok());
  Image bad = Grid(3);
  bad.vertices[0].x = std::numeric_limits<float>::infinity();
  const Status s = WriteSdvi(path, bad);
  CHECK(s.code() == StatusCode::kNonFinite);
  CHECK(s.message().find(path) == 0);
  CHECK(*ReadFileBytes(path) == *before);
  CHECK(std::distance(std::filesystem::directory_iterator(dir), {}) == 1);
  CHECK_FALSE(WriteSdvi((dir / "missing" / "x.sdvi").string(), Grid(2)).ok());
  CHECK(std::distance(std::filesystem::directory_iterator(dir), {}) == 1);
  auto read = ReadSdviFile(path);
  REQUIRE(read.ok());
  CHECK(read->file_bytes == before->size());
  std::filesystem::remove_all(dir);
}

TEST_CASE("ReadSdviFile reports a missing file with kNotFound") {
  CHECK(ReadSdviFile("/nonexistent/dir/none.sdvi").status().code() == StatusCode::kNotFound);
}

TEST_CASE("a compressed container keeps the payload and the non-mesh parts") {
  Image shell;
  shell.width = 640;
  shell.height = 480;
  shell.polylines = {{{0, 5, 9}, false}, {{1, 6, 10}, false}};
  shell.pairs = {{0, 1, 0.25f}};
  shell.metadata = {{"codec", "draco"}};
  PayloadSummary summary;
  summary.codec_version_major = 1;
  summary.codec_version_minor = 5;
  summary.vertex_count = 1234;
  summary.triangle_count = 2400;
  summary.params = {{"position_bits", "14"}, {"color_bits", "10"}};
  const std::vector<uint8_t> payload = {'D', 'R', 'A', 'C', 'O', 1, 2, 3, 4, 5, 6};
  auto bytes = EncodeSdviCompressed(shell, payload, summary);
  REQUIRE(bytes.ok());
  auto file = DecodeSdvi(*bytes, "draco.sdvi");
  REQUIRE(file.ok());
  CHECK(file->payload == PayloadKind::kDraco);
  CHECK(file->compressed_payload == payload);
  CHECK(file->payload_summary == summary);
  CHECK(file->image == shell);
  auto again = EncodeSdviCompressed(file->image, file->compressed_payload, file->payload_summary);
  REQUIRE(again.ok());
  CHECK(*again == *bytes);
  // Truncating the payload is kTruncated, flipping a payload byte kCorrupt.
  std::vector<uint8_t> cut(bytes->begin(), bytes->end() - 3);
  CHECK(DecodeCode(cut) == StatusCode::kTruncated);
  std::vector<uint8_t> flipped = *bytes;
  flipped[flipped.size() - 2] ^= 0x10;
  CHECK(DecodeCode(flipped) == StatusCode::kCorrupt);
  // The container refuses a mesh next to a payload, and an empty payload.
  Image with_mesh = shell;
  with_mesh.vertices.push_back({});
  CHECK(EncodeSdviCompressed(with_mesh, payload).status().code() == StatusCode::kInvalidArgument);
  CHECK(EncodeSdviCompressed(shell, {}).status().code() == StatusCode::kEmptyInput);
}

TEST_CASE("unaligned input decodes the same as aligned input") {
  const std::vector<uint8_t> bytes = Encode(FeatureMesh());
  std::vector<uint8_t> shifted(bytes.size() + 1);
  std::memcpy(shifted.data() + 1, bytes.data(), bytes.size());
  auto a = DecodeSdvi(bytes, "a");
  auto b = DecodeSdvi(std::span<const uint8_t>(shifted).subspan(1), "b");
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a->image == b->image);
}

TEST_CASE("golden v1.0 file reads (kept forever)") {
  auto file = DecodeSdvi(ReadData("golden_v1_0.sdvi"), "golden_v1_0.sdvi");
  REQUIRE(file.ok());
  CHECK(file->version_major == 1);
  CHECK(file->version_minor == 0);
  const Image& image = file->image;
  CHECK(image.width == 24);
  CHECK(image.height == 24);
  CHECK(image.vertices.size() == 49);
  CHECK(image.triangles.size() == 72);
  CHECK(file->tagged3 == 1);
  CHECK(file->tagged2 == 3);
  CHECK(file->tagged1 == 37);
  CHECK(image.crease_edges.size() == 35);
  CHECK(image.corners == std::vector<uint32_t>{0, 6, 16, 33, 42, 48});
  REQUIRE(image.polylines.size() == 3);
  CHECK(image.polylines[2].closed);
  CHECK_FALSE(image.polylines[0].closed);
  REQUIRE(image.pairs.size() == 1);
  CHECK(image.pairs[0].sharpness == 0.6f);
  CHECK(image.vertices[24].r == 0.1f);
  CHECK(image.vertices[24].g == 1e-30f);
  CHECK(image.metadata.size() == 2);
  // The golden mesh JSON describes the same image.
  const std::vector<uint8_t> json = ReadData("golden_v1_0.json");
  auto from_json = ParseMeshJson(std::string_view(reinterpret_cast<const char*>(json.data()),
                                                  json.size()), "golden_v1_0.json");
  REQUIRE(from_json.ok());
  CHECK(*from_json == image);
}

TEST_CASE("the 1.0 writer reproduces the golden file byte for byte") {
  auto file = DecodeSdvi(ReadData("golden_v1_0.sdvi"), "golden_v1_0.sdvi");
  REQUIRE(file.ok());
  CHECK(Encode(file->image) == ReadData("golden_v1_0.sdvi"));
}

TEST_CASE("CRC-32 matches the standard check value") {
  const std::string check = "123456789";
  CHECK(Crc32(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(check.data()),
                                       check.size())) == 0xCBF43926u);
}

}  // namespace
}  // namespace sdvi
