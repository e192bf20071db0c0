// SPDX-License-Identifier: GPL-3.0-or-later
// EXR output: opens in exrheader and OpenCV, matches the PNG within quantization.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "render_meshes.h"
#include "sdvi/exr_io.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"

using namespace sdvi;

namespace {

using test::TempPath;

// An object image: a coloured 12-gon with anti-aliased edges on a transparent background.
Raster ObjectRender() {
  std::vector<Vertex> v = {{16, 12, 250, 128, 10}};
  std::vector<Triangle> t;
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * M_PI * k / 12;
    v.push_back({float(16 + 11 * std::cos(a)), float(12 + 9 * std::sin(a)), float(20 * k), float(255 - 20 * k), 90});
  }
  for (uint32_t k = 0; k < 12; ++k) t.push_back({{0, 1 + k, 1 + (k + 1) % 12}});
  const std::vector<Edge> boundary = MeshBoundaryEdges(t);
  return RenderFineMesh(t, v, Viewport{64, 48, 2, 2, 0, 0}, &boundary);
}
}  // namespace

TEST_CASE("sRGB transfer functions invert each other", "[exr]") {
  for (double v : {0.0, 1.0, 10.0, 10.3, 100.0, 254.0, 255.0}) CHECK(LinearToSrgb(SrgbToLinear(v)) == Approx(v).margin(1e-9));
  CHECK(SrgbToLinear(255) == Approx(1.0));
  CHECK(SrgbToLinear(128) == Approx(0.2158605).epsilon(1e-5));
}

TEST_CASE("EXR opens in exrheader and OpenCV and matches the PNG within quantization", "[exr]") {
  const Raster render = ObjectRender();
  const std::string png = TempPath("object.png");
  REQUIRE(SaveRasterPng(png, render).ok());
  auto png_back = LoadRaster(png);
  REQUIRE(png_back.ok());
  Raster reference = render;
  for (size_t p = 0; p < reference.data.size(); p += 4) reference.data[p] = std::min(255.0f, reference.data[p] + 6);
  auto error = ErrorChannel(render, reference);
  REQUIRE(error.ok());
  for (bool half : {false, true}) {
    INFO((half ? "half" : "float"));
    const std::string exr = TempPath(half ? "object_half.exr" : "object_float.exr");
    ExrWriteOptions opts;
    opts.half = half;
    opts.error = &*error;
    REQUIRE(SaveExr(exr, render, opts).ok());
    // exrheader (Debian package openexr) reads it and lists our channels.
    const std::string listing = TempPath("exrheader.txt");
    const int rc = std::system(("exrheader '" + exr + "' > '" + listing + "' 2>&1").c_str());
    REQUIRE(rc == 0);
    std::FILE* f = std::fopen(listing.c_str(), "r");
    REQUIRE(f);
    std::string text(8192, '\0');
    text.resize(std::fread(text.data(), 1, text.size(), f));
    std::fclose(f);
    CHECK(text.find("error, ") != std::string::npos);
    CHECK(text.find(half ? "16-bit floating-point" : "32-bit floating-point") != std::string::npos);
    // Read back: unpremultiply, encode sRGB, compare with the 8-bit PNG.
    auto back = LoadExr(exr);
    REQUIRE(back.ok());
    REQUIRE(back->rgba.width == render.width);
    REQUIRE(back->error.size() == error->size());
    int worst_pixel = -1;
    double worst = 0;
    for (size_t p = 0; p < size_t(render.width) * render.height; ++p) {
      const float a = back->rgba.data[p * 4 + 3];
      CHECK(a == Approx(png_back->data[p * 4 + 3]).margin(half ? 1.5 / 255 : 0.5 / 255));
      CHECK(back->error[p] == Approx((*error)[p]).margin(half ? 0.01 : 1e-6));
      if (a < 1.0f / 255) continue;
      for (int c = 0; c < 3; ++c) {
        const double srgb = LinearToSrgb(back->rgba.data[p * 4 + c] / a);
        const double d = std::abs(srgb - png_back->data[p * 4 + c]);
        if (d > worst) worst = d, worst_pixel = int(p);
      }
    }
    INFO("worst difference " << worst << " at pixel " << worst_pixel);
    CHECK(worst <= (half ? 1.0 : 0.5 + 1e-3));
    // OpenCV reads the same file (BGRA float).
    setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 1);
    cv::Mat mat = cv::imread(exr, cv::IMREAD_UNCHANGED);
    REQUIRE(!mat.empty());
    CHECK(mat.cols == render.width);
    CHECK(mat.rows == render.height);
    REQUIRE(mat.depth() == CV_32F);
    REQUIRE(mat.channels() >= 3);
    const int p = (render.height / 2) * render.width + render.width / 2;
    const float* px = mat.ptr<float>(render.height / 2) + size_t(render.width / 2) * mat.channels();
    CHECK(px[2] == Approx(back->rgba.data[size_t(p) * 4 + 0]).margin(1e-6));
    CHECK(px[0] == Approx(back->rgba.data[size_t(p) * 4 + 2]).margin(1e-6));
    std::filesystem::remove(exr);
    std::filesystem::remove(listing);
  }
  std::filesystem::remove(png);
}

TEST_CASE("EXR I/O reports bad input with specific codes", "[exr][errors]") {
  CHECK(LoadExr(TempPath("missing.exr")).status().code() == StatusCode::kNotFound);
  const std::string junk = TempPath("junk.exr");
  REQUIRE(SaveRasterPng(junk, Raster(2, 2, 3)).ok());  // a PNG named .exr
  CHECK(LoadExr(junk).status().code() == StatusCode::kDecodeFailed);
  std::filesystem::remove(junk);
  CHECK(SaveExr(TempPath("e.exr"), Raster()).code() == StatusCode::kEmptyInput);
  std::vector<float> wrong(3);
  ExrWriteOptions opts;
  opts.error = &wrong;
  CHECK(SaveExr(TempPath("e.exr"), Raster(4, 4, 4), opts).code() == StatusCode::kInvalidArgument);
  CHECK(!std::filesystem::exists(TempPath("e.exr")));
  CHECK(SaveExr("/nonexistent-dir/x.exr", Raster(4, 4, 4)).code() != StatusCode::kOk);
  CHECK(ErrorChannel(Raster(4, 4, 3), Raster(5, 4, 3)).status().code() == StatusCode::kInvalidArgument);
}

TEST_CASE("EXR of a region keeps its data window inside the whole render's display window", "[exr]") {
  Raster region(7, 5, 3);
  for (size_t i = 0; i < region.data.size(); ++i) region.data[i] = float(i * 29 % 256);
  ExrWriteOptions opts;
  opts.data_x = 40, opts.data_y = -3;  // a region may start outside the image
  opts.display_width = 120, opts.display_height = 90;
  const std::string path = TempPath("region.exr");
  REQUIRE(SaveExr(path, region, opts).ok());
  auto back = LoadExr(path);
  REQUIRE(back.ok());
  CHECK(back->data_x == 40);
  CHECK(back->data_y == -3);
  CHECK(back->display_width == 120);
  CHECK(back->display_height == 90);
  CHECK_FALSE(back->has_alpha);  // RGB in, RGB out
  REQUIRE(back->rgba.width == 7);
  REQUIRE(back->rgba.height == 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x)
      for (int c = 0; c < 3; ++c)
        CHECK(LinearToSrgb(back->rgba.at(x, y, c)) == Approx(region.at(x, y, c)).margin(1e-3));
  // Without a window the data window is the display window at the origin.
  REQUIRE(SaveExr(path, region).ok());
  back = LoadExr(path);
  REQUIRE(back.ok());
  CHECK(back->data_x == 0);
  CHECK(back->data_y == 0);
  CHECK(back->display_width == 7);
  std::filesystem::remove(path);
}
