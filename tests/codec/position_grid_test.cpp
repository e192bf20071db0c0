// SPDX-License-Identifier: GPL-3.0-or-later
// SnapPositionsToGrid: positions on the codec's grid, folds mended locally (sdvi/codec.h,
// spec/RATE.md section 3).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "sdvi/codec.h"
#include "sliver_mesh.h"
#include "synthetic_mesh.h"

using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;

namespace {

// The positions a reader decodes from image at these bits, in image's vertex order.
std::vector<std::pair<float, float>> DecodedPositions(const Image& image, int bits) {
  CompressOptions options;
  options.position_bits = bits;
  options.keep_vertex_order = true;
  const auto file = sdvi::EncodeImage(image, &options);
  REQUIRE(file.ok());
  const auto decoded = sdvi::DecodeImage(*file, "ordered");
  REQUIRE(decoded.ok());
  std::vector<std::pair<float, float>> out;
  for (const sdvi::Vertex& v : decoded->vertices) out.push_back({v.x, v.y});
  return out;
}

std::vector<std::pair<float, float>> PositionsOf(const Image& image) {
  std::vector<std::pair<float, float>> out;
  for (const sdvi::Vertex& v : image.vertices) out.push_back({v.x, v.y});
  return out;
}

// Triangles of zero area or of the orientation opposite to the mesh's.
int Collapsed(const Image& image) {
  std::vector<double> areas;
  double total = 0;
  for (const sdvi::Triangle& t : image.triangles) {
    const sdvi::Vertex& a = image.vertices[t.v[0]];
    const sdvi::Vertex& b = image.vertices[t.v[1]];
    const sdvi::Vertex& c = image.vertices[t.v[2]];
    areas.push_back((double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x));
    total += areas.back();
  }
  int count = 0;
  for (double area : areas) count += !(area * total > 0);
  return count;
}

bool Folds(const Image& image, int bits) {
  CompressOptions options;
  options.position_bits = bits;
  const auto file = sdvi::EncodeImage(image, &options);
  if (file.ok()) return false;
  REQUIRE(file.status().code() == StatusCode::kFoldedTriangle);
  return true;
}

}  // namespace

TEST_CASE("SnapPositionsToGrid without folds puts every vertex where the reader decodes it", "[codec][grid]") {
  const Image image = sdvi::testing::SyntheticGridImage(64, 48, 9, 7);
  for (int bits : {12, 16}) {
    REQUIRE(!Folds(image, bits));
    int moved = -1;
    const auto snapped = sdvi::SnapPositionsToGrid(image, bits, &moved);
    REQUIRE(snapped.ok());
    CHECK(moved == 0);
    // Bit-exact: the grid is Draco's, in float as its decoder computes it.
    CHECK(PositionsOf(*snapped) == DecodedPositions(image, bits));
    // On the grid, encoding again keeps them exactly.
    CHECK(DecodedPositions(*snapped, bits) == PositionsOf(*snapped));
    // Colours and topology untouched.
    for (size_t i = 0; i < image.vertices.size(); ++i) CHECK(snapped->vertices[i].r == image.vertices[i].r);
    CHECK(snapped->triangles == image.triangles);
    CHECK(snapped->crease_edges == image.crease_edges);
  }
  CHECK(sdvi::SnapPositionsToGrid(image, 0).status().code() == StatusCode::kInvalidArgument);
  CHECK(sdvi::SnapPositionsToGrid(image, sdvi::kMaxQuantizationBits + 1).status().code() ==
        StatusCode::kInvalidArgument);
}

TEST_CASE("a sliver that folds at the chosen bits is mended by moving one vertex, not by more bits", "[codec][grid]") {
  constexpr int kBits = 8;  // step 64 / 255 px
  const float step = 64.f / 255.f;
  // A sliver whose edge ends round up and apex rounds down, so that plain rounding to the
  // 8-bit grid folds it.
  const std::optional<Image> sliver =
      sdvi::testing::FindFoldingSliver(step, [](const Image& candidate) { return Folds(candidate, kBits); });
  REQUIRE(sliver);
  REQUIRE(sdvi::ValidateImage(*sliver, "sliver").ok());
  // Plain rounding needs more bits for the whole mesh.
  int plain_bits = kBits;
  while (Folds(*sliver, plain_bits)) ++plain_bits;
  CHECK(plain_bits > kBits);

  int moved = -1;
  const auto mended = sdvi::SnapPositionsToGrid(*sliver, kBits, &moved);
  REQUIRE(mended.ok());
  CHECK(moved >= 1);
  CHECK(moved <= 2);
  // The mended mesh is valid and encodes at the chosen bits, positions kept exactly.
  CHECK(sdvi::ValidateImage(*mended, "mended").ok());
  CHECK(Collapsed(*mended) == 0);
  REQUIRE(!Folds(*mended, kBits));
  CHECK(DecodedPositions(*mended, kBits) == PositionsOf(*mended));
  // Every vertex is within kMendRadius + 1/2 steps of where it was, and all but the moved
  // ones are at their nearest grid point (where the reader of a plain file gets them).
  int off_nearest = 0;
  for (size_t i = 0; i < sliver->vertices.size(); ++i) {
    const auto& a = sliver->vertices[i];
    const auto& b = mended->vertices[i];
    CHECK(std::abs(a.x - b.x) <= (sdvi::kMendRadius + 0.5f) * step + 1e-4f);
    CHECK(std::abs(a.y - b.y) <= (sdvi::kMendRadius + 0.5f) * step + 1e-4f);
    off_nearest += std::abs(a.x - b.x) > 0.5f * step + 1e-4f || std::abs(a.y - b.y) > 0.5f * step + 1e-4f;
  }
  CHECK(off_nearest <= moved);
  // The image corners (the grid's extremes) stay where they are.
  for (size_t i = 0; i < 4; ++i) {
    CHECK(mended->vertices[i].x == sliver->vertices[i].x);
    CHECK(mended->vertices[i].y == sliver->vertices[i].y);
  }
  // Deterministic.
  const auto again = sdvi::SnapPositionsToGrid(*sliver, kBits);
  REQUIRE(again.ok());
  CHECK(PositionsOf(*again) == PositionsOf(*mended));
}

TEST_CASE("a dense jittered grid is mended at bits where plain rounding folds it", "[codec][grid][slow]") {
  const Image image = sdvi::testing::SyntheticGridImage(64, 64, 65, 65);
  int mended_bits = 0, plain_free = 0;
  for (int bits = 4; bits <= 16 && plain_free == 0; ++bits) {
    if (!Folds(image, bits)) {
      plain_free = bits;
      break;
    }
    int moved = 0;
    const auto mended = sdvi::SnapPositionsToGrid(image, bits, &moved);
    if (!mended.ok()) {
      CHECK(mended.status().code() == StatusCode::kFoldedTriangle);
      CHECK(mended.status().message().find("remain on the") != std::string::npos);
      continue;
    }
    CHECK(moved > 0);
    CHECK(!Folds(*mended, bits));
    CHECK(Collapsed(*mended) == 0);
    CHECK(DecodedPositions(*mended, bits) == PositionsOf(*mended));
    if (mended_bits == 0) mended_bits = bits;
  }
  INFO("lowest mended bits " << mended_bits << ", lowest fold-free plain bits " << plain_free);
  REQUIRE(plain_free > 0);
  CHECK(mended_bits > 0);
  CHECK(mended_bits < plain_free);
}
