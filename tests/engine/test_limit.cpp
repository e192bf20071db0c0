// SPDX-License-Identifier: GPL-3.0-or-later
// Limit masks: the limit of a vertex at level k equals the limit of its child at level
// k+1, for every vertex type; the sides of a crease decouple.
#include <catch2/catch.hpp>

#include <cmath>

#include "sdvi/subdiv.h"
#include "sdvi/tagged_mesh.h"
#include "test_meshes.h"

using namespace sdvi;

namespace {

// Checks limit invariance over two levels for every vertex of image; returns how many
// vertices of each tag were checked (smooth, crease, corner).
std::array<int, 3> CheckLimitInvariance(const Image& image, int levels = 2) {
  auto mesh = TaggedMesh::FromImage(image);
  REQUIRE(mesh.ok());
  TaggedMesh m = *mesh;
  std::vector<double> values = test::Values(image);
  std::array<int, 3> counts{};
  for (int k = 0; k < levels; ++k) {
    const auto limit_k = test::ApplyRows(LimitMasks(m), values);
    const auto next = test::ApplyRows(RefinementMasks(m), values);
    TaggedMesh child = m.Refine();
    const auto limit_k1 = test::ApplyRows(LimitMasks(child), next);
    for (uint32_t v = 0; v < m.num_vertices(); ++v) {
      ++counts[static_cast<int>(m.tag(v))];
      for (int c = 0; c < 5; ++c) {
        INFO("level " << k << " vertex " << v << " tag " << int(m.tag(v)) << " coordinate " << c);
        REQUIRE(limit_k1[5 * v + c] == Approx(limit_k[5 * v + c]).margin(1e-9));
      }
    }
    values = next;
    m = std::move(child);
  }
  return counts;
}

}  // namespace

TEST_CASE("Limit invariance: smooth vertices of valence 3..12", "[limit]") {
  for (int n = 3; n <= 12; ++n) {
    Image fan = test::FanImage(n, 40 + n);
    auto mesh = TaggedMesh::FromImage(fan);
    REQUIRE(mesh.ok());
    REQUIRE(mesh->tag(0) == VertexTag::kSmooth);
    REQUIRE(mesh->neighbours(0).size() == size_t(n));
    CheckLimitInvariance(fan);
  }
}

TEST_CASE("Limit invariance: crease vertices, next to one or two corners, corners", "[limit]") {
  for (int n : {1, 2, 3, 7}) {
    test::Strip strip = test::StripImage(n, 50 + n);
    const auto counts = CheckLimitInvariance(strip.image);
    CHECK(counts[1] > 0);
    CHECK(counts[2] > 0);
  }
  // An interior polyline with implicit corners (crease-degree 1 ends), a tagged corner
  // and a junction, in a jittered grid.
  Image grid = test::GridImage(8, 6, 3, 7);
  auto g = [](int i, int j) { return test::GridIndex(8, i, j); };
  for (int i = 1; i < 7; ++i) grid.crease_edges.push_back(Edge::Of(g(i, 3), g(i + 1, 3)));
  grid.crease_edges.push_back(Edge::Of(g(4, 3), g(4, 2)));
  grid.crease_edges.push_back(Edge::Of(g(4, 2), g(4, 1)));
  std::sort(grid.crease_edges.begin(), grid.crease_edges.end());
  grid.corners = {g(2, 3)};
  const auto counts = CheckLimitInvariance(grid);
  CHECK(counts[0] > 0);
  CHECK(counts[1] > 0);
  CHECK(counts[2] > 0);
}

TEST_CASE("Limit invariance: boundary loops and closed creases", "[limit]") {
  test::Annulus annulus = test::AnnulusImage(9, 3);
  const auto counts = CheckLimitInvariance(annulus.image);
  // Level 0: all 27 vertices lie on crease loops; level 1 adds the 27 crease edge points.
  CHECK(counts[1] == 27 + 54);
  CHECK(counts[0] > 0);
}

TEST_CASE("The two sides of a crease decouple", "[limit]") {
  // A crease across the whole grid along row 3 (y = 30); change every colour above it.
  const int nx = 8, ny = 6;
  Image image = test::GridImage(nx, ny, 3, 9);
  for (int i = 0; i < nx; ++i)
    image.crease_edges.push_back(Edge::Of(test::GridIndex(nx, i, 3), test::GridIndex(nx, i + 1, 3)));
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  Image changed = image;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i <= nx; ++i) {
      Vertex& v = changed.vertices[test::GridIndex(nx, i, j)];
      v.r = 255 - v.r;
      v.g += 500;
      v.b = -40;
    }
  LimitSurfaceOptions options;
  options.levels = 3;
  auto surface = BuildLimitSurface(image, options);
  REQUIRE(surface.ok());
  const auto before = EvaluateSurface(*surface, image.vertices);
  const auto after = EvaluateSurface(*surface, changed.vertices);
  int on_or_below = 0, above_changed = 0;
  for (size_t i = 0; i < before.size(); ++i) {
    CHECK(before[i].x == after[i].x);
    CHECK(before[i].y == after[i].y);
    if (before[i].y >= 30 - 1e-3) {
      ++on_or_below;
      CHECK(before[i].r == after[i].r);
      CHECK(before[i].g == after[i].g);
      CHECK(before[i].b == after[i].b);
    } else if (before[i].g != after[i].g) {
      ++above_changed;
    }
  }
  CHECK(on_or_below > 0);
  CHECK(above_changed > 0);
  // The crease curve itself: its vertices have y == 30 and keep their colours.
  int on_curve = 0;
  for (size_t i = 0; i < before.size(); ++i)
    if (std::abs(before[i].y - 30) < 1e-3) ++on_curve;
  CHECK(on_curve == nx * 8 + 1);
}
