// SPDX-License-Identifier: GPL-3.0-or-later
// Pattern fills in the artwork mode (spec/SVG.md section 1, "Patterns"): the tile's shapes
// are copied over what the pattern fills, in device space, clipped to their tile; the
// edges of the tiles' fills are chained into lines across the tiles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sdvi/bspline.h"
#include "sdvi/svg.h"
#include "svg_fixture.h"
#include "svg_internal.h"

TEST_CASE("svg pattern: a pattern fill gives its tiles' edges in device space, chained into lines", "[svg][pattern]") {
  // A 20 x 20 user-unit tile with a 10 x 10 square in one corner and a 10 x 10 square in the
  // opposite one (a checkerboard), filling a 60 x 30 rectangle at (20, 20); the viewBox
  // doubles everything: squares are 20 px, the fill covers 40..160 x 40..100.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"120\" viewBox=\"0 0 100 60\">"
      "<pattern id=\"P\" width=\"20\" height=\"20\" patternUnits=\"userSpaceOnUse\">"
      "<rect width=\"10\" height=\"10\" fill=\"#8030d0\"/>"
      "<rect x=\"10\" y=\"10\" width=\"10\" height=\"10\" fill=\"#d0d020\"/></pattern>"
      "<rect x=\"20\" y=\"20\" width=\"60\" height=\"30\" fill=\"url(#P)\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 200, 120);
  CHECK(traced.patterns_not_copied == 0);
  // The tiles' fills as one shape of lines, then the fill itself.
  REQUIRE(traced.shapes.size() == 2);
  const sdvi::SvgShape& lines = traced.shapes[0];
  CHECK(lines.tiled);
  CHECK(lines.paint == sdvi::SvgPaint::kFill);
  CHECK(traced.shapes[1].tiled);  // the fill, where the lines end
  // The fill's box 40..160 x 40..100 meets tile columns 1..4 and rows 1..2 (tiles of 40 px
  // from 0): 16 squares of 20 px, whose sides lie on x = 40, 60, ..., 200 and y = 40, 60,
  // ..., 120, each once.
  size_t segments = 0;
  for (const sdvi::SvgOutline& o : lines.outlines) {
    for (size_t k = 0; k + 3 < o.points.size(); k += 3) {
      ++segments;
      const sdvi::Point2 a = o.points[k], b = o.points[k + 3];
      CHECK(std::hypot(b.x - a.x, b.y - a.y) == Approx(20).margin(1e-6));
      const bool vertical = std::abs(a.x - b.x) < 1e-6;
      const double on = vertical ? a.x : a.y;  // the grid line
      CHECK(std::abs(on / 20 - std::round(on / 20)) < 1e-6);
    }
  }
  CHECK(segments == 64);
  // Through every corner where four squares meet the lines go on straight: one line per
  // grid line inside (x = 60..180 from y = 40 to 120, y = 60..100 from x = 40 to 200), and
  // the border in pieces that turn corners but cross nothing.
  size_t straight = 0;
  for (const sdvi::SvgOutline& o : lines.outlines) {
    const sdvi::Point2 a = o.points.front(), b = o.points.back();
    const bool along_x = std::abs(a.y - b.y) < 1e-6 && std::abs(std::abs(a.x - b.x) - 160) < 1e-6;
    const bool along_y = std::abs(a.x - b.x) < 1e-6 && std::abs(std::abs(a.y - b.y) - 80) < 1e-6;
    if ((along_x || along_y) && o.points.size() == (along_x ? 8u : 4u) * 3 + 1) ++straight;
  }
  CHECK(straight == 7 + 3);
}

TEST_CASE("svg pattern: what overflows a tile is clipped away, a lone shape stays a closed outline", "[svg][pattern]") {
  // A circle of radius 5 in a 20 x 20 tile (closed in every copy) and a bar from x = -5 to
  // 25 in 10 px segments that overflows the tile on both sides: the tile clips it, so only
  // the segments whose middle is inside the tile (x 5..15) are kept.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"60\" height=\"40\">"
      "<pattern id=\"P\" width=\"20\" height=\"20\" patternUnits=\"userSpaceOnUse\">"
      "<circle cx=\"10\" cy=\"7\" r=\"5\" fill=\"#202080\"/>"
      "<path d=\"M -5 15 L 5 15.5 L 15 16 L 25 16.5 L 25 18 L 15 18 L 5 18 L -5 18 Z\" fill=\"#802020\"/></pattern>"
      "<rect x=\"1\" y=\"1\" width=\"58\" height=\"38\" fill=\"url(#P)\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 60, 40);
  INFO(traced.incomplete);
  REQUIRE(traced.shapes.size() == 2);
  const sdvi::SvgShape& lines = traced.shapes[0];
  size_t circles = 0;
  for (const sdvi::SvgOutline& o : lines.outlines) {
    for (const sdvi::Point2& p : o.points) {  // the bar's parts outside a tile are gone
      const double fx = p.x - 20 * std::floor(p.x / 20);
      if (p.y > 14.9 && p.y < 18.1) CHECK(std::abs(fx - 10) <= 5 + 1e-6);
    }
    if (!o.closed) continue;
    ++circles;
    for (size_t k = 0; k < o.points.size(); k += 3) {
      const double cx = 20 * std::floor(o.points[k].x / 20) + 10, cy = 20 * std::floor(o.points[k].y / 20) + 7;
      CHECK(std::hypot(o.points[k].x - cx, o.points[k].y - cy) == Approx(5).margin(0.01));
    }
  }
  CHECK(circles == 6);  // 3 x 2 tiles
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
  const auto [reference, traced] = RenderAndTrace(doc, 96, 64);
  CHECK(traced.patterns_not_copied == 0);
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(traced.shapes, reference, {});
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
  const sdvi::SvgGeometry traced = Traced(doc, 40, 40);
  CHECK(traced.patterns_not_copied == 1);
  for (const sdvi::SvgShape& shape : traced.shapes) CHECK_FALSE(shape.tiled);
  sdvi::SvgArtworkOptions options;
  options.vectorize.max_triangles = 400;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  CHECK(result->approximate);
}

TEST_CASE("svg pattern: copies are bounded; a small tile over a large fill is left to edge detection", "[svg][pattern]") {
  // 3 px tiles over 2000 x 2000 px: 444,889 copies of a square, 1.3e7 points, over the
  // 10^6 points copies may have in one trace. The trace stays small and says so.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"2000\" height=\"2000\">"
      "<pattern id=\"P\" width=\"3\" height=\"3\" patternUnits=\"userSpaceOnUse\">"
      "<rect width=\"1.5\" height=\"1.5\" fill=\"black\"/></pattern>"
      "<rect x=\"1\" y=\"1\" width=\"1998\" height=\"1998\" fill=\"url(#P)\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 2000, 2000);
  CHECK(traced.patterns_not_copied == 1);
  REQUIRE(traced.shapes.size() == 1);  // the fill alone
  CHECK_FALSE(traced.shapes[0].tiled);
}
