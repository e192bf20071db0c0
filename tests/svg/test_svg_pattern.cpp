// SPDX-License-Identifier: GPL-3.0-or-later
// Pattern fills in the artwork mode (spec/SVG.md section 1, "Patterns"): the tile's shapes
// are copied over what the pattern fills, in device space, each seen only inside its tile.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sdvi/bspline.h"
#include "sdvi/svg.h"
#include "svg_internal.h"

namespace {

sdvi::SvgDocument Doc(const std::string& bytes) {
  auto document = sdvi::LoadSvg(bytes, "test.svg", {});
  INFO(document.status().ToString());
  REQUIRE(document.ok());
  return *document;
}

// The copies of a tile's shapes in a trace (SvgShape::tile_width > 0).
std::vector<const sdvi::SvgShape*> Copies(const sdvi::SvgGeometry& g) {
  std::vector<const sdvi::SvgShape*> out;
  for (const sdvi::SvgShape& s : g.shapes) {
    if (s.tile_width > 0) out.push_back(&s);
  }
  return out;
}

}  // namespace

TEST_CASE("svg pattern: a pattern fill gives its tile's shapes in device space, one copy per tile", "[svg][pattern]") {
  // A 20 x 20 user-unit tile with one 10 x 10 square, filling a 60 x 30 rectangle at (20, 20);
  // the viewBox doubles everything: tiles are 40 px, the fill covers 40..160 x 40..100.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"120\" viewBox=\"0 0 100 60\">"
      "<pattern id=\"P\" width=\"20\" height=\"20\" patternUnits=\"userSpaceOnUse\">"
      "<rect x=\"2\" y=\"4\" width=\"10\" height=\"10\" fill=\"#8030d0\"/></pattern>"
      "<rect x=\"20\" y=\"20\" width=\"60\" height=\"30\" fill=\"url(#P)\"/></svg>");
  auto traced = sdvi::TraceSvgGeometry(doc, 200, 120);
  REQUIRE(traced.ok());
  CHECK(traced->patterns_not_copied == 0);
  // Tiles at x 40, 80, 120 (+ the one ending at the fill's right side, 160) and y 40, 80:
  // the fill's box 40..160 x 40..100 meets tile columns 1..4 and rows 1..2.
  const std::vector<const sdvi::SvgShape*> copies = Copies(*traced);
  REQUIRE(copies.size() == 8);
  // The fill itself is the last shape, after its copies.
  REQUIRE(traced->shapes.size() == 9);
  CHECK(traced->shapes.back().tile_width == 0);
  std::vector<std::pair<double, double>> corners;
  for (const sdvi::SvgShape* s : copies) {
    REQUIRE(s->outlines.size() == 1);
    const sdvi::SvgOutline& o = s->outlines[0];
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (const sdvi::Point2& p : o.points) {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
    CHECK(x1 - x0 == Approx(20).margin(1e-6));
    CHECK(y1 - y0 == Approx(20).margin(1e-6));
    corners.push_back({x0, y0});
    // The copy's tile contains its square: the square's centre maps into [0, w] x [0, h].
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    const double u = s->tile[0] * cx + s->tile[2] * cy + s->tile[4], v = s->tile[1] * cx + s->tile[3] * cy + s->tile[5];
    CHECK(u >= 0);
    CHECK(u <= s->tile_width);
    CHECK(v >= 0);
    CHECK(v <= s->tile_height);
  }
  std::sort(corners.begin(), corners.end());
  // Squares at tile origin + (4, 8) px, tiles every 40 px from 0.
  const std::vector<std::pair<double, double>> expected = {{44, 48}, {44, 88}, {84, 48}, {84, 88},
                                                           {124, 48}, {124, 88}, {164, 48}, {164, 88}};
  for (size_t k = 0; k < expected.size(); ++k) {
    CHECK(corners[k].first == Approx(expected[k].first).margin(1e-3));
    CHECK(corners[k].second == Approx(expected[k].second).margin(1e-3));
  }
}

TEST_CASE("svg pattern: a turned pattern's squares become outline features where librsvg draws them", "[svg][pattern]") {
  // Dark 10 x 10 squares at (4, 4) in 20 x 20 tiles, the pattern turned by 20 degrees,
  // filling the rectangle 8..88 x 8..56 on white.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"96\" height=\"64\">"
      "<rect width=\"96\" height=\"64\" fill=\"white\"/>"
      "<pattern id=\"P\" width=\"20\" height=\"20\" patternUnits=\"userSpaceOnUse\" patternTransform=\"rotate(20)\">"
      "<rect x=\"4\" y=\"4\" width=\"10\" height=\"10\" fill=\"#202080\"/></pattern>"
      "<rect x=\"8\" y=\"8\" width=\"80\" height=\"48\" fill=\"url(#P)\"/></svg>");
  auto reference = sdvi::RenderSvg(doc, 96, 64);
  auto traced = sdvi::TraceSvgGeometry(doc, 96, 64);
  REQUIRE(reference.ok());
  REQUIRE(traced.ok());
  CHECK(traced->patterns_not_copied == 0);
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(traced->shapes, *reference, {});
  // The squares in device space: tile (i, j)'s square turned by 20 degrees about the origin.
  const double c = std::cos(20 * M_PI / 180), s = std::sin(20 * M_PI / 180);
  auto distance_to_squares = [&](sdvi::Point2 p) {
    const double u = c * p.x + s * p.y, v = -s * p.x + c * p.y;  // back into pattern space
    const double fu = u - 20 * std::floor(u / 20), fv = v - 20 * std::floor(v / 20);  // within the tile
    const double dx = std::max({4 - fu, 0.0, fu - 14}), dy = std::max({4 - fv, 0.0, fv - 14});
    if (dx > 0 || dy > 0) return std::hypot(dx, dy);
    return std::min({fu - 4, 14 - fu, fv - 4, 14 - fv});
  };
  // Whole squares inside the fill: about 80 x 48 / 400 of them; each gives a closed feature.
  size_t closed = 0, samples = 0, off = 0;
  for (const sdvi::FeatureCurve& curve : curves) {
    closed += curve.closed ? 1 : 0;
    for (const sdvi::Point2& p : sdvi::SampleFeatureCurve(curve, 4)) {
      ++samples;
      if (p.x < 9 || p.y < 9 || p.x > 87 || p.y > 55) continue;  // the fill's own outline
      off += distance_to_squares(p) > 0.6 ? 1 : 0;
    }
  }
  INFO(curves.size() << " features, " << closed << " closed, " << off << " of " << samples << " samples off");
  CHECK(closed >= 6);
  CHECK(samples > 0);
  CHECK(off == 0);
}

TEST_CASE("svg pattern: a tiny tile is not copied and the result says it is approximate", "[svg][pattern]") {
  // 1.5 px tiles: below the 2 px a copied tile needs.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"40\" height=\"40\">"
      "<rect width=\"40\" height=\"40\" fill=\"white\"/>"
      "<pattern id=\"P\" width=\"1.5\" height=\"1.5\" patternUnits=\"userSpaceOnUse\">"
      "<rect width=\"0.75\" height=\"0.75\" fill=\"black\"/></pattern>"
      "<circle cx=\"20\" cy=\"20\" r=\"15\" fill=\"url(#P)\"/></svg>");
  auto traced = sdvi::TraceSvgGeometry(doc, 40, 40);
  REQUIRE(traced.ok());
  CHECK(traced->patterns_not_copied == 1);
  for (const sdvi::SvgShape& shape : traced->shapes) CHECK(shape.tile_width == 0);
  sdvi::SvgArtworkOptions options;
  options.vectorize.max_triangles = 400;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  CHECK(result->approximate);
}
