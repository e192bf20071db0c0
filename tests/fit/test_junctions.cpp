// SPDX-License-Identifier: GPL-3.0-or-later
// Junctions (spec/METHOD.md section 6 step 3): features that cross at 30 degrees or more
// share a corner vertex at each crossing of their polylines instead of being cut.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/subdiv.h"
#include "sdvi/tagged_mesh.h"
#include "sdvi/vectorize.h"

namespace {

sdvi::FeatureCurve Segment(sdvi::Point2 a, sdvi::Point2 b, float width) {
  sdvi::FeatureCurve c;
  c.points = {a, b};
  c.width = width;
  return c;
}

// Crease-degree of every vertex.
std::vector<int> CreaseDegrees(const sdvi::Image& mesh) {
  std::vector<int> degree(mesh.vertices.size(), 0);
  for (const sdvi::Edge& e : mesh.crease_edges) {
    ++degree[e.a];
    ++degree[e.b];
  }
  return degree;
}

// Extent of a polyline's vertices along x and y.
struct Extent {
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
};
Extent ExtentOf(const sdvi::Image& mesh, const sdvi::FeaturePolyline& l) {
  Extent e;
  for (uint32_t v : l.vertices) {
    e.x0 = std::min(e.x0, double(mesh.vertices[v].x));
    e.x1 = std::max(e.x1, double(mesh.vertices[v].x));
    e.y0 = std::min(e.y0, double(mesh.vertices[v].y));
    e.y1 = std::max(e.y1, double(mesh.vertices[v].y));
  }
  return e;
}

// Two 1 px black lines on white crossing at (32.5, 32.5): rows 32 and column 32, x and y
// from 8 to 57.
sdvi::Raster CrossImage() {
  sdvi::Raster image(64, 64, 3);
  std::fill(image.data.begin(), image.data.end(), 255.f);
  for (int k = 8; k < 57; ++k) {
    for (int c = 0; c < 3; ++c) {
      image.at(k, 32, c) = 0.f;
      image.at(32, k, c) = 0.f;
    }
  }
  return image;
}

// PSNR (8-bit, R, G, B) of a reconstruction against the image over the square of pixels
// within `half` of (cx, cy).
double PsnrAround(const sdvi::Raster8& a, const sdvi::Raster& b, int cx, int cy, int half) {
  double sum = 0;
  int n = 0;
  for (int y = cy - half; y <= cy + half; ++y) {
    for (int x = cx - half; x <= cx + half; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.at(x, y, c)) - double(b.at(x, y, c));
        sum += d * d;
        ++n;
      }
    }
  }
  return 10 * std::log10(255.0 * 255.0 / std::max(sum / n, 1e-10));
}

}  // namespace

TEST_CASE("junctions: two crossing hairlines keep every polyline whole and share 9 corners", "[triangulate][junction]") {
  // Hairlines 1 px wide (three polylines each: outlines at +-1, the shared centre) crossing
  // at (32, 32) at right angles.
  const std::vector<sdvi::FeatureCurve> curves = {Segment({4, 32}, {60, 32}, 1.0f), Segment({32, 6}, {32, 58}, 1.0f)};
  auto mesh = sdvi::BuildControlMesh(64, 64, curves, {}, {});
  INFO(mesh.status().ToString());
  REQUIRE(mesh.ok());
  REQUIRE(mesh->polylines.size() == 7);  // the frame and 3 + 3, none cut
  REQUIRE(mesh->pairs.size() == 4);
  for (size_t k = 1; k < 4; ++k) {  // horizontal: from x = 4 to 60
    const Extent e = ExtentOf(*mesh, mesh->polylines[k]);
    CHECK(e.x0 == Approx(4));
    CHECK(e.x1 == Approx(60));
  }
  for (size_t k = 4; k < 7; ++k) {  // vertical: from y = 6 to 58
    const Extent e = ExtentOf(*mesh, mesh->polylines[k]);
    CHECK(e.y0 == Approx(6));
    CHECK(e.y1 == Approx(58));
  }
  // The 9 crossings (x, y in {31, 32, 33}) are vertices of both polylines, with crease-degree
  // 4, tagged corner in the file's list and by the subdivision's rule.
  const std::vector<int> degree = CreaseDegrees(*mesh);
  auto tagged = sdvi::TaggedMesh::FromImage(*mesh);
  REQUIRE(tagged.ok());
  std::set<std::pair<int, int>> found;
  for (uint32_t v = 0; v < mesh->vertices.size(); ++v) {
    if (degree[v] != 4) continue;
    const double x = mesh->vertices[v].x, y = mesh->vertices[v].y;
    found.insert({int(std::lround(x)), int(std::lround(y))});
    CHECK(x == Approx(std::round(x)).margin(1e-5));
    CHECK(y == Approx(std::round(y)).margin(1e-5));
    CHECK(std::binary_search(mesh->corners.begin(), mesh->corners.end(), v));
    CHECK(tagged->tag(v) == sdvi::VertexTag::kCorner);
    int in_polylines = 0;
    for (const auto& l : mesh->polylines)
      in_polylines += int(std::count(l.vertices.begin(), l.vertices.end(), v));
    CHECK(in_polylines == 2);
  }
  CHECK(found == std::set<std::pair<int, int>>{{31, 31}, {31, 32}, {31, 33}, {32, 31}, {32, 32},
                                               {32, 33}, {33, 31}, {33, 32}, {33, 33}});
  // The limit surface keeps each junction where it is (a corner is fixed).
  sdvi::LimitSurfaceOptions levels;
  levels.levels = 2;
  auto surface = sdvi::BuildLimitSurface(*mesh, levels);
  REQUIRE(surface.ok());
  std::vector<double> xs(mesh->vertices.size()), ys(mesh->vertices.size());
  for (size_t i = 0; i < xs.size(); ++i) xs[i] = mesh->vertices[i].x, ys[i] = mesh->vertices[i].y;
  for (uint32_t v = 0; v < mesh->vertices.size(); ++v) {
    if (degree[v] != 4) continue;
    double lx = 0, ly = 0;
    for (uint32_t k = surface->stencils.offsets[v]; k < surface->stencils.offsets[v + 1]; ++k) {
      lx += surface->stencils.weights[k] * xs[surface->stencils.indices[k]];
      ly += surface->stencils.weights[k] * ys[surface->stencils.indices[k]];
    }
    CHECK(lx == Approx(xs[v]).margin(1e-4));
    CHECK(ly == Approx(ys[v]).margin(1e-4));
  }
}

TEST_CASE("junctions: off, or at a shallow angle, a crossing is cut out", "[triangulate][junction]") {
  const std::vector<sdvi::FeatureCurve> cross = {Segment({4, 32}, {60, 32}, 0), Segment({32, 6}, {32, 58}, 0)};
  sdvi::ControlMeshOptions off;
  off.junctions = false;
  auto cut = sdvi::BuildControlMesh(64, 64, cross, {}, off);
  REQUIRE(cut.ok());
  CHECK(cut->polylines.size() == 7);  // the frame, the horizontal pair, the vertical pair in two
  for (int d : CreaseDegrees(*cut)) CHECK(d <= 2);
  auto joined = sdvi::BuildControlMesh(64, 64, cross, {}, {});
  REQUIRE(joined.ok());
  CHECK(joined->polylines.size() == 5);
  const std::vector<int> degree = CreaseDegrees(*joined);
  CHECK(std::count(degree.begin(), degree.end(), 4) == 4);
  // 20 degrees apart: under the 30 degree bound, cut.
  const double s = std::tan(20 * M_PI / 180);
  const std::vector<sdvi::FeatureCurve> shallow = {Segment({4, 32}, {60, 32}, 0),
                                                   Segment({4, 32 - 28 * s}, {60, 32 + 28 * s}, 0)};
  auto sharp_angle = sdvi::BuildControlMesh(64, 64, shallow, {}, {});
  REQUIRE(sharp_angle.ok());
  for (int d : CreaseDegrees(*sharp_angle)) CHECK(d <= 2);
}

TEST_CASE("junctions: a crossing of hairlines is reproduced, cut out it is not", "[vectorize][junction]") {
  const sdvi::Raster image = CrossImage();
  const std::vector<sdvi::FeatureCurve> curves = {Segment({8, 32.5}, {57, 32.5}, 1.0f),
                                                  Segment({32.5, 8}, {32.5, 57}, 1.0f)};
  sdvi::VectorizeOptions options;
  options.max_triangles = 1200;
  auto joined = sdvi::VectorizeWithFeatures(image, nullptr, curves, options);
  INFO(joined.status().ToString());
  REQUIRE(joined.ok());
  options.mesh.junctions = false;
  auto cut = sdvi::VectorizeWithFeatures(image, nullptr, curves, options);
  REQUIRE(cut.ok());
  // Within 6 px of the crossing.
  const double with = PsnrAround(joined->reconstruction, image, 32, 32, 6);
  const double without = PsnrAround(cut->reconstruction, image, 32, 32, 6);
  INFO("junctions " << with << " dB, cut " << without << " dB");
  CHECK(with > 30.0);
  CHECK(without < with - 6.0);
}

TEST_CASE("junctions: a segment beside a junction that comes back across the placed polyline is cut", "[triangulate][junction]") {
  // The placed polyline (longer, first): x = 32 with a vertex at (32, 32). The candidate
  // passes through that vertex (a junction) and, just before it, crosses x = 32 a second
  // time within the junction's gap; that crossing touches the placed segment away from the
  // junction, and the triangulation cannot keep both constraints.
  int failures = 0, cases = 0;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      const double x1 = 31.80 + 0.02 * j, y1 = 32.02 + 0.02 * i;
      sdvi::FeatureCurve placed;
      placed.points = {{32, 4}, {32, 32}, {32, 60}};
      placed.corners = {1};
      sdvi::FeatureCurve zigzag;
      zigzag.points = {{34, 35}, {x1, y1}, {32.02, 31.98}, {34, 29}, {36, 26}};
      zigzag.corners = {1, 2, 3};
      sdvi::ControlMeshOptions options;
      options.pairs = false;
      options.clearance = 0.5f;
      auto mesh = sdvi::BuildControlMesh(64, 64, {placed, zigzag}, {}, options);
      ++cases;
      if (!mesh.ok()) {
        ++failures;
        UNSCOPED_INFO(x1 << ", " << y1 << ": " << mesh.status().ToString());
      }
    }
  }
  CHECK(cases == 100);
  CHECK(failures == 0);  // before the rule, 77 of them stopped with a split crease edge
}
