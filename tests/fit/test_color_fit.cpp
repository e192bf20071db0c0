// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the colour least squares (color_fit.h): exact reproduction through the
// renderer, constants, linear precision, unseen vertices, determinism, bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "grid_triangles.h"
#include "sdvi/color_fit.h"
#include "sdvi/render.h"

namespace {

// A width x height image covered by a grid of (n+1) x (n+1) control vertices with
// diagonals alternating, the four image corners tagged corner, and (optionally) a vertical
// crease polyline through the middle column whose ends on the border are corners.
sdvi::Image GridImage(int width, int height, int n, bool crease) {
  sdvi::Image image;
  image.width = uint32_t(width);
  image.height = uint32_t(height);
  auto id = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      sdvi::Vertex v;
      v.x = float(width) * i / n;
      v.y = float(height) * j / n;
      image.vertices.push_back(v);
    }
  }
  sdvi::testing::AppendGridTriangles(n, n, id, &image.triangles);
  image.corners = {id(0, 0), id(n, 0), id(0, n), id(n, n)};
  if (crease) {
    const int mid = n / 2;
    for (int j = 0; j < n; ++j) image.crease_edges.push_back(sdvi::Edge::Of(id(mid, j), id(mid, j + 1)));
  }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  std::sort(image.corners.begin(), image.corners.end());
  return image;
}

// Deterministic colours in 20..235 (so that no rendered value is clamped).
void PaintPseudoRandom(sdvi::Image& image) {
  uint32_t state = 12345;
  auto next = [&state]() {
    state = state * 1664525u + 1013904223u;
    return 20.f + 215.f * float(state >> 8) / float(1u << 24);
  };
  for (sdvi::Vertex& v : image.vertices) {
    v.r = next();
    v.g = next();
    v.b = next();
  }
}

// The image rendered at its own size at level `levels`, as a colour fit's target.
sdvi::Raster RenderedTarget(const sdvi::Image& image, int levels, bool antialias = true) {
  sdvi::RenderOptions render;
  render.viewport = sdvi::Viewport::Identity(int(image.width), int(image.height));
  render.levels = levels;
  render.antialias = antialias;
  auto target = sdvi::Render(image, render);
  INFO(target.status().ToString());
  REQUIRE(target.ok());
  return std::move(*target);
}

sdvi::Raster ConstantRaster(int width, int height, float r, float g, float b) {
  sdvi::Raster raster(width, height, 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      raster.at(x, y, 0) = r;
      raster.at(x, y, 1) = g;
      raster.at(x, y, 2) = b;
    }
  }
  return raster;
}

double MaxColorDifference(const sdvi::Image& a, const sdvi::Image& b) {
  double worst = 0;
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    worst = std::max({worst, std::abs(double(a.vertices[i].r) - b.vertices[i].r),
                      std::abs(double(a.vertices[i].g) - b.vertices[i].g),
                      std::abs(double(a.vertices[i].b) - b.vertices[i].b)});
  }
  return worst;
}

}  // namespace

TEST_CASE("colour fit reproduces the colours of a rendered image on the same mesh", "[color_fit]") {
  sdvi::Image truth = GridImage(64, 64, 8, /*crease=*/true);
  PaintPseudoRandom(truth);
  const sdvi::Raster target = RenderedTarget(truth, 2, /*antialias=*/false);

  sdvi::Image fitted = truth;
  for (sdvi::Vertex& v : fitted.vertices) v.r = v.g = v.b = 0;
  sdvi::ColorFitOptions options;
  options.regularization = 1e-9;
  auto fit = sdvi::FitColors(fitted, target, nullptr, options);
  REQUIRE(fit.ok());
  CHECK(fit->domain_pixels == 64u * 64u);
  CHECK(MaxColorDifference(fitted, truth) < 2e-3);
  CHECK(fit->sum_squared_error < 1e-4 * 64 * 64);
  // Positions are not touched.
  for (size_t i = 0; i < truth.vertices.size(); ++i) {
    CHECK(fitted.vertices[i].x == truth.vertices[i].x);
    CHECK(fitted.vertices[i].y == truth.vertices[i].y);
  }
}

TEST_CASE("colour fit of a constant image is that constant", "[color_fit]") {
  sdvi::Image image = GridImage(48, 40, 6, /*crease=*/true);
  const sdvi::Raster target = ConstantRaster(48, 40, 100.f, 150.f, 200.f);
  auto fit = sdvi::FitColors(image, target, nullptr, sdvi::ColorFitOptions{});
  REQUIRE(fit.ok());
  for (const sdvi::Vertex& v : image.vertices) {
    CHECK(v.r == Approx(100.f).margin(1e-3));
    CHECK(v.g == Approx(150.f).margin(1e-3));
    CHECK(v.b == Approx(200.f).margin(1e-3));
  }
}

TEST_CASE("colour fit has linear precision at the limit and on the control mesh", "[color_fit]") {
  sdvi::Raster ramp(64, 48, 3);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      ramp.at(x, y, 0) = 20.f + 3.f * (x + 0.5f);
      ramp.at(x, y, 1) = 30.f + 4.f * (y + 0.5f);
      ramp.at(x, y, 2) = 40.f + 1.5f * (x + 0.5f) + 1.5f * (y + 0.5f);
    }
  }
  for (int levels : {0, 2}) {
    sdvi::Image image = GridImage(64, 48, 8, /*crease=*/false);
    sdvi::ColorFitOptions options;
    options.surface.levels = levels;
    options.surface.to_limit = levels > 0;
    options.regularization = 1e-8;  // the Laplacian of a ramp is not zero on the border
    auto fit = sdvi::FitColors(image, ramp, nullptr, options);
    REQUIRE(fit.ok());
    const double mse = fit->sum_squared_error / (3.0 * double(fit->domain_pixels));
    INFO("levels " << levels << " mse " << mse);
    CHECK(mse < 1e-4);
    // The control colours are the ramp at the control positions.
    for (const sdvi::Vertex& v : image.vertices) {
      CHECK(v.r == Approx(20.f + 3.f * v.x).margin(0.02));
      CHECK(v.g == Approx(30.f + 4.f * v.y).margin(0.02));
    }
  }
}

TEST_CASE("vertices no pixel sees get finite regularised colours", "[color_fit]") {
  sdvi::Image image = GridImage(64, 64, 8, /*crease=*/false);
  const sdvi::Raster target = ConstantRaster(64, 64, 80.f, 90.f, 100.f);
  // Object mask: only the left quarter of the image is in the domain.
  sdvi::Raster mask(64, 64, 1);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 16; ++x) mask.at(x, y, 0) = 255.f;
  }
  auto fit = sdvi::FitColors(image, target, &mask, sdvi::ColorFitOptions{});
  REQUIRE(fit.ok());
  CHECK(fit->domain_pixels == 16u * 64u);
  for (const sdvi::Vertex& v : image.vertices) {
    REQUIRE(std::isfinite(v.r));
    REQUIRE(std::isfinite(v.g));
    REQUIRE(std::isfinite(v.b));
    // Harmonic extension of a constant is that constant.
    CHECK(v.r == Approx(80.f).margin(0.05));
    CHECK(v.b == Approx(100.f).margin(0.05));
  }
}

TEST_CASE("colour fit does not depend on the thread count", "[color_fit]") {
  sdvi::Image truth = GridImage(96, 80, 12, /*crease=*/true);
  PaintPseudoRandom(truth);
  const sdvi::Raster target = RenderedTarget(truth, 3);
  sdvi::Image one = truth, three = truth;
  sdvi::ColorFitOptions options;
  options.threads = 1;
  REQUIRE(sdvi::FitColors(one, target, nullptr, options).ok());
  options.threads = 3;
  REQUIRE(sdvi::FitColors(three, target, nullptr, options).ok());
  CHECK(one == three);
}

TEST_CASE("colour fit with buffers from an earlier fit gives the same result", "[color_fit]") {
  // Buffers that held a different fit's coverage (another mesh, another size of array):
  // the result must be that of a fit without buffers, field by field.
  sdvi::Image truth = GridImage(96, 80, 12, /*crease=*/true);
  PaintPseudoRandom(truth);
  const sdvi::Raster target = RenderedTarget(truth, 3);
  sdvi::ColorFitOptions options;
  sdvi::ColorFitBuffers buffers;
  sdvi::Image coarse = GridImage(96, 80, 3, /*crease=*/false);
  auto first = sdvi::FitColors(coarse, target, nullptr, options, &buffers);
  REQUIRE(first.ok());
  buffers.coverage = std::move(first->coverage.owner);
  for (uint32_t& owner : buffers.coverage) owner = 7;  // stale contents
  sdvi::Image plain = truth, reused = truth;
  auto a = sdvi::FitColors(plain, target, nullptr, options);
  auto b = sdvi::FitColors(reused, target, nullptr, options, &buffers);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(plain == reused);
  CHECK(a->sum_squared_error == b->sum_squared_error);
  CHECK(a->domain_pixels == b->domain_pixels);
  CHECK(a->coverage.owner == b->coverage.owner);
  CHECK(a->coverage.corners == b->coverage.corners);
}

TEST_CASE("reconstruction draws the fitted colours on covered pixels", "[color_fit]") {
  sdvi::Image image = GridImage(32, 32, 4, /*crease=*/false);
  const sdvi::Raster target = ConstantRaster(32, 32, 10.f, 20.f, 30.f);
  auto fit = sdvi::FitColors(image, target, nullptr, sdvi::ColorFitOptions{});
  REQUIRE(fit.ok());
  const sdvi::Raster rec = sdvi::ReconstructRaster(*fit);
  REQUIRE(rec.channels == 4);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) {
      CHECK(rec.at(x, y, 3) == 1.f);
      CHECK(rec.at(x, y, 1) == Approx(20.f).margin(1e-3));
    }
  }
}

TEST_CASE("colour fit rejects mismatched sizes and bad options", "[color_fit]") {
  sdvi::Image image = GridImage(32, 32, 4, /*crease=*/false);
  const sdvi::Raster small = ConstantRaster(16, 32, 1.f, 2.f, 3.f);
  auto wrong_size = sdvi::FitColors(image, small, nullptr, sdvi::ColorFitOptions{});
  REQUIRE_FALSE(wrong_size.ok());
  CHECK(wrong_size.status().code() == sdvi::StatusCode::kInvalidArgument);

  const sdvi::Raster target = ConstantRaster(32, 32, 1.f, 2.f, 3.f);
  sdvi::ColorFitOptions bad;
  bad.regularization = -1;
  CHECK(sdvi::FitColors(image, target, nullptr, bad).status().code() ==
        sdvi::StatusCode::kInvalidArgument);

  const sdvi::Raster bad_mask = ConstantRaster(8, 8, 1.f, 1.f, 1.f);
  CHECK(sdvi::FitColors(image, target, &bad_mask, sdvi::ColorFitOptions{}).status().code() ==
        sdvi::StatusCode::kInvalidArgument);

  sdvi::Image broken = image;
  broken.triangles.push_back({{0, 0, 1}});  // degenerate
  CHECK_FALSE(sdvi::FitColors(broken, target, nullptr, sdvi::ColorFitOptions{}).ok());

  sdvi::Image empty;
  empty.width = 32;
  empty.height = 32;
  CHECK(sdvi::FitColors(empty, target, nullptr, sdvi::ColorFitOptions{}).status().code() ==
        sdvi::StatusCode::kEmptyInput);
}
