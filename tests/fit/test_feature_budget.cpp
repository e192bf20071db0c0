// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the feature budget (sdvi/feature_budget.h, spec/METHOD.md section 6 step 3):
// value per vertex, coarser polygons before dropping, and no cliff at low budgets.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sdvi/bspline.h"
#include "sdvi/feature_budget.h"
#include "sdvi/vectorize.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

// A circle of radius r fitted as the detector fits a chain (tolerance 1.5 px, spacing 8).
sdvi::FeatureCurve Circle(double cx, double cy, double r, float contrast) {
  std::vector<sdvi::Point2> samples;
  const int n = int(2 * kPi * r);  // about 1 px apart
  for (int k = 0; k < n; ++k) {
    const double a = 2 * kPi * k / n;
    samples.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  sdvi::BSplineFitOptions fit;
  fit.tolerance = 1.5;
  fit.initial_spacing = 8;
  fit.max_spacing = 12;
  sdvi::FeatureCurve curve = sdvi::FitChain(samples, true, {}, fit);
  curve.contrast = contrast;
  return curve;
}

sdvi::FeatureCurve Line(double x0, double y, double x1, int points, float contrast) {
  sdvi::FeatureCurve curve;
  for (int k = 0; k < points; ++k) curve.points.push_back({x0 + (x1 - x0) * k / (points - 1), y});
  curve.contrast = contrast;
  return curve;
}

sdvi::FeatureCurve Frame(double size) {
  sdvi::FeatureCurve curve;
  curve.points = {{0, 0}, {size, 0}, {size, size}, {0, size}};
  curve.closed = true;
  curve.boundary = true;
  curve.corners = {0, 1, 2, 3};
  return curve;
}

double Cost(const std::vector<sdvi::FeatureCurve>& curves) {
  double cost = 0;
  for (const sdvi::FeatureCurve& c : curves)
    if (!c.boundary) cost += sdvi::FeatureVertexCost(c, true);
  return cost;
}

// Flat-colour art: 3 x 3 discs of radius 20..28 px with a 5 px dark outline on white,
// 4 x 4 supersampled (anti-aliased edges): 18 colour discontinuities on circles.
sdvi::Raster Discs() {
  const int size = 192;
  const float fill[9][3] = {{232, 163, 60}, {60, 123, 232},  {92, 196, 92},  {217, 79, 112}, {155, 92, 217},
                            {242, 214, 75}, {75, 201, 242}, {242, 139, 75}, {120, 200, 160}};
  auto colour = [&](double x, double y, int c) -> float {
    for (int k = 0; k < 9; ++k) {
      const int i = k % 3, j = k / 3;
      const double r = 20 + 4 * ((i + 2 * j) % 3);
      const double d = std::hypot(x - (32 + 64 * i), y - (32 + 64 * j));
      if (d <= r - 5) return fill[k][c];
      if (d <= r) return 48;
    }
    return 255;
  };
  sdvi::Raster raster(size, size, 3);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int s = 0; s < 16; ++s) sum += colour(x + (s % 4 + 0.5) / 4, y + (s / 4 + 0.5) / 4, c);
        raster.at(x, y, c) = float(std::round(sum / 16));
      }
    }
  }
  return raster;
}

}  // namespace

TEST_CASE("feature budget: everything that fits is kept as it is", "[feature_budget]") {
  const std::vector<sdvi::FeatureCurve> curves = {Frame(200), Circle(100, 100, 50, 120),
                                                  Line(10, 20, 150, 12, 40)};
  sdvi::FeatureBudgetOptions options;
  options.vertex_budget = Cost(curves);
  sdvi::FeatureBudgetStats stats;
  const std::vector<sdvi::FeatureCurve> kept = sdvi::FitFeaturesToBudget(curves, options, &stats);
  REQUIRE(kept.size() == 3);
  for (size_t i = 0; i < 3; ++i) {
    REQUIRE(kept[i].points.size() == curves[i].points.size());
    for (size_t k = 0; k < kept[i].points.size(); ++k) {
      CHECK(kept[i].points[k].x == curves[i].points[k].x);
      CHECK(kept[i].points[k].y == curves[i].points[k].y);
    }
  }
  CHECK(stats.vertices_kept == stats.vertices_detected);
  CHECK(stats.dropped == 0);
  CHECK(stats.coarsened == 0);
  // Costs: twice the deBoor points (a pair), four times for a thin structure, once unpaired.
  sdvi::FeatureCurve thin = curves[2];
  thin.width = 1;
  CHECK(sdvi::FeatureVertexCost(curves[2], true) == 24);
  CHECK(sdvi::FeatureVertexCost(thin, true) == 48);
  CHECK(sdvi::FeatureVertexCost(curves[2], false) == 12);
}

TEST_CASE("feature budget: a feature that does not fit is coarsened before it is dropped", "[feature_budget]") {
  const sdvi::FeatureCurve circle = Circle(150, 150, 120, 200);
  const double full = sdvi::FeatureVertexCost(circle, true);
  REQUIRE(full >= 160);  // the detector's fit: about one deBoor point per 8 px
  sdvi::FeatureBudgetOptions options;
  options.vertex_budget = 0.6 * full;
  options.interior_spacing = 20;  // an interior too coarse to draw the edge itself
  sdvi::FeatureBudgetStats stats;
  const std::vector<sdvi::FeatureCurve> kept = sdvi::FitFeaturesToBudget({Frame(300), circle}, options, &stats);
  REQUIRE(kept.size() == 2);
  CHECK(kept[0].boundary);
  const sdvi::FeatureCurve& coarse = kept[1];
  CHECK(coarse.closed);
  CHECK(coarse.contrast == 200);
  CHECK(sdvi::FeatureVertexCost(coarse, true) <= options.vertex_budget);
  CHECK(stats.coarsened == 1);
  CHECK(stats.dropped == 0);
  CHECK(stats.vertices_kept == sdvi::FeatureVertexCost(coarse, true));
  // Still the circle: its spline within the coarser tolerance (1.5 x 2 px, plus the given
  // fit's 1.5 px) of radius 120.
  double off = 0;
  for (const sdvi::Point2& p : sdvi::SampleFeatureCurve(coarse)) off = std::max(off, std::fabs(std::hypot(p.x - 150, p.y - 150) - 120));
  CHECK(off < 4.5);
}

TEST_CASE("feature budget: features are kept by value per vertex, boundaries always", "[feature_budget]") {
  // Two equal lines: contrast 200 and 20. Room for one: the one removing more error stays.
  const std::vector<sdvi::FeatureCurve> curves = {Line(10, 20, 90, 8, 20), Frame(100), Line(10, 60, 90, 8, 200)};
  sdvi::FeatureBudgetOptions options;
  options.vertex_budget = 16;  // one line, paired
  options.coarse_levels = 0;
  sdvi::FeatureBudgetStats stats;
  const std::vector<sdvi::FeatureCurve> kept = sdvi::FitFeaturesToBudget(curves, options, &stats);
  REQUIRE(kept.size() == 2);
  CHECK(kept[0].boundary);  // input order kept
  CHECK(kept[1].contrast == 200);
  CHECK(stats.dropped == 1);
  CHECK(stats.vertices_kept == 16);
  // A budget of nothing keeps the boundary alone.
  options.vertex_budget = 0;
  const std::vector<sdvi::FeatureCurve> bare = sdvi::FitFeaturesToBudget(curves, options);
  REQUIRE(bare.size() == 1);
  CHECK(bare[0].boundary);
}

TEST_CASE("no cliff at low budgets: halving the budget of flat-colour art costs a few dB", "[feature_budget][vectorize]") {
  // 18 edges on circles in 192 x 192 px. At 50 pixels per vertex (737 vertices) the
  // features, kept longest first within half the budget and dropped when they did not
  // fit, lost 9.6 dB against 25 pixels per vertex; the budget split keeps every disc.
  const sdvi::Raster discs = Discs();
  sdvi::VectorizeOptions options;
  options.compression_ratio = 25;
  auto fine = sdvi::Vectorize(discs, nullptr, options);
  REQUIRE(fine.ok());
  options.compression_ratio = 50;
  auto half = sdvi::Vectorize(discs, nullptr, options);
  REQUIRE(half.ok());
  const double budget = 192.0 * 192.0 / 50;
  INFO("25 ppv: " << fine->report.psnr << " dB, " << fine->report.vertices << " vertices; 50 ppv: "
                  << half->report.psnr << " dB, " << half->report.vertices << " vertices");
  // 6 dB: with the flips' exact pixel partition both budgets gained (25 ppv 36.5 -> 39.3 dB,
  // 50 ppv 33.5 -> 33.9 dB), the larger one more; the cliff was 9.6 dB.
  CHECK(half->report.psnr > fine->report.psnr - 6);
  CHECK(half->report.vertices <= 1.03 * budget + 1);
  CHECK(half->report.feature_curves >= 12);
}

TEST_CASE("given features on top of the budget: exact features do not take the interior's vertices", "[feature_budget][vectorize]") {
  // The 18 circles of the discs given as exact features (as an importer knows them), at
  // 100 pixels per vertex (368 vertices): sharing the budget, the features are cut to their
  // share; with given_features_extra 1 their own cost (no crossings: no junctions) comes on
  // top, up to once more the budget.
  const sdvi::Raster discs = Discs();
  std::vector<sdvi::FeatureCurve> given;
  for (int k = 0; k < 9; ++k) {
    const int i = k % 3, j = k / 3;
    const double r = 20 + 4 * ((i + 2 * j) % 3);
    given.push_back(Circle(32 + 64 * i, 32 + 64 * j, r, 120));
    given.push_back(Circle(32 + 64 * i, 32 + 64 * j, r - 5, 120));
  }
  const double base = 192.0 * 192.0 / 100;
  const double extra = std::min(Cost(given), base);
  sdvi::VectorizeOptions options;
  options.compression_ratio = 100;
  auto shared = sdvi::VectorizeWithFeatures(discs, nullptr, given, options);
  REQUIRE(shared.ok());
  options.given_features_extra = 1;
  auto on_top = sdvi::VectorizeWithFeatures(discs, nullptr, given, options);
  REQUIRE(on_top.ok());
  INFO("shared: " << shared->report.psnr << " dB, " << shared->report.vertices << " vertices, "
                  << shared->report.feature_curves << " features; on top: " << on_top->report.psnr << " dB, "
                  << on_top->report.vertices << " vertices, " << on_top->report.feature_curves
                  << " features; cost " << Cost(given));
  CHECK(extra > 0.25 * base);
  CHECK(shared->report.vertices <= 1.03 * base + 1);
  CHECK(on_top->report.vertices <= 1.03 * (base + extra) + 1);
  CHECK(on_top->report.vertices > shared->report.vertices);
  CHECK(on_top->report.feature_curves >= shared->report.feature_curves);
  CHECK(on_top->report.psnr > shared->report.psnr);
  // Under max_triangles, a hard cap, the option changes nothing.
  options.max_triangles = 700;
  auto capped = sdvi::VectorizeWithFeatures(discs, nullptr, given, options);
  options.given_features_extra = 0;
  auto capped_shared = sdvi::VectorizeWithFeatures(discs, nullptr, given, options);
  REQUIRE(capped.ok());
  REQUIRE(capped_shared.ok());
  CHECK(capped->report.triangles == capped_shared->report.triangles);
  CHECK(capped->report.psnr == capped_shared->report.psnr);
  // Out of range: a clear error.
  options.given_features_extra = -1;
  auto bad = sdvi::VectorizeWithFeatures(discs, nullptr, given, options);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.status().code() == sdvi::StatusCode::kInvalidArgument);
}

TEST_CASE("feature budget: the same choice on 1, 2 and 3 threads", "[feature_budget]") {
  // Enough features for several chunks of coarser fits, a budget that coarsens and drops.
  std::vector<sdvi::FeatureCurve> curves;
  for (int k = 0; k < 70; ++k) {
    curves.push_back(Circle(60 + 37 * (k % 10), 60 + 41 * (k / 10), 8 + 3 * (k % 7), float(20 + k)));
    if (k % 4 == 0) curves.push_back(Line(10, 5 + 6 * k, 300 + k, 40, float(30 + k)));
  }
  sdvi::FeatureBudgetOptions options;
  options.vertex_budget = 900;
  options.interior_spacing = 10;
  sdvi::FeatureBudgetStats one_stats;
  const std::vector<sdvi::FeatureCurve> one = sdvi::FitFeaturesToBudget(curves, options, &one_stats);
  REQUIRE(one_stats.coarsened > 0);
  REQUIRE(one_stats.dropped > 0);
  for (int threads : {2, 3}) {
    options.threads = threads;
    sdvi::FeatureBudgetStats stats;
    const std::vector<sdvi::FeatureCurve> more = sdvi::FitFeaturesToBudget(curves, options, &stats);
    REQUIRE(stats.vertices_kept == one_stats.vertices_kept);
    REQUIRE(stats.coarsened == one_stats.coarsened);
    REQUIRE(stats.dropped == one_stats.dropped);
    REQUIRE(more.size() == one.size());
    for (size_t i = 0; i < one.size(); ++i) {
      REQUIRE(more[i].points.size() == one[i].points.size());
      for (size_t k = 0; k < one[i].points.size(); ++k) {
        REQUIRE(more[i].points[k].x == one[i].points[k].x);
        REQUIRE(more[i].points[k].y == one[i].points[k].y);
      }
      REQUIRE(more[i].corners == one[i].corners);
    }
  }
}
