// SPDX-License-Identifier: GPL-3.0-or-later
// B-spline evaluation and fitting of feature chains (spec/METHOD.md section 2 and section 6 step 2), checked against
// an independent de Boor evaluator written here from the knot vectors of spec/METHOD.md section 2.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "sdvi/bspline.h"

namespace {

using sdvi::Distance;
using sdvi::Point2;

// de Boor's algorithm on an explicit knot vector (degree 3).
Point2 DeBoor(const std::vector<double>& knots, const std::vector<Point2>& ctrl, double t) {
  const int p = 3;
  int k = p;
  while (k + 1 < int(ctrl.size()) && knots[k + 1] <= t) ++k;
  std::vector<Point2> d(p + 1);
  for (int j = 0; j <= p; ++j) d[j] = ctrl[j + k - p];
  for (int r = 1; r <= p; ++r)
    for (int j = p; j >= r; --j) {
      double den = knots[j + 1 + k - r] - knots[j + k - p];
      double a = den > 0 ? (t - knots[j + k - p]) / den : 0;
      d[j] = {(1 - a) * d[j - 1].x + a * d[j].x, (1 - a) * d[j - 1].y + a * d[j].y};
    }
  return d[p];
}

// Open end-interpolating spline of P0..Pn: deBoor P0,P0,P1..Pn,Pn, knots {0^4,1..n-1,n^4}.
Point2 IndependentOpen(const std::vector<Point2>& P, double t) {
  const int n = int(P.size()) - 1;
  std::vector<Point2> ctrl{P.front()};
  ctrl.insert(ctrl.end(), P.begin(), P.end());
  ctrl.push_back(P.back());
  std::vector<double> knots{0, 0, 0, 0};
  for (int i = 1; i < n; ++i) knots.push_back(i);
  for (int i = 0; i < 4; ++i) knots.push_back(n);
  return DeBoor(knots, ctrl, std::min(t, n - 1e-9));
}

// Uniform periodic spline of P0..P(n-1): wrap the points, integer knots.
Point2 IndependentClosed(const std::vector<Point2>& P, double t) {
  const int n = int(P.size());
  std::vector<Point2> ctrl;
  for (int i = -1; i <= n + 1; ++i) ctrl.push_back(P[(i + n) % n]);  // P(-1) .. P(n+1)
  // knots[j] = j - 3: on [i, i+1) de Boor uses ctrl[i..i+3] = P(i-1)..P(i+2).
  std::vector<double> knots;
  for (int i = -3; i <= n + 3; ++i) knots.push_back(i);
  return DeBoor(knots, ctrl, t);
}

// Max over samples of the distance to a dense sampling of the independent spline.
double MaxDistanceToSpline(const std::vector<Point2>& samples, const std::vector<Point2>& P, bool closed) {
  std::vector<Point2> dense;
  const int spans = closed ? int(P.size()) : int(P.size()) - 1;
  for (int i = 0; i <= spans * 200; ++i) {
    double t = i / 200.0;
    dense.push_back(closed ? IndependentClosed(P, std::fmod(t, spans)) : IndependentOpen(P, t));
  }
  double worst = 0;
  for (const Point2& s : samples) {
    double best = 1e9;
    for (const Point2& d : dense) best = std::min(best, Distance(s, d));
    worst = std::max(worst, best);
  }
  return worst;
}

}  // namespace

TEST_CASE("open spline evaluation matches an independent de Boor evaluation", "[bspline]") {
  std::vector<Point2> P{{0, 0}, {10, 3}, {14, 12}, {30, 8}, {35, -4}, {50, 2}};
  for (double t = 0; t <= 5.0; t += 0.05) {
    Point2 a = sdvi::EvaluateOpenBSpline(P, t), b = IndependentOpen(P, t);
    REQUIRE(Distance(a, b) < 1e-9);
  }
  REQUIRE(Distance(sdvi::EvaluateOpenBSpline(P, 0), P.front()) < 1e-12);
  REQUIRE(Distance(sdvi::EvaluateOpenBSpline(P, 5), P.back()) < 1e-12);
}

TEST_CASE("closed spline evaluation matches de Boor and the crease limit mask", "[bspline]") {
  std::vector<Point2> P{{0, 0}, {10, -2}, {20, 5}, {18, 16}, {6, 18}, {-3, 9}};
  const int n = int(P.size());
  for (double t = 0; t < n; t += 0.05) {
    Point2 a = sdvi::EvaluateClosedBSpline(P, t), b = IndependentClosed(P, t);
    REQUIRE(Distance(a, b) < 1e-9);
  }
  for (int i = 0; i < n; ++i) {
    const Point2 &l = P[(i + n - 1) % n], &c = P[i], &r = P[(i + 1) % n];
    Point2 mask{(l.x + 4 * c.x + r.x) / 6, (l.y + 4 * c.y + r.y) / 6};
    REQUIRE(Distance(sdvi::EvaluateClosedBSpline(P, i), mask) < 1e-9);
  }
}

TEST_CASE("open fit of a wavy chain stays under the error threshold", "[bspline]") {
  std::vector<Point2> samples;
  for (double x = 0; x <= 120; x += 1.0) samples.push_back({x, 20 * std::sin(x / 15.0) + 0.3 * std::sin(x * 1.7)});
  sdvi::BSplineFitOptions o;
  o.tolerance = 0.5;
  sdvi::BSplineFit fit = sdvi::FitOpenBSpline(samples, o);
  REQUIRE(fit.polygon.size() >= 4);
  REQUIRE(fit.polygon.size() < samples.size() / 2);
  REQUIRE(Distance(fit.polygon.front(), samples.front()) < 1e-9);
  REQUIRE(Distance(fit.polygon.back(), samples.back()) < 1e-9);
  REQUIRE(fit.max_error <= 0.5);
  REQUIRE(MaxDistanceToSpline(samples, fit.polygon, false) <= 0.5 + 1e-3);
}

TEST_CASE("closed fit of a circle stays under the error threshold", "[bspline]") {
  std::vector<Point2> samples;
  const double r = 40;
  for (int i = 0; i < 250; ++i) {
    double a = 2 * M_PI * i / 250;
    samples.push_back({100 + r * std::cos(a), 100 + r * std::sin(a)});
  }
  sdvi::BSplineFitOptions o;
  o.tolerance = 0.25;
  sdvi::BSplineFit fit = sdvi::FitClosedBSpline(samples, o);
  // deBoor count from the paper's rule max(4, len / 8) or denser for the error.
  REQUIRE(fit.polygon.size() >= size_t(2 * M_PI * r / 12));
  REQUIRE(fit.max_error <= 0.25);
  REQUIRE(MaxDistanceToSpline(samples, fit.polygon, true) <= 0.25 + 1e-3);
}

TEST_CASE("a chain with corners keeps them as interpolated kinks", "[bspline]") {
  // Square outline, corners at samples 0, 40, 80, 120.
  std::vector<Point2> samples;
  auto side = [&](Point2 a, Point2 b) {
    for (int i = 0; i < 40; ++i) samples.push_back({a.x + (b.x - a.x) * i / 40, a.y + (b.y - a.y) * i / 40});
  };
  side({10, 10}, {50, 10});
  side({50, 10}, {50, 50});
  side({50, 50}, {10, 50});
  side({10, 50}, {10, 10});
  double err = 1e9;
  sdvi::FeatureCurve c = sdvi::FitChain(samples, true, {0, 40, 80, 120}, sdvi::BSplineFitOptions{}, &err);
  REQUIRE(c.closed);
  REQUIRE(c.corners.size() == 4);
  const Point2 expected[4] = {{10, 10}, {50, 10}, {50, 50}, {10, 50}};
  for (int k = 0; k < 4; ++k) REQUIRE(Distance(c.points[c.corners[k]], expected[k]) < 1e-6);
  REQUIRE(err < 0.1);
  // The drawn curve passes through the corners.
  std::vector<Point2> drawn = sdvi::SampleFeatureCurve(c, 8);
  for (const Point2& e : expected) {
    double best = 1e9;
    for (const Point2& d : drawn) best = std::min(best, Distance(d, e));
    REQUIRE(best < 1e-6);
  }
}

TEST_CASE("degenerate chains give usable polygons", "[bspline]") {
  sdvi::BSplineFit two = sdvi::FitOpenBSpline({{1, 1}, {5, 1}}, {});
  REQUIRE(two.polygon.size() == 2);
  sdvi::BSplineFit three = sdvi::FitOpenBSpline({{1, 1}, {3, 2}, {5, 1}}, {});
  REQUIRE(three.polygon.size() >= 2);
  for (const Point2& p : three.polygon) REQUIRE(std::isfinite(p.x));
  sdvi::BSplineFit tri = sdvi::FitClosedBSpline({{0, 0}, {4, 0}, {2, 3}}, {});
  REQUIRE(tri.polygon.size() == 3);
  for (const Point2& p : tri.polygon) REQUIRE(std::isfinite(p.y));
}

TEST_CASE("PolygonOffset is the distance from a deBoor point to its own spline", "[bspline]") {
  // A closed square of "radius" a (points on the axes): the spline passes through
  // (P(i-1) + 4 P(i) + P(i+1)) / 6 = 2a/3 along each axis, a/3 inside the point.
  const double a = 6;
  const std::vector<Point2> diamond = {{a, 0}, {0, a}, {-a, 0}, {0, -a}};
  CHECK(sdvi::PolygonOffset(diamond, true) == Approx(a / 3).epsilon(1e-9));
  // A straight open polygon lies on its spline (up to the sampling, 1/16 of a span); fewer
  // than three points have no offset.
  CHECK(sdvi::PolygonOffset({{0, 0}, {5, 0}, {10, 0}, {20, 0}}, false) < 0.1);
  CHECK(sdvi::PolygonOffset({{0, 0}, {10, 0}}, false) == 0);
  // An open corner: P1 = (5, 5) between (0, 0) and (10, 0); the spline's nearest approach,
  // measured against the independent evaluator, is what PolygonOffset gives (up to its
  // 1/16-span sampling).
  const std::vector<Point2> tent = {{0, 0}, {5, 5}, {10, 0}};
  double nearest = 1e9;
  for (int k = 0; k <= 2000; ++k) {
    const Point2 c = IndependentOpen(tent, 2.0 * k / 2000);
    nearest = std::min(nearest, std::hypot(c.x - 5, c.y - 5));
  }
  CHECK(sdvi::PolygonOffset(tent, false) == Approx(nearest).margin(0.01));
}

TEST_CASE("max_polygon_offset adds deBoor points until the polygon keeps to its curve", "[bspline]") {
  // A small circle (a glyph's counter, radius 4): within the 0.5 px tolerance with few
  // points, whose polygon lies well outside the circle.
  std::vector<Point2> samples;
  for (int i = 0; i < 50; ++i) {
    const double t = 2 * M_PI * i / 50;
    samples.push_back({32 + 4 * std::cos(t), 32 + 4 * std::sin(t)});
  }
  sdvi::BSplineFitOptions options;
  options.tolerance = 0.5;
  const sdvi::BSplineFit loose = sdvi::FitClosedBSpline(samples, options);
  CHECK(loose.max_error <= 0.5);
  CHECK(sdvi::PolygonOffset(loose.polygon, true) > 1.0);
  options.max_polygon_offset = 0.5;
  const sdvi::BSplineFit near = sdvi::FitClosedBSpline(samples, options);
  CHECK(near.max_error <= 0.5);
  CHECK(sdvi::PolygonOffset(near.polygon, true) <= 0.5);
  CHECK(near.polygon.size() > loose.polygon.size());
  for (const Point2& p : near.polygon) CHECK(std::hypot(p.x - 32, p.y - 32) < 4.5 + 0.5);
}
