// SPDX-License-Identifier: GPL-3.0-or-later
#include "synthetic_mesh.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numeric>
#include <random>
#include <span>
#include <utility>

#include "grid_triangles.h"
#include "sdvi/codec.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"

namespace sdvi::testing {

Image SyntheticGridImage(uint32_t width, uint32_t height, uint32_t cols, uint32_t rows,
                         uint32_t seed, bool shuffle) {
  Image image;
  image.width = width;
  image.height = height;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  const float dx = float(width) / float(cols - 1), dy = float(height) / float(rows - 1);
  const uint32_t mid = rows / 2;
  auto id = [&](uint32_t i, uint32_t j) { return j * cols + i; };
  for (uint32_t j = 0; j < rows; ++j) {
    for (uint32_t i = 0; i < cols; ++i) {
      const bool interior = i > 0 && j > 0 && i + 1 < cols && j + 1 < rows;
      Vertex v;
      v.x = float(i) * dx + (interior ? jitter(rng) * dx : 0.f);
      v.y = float(j) * dy + (interior && j != mid ? jitter(rng) * dy : 0.f);
      const float u = float(i) / float(cols - 1), w = float(j) / float(rows - 1);
      v.r = 40 + 180 * u + (j > mid ? 30.f : 0.f);
      v.g = 200 - 150 * w + 10 * std::sin(7 * u);
      v.b = j <= mid ? 60.f + 20 * u : 220.f - 40 * w;
      image.vertices.push_back(v);
    }
  }
  testing::AppendGridTriangles(int(cols) - 1, int(rows) - 1,
                               [&](int i, int j) { return id(uint32_t(i), uint32_t(j)); },
                               &image.triangles);
  for (uint32_t i = 0; i + 1 < cols; ++i) {
    image.crease_edges.push_back(Edge::Of(id(i, 0), id(i + 1, 0)));
    image.crease_edges.push_back(Edge::Of(id(i, rows - 1), id(i + 1, rows - 1)));
    image.crease_edges.push_back(Edge::Of(id(i, mid), id(i + 1, mid)));
  }
  for (uint32_t j = 0; j + 1 < rows; ++j) {
    image.crease_edges.push_back(Edge::Of(id(0, j), id(0, j + 1)));
    image.crease_edges.push_back(Edge::Of(id(cols - 1, j), id(cols - 1, j + 1)));
  }
  image.corners = {id(0, 0), id(cols - 1, 0), id(0, rows - 1), id(cols - 1, rows - 1),
                   id(0, mid), id(cols - 1, mid)};
  FeaturePolyline line;
  for (uint32_t i = 0; i < cols; ++i) line.vertices.push_back(id(i, mid));
  image.polylines.push_back(line);
  image.metadata.push_back({"generator", "synthetic grid"});

  if (shuffle) {
    std::vector<uint32_t> perm(image.vertices.size());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Vertex> vertices(perm.size());
    for (size_t i = 0; i < perm.size(); ++i) vertices[perm[i]] = image.vertices[i];
    image.vertices = vertices;
    for (Triangle& t : image.triangles)
      for (uint32_t& v : t.v) v = perm[v];
    for (Edge& e : image.crease_edges) e = Edge::Of(perm[e.a], perm[e.b]);
    for (uint32_t& c : image.corners) c = perm[c];
    for (uint32_t& v : image.polylines[0].vertices) v = perm[v];
  }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                           image.crease_edges.end());
  std::sort(image.corners.begin(), image.corners.end());
  return image;
}

void FixPayloadChecksum(std::vector<uint8_t>* payload) {
  if (payload->size() < 40) return;
  const std::span<const uint8_t> bytes(*payload);
  const uint32_t crc = Crc32(bytes.subspan(40), Crc32(bytes.subspan(0, 36)));
  for (int i = 0; i < 4; ++i) (*payload)[36 + i] = static_cast<uint8_t>(crc >> (8 * i));
}

int DamagedPayloadErrors(const std::vector<uint8_t>& good, size_t draco_step, size_t stream_step, int* tried) {
  REQUIRE(good.size() >= 40);
  const uint32_t draco_size = uint32_t(good[28]) | uint32_t(good[29]) << 8 | uint32_t(good[30]) << 16 |
                              uint32_t(good[31]) << 24;
  int errors = 0;
  *tried = 0;
  for (size_t at = 40; at < good.size(); at += (at < 40 + size_t{draco_size} ? draco_step : stream_step)) {
    for (uint8_t flip : {uint8_t{0x5A}, uint8_t{0x01}, uint8_t{0x80}}) {
      std::vector<uint8_t> damaged = good;
      damaged[at] ^= flip;
      FixPayloadChecksum(&damaged);
      Image decoded;
      ++*tried;
      if (!DecodeDracoPayload(damaged, "damaged.sdvi", &decoded).ok()) ++errors;
    }
  }
  return errors;
}

void CheckRefused(const std::vector<uint8_t>& good, const std::vector<std::pair<size_t, uint8_t>>& byte_values,
                  const std::string& name) {
  for (const auto& [at, value] : byte_values) {
    REQUIRE(at < good.size());
    std::vector<uint8_t> bad = good;
    bad[at] = value;
    FixPayloadChecksum(&bad);
    Image out;
    const Status status = DecodeDracoPayload(bad, name, &out);
    INFO(at << " = " << int(value) << ": " << status.ToString());
    CHECK(status.code() == StatusCode::kCorrupt);
    CHECK(status.message().find(name) != std::string::npos);
  }
}

std::vector<uint8_t> MustEncode(const Image& image, const CompressOptions& options,
                                std::vector<uint32_t>* new_index) {
  auto payload = EncodeDracoPayload(image, options, new_index);
  INFO(payload.status().ToString());
  REQUIRE(payload.ok());
  return std::move(payload).value();
}

Image PhotoLikeGridImage(uint32_t seed, uint32_t cols) {
  Image image = SyntheticGridImage(256, 256, cols, cols, seed);
  std::mt19937 rng(seed);
  std::normal_distribution<float> detail(0.f, 18.f), tint(0.f, 6.f);
  for (auto& v : image.vertices) {
    const float y = 130 + 110 * std::sin(v.x / 40.f) * std::cos(v.y / 55.f) + detail(rng);
    v.r = y + 20 + tint(rng);
    v.g = y + tint(rng);
    v.b = y - 25 + tint(rng);
  }
  return image;
}

void CheckGoldenFile(const std::string& name) {
  INFO(name);
  const std::string dir = SDVI_TEST_DATA_DIR;
  auto read = ReadImage(dir + "/" + name + ".sdvi");
  INFO(read.status().ToString());
  REQUIRE(read.ok());
  std::ifstream json_file(dir + "/" + name + ".json", std::ios::binary);
  const std::string json((std::istreambuf_iterator<char>(json_file)), std::istreambuf_iterator<char>());
  auto expected = ParseMeshJson(json, name + ".json");
  REQUIRE(expected.ok());
  CHECK(expected->vertices == read->vertices);
  CHECK(expected->triangles == read->triangles);
  CHECK(expected->crease_edges == read->crease_edges);
  CHECK(expected->corners == read->corners);
  CHECK(expected->polylines == read->polylines);
  CHECK(expected->pairs == read->pairs);
}

bool SameBits(const Image& a, const Image& b) {
  return a.vertices.size() == b.vertices.size() &&
         std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vertex)) == 0 &&
         a.triangles == b.triangles && a.crease_edges == b.crease_edges && a.corners == b.corners &&
         a.polylines == b.polylines && a.pairs == b.pairs;
}

Image MustDecode(const std::vector<uint8_t>& payload) {
  Image image;
  const Status status = DecodeDracoPayload(payload, "test.sdvi", &image);
  INFO(status.ToString());
  REQUIRE(status.ok());
  return image;
}

Image MustReadBack(const Image& image, const CompressOptions& options) {
  auto file = EncodeImage(image, &options);
  INFO(file.status().ToString());
  REQUIRE(file.ok());
  auto read = DecodeImage(*file, "test.sdvi");
  INFO(read.status().ToString());
  REQUIRE(read.ok());
  return *std::move(read);
}

}  // namespace sdvi::testing
