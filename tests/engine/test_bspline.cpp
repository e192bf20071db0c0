// SPDX-License-Identifier: GPL-3.0-or-later
// Crease limit points lie on the cubic B-spline of spec/METHOD.md section 2, evaluated
// independently with de Boor's algorithm.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>

#include "sdvi/subdiv.h"
#include "sdvi/tagged_mesh.h"
#include "test_meshes.h"

using namespace sdvi;
using Point = std::array<double, 5>;

namespace {

// De Boor's algorithm: the cubic B-spline with control points d and knots u at t
// (u.size() == d.size() + 4; t in [u[3], u[d.size()]]).
Point DeBoor(const std::vector<Point>& d, const std::vector<double>& u, double t) {
  const size_t n = d.size();
  size_t s = 3;
  while (s + 1 < n && !(t < u[s + 1])) ++s;  // u[s] <= t < u[s+1], last span at the end
  std::array<Point, 4> p;
  for (int j = 0; j < 4; ++j) p[j] = d[s - 3 + j];
  for (int r = 1; r <= 3; ++r)
    for (int j = 3; j >= r; --j) {
      const size_t i = s - 3 + j;
      const double alpha = (t - u[i]) / (u[i + 4 - r] - u[i]);
      for (int c = 0; c < 5; ++c) p[j][c] = (1 - alpha) * p[j - 1][c] + alpha * p[j][c];
    }
  return p[3];
}

Point ValueOf(const std::vector<double>& values, uint32_t v) {
  Point p;
  for (int c = 0; c < 5; ++c) p[c] = values[5 * v + c];
  return p;
}

// Limit values (double, via the masks) of the level-`levels` vertices of image, and the
// fine chain of the control chain.
struct Refined {
  std::vector<double> limit;
  std::vector<uint32_t> chain;
};
Refined LimitAlong(const Image& image, std::vector<uint32_t> chain, bool closed, int levels) {
  auto mesh = TaggedMesh::FromImage(image);
  REQUIRE(mesh.ok());
  TaggedMesh m = *mesh;
  std::vector<double> values = test::Values(image);
  for (int k = 0; k < levels; ++k) {
    chain = test::RefinePolyline(m, chain, closed);
    values = test::ApplyRows(RefinementMasks(m), values);
    m = m.Refine();
  }
  return {test::ApplyRows(LimitMasks(m), values), chain};
}

double MaxDistance(const Point& a, const Point& b) {
  double d = 0;
  for (int c = 0; c < 5; ++c) d = std::max(d, std::abs(a[c] - b[c]));
  return d;
}

void CheckOpenPolyline(int n, uint32_t seed) {
  test::Strip strip = test::StripImage(n, seed);
  // The end-interpolating spline: deBoor points P0, P0, P1..Pn, Pn, knots {0,0,0,0,1..n-1,n,n,n,n}.
  const auto values = test::Values(strip.image);
  std::vector<Point> d{ValueOf(values, strip.polyline.front())};
  for (uint32_t v : strip.polyline) d.push_back(ValueOf(values, v));
  d.push_back(ValueOf(values, strip.polyline.back()));
  std::vector<double> u{0, 0, 0};
  for (int i = 0; i <= n; ++i) u.push_back(i);
  u.insert(u.end(), {double(n), double(n), double(n)});
  const int levels = 3;
  Refined r = LimitAlong(strip.image, strip.polyline, false, levels);
  REQUIRE(r.chain.size() == size_t(n) * 8 + 1);
  double worst = 0;
  for (size_t j = 0; j < r.chain.size(); ++j)
    worst = std::max(worst, MaxDistance(ValueOf(r.limit, r.chain[j]), DeBoor(d, u, j / 8.0)));
  INFO("n = " << n << ", worst deviation " << worst);
  CHECK(worst < 1e-9);

  // The float stencil path agrees to 1e-4 px (and colour units).
  LimitSurfaceOptions options;
  options.levels = levels;
  auto surface = BuildLimitSurface(strip.image, options);
  REQUIRE(surface.ok());
  const auto fine = EvaluateSurface(*surface, strip.image.vertices);
  double worst_float = 0;
  for (size_t j = 0; j < r.chain.size(); ++j) {
    const Vertex& v = fine[r.chain[j]];
    worst_float = std::max(worst_float, MaxDistance(Point{v.x, v.y, v.r, v.g, v.b}, DeBoor(d, u, j / 8.0)));
    CHECK(surface->vertex_tags[r.chain[j]] == (j == 0 || j + 1 == r.chain.size() ? VertexTag::kCorner : VertexTag::kCrease));
  }
  INFO("float worst deviation " << worst_float);
  CHECK(worst_float < 1e-4);
}

}  // namespace

TEST_CASE("Open polyline with one edge follows its B-spline", "[bspline]") { CheckOpenPolyline(1, 11); }
TEST_CASE("Open polyline with two edges follows its B-spline", "[bspline]") { CheckOpenPolyline(2, 12); }
TEST_CASE("Open polyline with three edges follows its B-spline", "[bspline]") { CheckOpenPolyline(3, 13); }
TEST_CASE("Open polyline with many edges follows its B-spline", "[bspline]") {
  CheckOpenPolyline(4, 14);
  CheckOpenPolyline(25, 15);
}

TEST_CASE("Closed polyline follows its periodic B-spline", "[bspline]") {
  for (int m : {3, 5, 17}) {
    test::Annulus annulus = test::AnnulusImage(m, 20 + m);
    const auto values = test::Values(annulus.image);
    // Uniform periodic spline: control points P_{m-1}, P_0, .., P_{m-1}, P_0, P_1 with knots
    // -3, -2, ..: the knot t = i is the vertex P_i.
    std::vector<Point> d;
    for (int j = 0; j < m + 3; ++j) d.push_back(ValueOf(values, annulus.polyline[(j - 1 + m) % m]));
    std::vector<double> u;
    for (int j = 0; j < m + 7; ++j) u.push_back(j - 3);
    Refined r = LimitAlong(annulus.image, annulus.polyline, true, 3);
    REQUIRE(r.chain.size() == size_t(m) * 8);
    double worst = 0;
    for (size_t j = 0; j < r.chain.size(); ++j)
      worst = std::max(worst, MaxDistance(ValueOf(r.limit, r.chain[j]), DeBoor(d, u, j / 8.0)));
    INFO("m = " << m << ", worst deviation " << worst);
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("Polyline with an interior corner is two clamped splines", "[bspline]") {
  test::Strip strip = test::StripImage(6, 31);
  strip.image.corners = {strip.polyline[2]};
  const auto values = test::Values(strip.image);
  Refined r = LimitAlong(strip.image, strip.polyline, false, 3);
  for (auto [first, last] : {std::pair<int, int>{0, 2}, std::pair<int, int>{2, 6}}) {
    const int n = last - first;
    std::vector<Point> d{ValueOf(values, strip.polyline[first])};
    for (int i = first; i <= last; ++i) d.push_back(ValueOf(values, strip.polyline[i]));
    d.push_back(ValueOf(values, strip.polyline[last]));
    std::vector<double> u{0, 0, 0};
    for (int i = 0; i <= n; ++i) u.push_back(i);
    u.insert(u.end(), {double(n), double(n), double(n)});
    double worst = 0;
    for (int j = 0; j <= 8 * n; ++j)
      worst = std::max(worst, MaxDistance(ValueOf(r.limit, r.chain[8 * first + j]), DeBoor(d, u, j / 8.0)));
    CHECK(worst < 1e-9);
  }
}
