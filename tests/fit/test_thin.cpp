// SPDX-License-Identifier: GPL-3.0-or-later
// Thin structures (FeatureCurve::width, spec/METHOD.md section 6 step 3): a hairline's two
// outlines are placed as one unit, so both stay sharp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/vectorize.h"

namespace {

sdvi::FeatureCurve Horizontal(double y, double x0, double x1, float width) {
  sdvi::FeatureCurve c;
  c.points = {{x0, y}, {x1, y}};
  c.width = width;
  return c;
}

// The y of each non-boundary polyline (all its vertices share it), in polyline order.
std::vector<double> PolylineRows(const sdvi::Image& mesh) {
  std::vector<double> rows;
  for (size_t k = 1; k < mesh.polylines.size(); ++k) {  // 0: the image rectangle
    const auto& l = mesh.polylines[k];
    const double y = mesh.vertices[l.vertices.front()].y;
    for (uint32_t v : l.vertices) CHECK(mesh.vertices[v].y == Approx(y).margin(1e-5));
    rows.push_back(y);
  }
  return rows;
}

}  // namespace

TEST_CASE("thin structure: under 1.5 px wide, two pairs share the centre polyline", "[triangulate][thin]") {
  // A 1 px hairline on y = 16.5: outlines at 16 and 17, each pair 1 px wide (sharpness 1).
  auto mesh = sdvi::BuildControlMesh(64, 32, {Horizontal(16.5, 8, 56, 1.0f)}, {}, {});
  INFO(mesh.status().ToString());
  REQUIRE(mesh.ok());
  const std::vector<double> rows = PolylineRows(*mesh);
  REQUIRE(rows.size() == 3);
  CHECK(rows[0] == Approx(17.5));  // +n side of a segment along +x is +y
  CHECK(rows[1] == Approx(16.5));
  CHECK(rows[2] == Approx(15.5));
  REQUIRE(mesh->pairs.size() == 2);
  CHECK(mesh->pairs[0].first == 1);
  CHECK(mesh->pairs[0].second == 2);
  CHECK(mesh->pairs[1].first == 2);  // shared
  CHECK(mesh->pairs[1].second == 3);
  CHECK(mesh->pairs[0].sharpness == 1.0f);
}

TEST_CASE("thin structure: from 1.5 px wide, two pairs with a plateau between them", "[triangulate][thin]") {
  auto mesh = sdvi::BuildControlMesh(64, 32, {Horizontal(16, 8, 56, 2.0f)}, {}, {});
  INFO(mesh.status().ToString());
  REQUIRE(mesh.ok());
  const std::vector<double> rows = PolylineRows(*mesh);
  REQUIRE(rows.size() == 4);
  CHECK(rows[0] == Approx(17.5));
  CHECK(rows[1] == Approx(16.5));
  CHECK(rows[2] == Approx(15.5));
  CHECK(rows[3] == Approx(14.5));
  REQUIRE(mesh->pairs.size() == 2);
  CHECK(mesh->pairs[0].first == 1);
  CHECK(mesh->pairs[0].second == 2);
  CHECK(mesh->pairs[1].first == 3);
  CHECK(mesh->pairs[1].second == 4);
}

TEST_CASE("thin structure: the same outlines as two features lose one pair", "[triangulate][thin]") {
  // Why the unit exists: two sharp features 1 px apart cannot both keep their pairs (the
  // second one's sides would lie on the first one's), so one outline of a hairline is lost.
  auto mesh = sdvi::BuildControlMesh(64, 32, {Horizontal(16, 8, 56, 0), Horizontal(17, 8, 56, 0)}, {}, {});
  REQUIRE(mesh.ok());
  CHECK(mesh->pairs.size() == 1);
}

TEST_CASE("thin structure: a 1 px line and a 2 px bar stay sharp on both sides", "[vectorize][thin]") {
  // White, a black line covering rows 12 (y in [12, 13]) and a dark blue bar covering rows
  // 30 and 31, both from x = 8 to 88.
  sdvi::Raster image(96, 48, 3);
  std::fill(image.data.begin(), image.data.end(), 255.f);
  for (int x = 8; x < 88; ++x) {
    for (int c = 0; c < 3; ++c) image.at(x, 12, c) = 0.f;
    for (int y : {30, 31}) {
      image.at(x, y, 0) = 20.f;
      image.at(x, y, 1) = 40.f;
      image.at(x, y, 2) = 160.f;
    }
  }
  const std::vector<sdvi::FeatureCurve> features = {Horizontal(12.5, 8, 88, 1.0f), Horizontal(31, 8, 88, 2.0f)};
  sdvi::VectorizeOptions options;
  options.max_triangles = 1500;
  auto result = sdvi::VectorizeWithFeatures(image, nullptr, features, options);
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  CHECK(result->image.pairs.size() == 4);
  // Across both structures, away from their ends, every pixel within 12 levels: both
  // outlines sharp (a lost outline leaves a ramp of about half the contrast on its side).
  for (int x : {24, 48, 72}) {
    for (int y = 9; y <= 35; ++y) {
      for (int c = 0; c < 3; ++c) {
        INFO("x " << x << " y " << y << " channel " << c);
        CHECK(std::fabs(result->reconstruction.at(x, y, c) - image.at(x, y, c)) < 12.f);
      }
    }
  }
}

TEST_CASE("a crossing cuts out its neighbourhood, not whole polygon segments", "[triangulate][thin]") {
  // Two sharp features crossing at (32, 32); the longer (horizontal) one is placed first.
  // The vertical one's deBoor polygon has 13 px segments; cut finely, it keeps everything
  // farther than 4 px from the crossing (pair 0.5 + clearance 1 + pair 0.5 + a 2 px piece).
  sdvi::FeatureCurve horizontal = Horizontal(32, 4, 60, 0);
  sdvi::FeatureCurve vertical;
  vertical.points = {{32, 6}, {32, 19}, {32, 32}, {32, 45}, {32, 58}};
  sdvi::ControlMeshOptions options;
  options.max_edge = 40;     // no segment split before placement
  options.junctions = false;  // (with them the crossing is a junction, test_junctions.cpp)
  auto mesh = sdvi::BuildControlMesh(64, 64, {horizontal, vertical}, {}, options);
  INFO(mesh.status().ToString());
  REQUIRE(mesh.ok());
  REQUIRE(mesh->polylines.size() == 7);  // the frame, the horizontal pair, two vertical pairs
  REQUIRE(mesh->pairs.size() == 3);
  double above = 0, below = 64;  // the vertical pieces' ends nearest the crossing
  for (size_t k = 3; k < 7; ++k) {
    for (uint32_t v : mesh->polylines[k].vertices) {
      const double y = mesh->vertices[v].y;
      CHECK(std::fabs(y - 32) >= 1.5);  // clear of the horizontal pair (32 +- 0.5) by 1 px
      if (y < 32) above = std::max(above, y);
      if (y > 32) below = std::min(below, y);
    }
  }
  CHECK(above > 28.0);
  CHECK(below < 36.0);
}
