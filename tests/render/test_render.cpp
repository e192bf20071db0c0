// SPDX-License-Identifier: GPL-3.0-or-later
// Render: the limit surface of an Image at any scale (spec/METHOD.md section 4).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "render_meshes.h"
#include "sdvi/render.h"

using namespace sdvi;
using sdvi::test::AddColumnCrease;
using sdvi::test::BoxDownsample;
using sdvi::test::GridImage;
using sdvi::test::GridSpec;
using sdvi::test::Lcg;
using sdvi::test::Steps;

namespace {

RenderOptions AtScale(const Image& img, double scale, int levels = -1) {
  RenderOptions o;
  o.viewport.width = int(std::floor(img.width * scale));
  o.viewport.height = int(std::floor(img.height * scale));
  o.viewport.scale_x = o.viewport.scale_y = scale;
  o.levels = levels;
  return o;
}

// A pair of vertical feature polylines at x = 24 -+ d/2 on a 48 x 24 image (d = rho (1 -
// sharpness), rho = 5, floor 0.25): colour 20 on the left, 230 on the right.
Image PairImage(double sharpness) {
  const double d = std::max(0.25, 5.0 * (1.0 - sharpness));
  GridSpec spec;
  spec.xs = {0, 6, 12, 18, 24 - d / 2, 24 + d / 2, 30, 36, 42, 48};
  spec.ys = Steps(0, 24, 6);
  spec.colour = [d](double x, double) {
    const float v = x <= 24 - d / 2 + 1e-6 ? 20.f : 230.f;
    return std::array<float, 3>{v, v, v};
  };
  Image img = GridImage(spec);
  AddColumnCrease(img, 10, 7, 4);
  AddColumnCrease(img, 10, 7, 5);
  return img;
}

// 10%-90% width of the step along the middle row, in source pixels.
double StepWidth(const Raster& r, double scale) {
  const int j = r.height / 2;
  auto level = [&](double t) {
    for (int i = 0; i + 1 < r.width; ++i) {
      const double a = (r.at(i, j, 0) - 20) / 210, b = (r.at(i + 1, j, 0) - 20) / 210;
      if (a < t && b >= t) return i + 0.5 + (t - a) / (b - a);
    }
    return -1.0;
  };
  return (level(0.9) - level(0.1)) / scale;
}

// A 40 x 32 image with a smooth colour field, jittered vertices and a soft feature pair
// (sharpness 0.5, distance 2.5 px) with an 80-unit colour step.
Image FeatureImage() {
  Lcg rng(11);
  GridSpec spec;
  spec.xs = {0, 5, 10, 15, 18.75, 21.25, 25, 30, 35, 40};
  spec.ys = Steps(0, 32, 8);
  spec.jitter = [&](double, double) {
    return std::array<double, 2>{(rng.Next() - 0.5) * 1.0, (rng.Next() - 0.5) * 2.0};
  };
  spec.colour = [](double x, double y) {
    const double base = 100 + 60 * std::sin(x / 7) * std::cos(y / 5) + (x > 20 ? 80 : 0);
    return std::array<float, 3>{float(base), float(255 - base), float(0.5 * base + 40)};
  };
  Image img = GridImage(spec);
  AddColumnCrease(img, 10, 9, 4);
  AddColumnCrease(img, 10, 9, 5);
  return img;
}

}  // namespace

TEST_CASE("A constant-colour mesh renders exactly that colour on every domain pixel", "[render]") {
  Lcg rng(5);
  GridSpec spec;
  spec.xs = Steps(0, 29, 7);
  spec.ys = Steps(0, 19, 5);
  spec.jitter = [&](double, double) { return std::array<double, 2>{rng.Next() * 2 - 1, rng.Next() * 2 - 1}; };
  spec.colour = [](double, double) { return std::array<float, 3>{37, 101, 203}; };
  const Image img = GridImage(spec);
  for (double scale : {1.0, 2.5, 0.7}) {
    auto r = Render(img, AtScale(img, scale, 3));
    REQUIRE(r.ok());
    INFO("scale " << scale);
    int off = 0;
    for (size_t p = 0; p < r->data.size() / 4; ++p) {
      const float* px = &r->data[p * 4];
      off += px[3] != 1.0f || std::abs(px[0] - 37) > 1e-3f || std::abs(px[1] - 101) > 1e-3f ||
             std::abs(px[2] - 203) > 1e-3f;
    }
    CHECK(off == 0);  // the rectangle is the domain: every pixel, alpha 1
  }
}

TEST_CASE("A sharp pair renders a step whose width shrinks with sharpness", "[render][pair]") {
  double previous = 1e9;
  for (double s : {0.0, 0.5, 0.8, 0.95}) {
    const Image img = PairImage(s);
    auto r = Render(img, AtScale(img, 4, 3));
    REQUIRE(r.ok());
    const double d = std::max(0.25, 5.0 * (1.0 - s));
    const double width = StepWidth(*r, 4);
    INFO("sharpness " << s << " pair distance " << d << " 10-90 width " << width);
    CHECK(width > 0);
    CHECK(width < previous);
    CHECK(std::abs(width / 0.8 - d) < 0.5);
    previous = width;
  }
}

TEST_CASE("The x4 render box-downsampled matches the x1 render (>= 40 dB) with features", "[render][scale]") {
  const Image img = FeatureImage();
  // One-pixel fine triangles at both scales: different levels (3 and 5).
  RenderOptions o1 = AtScale(img, 1), o4 = AtScale(img, 4);
  o1.max_fine_edge_px = o4.max_fine_edge_px = 1;
  auto x1 = Render(img, o1);
  auto x4 = Render(img, o4);
  REQUIRE(x1.ok());
  REQUIRE(x4.ok());
  CHECK(ChooseRenderLevels(img, o4) > ChooseRenderLevels(img, o1));
  auto m = CompareImages(BoxDownsample(*x4, 4), *x1);
  REQUIRE(m.ok());
  INFO("PSNR " << m->psnr << " MSSIM " << m->mssim);
  CHECK(m->psnr >= 40.0);
  CHECK(m->pixels == 40u * 32u);
}

TEST_CASE("Rendering a region equals the same crop of the full render", "[render][region]") {
  const Image img = FeatureImage();
  const double scale = 3;
  auto full = Render(img, AtScale(img, scale, 3));
  REQUIRE(full.ok());
  RenderOptions o = AtScale(img, scale, 3);
  const int x0 = 31, y0 = 20;
  o.viewport.width = 40, o.viewport.height = 30;
  o.viewport.origin_x = x0 / scale, o.viewport.origin_y = y0 / scale;
  REQUIRE(ControlTrianglesInViewport(img, o.viewport, 2).size() < img.triangles.size());
  auto crop = Render(img, o);
  REQUIRE(crop.ok());
  int diff = 0;
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 40; ++i)
      for (int c = 0; c < 4; ++c) diff += std::abs(crop->at(i, j, c) - full->at(x0 + i, y0 + j, c)) > 1e-3f;
  CHECK(diff == 0);
}

TEST_CASE("The level grows with the output scale and respects the bounds", "[render][levels]") {
  const Image img = FeatureImage();  // mean control edge ~5 px
  RenderOptions o = AtScale(img, 1);
  CHECK(ChooseRenderLevels(img, o) == 2);  // default: fine edges <= 16 px, at least the fit's level
  o.viewport.scale_x = o.viewport.scale_y = 8;
  CHECK(ChooseRenderLevels(img, o) == 2);  // 40 px -> 10 px
  o.viewport.scale_x = o.viewport.scale_y = 16;
  CHECK(ChooseRenderLevels(img, o) == 3);  // 80 px -> 10 px
  o.viewport.scale_x = o.viewport.scale_y = 8;
  o.max_fine_edge_px = 1;
  CHECK(ChooseRenderLevels(img, o) == 6);  // 40 px -> 0.6 px
  o.viewport.scale_x = o.viewport.scale_y = 1;
  CHECK(ChooseRenderLevels(img, o) == 3);  // 5 px -> 0.6 px
  o.viewport.scale_x = o.viewport.scale_y = 8;
  o.max_fine_edge_px = 4;
  CHECK(ChooseRenderLevels(img, o) == 4);
  o.viewport.scale_x = o.viewport.scale_y = 0.1;
  CHECK(ChooseRenderLevels(img, o) == 2);  // never below the fit's level
  o.levels = 1;
  CHECK(ChooseRenderLevels(img, o) == 1);
}

TEST_CASE("Render reports bad input with specific codes", "[render][errors]") {
  const Image img = FeatureImage();
  RenderOptions o = AtScale(img, 1);
  CHECK(Render(Image{}, o).status().code() == StatusCode::kEmptyInput);
  Image nan = img;
  nan.vertices[3].g = NAN;
  CHECK(Render(nan, o).status().code() == StatusCode::kNonFinite);
  RenderOptions bad = o;
  bad.viewport.width = 0;
  CHECK(Render(img, bad).status().code() == StatusCode::kInvalidArgument);
  bad = o;
  bad.viewport.scale_x = -1;
  CHECK(Render(img, bad).status().code() == StatusCode::kInvalidArgument);
  bad = o;
  bad.viewport.width = bad.viewport.height = 60000;
  CHECK(Render(img, bad).status().code() == StatusCode::kLimitExceeded);
  bad = o;
  bad.levels = 40;
  CHECK(Render(img, bad).status().code() == StatusCode::kInvalidArgument);
  Image broken = img;
  broken.triangles[0].v[1] = 9999;
  CHECK(!Render(broken, o).ok());
  // A viewport that sees none of the surface is transparent, not an error.
  RenderOptions away = o;
  away.viewport.origin_x = 1000;
  auto empty = Render(img, away);
  REQUIRE(empty.ok());
  for (float v : empty->data) CHECK(v == 0.0f);
}

TEST_CASE("Object images through Render: alpha 0 outside and in holes, coverage on both edges", "[render][alpha]") {
  // An annulus: rings of radius 4 and 10 around (12, 12), 24 vertices each, colour (200, 60, 30).
  Image img;
  img.width = img.height = 24;
  const int n = 24;
  for (double radius : {4.0, 10.0})
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n;
      img.vertices.push_back({float(12 + radius * std::cos(a)), float(12 + radius * std::sin(a)), 200, 60, 30});
    }
  for (uint32_t k = 0; k < uint32_t(n); ++k) {
    const uint32_t i0 = k, i1 = (k + 1) % n, o0 = n + k, o1 = n + (k + 1) % n;
    img.triangles.push_back({{i0, o0, o1}});
    img.triangles.push_back({{i0, o1, i1}});
  }
  RenderOptions o = AtScale(img, 3, 3);
  auto r = Render(img, o);
  REQUIRE(r.ok());
  auto alpha_at = [&](double x, double y) { return r->at(int(x * 3), int(y * 3), 3); };
  CHECK(alpha_at(12, 12) == 0.0f);   // the hole
  CHECK(alpha_at(0.5, 0.5) == 0.0f); // outside
  CHECK(alpha_at(12, 12 + 7) == 1.0f);
  CHECK(alpha_at(12 + 7, 12) == 1.0f);
  int partial = 0, partial_inner = 0;
  for (int j = 0; j < o.viewport.height; ++j)
    for (int i = 0; i < o.viewport.width; ++i) {
      const float a = r->at(i, j, 3);
      if (a <= 0 || a >= 1) continue;
      ++partial;
      const double d = std::hypot((i + 0.5) / 3 - 12, (j + 0.5) / 3 - 12);
      partial_inner += d < 7;
      REQUIRE(r->at(i, j, 0) == Approx(200).margin(1e-3));  // edge pixels keep the colour
      REQUIRE(d > 3);
      REQUIRE(d < 10.5);
    }
  CHECK(partial_inner > 40);            // the hole's edge is anti-aliased
  CHECK(partial - partial_inner > 100); // and the outer edge
}
