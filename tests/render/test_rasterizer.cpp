// SPDX-License-Identifier: GPL-3.0-or-later
// The scan converter on plain triangle meshes: fill rule, barycentrics, folds, coverage.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "render_meshes.h"
#include "sdvi/render.h"

using namespace sdvi;
using sdvi::test::GridImage;
using sdvi::test::Lcg;
using sdvi::test::GridSpec;
using sdvi::test::Steps;

namespace {

// Hit count of every pixel, scan-converting each triangle on its own (no first-wins rule
// can hide a double hit).
std::vector<int> HitCounts(const Image& img, const Viewport& vp) {
  std::vector<int> hits(size_t(vp.width) * vp.height, 0);
  for (const Triangle& t : img.triangles) {
    const CoverageMap m = MapPixels({t}, img.vertices, vp);
    for (const PixelSample& s : m.samples) ++hits[s.pixel];
  }
  return hits;
}

Viewport ScaledViewport(const Image& img, double scale) {
  Viewport vp;
  vp.width = int(std::floor(img.width * scale));
  vp.height = int(std::floor(img.height * scale));
  vp.scale_x = vp.scale_y = scale;
  return vp;
}

}  // namespace

TEST_CASE("A mesh tiling the rectangle covers every pixel exactly once, several scales and odd sizes",
          "[render][fill]") {
  Lcg rng(7);
  GridSpec spec;
  spec.xs = Steps(0, 37, 9);
  spec.ys = Steps(0, 23, 5);
  spec.jitter = [&](double, double) { return std::array<double, 2>{rng.Next() * 2 - 1, rng.Next() * 2 - 1}; };
  const Image img = GridImage(spec);
  for (double scale : {1.0, 0.37, 1.5, 2.0, 3.3}) {
    const Viewport vp = ScaledViewport(img, scale);
    const std::vector<int> hits = HitCounts(img, vp);
    int bad = 0;
    for (int h : hits) bad += h != 1;
    INFO("scale " << scale << " size " << vp.width << "x" << vp.height);
    CHECK(bad == 0);
  }
  // A magnified region: triangles much larger than the viewport, vertices far outside it.
  for (double scale : {40.0, 97.3}) {
    const Viewport vp{161, 123, scale, scale, 13.37, 9.11};
    const std::vector<int> hits = HitCounts(img, vp);
    int bad = 0;
    for (int h : hits) bad += h != 1;
    INFO("region at scale " << scale);
    CHECK(bad == 0);
  }
}

TEST_CASE("Shared edges and vertices through pixel centres are owned exactly once", "[render][fill]") {
  // Vertices on pixel centres and edges along rows, columns and diagonals of centres.
  GridSpec spec;
  spec.xs = {0.5, 3.5, 6.5, 9.5, 13.5};
  spec.ys = {0.5, 3.5, 7.5, 10.5};
  Image img = GridImage(spec);
  const Viewport vp = Viewport::Identity(14, 11);
  const std::vector<int> hits = HitCounts(img, vp);
  for (int j = 0; j < vp.height; ++j)
    for (int i = 0; i < vp.width; ++i) {
      // Centres on the mesh's own left/top edge (x or y = 0.5) are owned, on its right/bottom
      // edge (x = 13.5, y = 10.5) not: the top-left rule.
      const bool inside = i <= 12 && j <= 9;
      INFO("pixel " << i << "," << j);
      CHECK(hits[size_t(j) * vp.width + i] == (inside ? 1 : 0));
    }
}

TEST_CASE("A triangle owns exactly the pixel centres the exact edge test gives it", "[render][fill]") {
  // Random triangles (corners on the 1/256 grid, so fixed point holds them exactly; some on
  // pixel centres, some with a horizontal or vertical edge), thin and wide, partly outside
  // the viewport: MapPixels' spans against every edge function evaluated at every centre.
  const Viewport vp = Viewport::Identity(37, 29);
  Lcg rng(91);
  int triangles = 0;
  for (int it = 0; it < 3000; ++it) {
    const double extent = it % 3 == 0 ? 4.0 : it % 3 == 1 ? 40.0 : 400.0;
    auto coord = [&](double centre) {
      double v = centre + (rng.Next() - 0.5) * extent;
      v = std::round(v * 256.0) / 256.0;
      if (it % 5 == 0) v = std::floor(v) + 0.5;  // on a pixel centre
      return v;
    };
    Image img;
    for (int k = 0; k < 3; ++k) img.vertices.push_back({float(coord(18)), float(coord(14)), 0, 0, 0});
    if (it % 7 == 0) img.vertices[1].y = img.vertices[0].y;
    if (it % 11 == 0) img.vertices[2].x = img.vertices[0].x;
    img.triangles.push_back({{0, 1, 2}});
    std::vector<uint8_t> mapped(size_t(vp.width) * vp.height, 0), expected(mapped.size(), 0);
    for (const PixelSample& s : MapPixels(img.triangles, img.vertices, vp).samples) mapped[s.pixel] = 1;
    // The rule of sdvi/render.h in 1/256 units: E > 0 inside a positively oriented triangle,
    // E = 0 owned on a top (dy = 0, dx > 0) or left (dy < 0) edge.
    int64_t x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = std::llround(img.vertices[k].x * 256.0), y[k] = std::llround(img.vertices[k].y * 256.0);
    const int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if (area < 0) std::swap(x[1], x[2]), std::swap(y[1], y[2]);
    if (area != 0) ++triangles;
    for (int j = 0; j < vp.height && area != 0; ++j)
      for (int i = 0; i < vp.width; ++i) {
        bool owned = true;
        for (int k = 0; k < 3; ++k) {
          const int a = (k + 1) % 3, b = (k + 2) % 3;
          const int64_t dx = x[b] - x[a], dy = y[b] - y[a];
          const int64_t e = dx * (j * 256 + 128 - y[a]) - dy * (i * 256 + 128 - x[a]);
          owned = owned && (e > 0 || (e == 0 && ((dy == 0 && dx > 0) || dy < 0)));
        }
        expected[size_t(j) * vp.width + i] = owned;
      }
    INFO("triangle " << it);
    REQUIRE(mapped == expected);
  }
  CHECK(triangles > 2500);
}

TEST_CASE("Barycentric interpolation reproduces an affine colour field", "[render][interp]") {
  Lcg rng(3);
  GridSpec spec;
  spec.xs = Steps(0, 31, 6);
  spec.ys = Steps(0, 17, 4);
  spec.jitter = [&](double, double) { return std::array<double, 2>{rng.Next() * 2 - 1, rng.Next() * 2 - 1}; };
  auto field = [](double x, double y) {
    return std::array<float, 3>{float(10 + 3 * x + 2 * y), float(200 - 4 * y), float(50 + 2 * x)};
  };
  spec.colour = field;
  const Image img = GridImage(spec);
  const Viewport vp = ScaledViewport(img, 2.0);
  const Raster r = RenderFineMesh(img.triangles, img.vertices, vp);
  for (int j = 0; j < vp.height; ++j)
    for (int i = 0; i < vp.width; ++i) {
      const auto want = field((i + 0.5) / 2.0, (j + 0.5) / 2.0);
      REQUIRE(r.at(i, j, 3) == 1.0f);
      for (int c = 0; c < 3; ++c) REQUIRE(r.at(i, j, c) == Approx(want[c]).margin(1e-2));  // 1/512 px snapping
    }
  // MapPixels gives the same weights: reconstruct the colour from the samples.
  const CoverageMap m = MapPixels(img.triangles, img.vertices, vp);
  REQUIRE(m.samples.size() == size_t(vp.width) * vp.height);
  for (size_t k = 0; k < m.samples.size(); ++k) {
    const PixelSample& s = m.samples[k];
    REQUIRE(s.pixel == k);  // sorted, one per pixel
    const Triangle& t = img.triangles[s.triangle];
    CHECK(s.w0 + s.w1 + s.w2 == Approx(1.0f).margin(1e-5));
    const double red = s.w0 * img.vertices[t.v[0]].r + s.w1 * img.vertices[t.v[1]].r + s.w2 * img.vertices[t.v[2]].r;
    CHECK(red == Approx(r.data[k * 4]).margin(1e-3));
  }
}

TEST_CASE("Folded triangles: the lowest fine triangle index wins in MapPixels and rendering",
          "[render][fold]") {
  // Two overlapping triangles of different colours, in both index orders.
  std::vector<Vertex> v = {{1, 1, 255, 0, 0}, {9, 1, 255, 0, 0}, {1, 9, 255, 0, 0},
                           {2, 2, 0, 0, 255}, {10, 3, 0, 0, 255}, {3, 10, 0, 0, 255}};
  const Triangle red{{0, 1, 2}}, blue{{3, 5, 4}};  // blue has the opposite orientation
  const Viewport vp = Viewport::Identity(12, 12);
  for (bool red_first : {true, false}) {
    std::vector<Triangle> tris = red_first ? std::vector<Triangle>{red, blue} : std::vector<Triangle>{blue, red};
    const Raster r = RenderFineMesh(tris, v, vp);
    const CoverageMap m = MapPixels(tris, v, vp);
    // Pixel (3, 3) is inside both.
    const size_t p = 3 * 12 + 3;
    CHECK(r.data[p * 4 + 0] == (red_first ? 255.0f : 0.0f));
    CHECK(r.data[p * 4 + 2] == (red_first ? 0.0f : 255.0f));
    bool found = false;
    for (const PixelSample& s : m.samples) {
      if (s.pixel != p) continue;
      found = true;
      CHECK(s.triangle == 0u);
    }
    CHECK(found);
  }
}

TEST_CASE("Object images: alpha 0 outside the domain, coverage on the edge", "[render][alpha]") {
  // A regular 24-gon of radius 10 (fan around its centre), rendered at 3x.
  Image img;
  const double cx = 12, cy = 12, rad = 10;
  const int n = 24;
  img.vertices.push_back({float(cx), float(cy), 40, 80, 120});
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    img.vertices.push_back({float(cx + rad * std::cos(a)), float(cy + rad * std::sin(a)), 40, 80, 120});
  }
  for (int k = 0; k < n; ++k) img.triangles.push_back({{0, uint32_t(1 + k), uint32_t(1 + (k + 1) % n)}});
  const Viewport vp{72, 72, 3, 3, 0, 0};
  const std::vector<Edge> boundary = MeshBoundaryEdges(img.triangles);
  REQUIRE(boundary.size() == size_t(n));
  const Raster r = RenderFineMesh(img.triangles, img.vertices, vp, &boundary);
  double alpha_sum = 0;
  int partial = 0;
  for (int j = 0; j < vp.height; ++j)
    for (int i = 0; i < vp.width; ++i) {
      const double a = r.at(i, j, 3);
      alpha_sum += a;
      partial += a > 0 && a < 1;
      const double d = std::hypot((i + 0.5) / 3 - cx, (j + 0.5) / 3 - cy) * 3;  // output px from centre
      if (d > rad * 3 + 1) REQUIRE(a == 0.0);
      if (d < rad * 3 * std::cos(M_PI / n) - 1) {
        REQUIRE(a == 1.0);
        REQUIRE(r.at(i, j, 1) == 80.0f);
      }
      if (a > 0) REQUIRE(r.at(i, j, 2) == Approx(120.0f));  // edge pixels keep the domain colour
    }
  const double area = 0.5 * n * (rad * 3) * (rad * 3) * std::sin(2 * M_PI / n);
  CHECK(alpha_sum == Approx(area).epsilon(0.01));
  CHECK(partial > 100);
}

TEST_CASE("MeshBoundaryEdges finds the outer boundary and holes only", "[render][alpha]") {
  GridSpec spec;
  spec.xs = Steps(0, 4, 4);
  spec.ys = Steps(0, 4, 4);
  Image img = GridImage(spec);
  // Remove the two triangles of the centre cell (1..2 x 1..2 is cell (1,1)): a hole.
  std::vector<Triangle> kept;
  for (size_t t = 0; t < img.triangles.size(); ++t)
    if (t / 2 != size_t(1 * 4 + 1)) kept.push_back(img.triangles[t]);
  CHECK(MeshBoundaryEdges(img.triangles).size() == 16u);
  CHECK(MeshBoundaryEdges(kept).size() == 20u);
}

TEST_CASE("Invalid input never crashes the scan converter", "[render][errors]") {
  std::vector<Vertex> v = {{0, 0, 1, 1, 1}, {5, 0, 1, 1, 1}, {0, 5, 1, 1, 1}, {NAN, 2, 1, 1, 1}, {1e30f, 0, 1, 1, 1}};
  std::vector<Triangle> t = {{{0, 1, 2}}, {{0, 1, 3}}, {{0, 4, 2}}, {{0, 1, 99}}, {{1, 1, 1}}};
  const CoverageMap m = MapPixels(t, v, Viewport::Identity(6, 6));
  for (const PixelSample& s : m.samples) CHECK(s.triangle == 0u);
  CHECK(m.samples.size() == 10u);  // centres with x + y < 5; the hypotenuse is a right edge
  CHECK(MapPixels(t, v, Viewport{0, 5, 1, 1, 0, 0}).samples.empty());
  CHECK(RenderFineMesh(t, v, Viewport{4, 4, NAN, 1, 0, 0}).empty());
}

TEST_CASE("Row-band drawing: every pixel is drawn by the lowest-index triangle MapPixels finds there",
          "[render][fold][bands]") {
  // Overlapping triangles of every size (sub-pixel to taller than many row bands), some
  // off-screen, each of one colour that names its index; drawn in row bands (the pixels'
  // cache) they must give exactly the owner MapPixels finds by scanning all triangles.
  Lcg rng(91);
  auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * rng.Next(); };
  const Viewport vp = Viewport::Identity(700, 900);
  std::vector<Vertex> v;
  std::vector<Triangle> tris;
  for (uint32_t t = 0; t < 9000; ++t) {
    const double cx = uniform(-50, 750), cy = uniform(-50, 950);
    const double size = t % 10 == 0 ? uniform(20, 200) : uniform(0.3, 12);
    const float r = float(t % 256), g = float(t / 256), b = 7;
    for (int k = 0; k < 3; ++k)
      v.push_back({float(cx + size * uniform(-1, 1)), float(cy + size * uniform(-1, 1)), r, g, b});
    tris.push_back({{3 * t, 3 * t + 1, 3 * t + 2}});
  }
  const CoverageMap m = MapPixels(tris, v, vp);
  std::vector<uint32_t> owner(size_t(vp.width) * vp.height, UINT32_MAX);
  for (const PixelSample& s : m.samples) owner[s.pixel] = s.triangle;
  for (int threads : {1, 2, 5}) {
    const Raster8 r = RenderFineMesh8(tris, v, vp, nullptr, threads);
    const Raster f = RenderFineMesh(tris, v, vp, nullptr, threads);
    REQUIRE(r.data.size() == owner.size() * 4);
    size_t wrong = 0;
    for (size_t p = 0; p < owner.size(); ++p) {
      const uint32_t t = owner[p];
      const bool ok8 = t == UINT32_MAX ? r.data[4 * p + 3] == 0
                                       : r.data[4 * p] == t % 256 && r.data[4 * p + 1] == t / 256 &&
                                             r.data[4 * p + 2] == 7 && r.data[4 * p + 3] == 255;
      const bool okf = t == UINT32_MAX ? f.data[4 * p + 3] == 0.0f
                                       : std::lround(f.data[4 * p]) == long(t % 256) &&
                                             std::lround(f.data[4 * p + 1]) == long(t / 256) && f.data[4 * p + 3] == 1.0f;
      wrong += !ok8 || !okf;
    }
    INFO(threads << " threads");
    CHECK(wrong == 0);
  }
  CHECK(m.samples.size() > owner.size() / 2);  // the test covers most of the output
  // MapPixelsInto on storage holding another map (a larger viewport's, then stale values)
  // gives the same map.
  CoverageMap reused = MapPixels(tris, v, Viewport::Identity(900, 1000));
  for (PixelSample& s : reused.samples) s = PixelSample{1, 2, 3, 4, 5};
  MapPixelsInto(tris, v, vp, reused);
  CHECK(reused.width == m.width);
  CHECK(reused.height == m.height);
  REQUIRE(reused.samples.size() == m.samples.size());
  size_t differ = 0;
  for (size_t q = 0; q < m.samples.size(); ++q) {
    const PixelSample &a = m.samples[q], &b = reused.samples[q];
    differ += a.pixel != b.pixel || a.triangle != b.triangle || a.w0 != b.w0 || a.w1 != b.w1 || a.w2 != b.w2;
  }
  CHECK(differ == 0);
}

TEST_CASE("PixelOwners give MapPixels' samples bit for bit, by pixel range and by triangle",
          "[render][fold][owners]") {
  // Overlapping triangles of every size, some off-screen, at a non-identity viewport: the
  // owners' samples, read by ranges of pixels or triangle by triangle, are MapPixels' own.
  Lcg rng(17);
  auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * rng.Next(); };
  Viewport vp = Viewport::Identity(310, 270);
  vp.scale_x = 1.7, vp.scale_y = 1.3, vp.origin_x = -3.25, vp.origin_y = 2.5;
  std::vector<Vertex> v;
  std::vector<Triangle> tris;
  for (uint32_t t = 0; t < 3000; ++t) {
    const double cx = uniform(-20, 200), cy = uniform(-20, 220);
    const double size = t % 10 == 0 ? uniform(10, 80) : uniform(0.2, 6);
    for (int k = 0; k < 3; ++k) v.push_back({float(cx + size * uniform(-1, 1)), float(cy + size * uniform(-1, 1)), 0, 0, 0});
    tris.push_back({{3 * t, 3 * t + 1, 3 * t + 2}});
  }
  const CoverageMap m = MapPixels(tris, v, vp);
  PixelOwners owners;
  owners.owner.assign(5, 3);  // stale storage
  MapPixelOwnersInto(tris, v, vp, owners);
  REQUIRE(owners.width == vp.width);
  REQUIRE(owners.height == vp.height);
  auto same = [](const PixelSample& a, const PixelSample& b) {
    return a.pixel == b.pixel && a.triangle == b.triangle && a.w0 == b.w0 && a.w1 == b.w1 && a.w2 == b.w2;
  };
  std::vector<PixelSample> by_range;
  const size_t pixels = size_t(vp.width) * vp.height;
  for (size_t p = 0; p < pixels; p += 997) AppendSamplesInRange(owners, tris, p, std::min(pixels, p + 997), by_range);
  REQUIRE(by_range.size() == m.samples.size());
  size_t differ = 0;
  for (size_t q = 0; q < m.samples.size(); ++q) differ += !same(by_range[q], m.samples[q]);
  CHECK(differ == 0);
  std::vector<PixelSample> by_triangle;
  for (uint32_t t = 0; t < tris.size(); ++t) {
    const size_t first = by_triangle.size();
    AppendOwnedSamples(owners, tris, t, by_triangle);
    for (size_t q = first + 1; q < by_triangle.size(); ++q) CHECK(by_triangle[q - 1].pixel < by_triangle[q].pixel);
  }
  REQUIRE(by_triangle.size() == m.samples.size());
  std::sort(by_triangle.begin(), by_triangle.end(),
            [](const PixelSample& a, const PixelSample& b) { return a.pixel < b.pixel; });
  differ = 0;
  for (size_t q = 0; q < m.samples.size(); ++q) differ += !same(by_triangle[q], m.samples[q]);
  CHECK(differ == 0);
  CHECK(m.samples.size() > pixels / 2);
}
