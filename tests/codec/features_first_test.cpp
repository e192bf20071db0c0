// SPDX-License-Identifier: GPL-3.0-or-later
// Features first (payload 1.2, spec/FORMAT.md 8.5): the feature layer before the crease edges,
// its polylines along mesh edges ordered by the decoded positions. It decodes to exactly the
// tags written (whatever the polylines: escapes, revisits, empty, closed, segments that are
// not crease edges), the same bytes when coded again, in fewer bytes than the crease edges
// first where crease edges run along the polylines; damaged streams are errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "sdvi/codec.h"
#include "synthetic_mesh.h"
#include "tag_stream.h"

namespace ci = sdvi::codec_internal;
using sdvi::Edge;
using sdvi::FeaturePair;
using sdvi::FeaturePolyline;
using sdvi::Image;
using sdvi::StatusCode;

namespace {

constexpr uint32_t kCols = 24, kRows = 24;
uint32_t Id(uint32_t i, uint32_t j) { return j * kCols + i; }

// The synthetic grid with a vectorizer-like feature layer: pairs of polylines along two
// neighbouring rows (the second of each pair right after the first), a closed rectangle,
// and their segments as crease edges; then polylines that exercise every path of the
// coding: an escape (a step to a vertex that is no mesh neighbour), a polyline over vertices
// already used, an empty one, a one-vertex one, a pair whose second is shorter than its first
// and a segment that is no crease edge.
Image FeatureGrid() {
  Image image = sdvi::testing::SyntheticGridImage(300, 300, kCols, kRows, 5);
  auto row = [](uint32_t j, uint32_t from, uint32_t to) {
    FeaturePolyline line;
    for (uint32_t i = from; i <= to; ++i) line.vertices.push_back(Id(i, j));
    return line;
  };
  for (uint32_t j = 2; j + 1 < kRows / 2 - 1; j += 3) {
    const uint32_t first = uint32_t(image.polylines.size());
    image.polylines.push_back(row(j, 1 + j % 4, kCols - 2 - j % 3));
    image.polylines.push_back(row(j + 1, 1 + j % 4, kCols - 2 - j % 3));
    image.pairs.push_back({first, first + 1, j % 2 ? 0.5f : 0.875f});
  }
  FeaturePolyline rectangle;
  for (uint32_t i = 3; i <= 9; ++i) rectangle.vertices.push_back(Id(i, 15));
  for (uint32_t j = 16; j <= 19; ++j) rectangle.vertices.push_back(Id(9, j));
  for (uint32_t i = 8; i >= 3; --i) rectangle.vertices.push_back(Id(i, 19));
  for (uint32_t j = 18; j >= 16; --j) rectangle.vertices.push_back(Id(3, j));
  rectangle.closed = true;
  image.polylines.push_back(rectangle);
  for (const FeaturePolyline& line : image.polylines) {
    for (size_t k = 0; k + 1 < line.vertices.size(); ++k)
      image.crease_edges.push_back(Edge::Of(line.vertices[k], line.vertices[k + 1]));
    if (line.closed) image.crease_edges.push_back(Edge::Of(line.vertices.back(), line.vertices.front()));
  }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                           image.crease_edges.end());
  // The paths the vectorizer does not make (added after the crease edges: their segments are
  // not crease edges).
  image.polylines.push_back({{Id(14, 16), Id(15, 16), Id(20, 20), Id(19, 20)}, false});  // escape
  image.polylines.push_back({{Id(5, 2), Id(6, 2), Id(6, 3)}, false});                    // used vertices
  image.polylines.push_back({{}, false});
  image.polylines.push_back({{Id(12, 12)}, true});
  const uint32_t first = uint32_t(image.polylines.size());
  image.polylines.push_back(row(21, 2, 12));
  image.polylines.push_back(row(22, 2, 7));
  image.pairs.push_back({first, first + 1, 1.0f});
  image.pairs.push_back({first + 1, 0, 0.25f});  // second before first: no partner
  return image;
}

ci::Tags TagsOf(const Image& image, bool features_first) {
  ci::Tags tags;
  tags.crease_edges = image.crease_edges;
  tags.corners = image.corners;
  tags.has_feature_layer = true;
  tags.polylines = image.polylines;
  tags.pairs = image.pairs;
  tags.features_first = features_first;
  return tags;
}

ci::Tags Decode(const Image& image, const std::vector<uint8_t>& stream, bool features_first) {
  ci::Tags out;
  const sdvi::Status status = ci::DecodeTags(
      stream, uint32_t(image.vertices.size()), ci::CollectMeshEdges(image.triangles),
      uint32_t(image.crease_edges.size()), uint32_t(image.corners.size()), true, true, true, "first.sdvi", &out,
      features_first, image.vertices);
  INFO(status.ToString());
  REQUIRE(status.ok());
  return out;
}

}  // namespace

TEST_CASE("features first decodes to the tags written, codes them again to the same bytes, in fewer bytes",
          "[codec][features]") {
  const Image image = FeatureGrid();
  const auto edges = ci::CollectMeshEdges(image.triangles);
  const uint32_t n = uint32_t(image.vertices.size());
  size_t feature_bytes = 0;
  const std::vector<uint8_t> first = ci::EncodeTags(n, edges, TagsOf(image, true), image.vertices, &feature_bytes);
  const ci::Tags decoded = Decode(image, first, true);
  CHECK(decoded.polylines == image.polylines);
  CHECK(decoded.pairs == image.pairs);
  CHECK(decoded.crease_edges == image.crease_edges);
  CHECK(decoded.corners == image.corners);
  Image again = image;
  again.polylines = decoded.polylines;
  again.pairs = decoded.pairs;
  again.crease_edges = decoded.crease_edges;
  again.corners = decoded.corners;
  CHECK(ci::EncodeTags(n, edges, TagsOf(again, true), image.vertices) == first);
  // The feature layer is the start of the stream.
  CHECK(feature_bytes > 0);
  CHECK(feature_bytes < first.size());

  const std::vector<uint8_t> crease_first = ci::EncodeTags(n, edges, TagsOf(image, false));
  CHECK(Decode(image, crease_first, false).polylines == image.polylines);
  INFO("features first " << first.size() << " bytes, crease edges first " << crease_first.size());
  CHECK(first.size() < 0.9 * crease_first.size());
}

TEST_CASE("features first orders by the decoded positions: other positions decode other polylines",
          "[codec][features]") {
  const Image image = FeatureGrid();
  const auto edges = ci::CollectMeshEdges(image.triangles);
  const uint32_t n = uint32_t(image.vertices.size());
  const std::vector<uint8_t> stream = ci::EncodeTags(n, edges, TagsOf(image, true), image.vertices);
  // The positions of other vertices (a fixed permutation): the same bits pick other
  // neighbours (or the decoder finds the stream inconsistent), never the polylines written.
  Image mirrored = image;
  for (size_t v = 0; v < n; ++v) mirrored.vertices[v] = image.vertices[(v * 7919 + 13) % n];
  ci::Tags out;
  const sdvi::Status status =
      ci::DecodeTags(stream, n, edges, uint32_t(image.crease_edges.size()), uint32_t(image.corners.size()), true,
                     true, true, "mirrored.sdvi", &out, true, mirrored.vertices);
  CHECK((!status.ok() || out.polylines != image.polylines));
  // Without positions the reader refuses rather than guesses.
  CHECK(ci::DecodeTags(stream, n, edges, uint32_t(image.crease_edges.size()), uint32_t(image.corners.size()), true,
                       true, true, "none.sdvi", &out, true, {})
            .code() == StatusCode::kInternal);
}

TEST_CASE("a features-first payload (1.2) round trips, and without features first it is 1.1 and larger",
          "[codec][features]") {
  const Image image = FeatureGrid();
  sdvi::CompressOptions options;
  options.position_bits = 12;
  options.color_bits = 10;
  std::vector<uint32_t> new_index;
  const std::vector<uint8_t> payload = sdvi::testing::MustEncode(image, options, &new_index);
  CHECK(payload[5] == 2);
  CHECK((payload[6] & 64) != 0);
  const Image decoded = sdvi::testing::MustDecode(payload);
  Image expected = image;
  REQUIRE(sdvi::RenumberVertices(new_index, &expected).ok());
  CHECK(decoded.polylines == expected.polylines);
  CHECK(decoded.pairs == expected.pairs);
  CHECK(decoded.crease_edges == expected.crease_edges);
  CHECK(decoded.corners == expected.corners);
  CHECK(sdvi::testing::MustEncode(image, options) == payload);

  options.features_first = false;
  const std::vector<uint8_t> older = sdvi::testing::MustEncode(image, options);
  CHECK(older[5] == 1);
  CHECK((older[6] & 64) == 0);
  const Image decoded_older = sdvi::testing::MustDecode(older);
  CHECK(decoded_older.polylines == decoded.polylines);
  CHECK(decoded_older.pairs == decoded.pairs);
  CHECK(decoded_older.vertices == decoded.vertices);
  CHECK(older.size() > payload.size());
}

TEST_CASE("features-first header rules and damaged streams", "[codec][features][corrupt]") {
  const Image image = FeatureGrid();
  auto good = sdvi::EncodeDracoPayload(image, sdvi::CompressOptions{});
  REQUIRE(good.ok());
  Image out;
  // Flag bit 6 in a 1.1 payload, or without ranked starts or compact pairs: corrupt.
  for (const auto& [minor, clear] : std::vector<std::pair<uint8_t, uint8_t>>{{1, 0}, {2, 16}, {2, 32}}) {
    std::vector<uint8_t> bad = *good;
    bad[5] = minor;
    bad[6] = static_cast<uint8_t>(bad[6] & ~clear);
    sdvi::testing::FixPayloadChecksum(&bad);
    const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "flags.sdvi", &out);
    CHECK(status.code() == StatusCode::kCorrupt);
    CHECK(status.message().find("flags.sdvi") != std::string::npos);
  }
  // Every byte of the tag stream damaged (checksum fixed): an error or an image, never a crash;
  // an image's polylines name vertices that exist.
  const uint32_t draco_size = uint32_t((*good)[28]) | uint32_t((*good)[29]) << 8 | uint32_t((*good)[30]) << 16 |
                              uint32_t((*good)[31]) << 24;
  int errors = 0;
  for (size_t at = 40 + draco_size; at < good->size(); ++at) {
    for (uint8_t flip : {0x01, 0x10, 0xFF}) {
      std::vector<uint8_t> bad = *good;
      bad[at] ^= flip;
      sdvi::testing::FixPayloadChecksum(&bad);
      Image damaged;
      const sdvi::Status status = sdvi::DecodeDracoPayload(bad, "damaged.sdvi", &damaged);
      if (!status.ok()) {
        ++errors;
        CHECK(status.code() == StatusCode::kCorrupt);
        continue;
      }
      for (const FeaturePolyline& line : damaged.polylines)
        for (uint32_t v : line.vertices) CHECK(v < damaged.vertices.size());
    }
  }
  CHECK(errors > 0);
}
