// SPDX-License-Identifier: GPL-3.0-or-later
// Render8: the 8-bit render equals the float render quantised by the PNG rule, byte for
// byte, for any thread count (spec/METHOD.md section 4, item 5).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "render_meshes.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"

using namespace sdvi;
using sdvi::test::AddColumnCrease;
using sdvi::test::GridImage;
using sdvi::test::GridSpec;
using sdvi::test::Lcg;
using sdvi::test::Steps;

namespace {

// A 40 x 32 image: jittered vertices, a crease pair, colours running past 0..255 (the
// clamp) with a feature step.
Image JitteredImage() {
  Lcg rng(23);
  GridSpec spec;
  spec.xs = {0, 5, 10, 15, 18.75, 21.25, 25, 30, 35, 40};
  spec.ys = Steps(0, 32, 8);
  spec.jitter = [&](double, double) {
    return std::array<double, 2>{(rng.Next() - 0.5) * 1.5, (rng.Next() - 0.5) * 2.5};
  };
  spec.colour = [](double x, double y) {
    const double base = 90 + 170 * std::sin(x / 6) * std::cos(y / 4) + (x > 20 ? 70 : 0);
    return std::array<float, 3>{float(base), float(255 - base), float(0.37 * base + 11.3)};
  };
  Image img = GridImage(spec);
  AddColumnCrease(img, 10, 9, 4);
  AddColumnCrease(img, 10, 9, 5);
  return img;
}

// An annulus around (12, 12) (radii 4 and 10): a domain edge outside and around the hole.
Image AnnulusImage() {
  Image img;
  img.width = img.height = 24;
  const int n = 24;
  for (double radius : {4.0, 10.0})
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n;
      img.vertices.push_back({float(12 + radius * std::cos(a)), float(12 + radius * std::sin(a)),
                              float(200 + 3.3 * k), float(60 - 2.7 * k), float(30 + radius)});
    }
  for (uint32_t k = 0; k < uint32_t(n); ++k) {
    const uint32_t i0 = k, i1 = (k + 1) % n, o0 = n + k, o1 = n + (k + 1) % n;
    img.triangles.push_back({{i0, o0, o1}});
    img.triangles.push_back({{i0, o1, i1}});
  }
  return img;
}

// The PNG writer's quantisation of a float RGBA raster, computed here on its own terms:
// colours round(clamp(v, 0, 255)), alpha round(255 clamp(a, 0, 1)), halves away from zero.
std::vector<uint8_t> QuantiseLikePng(const Raster& r) {
  std::vector<uint8_t> out(r.data.size());
  for (size_t i = 0; i < r.data.size(); ++i) {
    const double v = r.data[i];
    out[i] = uint8_t(i % 4 == 3 ? std::round(std::clamp(v, 0.0, 1.0) * 255.0) : std::round(std::clamp(v, 0.0, 255.0)));
  }
  return out;
}

RenderOptions AtScaleOnThreads(const Image& img, double scale, int threads) {
  RenderOptions o;
  o.viewport = Viewport{int(std::lround(img.width * scale)), int(std::lround(img.height * scale)), scale, scale, 0, 0};
  o.threads = threads;
  return o;
}

// Pixels whose bytes differ between a and b (4 channels).
size_t DifferingPixels(std::span<const uint8_t> a, std::span<const uint8_t> b) {
  size_t n = 0;
  for (size_t p = 0; p + 3 < std::min(a.size(), b.size()); p += 4)
    n += !std::equal(a.begin() + p, a.begin() + p + 4, b.begin() + p);
  return n + (a.size() != b.size());
}

}  // namespace

TEST_CASE("Render8 equals the float render quantised as the PNG writer does", "[render][render8]") {
  struct Case {
    const char* name;
    Image image;
    RenderOptions options;
  };
  std::vector<Case> cases;
  const Image jittered = JitteredImage(), annulus = AnnulusImage();
  // 1600 x 1280 at x40: fine triangles of a few pixels, many per row band.
  for (double scale : {1.0, 3.7, 8.0, 40.0}) cases.push_back({"jittered", jittered, AtScaleOnThreads(jittered, scale, 2)});
  for (double scale : {1.0, 5.0}) cases.push_back({"annulus", annulus, AtScaleOnThreads(annulus, scale, 2)});
  Case region{"region", jittered, AtScaleOnThreads(jittered, 6.0, 2)};
  region.options.viewport.width = 101, region.options.viewport.height = 77;
  region.options.viewport.origin_x = 13.2, region.options.viewport.origin_y = 7.9;
  cases.push_back(region);
  Case fixed_level{"level 4", annulus, AtScaleOnThreads(annulus, 2.0, 3)};
  fixed_level.options.levels = 4;
  cases.push_back(fixed_level);
  for (const Case& c : cases) {
    INFO(c.name << " " << c.options.viewport.width << "x" << c.options.viewport.height);
    auto f = Render(c.image, c.options);
    auto b = Render8(c.image, c.options);
    REQUIRE(f.ok());
    REQUIRE(b.ok());
    REQUIRE(b->width == f->width);
    REQUIRE(b->height == f->height);
    REQUIRE(b->channels == 4);
    CHECK(DifferingPixels(b->data, QuantiseLikePng(*f)) == 0);
  }
}

TEST_CASE("Render8 gives the same bytes for 1 and N threads", "[render][render8]") {
  const Image img = JitteredImage();
  RenderOptions o = AtScaleOnThreads(img, 40.0, 1);  // 1600 x 1280
  auto one = Render8(img, o);
  REQUIRE(one.ok());
  for (int threads : {2, 3, 7, 16}) {
    o.threads = threads;
    auto many = Render8(img, o);
    REQUIRE(many.ok());
    INFO(threads << " threads");
    CHECK(DifferingPixels(many->data, one->data) == 0);
  }
}

TEST_CASE("RenderFineMesh8Into a prepared raster writes every byte RenderFineMesh8 does", "[render][render8]") {
  const Image img = AnnulusImage();  // pixels outside the domain: alpha 0 must be written too
  const RenderOptions o = AtScaleOnThreads(img, 30.0, 2);
  LimitSurfaceOptions lso;
  lso.levels = ChooseRenderLevels(img, o);
  auto fine = RefineImage(img, lso);
  REQUIRE(fine.ok());
  const std::vector<Edge> boundary = MeshBoundaryEdges(fine->triangles, &fine->vertex_tags);
  const Raster8 direct = RenderFineMesh8(fine->triangles, fine->vertices, o.viewport, &boundary, 2);
  Raster8 prepared;
  PrepareRaster8(o.viewport, prepared);
  REQUIRE(prepared.data.size() == direct.data.size());
  std::fill(prepared.data.begin(), prepared.data.end(), uint8_t(0xa5));  // storage that is not zero
  RenderFineMesh8Into(fine->triangles, fine->vertices, o.viewport, &boundary, 2, prepared);
  CHECK(prepared.width == direct.width);
  CHECK(prepared.height == direct.height);
  CHECK(DifferingPixels(prepared.data, direct.data) == 0);
  auto whole = Render8(img, o);
  REQUIRE(whole.ok());
  CHECK(DifferingPixels(whole->data, direct.data) == 0);
}

TEST_CASE("Render8 rounds halves away from zero, as the PNG writer does", "[render][render8]") {
  GridSpec spec;
  spec.xs = Steps(0, 12, 3);
  spec.ys = Steps(0, 8, 2);
  spec.colour = [](double, double) { return std::array<float, 3>{100.5f, 0.5f, 254.5f}; };
  const Image img = GridImage(spec);
  auto b = Render8(img, AtScaleOnThreads(img, 2.0, 0));
  REQUIRE(b.ok());
  size_t off = 0;
  for (size_t p = 0; p < b->data.size(); p += 4)
    off += b->data[p] != 101 || b->data[p + 1] != 1 || b->data[p + 2] != 255 || b->data[p + 3] != 255;
  CHECK(off == 0);
}

TEST_CASE("The 8-bit render's PNG is the float render's PNG, byte for byte", "[render][render8]") {
  const Image img = AnnulusImage();  // alpha: edge coverage, the hole
  const RenderOptions o = AtScaleOnThreads(img, 4.0, 2);
  auto f = Render(img, o);
  auto b = Render8(img, o);
  REQUIRE(f.ok());
  REQUIRE(b.ok());
  auto from_float = EncodePng(*f, 8);
  auto from_bytes = EncodePng(*b);
  REQUIRE(from_float.ok());
  REQUIRE(from_bytes.ok());
  CHECK(*from_float == *from_bytes);
  // And after dropping the channels an output does not need (here: none; RGB of a full image).
  const Image grid = JitteredImage();
  auto gf = Render(grid, AtScaleOnThreads(grid, 2.0, 2));
  auto gb = Render8(grid, AtScaleOnThreads(grid, 2.0, 2));
  REQUIRE(gf.ok());
  REQUIRE(gb.ok());
  const Raster8 rgb = WithNeededChannels(*gb);
  CHECK(rgb.channels == 3);
  CHECK(*EncodePng(rgb) == *EncodePng(WithNeededChannels(*gf), 8));
}

TEST_CASE("Render8 reports bad input with Render's codes", "[render][render8][errors]") {
  const Image img = JitteredImage();
  RenderOptions o = AtScaleOnThreads(img, 1.0, 0);
  o.viewport.width = 0;
  CHECK(Render8(img, o).status().code() == StatusCode::kInvalidArgument);
  CHECK(Render8(Image(), AtScaleOnThreads(img, 1.0, 0)).status().code() == StatusCode::kEmptyInput);
  RenderOptions away = AtScaleOnThreads(img, 1.0, 0);
  away.viewport.origin_x = 1000;
  auto empty = Render8(img, away);
  REQUIRE(empty.ok());
  CHECK(std::all_of(empty->data.begin(), empty->data.end(), [](uint8_t v) { return v == 0; }));
}
