// SPDX-License-Identifier: GPL-3.0-or-later
// The feature layer's share of the vertex budget: value per vertex, coarser polygons
// before dropping (rules in sdvi/feature_budget.h, spec/METHOD.md section 6 step 3).
#include "sdvi/feature_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

#include "parallel.h"
#include "sdvi/bspline.h"

namespace sdvi {
namespace {

// One segment of a polyline: its start and direction, and its bounding box.
struct Segment {
  Point2 a;
  double vx, vy, l2;
  double x0, x1, y0, y1;
};

// Mean distance from the points of `a` to the polyline `b`, both samples of one curve in
// the same direction: point j is compared with the segments of b around the same share of
// the curve (a window of 64 segments each side), so the cost is linear in the samples.
// A point's distance is the least of hypot(offset to the segment's nearest point) over the
// window's segments, in any order (the one at the centre first): a segment is skipped when
// its bounding box is farther than the least so far plus a margin, or its offset's square
// is more than (1 + 1e-9) times that least's square: far beyond the rounding of the
// coordinates (the margin, 1e-9 of their magnitude), of the squares and of hypot, so the
// skipped ones would not have been less (the same doubles with few hypot calls).
double MeanDistance(const std::vector<Point2>& a, const std::vector<Point2>& b, bool closed) {
  if (a.empty() || b.size() < 2) return 0;
  const int64_t segments = closed ? int64_t(b.size()) : int64_t(b.size()) - 1;
  constexpr int64_t kWindow = 64;
  double extent = 0;
  for (const std::vector<Point2>* points : {&a, &b})
    for (const Point2& p : *points) extent = std::max({extent, std::fabs(p.x), std::fabs(p.y)});
  const double margin = 1e-9 * (1 + extent);
  std::vector<Segment> segs(static_cast<size_t>(segments));
  for (size_t i = 0; i < segs.size(); ++i) {
    const Point2 s = b[i], e = b[(i + 1) % b.size()];
    const double vx = e.x - s.x, vy = e.y - s.y;
    segs[i] = {s, vx, vy, vx * vx + vy * vy, std::min(s.x, e.x), std::max(s.x, e.x), std::min(s.y, e.y),
               std::max(s.y, e.y)};
  }
  double sum = 0;
  for (size_t j = 0; j < a.size(); ++j) {
    const Point2 p = a[j];
    const auto centre = std::min(segments - 1, int64_t(double(j) / double(a.size()) * double(segments)));
    double best = INFINITY, above2 = INFINITY, box2 = INFINITY;
    auto visit = [&](const Segment& s) {
      const double gx = std::max({s.x0 - p.x, p.x - s.x1, 0.0}), gy = std::max({s.y0 - p.y, p.y - s.y1, 0.0});
      if (gx * gx + gy * gy > box2) return;
      const double t = s.l2 > 0 ? std::clamp(((p.x - s.a.x) * s.vx + (p.y - s.a.y) * s.vy) / s.l2, 0.0, 1.0) : 0.0;
      const double dx = p.x - (s.a.x + t * s.vx), dy = p.y - (s.a.y + t * s.vy);
      if (dx * dx + dy * dy > above2) return;
      const double d = std::hypot(dx, dy);
      if (d < best) {
        best = d;
        above2 = best * best * (1 + 1e-9);
        box2 = (best + margin) * (best + margin);
      }
    };
    visit(segs[size_t(centre)]);  // likely the nearest: the bounds then skip most of the rest
    if (!closed) {
      for (int64_t k = std::max<int64_t>(0, centre - kWindow); k <= std::min(segments - 1, centre + kWindow); ++k)
        visit(segs[size_t(k)]);
    } else if (segments <= 2 * kWindow + 1) {
      for (const Segment& s : segs) visit(s);  // the window wraps round them all
    } else {
      int64_t i = ((centre - kWindow) % segments + segments) % segments;
      for (int64_t k = 0; k <= 2 * kWindow; ++k) {
        visit(segs[size_t(i)]);
        if (++i == segments) i = 0;
      }
    }
    sum += best;
  }
  return sum / double(a.size());
}

// The curve refitted to its own spline at a coarser tolerance and spacing (x scale);
// *error gets the mean distance from the given spline to the new one.
FeatureCurve Coarsen(const FeatureCurve& curve, double scale, double* error) {
  constexpr int kPerSpan = 8;
  const std::vector<Point2> samples = SampleFeatureCurve(curve, kPerSpan);
  // The sample index of each corner: SampleFeatureCurve walks the open pieces between
  // corners from the first corner (closed) or the first point (open), kPerSpan a span.
  std::vector<uint32_t> corners;
  for (uint32_t c : curve.corners)
    if (c < curve.points.size()) corners.push_back(c);
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  std::vector<uint32_t> corner_samples;
  if (curve.closed && !corners.empty()) {
    for (uint32_t c : corners) corner_samples.push_back(kPerSpan * (c - corners.front()));
  } else if (!curve.closed) {
    for (uint32_t c : corners)
      if (c > 0 && c + 1 < curve.points.size()) corner_samples.push_back(kPerSpan * c);
  }
  BSplineFitOptions fit;
  fit.tolerance = 1.5 * scale;
  fit.initial_spacing = 8 * scale;
  fit.max_spacing = 12 * scale;
  FeatureCurve out = FitChain(samples, curve.closed, corner_samples, fit);
  // The new curve's samples start where the given ones do (at the first corner of a
  // closed curve with corners, at its first point otherwise; FitChain keeps that start).
  *error = MeanDistance(samples, SampleFeatureCurve(out, kPerSpan), curve.closed);
  out.sharpness = curve.sharpness;
  out.boundary = curve.boundary;
  out.contrast = curve.contrast;
  out.width = curve.width;
  return out;
}

struct Choice {
  double cost = 0, value = 0;
  int level = -1;  // -1 dropped, 0 as given, k > 0 the k-th coarser fit
};

// The upper convex hull of (cost, value) from "dropped" (0, 0): the options worth taking,
// by increasing cost, with strictly decreasing value per added vertex.
std::vector<Choice> UpperHull(std::vector<Choice> choices) {
  std::stable_sort(choices.begin(), choices.end(), [](const Choice& a, const Choice& b) {
    return std::tie(a.cost, b.value) < std::tie(b.cost, a.value);
  });
  std::vector<Choice> hull;
  for (const Choice& c : choices) {
    if (!hull.empty() && c.value <= hull.back().value) continue;  // dominated
    while (hull.size() >= 2) {
      const Choice& a = hull[hull.size() - 2];
      const Choice& b = hull.back();
      // b lies on or below the chord a -> c: not on the hull.
      if ((b.value - a.value) * (c.cost - a.cost) <= (c.value - a.value) * (b.cost - a.cost)) hull.pop_back();
      else break;
    }
    hull.push_back(c);
  }
  return hull;
}

// Polylines a feature is placed as (src/pairs.h): a thin structure 3 (two pairs sharing the
// centre; 4 when wide, counted 3), a pair 2, without pairs 1.
double PolylinesOf(const FeatureCurve& c, bool pairs) { return pairs ? (c.width > 0 ? 3.0 : 2.0) : 1.0; }

// Junction vertices each feature adds when placed with the others (ControlMeshOptions::
// junctions): every crossing of two features' control polygons is a junction of each of
// one's polylines with each of the other's, half of them counted to each feature.
std::vector<double> JunctionVertexCosts(const std::vector<FeatureCurve>& curves, bool pairs) {
  std::vector<double> extra(curves.size(), 0.0);
  struct Seg {
    Point2 a, b;
    uint32_t curve;
  };
  std::vector<Seg> segs;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (size_t i = 0; i < curves.size(); ++i) {
    const FeatureCurve& c = curves[i];
    if (c.boundary || c.points.size() < 2) continue;
    const size_t m = c.points.size(), n = c.closed ? m : m - 1;
    for (size_t k = 0; k < n; ++k) {
      const Point2 a = c.points[k], b = c.points[(k + 1) % m];
      segs.push_back({a, b, uint32_t(i)});
      x0 = std::min({x0, a.x, b.x}), y0 = std::min({y0, a.y, b.y});
      x1 = std::max({x1, a.x, b.x}), y1 = std::max({y1, a.y, b.y});
    }
  }
  if (segs.empty()) return extra;
  // Square cells of at least 16 px, at most about one per segment.
  const double cell = std::max(16.0, std::sqrt((x1 - x0 + 1) * (y1 - y0 + 1) / double(segs.size())));
  const int nx = int((x1 - x0) / cell) + 1, ny = int((y1 - y0) / cell) + 1;
  const double cx = cell, cy = cell;
  std::vector<std::vector<uint32_t>> cells(size_t(nx) * size_t(ny));
  auto cells_of = [&](const Seg& s, auto&& f) {
    const int a0 = std::clamp(int((std::min(s.a.x, s.b.x) - x0) / cx), 0, nx - 1);
    const int a1 = std::clamp(int((std::max(s.a.x, s.b.x) - x0) / cx), 0, nx - 1);
    const int b0 = std::clamp(int((std::min(s.a.y, s.b.y) - y0) / cy), 0, ny - 1);
    const int b1 = std::clamp(int((std::max(s.a.y, s.b.y) - y0) / cy), 0, ny - 1);
    for (int y = b0; y <= b1; ++y)
      for (int x = a0; x <= a1; ++x) f(cells[size_t(y) * size_t(nx) + size_t(x)]);
  };
  for (uint32_t k = 0; k < segs.size(); ++k) cells_of(segs[k], [&](std::vector<uint32_t>& c) { c.push_back(k); });
  auto cross = [](Point2 o, Point2 a, Point2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  std::vector<uint32_t> last(segs.size(), UINT32_MAX);
  for (uint32_t k = 0; k < segs.size(); ++k) {
    const Seg& s = segs[k];
    cells_of(s, [&](std::vector<uint32_t>& c) {
      for (uint32_t j : c) {
        if (j <= k || last[j] == k || segs[j].curve == s.curve) continue;
        last[j] = k;
        const Seg& t = segs[j];
        const double d1 = cross(t.a, t.b, s.a), d2 = cross(t.a, t.b, s.b);
        const double d3 = cross(s.a, s.b, t.a), d4 = cross(s.a, s.b, t.b);
        if (!(((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))) continue;
        const double half = 0.5 * PolylinesOf(curves[s.curve], pairs) * PolylinesOf(curves[t.curve], pairs);
        extra[s.curve] += half;
        extra[t.curve] += half;
      }
    });
  }
  return extra;
}

}  // namespace

double FeatureVertexCost(const FeatureCurve& curve, bool pairs) {
  return double(curve.points.size()) * (pairs ? 2 : 1) * (curve.width > 0 ? 2 : 1);
}

std::vector<FeatureCurve> FitFeaturesToBudget(const std::vector<FeatureCurve>& curves,
                                              const FeatureBudgetOptions& options,
                                              FeatureBudgetStats* stats) {
  FeatureBudgetStats local;
  FeatureBudgetStats& s = stats != nullptr ? *stats : local;
  s = FeatureBudgetStats();
  const std::vector<double> junction_cost =
      options.junctions ? JunctionVertexCosts(curves, options.pairs) : std::vector<double>(curves.size(), 0.0);
  for (size_t i = 0; i < curves.size(); ++i)
    if (!curves[i].boundary) s.vertices_detected += FeatureVertexCost(curves[i], options.pairs) + junction_cost[i];
  if (s.vertices_detected <= options.vertex_budget) {
    s.vertices_kept = s.vertices_detected;
    return curves;
  }

  // Each feature's options and the steps along their hull.
  std::vector<std::vector<FeatureCurve>> coarse(curves.size());
  std::vector<std::vector<Choice>> hulls(curves.size());
  struct Step {
    double ratio;
    uint32_t feature, index;  // hulls[feature][index] is reached by this step
  };
  std::vector<Step> steps;
  const double spacing = std::max(1e-9, options.interior_spacing);
  // The coarser fits of each feature, features in chunks on the threads.
  const int levels = std::max(0, options.coarse_levels);
  std::vector<std::vector<double>> errors(curves.size());
  constexpr size_t kCurveChunk = 16;
  fit_internal::ForEachChunk(curves.size(), kCurveChunk, options.threads, [&](size_t, size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) {
      if (curves[i].boundary) continue;
      for (int k = 1; k <= levels; ++k) {
        double error = 0;
        coarse[i].push_back(Coarsen(curves[i], std::ldexp(1.0, k), &error));
        errors[i].push_back(error);
      }
    }
  });
  for (size_t i = 0; i < curves.size(); ++i) {
    const FeatureCurve& c = curves[i];
    if (c.boundary) continue;
    const double contrast = c.contrast > 0 ? double(c.contrast) : 1.0;
    const double full_value = contrast * contrast * PolygonLength(c);
    std::vector<Choice> choices = {{0, 0, -1}, {FeatureVertexCost(c, options.pairs) + junction_cost[i], full_value, 0}};
    double finer_cost = choices.back().cost;
    for (int k = 1; k <= levels; ++k) {
      const FeatureCurve& coarser = coarse[i][size_t(k) - 1];
      const double error = errors[i][size_t(k) - 1];
      const double cost = FeatureVertexCost(coarser, options.pairs) + junction_cost[i];
      const double value = full_value * std::max(0.0, 1.0 - 12.0 * error / spacing);
      if (!(cost < finer_cost) || !(value > 0)) continue;
      finer_cost = cost;
      choices.push_back({cost, value, k});
    }
    hulls[i] = UpperHull(std::move(choices));
    for (uint32_t k = 1; k < hulls[i].size(); ++k) {
      const Choice& a = hulls[i][k - 1];
      const Choice& b = hulls[i][k];
      steps.push_back({(b.value - a.value) / (b.cost - a.cost), uint32_t(i), k});
    }
  }
  std::stable_sort(steps.begin(), steps.end(), [](const Step& a, const Step& b) {
    return std::tie(b.ratio, a.feature, a.index) < std::tie(a.ratio, b.feature, b.index);
  });
  std::vector<uint32_t> reached(curves.size(), 0);
  std::vector<uint8_t> stopped(curves.size(), 0);
  double used = 0;
  for (const Step& step : steps) {
    if (stopped[step.feature] || reached[step.feature] + 1 != step.index) continue;
    const std::vector<Choice>& hull = hulls[step.feature];
    const double added = hull[step.index].cost - hull[step.index - 1].cost;
    if (used + added > options.vertex_budget) {
      stopped[step.feature] = 1;  // its finer options come after this one
      continue;
    }
    used += added;
    reached[step.feature] = step.index;
  }

  std::vector<FeatureCurve> kept;
  for (size_t i = 0; i < curves.size(); ++i) {
    if (curves[i].boundary) {
      kept.push_back(curves[i]);
      continue;
    }
    const int level = hulls[i][reached[i]].level;
    if (level < 0) {
      ++s.dropped;
      continue;
    }
    if (level > 0) ++s.coarsened;
    kept.push_back(level == 0 ? curves[i] : coarse[i][size_t(level) - 1]);
  }
  s.vertices_kept = used;
  return kept;
}

}  // namespace sdvi
