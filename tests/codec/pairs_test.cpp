// SPDX-License-Identifier: GPL-3.0-or-later
// Feature pairs in the tag stream (spec/FORMAT.md 8.5 step 3): written out (payload 1.0) and
// compact (payload 1.1) decode to the same pairs; compact costs a few bits a pair where pairs
// follow each other and sharpness values repeat.
#include <catch2/catch.hpp>

#include <cstring>
#include <random>

#include "sdvi/codec.h"
#include "synthetic_mesh.h"
#include "tag_stream.h"

namespace ci = sdvi::codec_internal;

namespace {

// Tags of the synthetic grid with `lines` one-vertex polylines and the given pairs.
ci::Tags TagsWithPairs(const sdvi::Image& image, uint32_t lines, std::vector<sdvi::FeaturePair> pairs) {
  ci::Tags tags;
  tags.crease_edges = image.crease_edges;
  std::sort(tags.crease_edges.begin(), tags.crease_edges.end());
  tags.corners = image.corners;
  std::sort(tags.corners.begin(), tags.corners.end());
  tags.has_feature_layer = true;
  for (uint32_t i = 0; i < lines; ++i) tags.polylines.push_back({{i % uint32_t(image.vertices.size())}, false});
  tags.pairs = std::move(pairs);
  return tags;
}

std::vector<sdvi::FeaturePair> RoundTrip(const sdvi::Image& image, const ci::Tags& tags, size_t* bytes) {
  const auto edges = ci::CollectMeshEdges(image.triangles);
  const std::vector<uint8_t> stream = ci::EncodeTags(uint32_t(image.vertices.size()), edges, tags);
  *bytes = stream.size();
  ci::Tags out;
  const sdvi::Status status =
      ci::DecodeTags(stream, uint32_t(image.vertices.size()), edges, uint32_t(tags.crease_edges.size()),
                     uint32_t(tags.corners.size()), true, tags.compact_pairs, tags.ranked_starts, "pairs.sdvi", &out);
  INFO(status.ToString());
  REQUIRE(status.ok());
  CHECK(out.polylines == tags.polylines);
  return out.pairs;
}

}  // namespace

TEST_CASE("compact pairs decode to the pairs written out, in a fraction of the bytes", "[codec][features]") {
  const sdvi::Image image = sdvi::testing::SyntheticGridImage(200, 200, 15, 15, 4);
  // 200 polylines: 90 pairs (2k+1, 2k+2) as the vectorizer makes them, with two sharpness
  // values, then pairs out of order, a polyline paired with itself, and 12 distinct
  // sharpness values cycling (more than the 8 recent ones kept), including -0 and 1.
  std::vector<sdvi::FeaturePair> pairs;
  for (uint32_t k = 0; k < 90; ++k) pairs.push_back({2 * k + 1, 2 * k + 2, k % 3 ? 0.96717405f : 0.22865377f});
  pairs.push_back({7, 3, 0.5f});
  pairs.push_back({199, 199, 0.0f});
  pairs.push_back({0, 5, -0.0f});
  std::mt19937 rng(3);
  for (int k = 0; k < 40; ++k) {
    const uint32_t first = uint32_t(rng() % 200);
    const uint32_t second = uint32_t((first + 1 + rng() % 2) % 200);
    pairs.push_back({first, second, 1.0f - float(k % 12) / 16});
  }
  ci::Tags tags = TagsWithPairs(image, 200, pairs);
  size_t compact_bytes = 0, plain_bytes = 0, no_pairs_bytes = 0;
  const auto compact = RoundTrip(image, tags, &compact_bytes);
  REQUIRE(compact.size() == pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    INFO(k);
    CHECK(compact[k].first == pairs[k].first);
    CHECK(compact[k].second == pairs[k].second);
    CHECK(std::memcmp(&compact[k].sharpness, &pairs[k].sharpness, 4) == 0);  // -0 stays -0
  }
  tags.compact_pairs = false;
  CHECK(RoundTrip(image, tags, &plain_bytes) == compact);
  tags.pairs.clear();
  RoundTrip(image, tags, &no_pairs_bytes);
  // Written out: 2 x 8 + 32 bits a pair. Compact: ~2 bits for the 90 regular pairs' indices
  // and ~1-2 for their sharpness.
  CHECK(plain_bytes - no_pairs_bytes >= pairs.size() * 48 / 8 - 2);
  CHECK(compact_bytes - no_pairs_bytes < (plain_bytes - no_pairs_bytes) / 2);
}

TEST_CASE("compact pairs naming a missing polyline are corrupt", "[codec][features][corrupt]") {
  const sdvi::Image image = sdvi::testing::SyntheticGridImage(60, 60, 6, 6, 2);
  // Pair (3, 4) of 4 polylines (the writer's API refuses it; the tag coder does not check):
  // its second, coded as first + 1, is out of range for the decoder.
  const ci::Tags tags = TagsWithPairs(image, 4, {{3, 4, 0.5f}});
  const auto edges = ci::CollectMeshEdges(image.triangles);
  const std::vector<uint8_t> stream = ci::EncodeTags(uint32_t(image.vertices.size()), edges, tags);
  ci::Tags out;
  const sdvi::Status status =
      ci::DecodeTags(stream, uint32_t(image.vertices.size()), edges, uint32_t(tags.crease_edges.size()),
                     uint32_t(tags.corners.size()), true, true, true, "bad_pair.sdvi", &out);
  CHECK(status.code() == sdvi::StatusCode::kCorrupt);
  CHECK(status.message().find("bad_pair.sdvi") != std::string::npos);
}

TEST_CASE("ranked polyline starts decode to the starts written out, in fewer bytes", "[codec][features]") {
  const sdvi::Image image = sdvi::testing::SyntheticGridImage(300, 300, 24, 24, 8, /*shuffle=*/true);
  ci::Tags tags = TagsWithPairs(image, 0, {});
  // Walks of two crease edges from crease vertices on no polyline yet (ranked), starts within
  // 4 indices of the previous start (near; also one 4 below), a start already used
  // (written out), a vertex without crease edges (written out), and an empty polyline.
  std::vector<std::vector<uint32_t>> adjacent(image.vertices.size());
  for (const auto& e : tags.crease_edges) {
    adjacent[e.a].push_back(e.b);
    adjacent[e.b].push_back(e.a);
  }
  uint32_t lonely = 0;
  while (!adjacent[lonely].empty()) ++lonely;
  std::vector<char> used(image.vertices.size(), 0);
  for (const auto& e : tags.crease_edges) {
    if (used[e.a] || used[e.b] || tags.polylines.size() >= 60) continue;
    tags.polylines.push_back({{e.a, e.b}, false});
    used[e.a] = used[e.b] = 1;
  }
  REQUIRE(tags.polylines.size() >= 20);
  const uint32_t last = tags.polylines.back().vertices[0];
  REQUIRE(last >= 1);
  REQUIRE(last + 3 < image.vertices.size());
  tags.polylines.push_back({{last + 3}, false});
  tags.polylines.push_back({{last - 1}, false});
  tags.polylines.push_back({{last - 1}, true});  // the same start: not near (delta 0)
  tags.polylines.push_back({{tags.polylines[0].vertices[0], tags.polylines[0].vertices[1]}, false});
  tags.polylines.push_back({{lonely}, false});
  tags.polylines.push_back({{}, false});
  tags.polylines.push_back({{uint32_t(image.vertices.size() - 1)}, false});
  const auto edges = ci::CollectMeshEdges(image.triangles);
  auto round_trip = [&](bool ranked, size_t* bytes) {
    tags.ranked_starts = ranked;
    const std::vector<uint8_t> stream = ci::EncodeTags(uint32_t(image.vertices.size()), edges, tags);
    *bytes = stream.size();
    ci::Tags out;
    const sdvi::Status status =
        ci::DecodeTags(stream, uint32_t(image.vertices.size()), edges, uint32_t(tags.crease_edges.size()),
                       uint32_t(tags.corners.size()), true, true, ranked, "starts.sdvi", &out);
    INFO(status.ToString());
    REQUIRE(status.ok());
    CHECK(out.polylines == tags.polylines);
  };
  size_t ranked_bytes = 0, plain_bytes = 0;
  round_trip(true, &ranked_bytes);
  round_trip(false, &plain_bytes);
  CHECK(ranked_bytes < plain_bytes);
}
