// SPDX-License-Identifier: GPL-3.0-or-later
// Curves mode (spec/CURVES.md): the sdvi attributes are read, each side's colour is
// reproduced away from the curve, the transition widens as sharpness falls, bad attributes
// are specific errors, and the example drawings in examples/curves import and render like
// the renders committed beside them.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/svg.h"

namespace {

std::string Drawing(const std::string& attributes, const std::string& extra = "") {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:c=\"https://sdvi.dev/ns/curves/1\" width=\"64\" "
         "height=\"64\"><path id=\"edge\" d=\"M 32 -4 L 32 68\" fill=\"none\" stroke=\"black\" " +
         attributes + "/>" + extra + "</svg>";
}

sdvi::StatusOr<sdvi::SvgCurvesResult> Import(const std::string& bytes, sdvi::SvgError* error = nullptr) {
  auto document = sdvi::LoadSvg(bytes, "curves.svg", {});
  if (!document.ok()) return document.status();
  return sdvi::ImportSvgCurves(*document, {}, error);
}

sdvi::Raster RenderScaled(const sdvi::Image& image, int width, int height, int scale) {
  sdvi::RenderOptions options;
  options.viewport = sdvi::Viewport{width * scale, height * scale, double(scale), double(scale), 0, 0};
  auto raster = sdvi::Render(image, options);
  REQUIRE(raster.ok());
  return *raster;
}

// Width in px (output pixels / scale) over which the red channel along row y goes from 10%
// to 90% of its step between x = 8 and x = 56.
double TransitionWidth(const sdvi::Raster& r, int scale) {
  const int y = 32 * scale;
  const float a = r.at(8 * scale, y, 0), b = r.at(56 * scale, y, 0);
  double x10 = -1, x90 = -1;
  for (int x = 8 * scale; x < 56 * scale; ++x) {
    const double t = (r.at(x, y, 0) - a) / (b - a);
    if (x10 < 0 && t >= 0.1) x10 = x;
    if (x90 < 0 && t >= 0.9) x90 = x;
  }
  return (x90 - x10) / scale;
}

}  // namespace

TEST_CASE("svg curves: each side's colour away from the curve", "[svg][curves]") {
  // Walking down the screen, the left side is +x.
  auto result = Import(Drawing("c:left-color=\"#e03020\" c:right-color=\"rgb(32, 64, 192)\""));
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  CHECK(result->curves == 1);
  CHECK(result->width == 64);
  const sdvi::Raster r = RenderScaled(result->image, 64, 64, 1);
  // 20 px from the curve; the harmonic fill lets a little of the other side through around
  // the curve's clipped ends (spec/CURVES.md: measured leak), hence 4 units.
  for (int y : {8, 32, 56}) {
    CHECK(r.at(52, y, 0) == Approx(0xe0).margin(4));
    CHECK(r.at(52, y, 1) == Approx(0x30).margin(4));
    CHECK(r.at(52, y, 2) == Approx(0x20).margin(4));
    CHECK(r.at(12, y, 0) == Approx(32).margin(4));
    CHECK(r.at(12, y, 1) == Approx(64).margin(4));
    CHECK(r.at(12, y, 2) == Approx(192).margin(4));
  }
}

TEST_CASE("svg curves: the transition across a curve widens as sharpness falls", "[svg][curves]") {
  double previous = 0;
  for (const char* sharpness : {"1", "0.5", "0"}) {
    auto result = Import(Drawing(std::string("c:left-color=\"white\" c:right-color=\"black\" c:sharpness=\"") +
                                 sharpness + "\""));
    REQUIRE(result.ok());
    const double width = TransitionWidth(RenderScaled(result->image, 64, 64, 4), 4);
    INFO("sharpness " << sharpness << ": transition " << width << " px");
    CHECK(width > previous + 0.5);
    previous = width;
  }
}

TEST_CASE("svg curves: colour keywords, percentages and stops", "[svg][curves]") {
  auto result = Import(Drawing("c:left-color=\"green\" c:right-color=\"0 red; 100% rgb(0%, 0%, 100%)\""));
  INFO(result.status().ToString());
  REQUIRE(result.ok());
  const sdvi::Raster r = RenderScaled(result->image, 64, 64, 1);
  CHECK(r.at(52, 32, 0) == Approx(0).margin(2));
  CHECK(r.at(52, 32, 1) == Approx(128).margin(2));  // CSS green, not X11's
  // The right side runs from red at the top to blue at the bottom (diffused 20 px away).
  CHECK(r.at(12, 4, 0) > r.at(12, 60, 0) + 80);
  CHECK(r.at(12, 60, 2) > r.at(12, 4, 2) + 80);
}

TEST_CASE("svg curves: bad attributes name the element and the attribute", "[svg][curves]") {
  sdvi::SvgError error = sdvi::SvgError::kNone;
  auto bad_colour = Import(Drawing("c:left-color=\"#12345\""), &error);
  REQUIRE_FALSE(bad_colour.ok());
  CHECK(error == sdvi::SvgError::kBadCurveAttribute);
  CHECK(bad_colour.status().code() == sdvi::StatusCode::kInvalidArgument);
  CHECK(bad_colour.status().message().find("id=\"edge\"") != std::string::npos);
  CHECK(bad_colour.status().message().find("sdvi:left-color") != std::string::npos);

  auto bad_sharpness = Import(Drawing("c:left-color=\"red\" c:sharpness=\"1.5\""), &error);
  REQUIRE_FALSE(bad_sharpness.ok());
  CHECK(error == sdvi::SvgError::kBadCurveAttribute);
  CHECK(bad_sharpness.status().message().find("sdvi:sharpness") != std::string::npos);

  auto decreasing = Import(Drawing("c:left-color=\"0.6 red; 0.2 blue\""), &error);
  REQUIRE_FALSE(decreasing.ok());
  CHECK(decreasing.status().message().find("must not decrease") != std::string::npos);

  auto none = Import("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"8\" height=\"8\"><rect width=\"4\" "
                     "height=\"4\"/></svg>",
                     &error);
  REQUIRE_FALSE(none.ok());
  CHECK(error == sdvi::SvgError::kNoCurves);
  CHECK(none.status().code() == sdvi::StatusCode::kEmptyInput);
}

TEST_CASE("svg curves: elements without attributes are skipped with a warning", "[svg][curves]") {
  auto result = Import(Drawing("c:left-color=\"red\" c:right-color=\"blue\"",
                               "<circle id=\"plain\" cx=\"10\" cy=\"10\" r=\"3\"/><defs><rect id=\"d\" "
                               "width=\"3\" height=\"3\" c:left-color=\"red\"/></defs>"));
  REQUIRE(result.ok());
  CHECK(result->curves == 1);
  REQUIRE(result->warnings.size() == 1);
  CHECK(result->warnings[0].find("id=\"plain\"") != std::string::npos);
}

TEST_CASE("svg curves: the example drawings import and render like their committed renders", "[svg][curves]") {
  const std::filesystem::path dir = SDVI_EXAMPLES_DIR "/curves";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".svg") continue;
    const std::filesystem::path png = entry.path().parent_path() / (entry.path().stem().string() + ".png");
    INFO(entry.path());
    auto document = sdvi::LoadSvgFile(entry.path().string(), {});
    REQUIRE(document.ok());
    auto result = sdvi::ImportSvgCurves(*document, {});
    INFO(result.status().ToString());
    REQUIRE(result.ok());
    CHECK(result->curves > 0);
    if (!std::filesystem::exists(png)) continue;
    auto committed = sdvi::LoadRaster(png.string());
    REQUIRE(committed.ok());
    REQUIRE(committed->width == result->width);
    REQUIRE(committed->height == result->height);
    const sdvi::Raster rendered = RenderScaled(result->image, result->width, result->height, 1);
    auto metrics = sdvi::CompareImages(rendered, *committed);
    REQUIRE(metrics.ok());
    INFO("PSNR " << metrics->psnr);
    CHECK(metrics->psnr > 35.0);
    ++count;
  }
  CHECK(count >= 3);
}
