// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "synthetic_mesh.h"

using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;

namespace {

std::string TempPath(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "sdvi_codec_tests";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

Image MustRead(const std::string& path) {
  auto image = sdvi::ReadImage(path);
  INFO(image.status().ToString());
  REQUIRE(image.ok());
  return std::move(image).value();
}

}  // namespace

TEST_CASE("a compressed file reads back with the same topology, tags and feature layer",
          "[codec][io]") {
  Image image = sdvi::testing::SyntheticGridImage(320, 240, 30, 22, 13, /*shuffle=*/true);
  image.pairs.push_back({0, 0, 0.75f});
  const std::string raw_path = TempPath("grid_raw.sdvi"), draco_path = TempPath("grid_draco.sdvi");
  REQUIRE(sdvi::WriteImage(raw_path, image, nullptr).ok());
  const CompressOptions options;
  REQUIRE(sdvi::WriteImage(draco_path, image, &options).ok());
  const Image raw = MustRead(raw_path);
  const Image draco = MustRead(draco_path);
  CHECK(std::filesystem::file_size(draco_path) * 4 < std::filesystem::file_size(raw_path));

  CHECK(draco.width == raw.width);
  CHECK(draco.height == raw.height);
  CHECK(draco.metadata == raw.metadata);
  CHECK(draco.pairs == raw.pairs);
  REQUIRE(draco.vertices.size() == raw.vertices.size());
  CHECK(draco.triangles.size() == raw.triangles.size());
  CHECK(draco.crease_edges.size() == raw.crease_edges.size());
  CHECK(draco.corners.size() == raw.corners.size());
  // Same vertices along the feature polyline, up to quantization.
  const auto bound = sdvi::CompressionErrorBound(image, sdvi::DefaultPositionBits(image),
                                                 sdvi::DefaultColorBits(image));
  REQUIRE(draco.polylines.size() == 1);
  const auto& a = raw.polylines[0].vertices;
  const auto& b = draco.polylines[0].vertices;
  REQUIRE(a.size() == b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    CHECK(std::abs(raw.vertices[a[k]].x - draco.vertices[b[k]].x) <= bound.position);
    CHECK(std::abs(raw.vertices[a[k]].r - draco.vertices[b[k]].r) <= bound.color);
  }
  // Corners and crease edges map onto each other through the position match.
  for (size_t k = 0; k + 1 < b.size(); ++k)
    CHECK(std::binary_search(draco.crease_edges.begin(), draco.crease_edges.end(),
                             sdvi::Edge::Of(b[k], b[k + 1])));
}

TEST_CASE("decompressing gives a raw file that reads back identical", "[codec][io]") {
  const Image image = sdvi::testing::SyntheticGridImage(200, 150, 18, 14, 17, true);
  CompressOptions options;
  options.position_bits = 12;
  auto compressed = sdvi::EncodeImage(image, &options);
  REQUIRE(compressed.ok());
  auto from_draco = sdvi::DecodeImage(*compressed, "mem.sdvi");
  REQUIRE(from_draco.ok());
  auto raw = sdvi::EncodeImage(*from_draco, nullptr);
  REQUIRE(raw.ok());
  auto from_raw = sdvi::DecodeImage(*raw, "mem_raw.sdvi");
  REQUIRE(from_raw.ok());
  CHECK(*from_raw == *from_draco);
  // Compressing the decompressed image again gives the same image (quantization is
  // idempotent on its own grid).
  auto again = sdvi::EncodeImage(*from_draco, &options);
  REQUIRE(again.ok());
  auto from_again = sdvi::DecodeImage(*again, "again.sdvi");
  REQUIRE(from_again.ok());
  CHECK(from_again->triangles.size() == from_draco->triangles.size());
  CHECK(from_again->crease_edges.size() == from_draco->crease_edges.size());
}

TEST_CASE("compressed files are deterministic and damaged ones are errors", "[codec][io]") {
  const Image image = sdvi::testing::SyntheticGridImage(128, 128, 12, 12, 23);
  const CompressOptions options;
  auto first = sdvi::EncodeImage(image, &options);
  auto second = sdvi::EncodeImage(image, &options);
  REQUIRE(first.ok());
  REQUIRE(second.ok());
  CHECK(*first == *second);
  std::vector<uint8_t> bad = *first;
  bad[bad.size() / 2] ^= 0x01;
  auto damaged = sdvi::DecodeImage(bad, "damaged.sdvi");
  REQUIRE_FALSE(damaged.ok());
  CHECK(damaged.status().code() == StatusCode::kCorrupt);
  CHECK(damaged.status().message().find("damaged.sdvi") != std::string::npos);
  bad = *first;
  bad.resize(bad.size() - 9);
  CHECK_FALSE(sdvi::DecodeImage(bad, "short.sdvi").ok());
}

TEST_CASE("invalid images are not written and leave no file", "[codec][io]") {
  Image image = sdvi::testing::SyntheticGridImage(64, 64, 6, 6);
  image.triangles[0].v[1] = image.triangles[0].v[0];
  const std::string path = TempPath("invalid.sdvi");
  std::filesystem::remove(path);
  const CompressOptions options;
  const sdvi::Status status = sdvi::WriteImage(path, image, &options);
  CHECK(status.code() == StatusCode::kDegenerateTriangle);
  CHECK_FALSE(std::filesystem::exists(path));
}

TEST_CASE("the compression report reads the payload header", "[codec][io]") {
  const Image image = sdvi::testing::SyntheticGridImage(256, 256, 30, 30, 29);
  const CompressOptions options;
  auto bytes = sdvi::EncodeImage(image, &options);
  REQUIRE(bytes.ok());
  auto file = sdvi::DecodeSdvi(*bytes, "r.sdvi");
  REQUIRE(file.ok());
  auto report = sdvi::ReportCompression(*file, "r.sdvi");
  REQUIRE(report.ok());
  CHECK(report->payload == sdvi::PayloadKind::kDraco);
  CHECK(report->vertex_count == 900);
  CHECK(report->file_bytes == bytes->size());
  CHECK(report->paper_bytes == sdvi::PaperSizeBytes(900, image.triangles.size()));
  CHECK(report->bits_per_pixel == Approx(8.0 * bytes->size() / (256.0 * 256.0)));
  CHECK(report->draco.position_bits == sdvi::DefaultPositionBits(image));
  CHECK_FALSE(report->draco.has_vertex_ids);
  CHECK(file->payload_summary.vertex_count == 900);
}

TEST_CASE("container params are optional: without them the file is smaller and decodes the same",
          "[codec][io]") {
  const Image image = sdvi::testing::SyntheticGridImage(64, 48, 8, 6, 3, /*shuffle=*/false);
  CompressOptions lean, v1;
  v1.container_params = true;
  auto a = sdvi::EncodeImage(image, &lean);
  auto b = sdvi::EncodeImage(image, &v1);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a->size() + 150 < b->size());
  auto da = sdvi::DecodeImage(*a, "lean");
  auto db = sdvi::DecodeImage(*b, "v1");
  REQUIRE(da.ok());
  REQUIRE(db.ok());
  CHECK(*da == *db);
  auto fa = sdvi::DecodeSdvi(*a, "lean");
  auto fb = sdvi::DecodeSdvi(*b, "v1");
  REQUIRE(fa.ok());
  REQUIRE(fb.ok());
  CHECK(fa->payload_summary.params.empty());
  CHECK(fb->payload_summary.params.size() == 5);
  CHECK(fa->payload_summary.vertex_count == fb->payload_summary.vertex_count);
}

TEST_CASE("the writer reads back what it writes: position bits that fold a triangle are refused, default bits rise",
          "[codec][io]") {
  // A dense jittered grid: coarse position grids move vertices across their neighbours' edges.
  const Image image = sdvi::testing::SyntheticGridImage(64, 64, 97, 97);
  int folded = 0, lowest_fold_free = 0;
  for (int bits = 4; bits <= 16; ++bits) {
    CompressOptions options;
    options.position_bits = bits;
    const auto file = sdvi::EncodeImage(image, &options);
    if (file.ok()) {
      CHECK(sdvi::DecodeImage(*file, "read back").ok());
      if (lowest_fold_free == 0) lowest_fold_free = bits;
    } else {
      INFO(file.status().ToString());
      CHECK(file.status().code() == StatusCode::kFoldedTriangle);
      CHECK(file.status().message().find("quantised to " + std::to_string(bits) + " bits") != std::string::npos);
      ++folded;
    }
  }
  CHECK(folded > 0);
  REQUIRE(lowest_fold_free > 0);
  // Default bits from a large reference MSE start coarse and rise until nothing folds.
  CompressOptions coarse;
  coarse.reference_mse = 1e6;
  const auto file = sdvi::EncodeImage(image, &coarse);
  REQUIRE(file.ok());
  CHECK(sdvi::DecodeImage(*file, "read back").ok());
  auto sdvi_file = sdvi::DecodeSdvi(*file, "read back");
  REQUIRE(sdvi_file.ok());
  const auto info = sdvi::InspectDracoPayload(sdvi_file->compressed_payload, "read back");
  REQUIRE(info.ok());
  CHECK(info->position_bits >= sdvi::DefaultPositionBits(image, coarse.reference_mse));
  INFO("default bits " << sdvi::DefaultPositionBits(image, coarse.reference_mse) << ", used "
                       << info->position_bits << ", lowest fold-free " << lowest_fold_free);
  CHECK(info->position_bits >= std::min(lowest_fold_free, 24));
}
