// SPDX-License-Identifier: GPL-3.0-or-later
// Geometry capture (librsvg -> cairo script -> device-space outlines), the reference
// raster and the artwork mode, on small drawings written here.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "sdvi/bspline.h"
#include "sdvi/svg.h"
#include "svg_fixture.h"
#include "svg_internal.h"

namespace {

double DistanceToRectangle(sdvi::Point2 p, double x0, double y0, double x1, double y1) {
  // Distance from p to the boundary of the axis-aligned rectangle.
  const double inside_dx = std::min(p.x - x0, x1 - p.x), inside_dy = std::min(p.y - y0, y1 - p.y);
  if (inside_dx >= 0 && inside_dy >= 0) return std::min(inside_dx, inside_dy);
  const double dx = std::max({x0 - p.x, 0.0, p.x - x1}), dy = std::max({y0 - p.y, 0.0, p.y - y1});
  return std::hypot(dx, dy);
}

}  // namespace

TEST_CASE("svg geometry: viewBox, transforms and use give device-space outlines", "[svg]") {
  // viewBox 200x100 shown at 100x50: user units x 0.5.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"50\" viewBox=\"0 0 200 100\">"
      "<defs><rect id=\"r\" x=\"20\" y=\"10\" width=\"40\" height=\"30\"/></defs>"
      "<g transform=\"translate(10,0)\"><use href=\"#r\" x=\"100\"/></g></svg>");
  CHECK(doc.width == 100);
  CHECK(doc.height == 50);
  const sdvi::SvgGeometry traced = Traced(doc, 100, 50);
  CHECK(traced.incomplete.empty());
  const auto* shapes = &traced.shapes;
  REQUIRE(shapes->size() == 1);
  const sdvi::SvgShape& s = (*shapes)[0];
  CHECK(s.paint == sdvi::SvgPaint::kFill);
  REQUIRE(s.outlines.size() == 1);
  CHECK(s.outlines[0].closed);
  double min_x = 1e9, min_y = 1e9, max_x = -1e9, max_y = -1e9;
  for (const sdvi::Point2& p : s.outlines[0].points) {
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  // (20 + 100 + 10) * 0.5 = 65 .. (60 + 110) * 0.5 = 85; 10 * 0.5 = 5 .. 40 * 0.5 = 20.
  CHECK(min_x == Approx(65).margin(1e-4));
  CHECK(max_x == Approx(85).margin(1e-4));
  CHECK(min_y == Approx(5).margin(1e-4));
  CHECK(max_y == Approx(20).margin(1e-4));
}

TEST_CASE("svg geometry: arcs and circles come out as cubics on the circle", "[svg]") {
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"64\" height=\"64\">"
      "<circle cx=\"32\" cy=\"30\" r=\"20\" fill=\"red\"/>"
      "<path d=\"M 12 60 A 10 10 0 0 1 32 60\" fill=\"none\" stroke=\"blue\" stroke-width=\"4\" "
      "transform=\"scale(1)\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 128, 128);  // rendered at twice the size
  const auto* shapes = &traced.shapes;
  REQUIRE(shapes->size() == 2);
  const sdvi::SvgOutline& circle = (*shapes)[0].outlines.at(0);
  CHECK(circle.closed);
  REQUIRE(circle.points.size() >= 13);
  for (size_t i = 0; i < circle.points.size(); i += 3) {  // segment end points lie on the circle
    CHECK(std::hypot(circle.points[i].x - 64, circle.points[i].y - 60) == Approx(40).margin(1e-3));
  }
  const sdvi::SvgShape& arc = (*shapes)[1];
  CHECK(arc.paint == sdvi::SvgPaint::kStroke);
  CHECK(arc.stroke_width == Approx(8).margin(1e-6));  // 4 user units x 2
  const sdvi::SvgOutline& a = arc.outlines.at(0);
  CHECK_FALSE(a.closed);
  CHECK(a.points.front().x == Approx(24).margin(1e-3));
  CHECK(a.points.back().x == Approx(64).margin(1e-3));
  for (size_t i = 0; i < a.points.size(); i += 3) {  // a half circle of radius 20 around (44, 120)
    CHECK(std::hypot(a.points[i].x - 44, a.points[i].y - 120) == Approx(20).margin(1e-3));
  }
}

TEST_CASE("svg geometry: a gradient's matrix does not change the stroke width", "[svg]") {
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"48\" height=\"48\" viewBox=\"0 0 12 12\">"
      "<defs><linearGradient id=\"g\" x1=\"0\" y1=\"0\" x2=\"0.1\" y2=\"0\" gradientUnits=\"userSpaceOnUse\">"
      "<stop offset=\"0\" stop-color=\"red\"/><stop offset=\"1\" stop-color=\"blue\"/></linearGradient></defs>"
      "<path d=\"M 2 2 L 10 10\" stroke=\"url(#g)\" stroke-width=\"1.5\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 48, 48);
  // The line has no area: the traced document does not fill it (spec/SVG.md), the stroke stays.
  REQUIRE(traced.shapes.size() == 1);
  CHECK(traced.shapes[0].paint == sdvi::SvgPaint::kStroke);
  CHECK(traced.shapes[0].stroke_width == Approx(6.0).margin(1e-4));  // 1.5 user units x 4
}

TEST_CASE("svg geometry: a repeating pattern's tile is not traced where it is not seen", "[svg]") {
  // The tile (two 5 px squares) is drawn into its own surface in tile space, at 0..10; the
  // pattern fills the rectangle at 20..40. The tile is not traced there: the rectangle is,
  // and the tile's copies over it (tests/svg/test_svg_pattern.cpp), before it.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"60\" height=\"60\"><defs>"
      "<pattern id=\"p\" patternUnits=\"userSpaceOnUse\" width=\"10\" height=\"10\">"
      "<rect width=\"5\" height=\"5\" fill=\"red\"/><rect x=\"5\" y=\"5\" width=\"5\" height=\"5\" "
      "fill=\"blue\"/></pattern></defs><rect x=\"20\" y=\"20\" width=\"20\" height=\"20\" fill=\"url(#p)\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 60, 60);
  REQUIRE(traced.shapes.size() == 2);
  CHECK(traced.shapes[1].outlines[0].points[0].x == Approx(20));
  CHECK(traced.shapes[1].outlines[0].points[0].y == Approx(20));
  for (const sdvi::SvgOutline& o : traced.shapes[0].outlines) {
    for (const sdvi::Point2& p : o.points) {
      CHECK(p.x >= 20);
      CHECK(p.y >= 20);
    }
  }
}

TEST_CASE("svg geometry: shapes without area do not stop the trace", "[svg]") {
  // cairo's script surface fails on the fill of an axis-aligned line (default fill black)
  // and then refuses every later operation; the traced document leaves such shapes unfilled.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"40\" height=\"40\">"
      "<line x1=\"2\" y1=\"4.5\" x2=\"38\" y2=\"4.5\" stroke=\"gray\"/>"
      "<path d=\"M 2 8.5 h 30 h -10 z\" stroke=\"gray\"/><polyline points=\"2,12 20,12 30,12\" stroke=\"gray\"/>"
      "<rect x=\"10\" y=\"20\" width=\"20\" height=\"10\" fill=\"red\"/></svg>");
  CHECK_FALSE(doc.traced.empty());
  const sdvi::SvgGeometry traced = Traced(doc, 40, 40);
  CHECK(traced.incomplete.empty());
  REQUIRE(traced.shapes.size() == 4);
  for (int k = 0; k < 3; ++k) CHECK(traced.shapes[k].paint == sdvi::SvgPaint::kStroke);
  CHECK(traced.shapes[3].paint == sdvi::SvgPaint::kFill);
  CHECK(traced.shapes[3].outlines[0].points[0].x == Approx(10));
  // Shapes with area keep their fill: a curve whose control points leave the line, an arc.
  CHECK(Doc("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"9\" height=\"9\">"
            "<path d=\"M0 0 C 1 1 2 0 3 0\"/><path d=\"M0 0 A 2 2 0 0 1 4 0\"/></svg>").traced.empty());
}

TEST_CASE("svg raster: librsvg colours un-premultiplied, transparent background", "[svg]") {
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"20\" height=\"10\">"
      "<rect x=\"0\" y=\"0\" width=\"10\" height=\"10\" fill=\"#ff8000\"/>"
      "<rect x=\"10\" y=\"0\" width=\"10\" height=\"10\" fill=\"#0000ff\" fill-opacity=\"0.5\"/></svg>");
  auto raster = sdvi::RenderSvg(doc, 20, 10);
  REQUIRE(raster.ok());
  REQUIRE(raster->channels == 4);
  CHECK(raster->at(3, 5, 0) == 255.f);
  CHECK(raster->at(3, 5, 1) == Approx(128).margin(0.01));
  CHECK(raster->at(3, 5, 2) == 0.f);
  CHECK(raster->at(3, 5, 3) == 1.f);
  CHECK(raster->at(15, 5, 2) == Approx(255).margin(1.5));
  CHECK(raster->at(15, 5, 3) == Approx(0.5).margin(0.01));
}

TEST_CASE("svg artwork: features follow the visible outline only", "[svg]") {
  // A white background, a red square, and a blue square covering its right part.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"96\" height=\"96\">"
      "<rect width=\"96\" height=\"96\" fill=\"white\"/>"
      "<rect x=\"16.3\" y=\"20.6\" width=\"40\" height=\"50\" fill=\"#d02020\"/>"
      "<rect x=\"40.2\" y=\"10.4\" width=\"40\" height=\"40\" fill=\"#2040d0\"/></svg>");
  const auto [reference, traced] = RenderAndTrace(doc, 96, 96);
  const auto* shapes = &traced.shapes;
  sdvi::SvgArtworkOptions options;
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(*shapes, reference, options);
  REQUIRE(!curves.empty());
  for (const sdvi::FeatureCurve& c : curves) {
    CHECK(c.sharpness == 1.0f);
    CHECK_FALSE(c.boundary);
    for (const sdvi::Point2& p : sdvi::SampleFeatureCurve(c, 8)) {
      const double to_red = DistanceToRectangle(p, 16.3, 20.6, 56.3, 70.6);
      const double to_blue = DistanceToRectangle(p, 40.2, 10.4, 80.2, 50.4);
      CHECK(std::min(to_red, to_blue) < options.tolerance + 0.05);
      // Nothing on the hidden part of the red square's outline (inside the blue one).
      const bool hidden = p.x > 41.5 && p.x < 79 && p.y > 11.5 && p.y < 49;
      CHECK_FALSE(hidden);
    }
  }
  // The whole blue outline is one closed feature with four kinks.
  const auto closed = std::count_if(curves.begin(), curves.end(), [](const auto& c) { return c.closed; });
  CHECK(closed == 1);
}

TEST_CASE("svg artwork: an object drawing imports as an object image close to librsvg", "[svg]") {
  const std::string bytes =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"80\" height=\"64\" viewBox=\"0 0 40 32\">"
      "<defs><linearGradient id=\"g\" x1=\"0\" x2=\"1\"><stop offset=\"0\" stop-color=\"#ffd040\"/>"
      "<stop offset=\"1\" stop-color=\"#e06000\"/></linearGradient></defs>"
      "<circle cx=\"20\" cy=\"16\" r=\"13\" fill=\"url(#g)\"/>"
      "<path d=\"M 12 18 Q 20 26 28 18\" fill=\"none\" stroke=\"#402010\" stroke-width=\"2\"/>"
      "<ellipse cx=\"15\" cy=\"12\" rx=\"2\" ry=\"3\" fill=\"#402010\"/></svg>";
  const sdvi::SvgDocument doc = Doc(bytes);
  sdvi::SvgArtworkOptions options;
  options.vectorize.max_triangles = 1200;
  auto a = sdvi::ImportSvgArtwork(doc, options);
  INFO(a.status().ToString());
  REQUIRE(a.ok());
  CHECK(a->reference.width == 80);
  CHECK(a->reference.height == 64);
  CHECK(a->outline_features >= 3);
  CHECK(a->object_image);
  CHECK_FALSE(a->approximate);
  CHECK(a->vectorized.report.triangles <= 1200);
  CHECK(a->vectorized.report.psnr > 30.0);
  // Outside the disc the image has no domain: an object image.
  bool has_hole = false;
  for (int y = 0; y < 64 && !has_hole; ++y) has_hole = a->vectorized.reconstruction.at(0, y, 3) < 128;
  CHECK(has_hole);
  // Deterministic.
  auto b = sdvi::ImportSvgArtwork(doc, options);
  REQUIRE(b.ok());
  REQUIRE(a->vectorized.image.vertices.size() == b->vectorized.image.vertices.size());
  for (size_t i = 0; i < a->vectorized.image.vertices.size(); ++i) {
    const auto& va = a->vectorized.image.vertices[i];
    const auto& vb = b->vectorized.image.vertices[i];
    CHECK((va.x == vb.x && va.y == vb.y && va.r == vb.r && va.g == vb.g && va.b == vb.b));
  }
}

TEST_CASE("svg artwork: text, filters and external images are named in warnings", "[svg]") {
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"48\" "
      "height=\"48\">\n<rect width=\"48\" height=\"48\" fill=\"#fff\"/>\n"
      "<filter id=\"f\"><feGaussianBlur stdDeviation=\"2\"/></filter>\n"
      "<circle cx=\"24\" cy=\"24\" r=\"10\" fill=\"#080\" filter=\"url(#f)\"/>\n"
      "<text x=\"4\" y=\"40\">Hi</text>\n<image xlink:href=\"/nonexistent/picture.png\" width=\"8\" "
      "height=\"8\"/>\n</svg>");
  CHECK(std::find(doc.unsupported.begin(), doc.unsupported.end(), "filter (line 3)") != doc.unsupported.end());
  // Text is traced as glyph outlines (thin fills): not approximated.
  CHECK(std::find(doc.unsupported.begin(), doc.unsupported.end(), "text (line 5)") == doc.unsupported.end());
  REQUIRE(doc.warnings.size() == 1);
  CHECK(doc.warnings[0].find("/nonexistent/picture.png") != std::string::npos);
  sdvi::SvgArtworkOptions options;
  options.vectorize.max_triangles = 600;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  CHECK(result->approximate);
  bool named = false;
  for (const std::string& w : result->warnings) named = named || w.find("filter (line 3)") != std::string::npos;
  CHECK(named);
}

TEST_CASE("svg: a document without size needs an output width", "[svg]") {
  sdvi::SvgError error = sdvi::SvgError::kNone;
  const sdvi::SvgDocument doc = Doc("<svg xmlns=\"http://www.w3.org/2000/svg\"><rect width=\"5\" height=\"5\"/></svg>");
  auto size = sdvi::ChooseSvgSize(doc, 0, 0, {}, &error);
  if (doc.width > 0) {
    SUCCEED("librsvg gives this document a default size");
  } else {
    REQUIRE_FALSE(size.ok());
    CHECK(error == sdvi::SvgError::kNoSize);
  }
}

TEST_CASE("svg artwork: a transparent drawing of hairlines is composited over white", "[svg]") {
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"64\" height=\"64\">"
      "<rect x=\"0.5\" y=\"0.5\" width=\"63\" height=\"63\" fill=\"none\" stroke=\"black\"/>"
      "<path d=\"M 8 8 L 56 40 M 8 40 L 56 8\" stroke=\"#0000c0\"/></svg>");
  sdvi::SvgArtworkOptions options;
  options.vectorize.max_triangles = 800;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  CHECK_FALSE(result->object_image);
  CHECK(result->reference.at(32, 50, 0) == 255.f);  // white where nothing is drawn
  CHECK(result->vectorized.reconstruction.at(32, 50, 3) == 255);
  options.background = sdvi::SvgBackground::kTransparent;
  auto object = sdvi::ImportSvgArtwork(doc, options);
  if (object.ok()) CHECK(object->object_image);
}

TEST_CASE("svg artwork: a 1 px stroke is one thin feature, sharp on both sides", "[svg][thin]") {
  // Hairlines on white: a horizontal one covering row 20, a circle of radius 14.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"80\" height=\"64\">"
      "<rect width=\"80\" height=\"64\" fill=\"white\"/>"
      "<path d=\"M 6 20.5 L 74 20.5\" stroke=\"black\" stroke-width=\"1\"/>"
      "<circle cx=\"40\" cy=\"44\" r=\"14\" fill=\"none\" stroke=\"#c00000\" stroke-width=\"1\"/></svg>");
  const auto [reference, traced] = RenderAndTrace(doc, 80, 64);
  sdvi::SvgArtworkOptions options;
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(traced.shapes, reference, options);
  REQUIRE(curves.size() == 2);  // the centrelines, not two sides each
  for (const sdvi::FeatureCurve& c : curves) CHECK(c.width == 1.0f);
  options.vectorize.max_triangles = 2000;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  // Across the line (rows 17..23) and the circle's top and bottom (x = 40), every pixel
  // within 16 levels of librsvg: both outlines sharp.
  for (int x : {20, 40, 60}) {
    for (int y = 17; y <= 23; ++y) {
      for (int c = 0; c < 3; ++c) {
        INFO("x " << x << " y " << y);
        CHECK(std::fabs(result->vectorized.reconstruction.at(x, y, c) - result->reference.at(x, y, c)) < 16.f);
      }
    }
  }
  // The circle's top and bottom: 18 levels (the flips' exact pixel partition left 16.2 at
  // (40, 30), from 13.0, the mesher's 10 degree angle bound 17.0 there (spec/METHOD.md
  // section 6 step 4); the other pixels here within 15, the line's rows above unchanged).
  for (int y : {27, 28, 29, 30, 31, 57, 58, 59, 60, 61}) {
    for (int c = 0; c < 3; ++c) {
      INFO("x 40 y " << y);
      CHECK(std::fabs(result->vectorized.reconstruction.at(40, y, c) - result->reference.at(40, y, c)) < 18.f);
    }
  }
}

TEST_CASE("svg artwork: a fill thinner than 2 px is one thin feature on its centreline", "[svg][thin]") {
  // A black bar 1.5 px wide (x 20..21.5, y 8..48) and a grey one 1.75 px wide lying across
  // (x 40..72, y 30..31.75), on white.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"80\" height=\"56\">"
      "<rect width=\"80\" height=\"56\" fill=\"white\"/>"
      "<rect x=\"20\" y=\"8\" width=\"1.5\" height=\"40\" fill=\"black\"/>"
      "<path d=\"M 40 30 H 72 V 31.75 H 40 Z\" fill=\"#606060\"/></svg>");
  const auto [reference, traced] = RenderAndTrace(doc, 80, 56);
  sdvi::SvgArtworkOptions options;
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(traced.shapes, reference, options);
  REQUIRE(curves.size() == 2);  // one centreline each, not two sides
  int vertical = 0, horizontal = 0;
  for (const sdvi::FeatureCurve& c : curves) {
    const std::vector<sdvi::Point2> samples = sdvi::SampleFeatureCurve(c, 4);
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const sdvi::Point2& p : samples) {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
    if (y1 - y0 > x1 - x0) {
      ++vertical;
      CHECK(c.width == Approx(1.5f));
      CHECK(x0 == Approx(20.75).margin(0.05));  // the centreline
      CHECK(x1 == Approx(20.75).margin(0.05));
      CHECK(y1 - y0 > 36);
    } else {
      ++horizontal;
      CHECK(c.width == Approx(1.75f));
      CHECK(y0 == Approx(30.875).margin(0.05));
      CHECK(y1 == Approx(30.875).margin(0.05));
      CHECK(x1 - x0 > 28);
    }
  }
  CHECK(vertical == 1);
  CHECK(horizontal == 1);
  // The ablation: the fills' outlines only, on which the probes reach across the bar.
  options.thin_fills = false;
  for (const sdvi::FeatureCurve& c : sdvi::ArtworkFeatures(traced.shapes, reference, options)) CHECK(c.width == 0);
}

TEST_CASE("svg artwork: small text's glyph stems are thin features, sharper than without them", "[svg][thin]") {
  // 11 px text: stems about 1 px wide (any sans-serif font fontconfig finds).
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"160\" height=\"40\">"
      "<rect width=\"160\" height=\"40\" fill=\"white\"/>"
      "<text x=\"6\" y=\"24\" font-family=\"DejaVu Sans, sans-serif\" font-size=\"11\" fill=\"black\">"
      "Hill mill lily 1111</text></svg>");
  CHECK(doc.unsupported.empty());
  const auto [reference, traced] = RenderAndTrace(doc, 160, 40);
  // The glyphs' outlines, one filled path with a subpath per contour (at least one per
  // letter); the background covers the surface and is painted, not filled.
  REQUIRE(traced.shapes.size() == 1);
  CHECK(traced.shapes[0].paint == sdvi::SvgPaint::kFill);
  CHECK(traced.shapes[0].outlines.size() >= 16);
  sdvi::SvgArtworkOptions options;
  size_t thin = 0;
  for (const sdvi::FeatureCurve& c : sdvi::ArtworkFeatures(traced.shapes, reference, options)) {
    if (c.width > 0) {
      ++thin;
      CHECK(c.width < 3);
    }
  }
  CHECK(thin >= 10);  // the many stems (about 16 of them)
  // Imported at the same budget with and without thin fills: the text is closer to
  // librsvg's rendering with them.
  options.vectorize.max_triangles = 1600;
  auto with = sdvi::ImportSvgArtwork(doc, options);
  options.thin_fills = false;
  auto without = sdvi::ImportSvgArtwork(doc, options);
  REQUIRE(with.ok());
  REQUIRE(without.ok());
  CHECK_FALSE(with->approximate);
  auto error = [](const sdvi::SvgArtworkResult& r) {
    double sum = 0;
    for (int y = 10; y < 28; ++y) {
      for (int x = 0; x < 160; ++x) {
        for (int c = 0; c < 3; ++c) sum += std::fabs(r.vectorized.reconstruction.at(x, y, c) - r.reference.at(x, y, c));
      }
    }
    return sum / (18 * 160 * 3);
  };
  INFO("mean error with thin fills " << error(*with) << ", without " << error(*without));
  // Measured: 5.41 with, 6.58 without (6.24 and 8.13 before pair sides lost their spikes,
  // which helped the outlines-only import more).
  CHECK(error(*with) < 0.85 * error(*without));
}

TEST_CASE("svg artwork: a thin fill drawn over itself thousands of times stays linear", "[svg][thin]") {
  // One path of 4000 identical 1 x 24 px bars: about 400,000 outline samples, all within
  // a few 4 px cells. Searched naively each sample would look at every other one (1.6e11
  // tests); the crowded cells are skipped, so no thin part is found and the outline alone
  // remains (it is not a colour discontinuity of its own: every copy covers the same pixels).
  std::string d;
  for (int k = 0; k < 4000; ++k) d += "M 20 8 h 1 v 24 h -1 z ";
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"48\" height=\"40\">"
      "<rect width=\"48\" height=\"40\" fill=\"white\"/><path d=\"" + d + "\" fill=\"black\"/></svg>");
  const auto [reference, traced] = RenderAndTrace(doc, 48, 40);
  REQUIRE(traced.shapes.size() == 1);
  CHECK(traced.shapes[0].outlines.size() == 4000);
  sdvi::SvgArtworkOptions options;
  for (const sdvi::FeatureCurve& c : sdvi::ArtworkFeatures(traced.shapes, reference, options)) CHECK(c.width == 0);
}

TEST_CASE("svg geometry: text comes as glyph outlines; glyphs drawn from a font are counted", "[svg]") {
  // librsvg fills the glyphs' outlines: the trace has them and no show-glyphs.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"64\" height=\"32\">"
      "<text x=\"4\" y=\"24\" font-family=\"DejaVu Sans, sans-serif\" font-size=\"20\">mop</text></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 64, 32);
  INFO("incomplete: " << traced.incomplete);
  CHECK(traced.incomplete.empty());
  CHECK(traced.glyph_runs == 0);
  REQUIRE(traced.shapes.size() == 1);
  CHECK(traced.shapes[0].outlines.size() >= 4);  // m, o and its counter, p and its counter
  // A script that draws text from a font (as cairo writes it for cairo_show_glyphs).
  size_t runs = 0;
  const std::vector<sdvi::SvgShape> shapes = sdvi::ReadCairoScript(
      "%!CairoScript\n<< /content //COLOR_ALPHA /width 64 /height 32 >> surface context\n"
      "<< /type 42 /source <|6Pl/b~> >> font-face\n[12 0 0 12 0 0] set-font-matrix\n"
      "[[4 24 <0102>]] show-glyphs\nn 1 1 m 9 1 l 9 9 l h\nfill+\n[[20 24 <03>]] show-glyphs\npop\n",
      &runs);
  CHECK(runs == 2);
  REQUIRE(shapes.size() == 1);
  CHECK(shapes[0].outlines.size() == 1);
}

TEST_CASE("svg geometry: straight-edged fills that are not boxes do not stop the trace", "[svg]") {
  // cairo 1.16's script surface refuses these fills (INVALID_PATH_DATA) and everything after
  // them: a T-shaped polygon, text whose glyphs are all straight ("HI TILT"), then a circle.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"160\" height=\"40\">"
      "<path d=\"M 2 2 H 12 V 6 H 8 V 12 H 6 V 6 H 2 Z\" fill=\"#800000\"/>"
      "<text x=\"20\" y=\"30\" font-family=\"DejaVu Sans, sans-serif\" font-size=\"20\">HI TILT</text>"
      "<circle cx=\"140\" cy=\"20\" r=\"10\" fill=\"#008000\"/></svg>");
  const sdvi::SvgGeometry traced = Traced(doc, 160, 40);
  INFO("incomplete: " << traced.incomplete);
  CHECK(traced.incomplete.empty());
  REQUIRE(traced.shapes.size() == 3);
  // The T: its 8 corners within 0.003 px (the trace turned by 0.01 rad and back, on cairo's
  // 1/256 px grid), in order.
  const std::vector<sdvi::Point2> corners = {{2, 2}, {12, 2}, {12, 6}, {8, 6}, {8, 12}, {6, 12}, {6, 6}, {2, 6}};
  REQUIRE(traced.shapes[0].outlines.size() == 1);
  const sdvi::SvgOutline& t = traced.shapes[0].outlines[0];
  REQUIRE(t.points.size() == 3 * 8 + 1);
  for (size_t k = 0; k < 8; ++k) {
    CHECK(t.points[3 * k].x == Approx(corners[k].x).margin(0.003));
    CHECK(t.points[3 * k].y == Approx(corners[k].y).margin(0.003));
  }
  CHECK(traced.shapes[1].outlines.size() >= 6);  // H, I, T, I, L, T
  REQUIRE(traced.shapes[2].outlines.size() == 1);
  const std::vector<sdvi::Point2>& circle = traced.shapes[2].outlines[0].points;
  for (size_t k = 0; k < circle.size(); k += 3) {  // the segments' ends lie on the circle
    CHECK(std::hypot(circle[k].x - 140, circle[k].y - 20) == Approx(10).margin(0.01));
  }
}

TEST_CASE("svg artwork: crossing hairlines meet at junctions, not cut around the crossing", "[svg][thin][junction]") {
  // A grid of two 1 px lines crossing at (40.5, 32.5), drawn as two strokes on white.
  const sdvi::SvgDocument doc = Doc(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"80\" height=\"64\">"
      "<rect width=\"80\" height=\"64\" fill=\"white\"/>"
      "<path d=\"M 8 32.5 L 72 32.5\" stroke=\"black\" stroke-width=\"1\"/>"
      "<path d=\"M 40.5 6 L 40.5 58\" stroke=\"black\" stroke-width=\"1\"/></svg>");
  const auto [reference, traced] = RenderAndTrace(doc, 80, 64);
  sdvi::SvgArtworkOptions options;
  // The lower line crosses the upper one's claim: it stays one feature through the crossing.
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(traced.shapes, reference, options);
  REQUIRE(curves.size() == 2);
  for (const sdvi::FeatureCurve& c : curves) {
    double y0 = 1e9, y1 = -1e9, x0 = 1e9, x1 = -1e9;
    for (const sdvi::Point2& p : c.points) {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
    CHECK(std::max(x1 - x0, y1 - y0) > 50.0);
  }
  options.vectorize.max_triangles = 2000;
  auto joined = sdvi::ImportSvgArtwork(doc, options);
  INFO(joined.status().ToString());
  REQUIRE(joined.ok());
  options.vectorize.mesh.junctions = false;
  auto cut = sdvi::ImportSvgArtwork(doc, options);
  REQUIRE(cut.ok());
  // PSNR against librsvg over the 13 x 13 pixels around the crossing.
  auto psnr = [&](const sdvi::Raster8& r) {
    double sum = 0;
    int n = 0;
    for (int y = 26; y <= 38; ++y)
      for (int x = 34; x <= 46; ++x)
        for (int c = 0; c < 3; ++c) {
          const double d = double(r.at(x, y, c)) - double(joined->reference.at(x, y, c));
          sum += d * d, ++n;
        }
    return 10 * std::log10(255.0 * 255.0 / std::max(sum / n, 1e-10));
  };
  const double with = psnr(joined->vectorized.reconstruction), without = psnr(cut->vectorized.reconstruction);
  INFO("junctions " << with << " dB, cut " << without << " dB");
  CHECK(with > 30.0);
  CHECK(without < with - 6.0);
}

TEST_CASE("svg artwork: an open stroke with round caps is one closed feature around its outline", "[svg]") {
  // A 10 px wide horizontal line from (24, 32) to (104, 32): its outline is the two sides at
  // y = 27 and 37 and half circles of radius 5 around both ends.
  auto doc_with = [](const std::string& cap) {
    return Doc("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"128\" height=\"64\">"
               "<rect width=\"128\" height=\"64\" fill=\"white\"/>"
               "<line x1=\"24\" y1=\"32\" x2=\"104\" y2=\"32\" stroke=\"black\" stroke-width=\"10\"" +
               cap + "/></svg>");
  };
  const sdvi::SvgDocument round = doc_with(" stroke-linecap=\"round\"");
  const sdvi::SvgGeometry traced = Traced(round, 128, 64);
  // The background covers the surface and is painted, not filled: the stroke is the shape.
  REQUIRE(traced.shapes.size() == 1);
  CHECK(traced.shapes[0].paint == sdvi::SvgPaint::kStroke);
  CHECK(traced.shapes[0].line_cap == sdvi::SvgLineCap::kRound);
  CHECK(Traced(doc_with(" stroke-linecap=\"square\""), 128, 64).shapes[0].line_cap == sdvi::SvgLineCap::kSquare);
  CHECK(Traced(doc_with(""), 128, 64).shapes[0].line_cap == sdvi::SvgLineCap::kButt);

  auto reference = sdvi::RenderSvg(round, 128, 64);
  REQUIRE(reference.ok());
  const std::vector<sdvi::FeatureCurve> curves = sdvi::ArtworkFeatures(traced.shapes, *reference, {});
  REQUIRE(curves.size() == 1);
  CHECK(curves[0].closed);
  CHECK(curves[0].width == 0);
  // The spline follows the outline: distance 5 from the centre segment, within 0.5 px.
  double x_min = 1e9, x_max = -1e9;
  for (const sdvi::Point2& p : sdvi::SampleFeatureCurve(curves[0])) {
    const double dx = std::max({24.0 - p.x, 0.0, p.x - 104.0});
    CHECK(std::hypot(dx, p.y - 32) == Approx(5).margin(0.5));
    x_min = std::min(x_min, p.x), x_max = std::max(x_max, p.x);
  }
  CHECK(x_min < 19.5);  // around both caps
  CHECK(x_max > 108.5);

  // A butt-capped one keeps its two sides as open features.
  const sdvi::SvgDocument butt = doc_with("");
  auto butt_reference = sdvi::RenderSvg(butt, 128, 64);
  REQUIRE(butt_reference.ok());
  const std::vector<sdvi::FeatureCurve> sides =
      sdvi::ArtworkFeatures(Traced(butt, 128, 64).shapes, *butt_reference, {});
  REQUIRE(sides.size() == 2);
  CHECK_FALSE(sides[0].closed);
  CHECK_FALSE(sides[1].closed);
}

TEST_CASE("svg artwork: a small ring keeps its hole (a glyph's counter)", "[svg]") {
  // Black rings 2.5 px wide around holes of radius 4, 16 px apart (a row of 'o's at 30 px):
  // each hole a closed outline whose few deBoor points (4 fit it within 0.5 px) lay 2 px
  // outside it, within the clearance of the ring's outer outline, so the mesh cut the hole
  // out and it was filled grey. With the polygon within polygon_offset of its curve the
  // hole is a feature and stays white.
  std::string body;
  for (int k = 0; k < 4; ++k) {
    const double cx = 10.3 + 16 * k, cy = 16.6;
    char ring[256];
    std::snprintf(ring, sizeof ring,
                  "<path fill-rule=\"evenodd\" d=\"M %g %g a 6.5 6.5 0 1 0 13 0 a 6.5 6.5 0 1 0 -13 0 z "
                  "M %g %g a 4 4 0 1 0 8 0 a 4 4 0 1 0 -8 0 z\"/>",
                  cx - 6.5, cy, cx - 4, cy);
    body += ring;
  }
  const sdvi::SvgDocument doc = Doc("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"72\" height=\"32\">"
                                    "<rect width=\"72\" height=\"32\" fill=\"white\"/>" + body + "</svg>");
  const auto [reference, traced] = RenderAndTrace(doc, 72, 32);
  sdvi::SvgArtworkOptions options;
  size_t holes = 0;
  for (const sdvi::FeatureCurve& c : sdvi::ArtworkFeatures(traced.shapes, reference, options)) {
    CHECK(sdvi::PolygonOffset(c.points, c.closed) <= options.polygon_offset);
    // A hole's spline: within 0.5 px of radius 4 around its ring's centre.
    const std::vector<sdvi::Point2> spline = sdvi::SampleFeatureCurve(c);
    const double cx = 10.3 + 16 * std::floor(spline[0].x / 16);
    holes += c.closed && std::all_of(spline.begin(), spline.end(), [&](sdvi::Point2 p) {
               return std::fabs(std::hypot(p.x - cx, p.y - 16.6) - 4) < 0.5;
             });
  }
  CHECK(holes == 4);
  options.vectorize.compression_ratio = 16;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  REQUIRE(result.ok());
  for (int k = 0; k < 4; ++k) {
    // The hole's centre is white in librsvg's drawing and in the import.
    const int x = int(10.3 + 16 * k), y = 16;
    INFO("ring " << k);
    CHECK(reference.at(x, y, 0) > 250);
    for (int c = 0; c < 3; ++c) CHECK(result->vectorized.reconstruction.at(x, y, c) > 230);
  }
}

TEST_CASE("svg artwork: a hairline 2 px above a black edge keeps its feature", "[svg][thin]") {
  // A grey 1 px line (y = 10..11) above a black bar whose top edge is at y = 12.75: the text
  // of a W3C test on its grid. The line's polylines (+-1 px around y = 10.5) and the edge's
  // pair (y = 12.25 and 13.25) are 0.75 px apart: with the vectorizer's 1 px clearance the
  // line was cut out where it runs along the bar and its pixels were left to the interior;
  // with the artwork's 0.5 px both are features and the line stays grey.
  const sdvi::SvgDocument doc =
      Doc("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"64\" height=\"32\">"
          "<rect width=\"64\" height=\"32\" fill=\"white\"/>"
          "<path d=\"M 4 10.5 L 60 10.5\" stroke=\"#cccccc\" stroke-width=\"1\"/>"
          "<rect x=\"12\" y=\"12.75\" width=\"40\" height=\"8\" fill=\"black\"/></svg>");
  sdvi::SvgArtworkOptions options;
  CHECK(options.vectorize.mesh.clearance == 0.5f);
  options.vectorize.compression_ratio = 16;
  auto result = sdvi::ImportSvgArtwork(doc, options);
  REQUIRE(result.ok());
  double worst = 0;
  for (int x = 14; x < 50; ++x) {
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, double(std::fabs(result->vectorized.reconstruction.at(x, 10, c) -
                                               result->reference.at(x, 10, c))));
  }
  INFO("largest error on the line above the bar " << worst);
  CHECK(worst < 4);  // measured: 0.03; 9.8 with a 1 px clearance
}
