// SPDX-License-Identifier: GPL-3.0-or-later
// Creating an image from coloured curves (paper section V; spec/CURVES.md section 1):
// validate -> sample each Bezier path by arc length -> clip it to the frame -> fit a cubic
// B-spline control polygon -> the frame as boundary, feature pairs and CDT
// (BuildControlMesh) -> colours of the pair vertices from the side colour stops ->
// harmonic interpolation of every other vertex colour.
#include "sdvi/create.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "sdvi/bspline.h"
#include "sdvi/subdiv_rules.h"

namespace sdvi {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSampleSpacing = 0.5;  // arc length between fit samples, px
constexpr double kMinLength = 1e-3;     // shorter curves are an error, px

double Dist(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }
bool Finite(Point2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

Point2 EvaluateBezier(Point2 p0, const CubicBezier& s, double t) {
  const double u = 1 - t;
  const double b0 = u * u * u, b1 = 3 * u * u * t, b2 = 3 * u * t * t, b3 = t * t * t;
  return {b0 * p0.x + b1 * s.c1.x + b2 * s.c2.x + b3 * s.end.x, b0 * p0.y + b1 * s.c1.y + b2 * s.c2.y + b3 * s.end.y};
}

std::string CurveName(const ColoredCurve& c, size_t index) {
  std::string s = "curve " + std::to_string(index);
  if (!c.name.empty()) s += " (" + c.name + ")";
  return s;
}

// ---- Validation ----

Status ValidateStops(const std::vector<CurveColorStop>& stops, const std::string& where, const char* side) {
  auto bad = [&](StatusCode code, const std::string& what) {
    return Status(code, "CreateFromCurves: " + where + " " + side + " colour " + what);
  };
  if (stops.empty()) return bad(StatusCode::kInvalidArgument, "has no colour stop");
  for (size_t k = 0; k < stops.size(); ++k) {
    const CurveColorStop& s = stops[k];
    const std::string stop = "stop " + std::to_string(k);
    if (!std::isfinite(s.offset) || !std::isfinite(s.color.r) || !std::isfinite(s.color.g) ||
        !std::isfinite(s.color.b))
      return bad(StatusCode::kNonFinite, stop + " is not finite");
    if (s.offset < 0 || s.offset > 1)
      return bad(StatusCode::kInvalidArgument, stop + " has offset " + std::to_string(s.offset) + " outside [0, 1]");
    if (k > 0 && s.offset < stops[k - 1].offset)
      return bad(StatusCode::kInvalidArgument, stop + " has offset " + std::to_string(s.offset) +
                                                   " below the previous stop's " + std::to_string(stops[k - 1].offset));
  }
  return Status::Ok();
}

Status ValidateDrawing(const CurveDrawing& d, const CreateOptions& o) {
  const std::string prefix = "CreateFromCurves: ";
  if (!(o.rho >= 0 && o.rho < 1000) || !(o.min_distance > 0 && o.min_distance < 1000) ||
      !(o.fit_tolerance > 0.01 && o.fit_tolerance <= 100) || !(o.max_spacing >= 1 && o.max_spacing <= 1000) ||
      !(o.corner_angle_deg >= 0 && o.corner_angle_deg <= 180) ||
      !(o.min_angle_deg >= 0 && o.min_angle_deg <= 30) || !(o.max_edge >= 0 && std::isfinite(o.max_edge)) ||
      !(o.clearance > 0 && o.clearance < 1000) || o.max_size <= 0 || !(o.max_length > 0))
    return Status(StatusCode::kInvalidArgument,
                  prefix + "options out of range (rho in [0, 1000), min_distance in (0, 1000), fit_tolerance in "
                           "(0.01, 100], max_spacing in [1, 1000], corner_angle_deg in [0, 180], min_angle_deg in "
                           "[0, 30], max_edge >= 0, clearance in (0, 1000), max_size > 0, max_length > 0)");
  if (d.width <= 0 || d.height <= 0)
    return Status(StatusCode::kInvalidArgument, prefix + "drawing size " + std::to_string(d.width) + "x" +
                                                    std::to_string(d.height) + " is not positive");
  if (d.width > o.max_size || d.height > o.max_size)
    return Status(StatusCode::kLimitExceeded, prefix + "drawing size " + std::to_string(d.width) + "x" +
                                                  std::to_string(d.height) + " exceeds max_size " +
                                                  std::to_string(o.max_size));
  if (d.curves.empty()) return Status(StatusCode::kEmptyInput, prefix + "the drawing has no curves");
  if (d.curves.size() > o.max_curves)
    return Status(StatusCode::kLimitExceeded, prefix + std::to_string(d.curves.size()) +
                                                  " curves exceed max_curves " + std::to_string(o.max_curves));
  size_t segments = 0, stops = 0;
  double length = 0;
  for (size_t i = 0; i < d.curves.size(); ++i) {
    const ColoredCurve& c = d.curves[i];
    const std::string where = CurveName(c, i);
    segments += c.segments.size();
    stops += c.left.size() + c.right.size();
    if (segments > o.max_segments)
      return Status(StatusCode::kLimitExceeded, prefix + "more than max_segments " + std::to_string(o.max_segments) +
                                                    " Bezier segments (at " + where + ")");
    if (stops > o.max_color_stops)
      return Status(StatusCode::kLimitExceeded, prefix + "more than max_color_stops " +
                                                    std::to_string(o.max_color_stops) + " colour stops (at " + where +
                                                    ")");
    if (c.segments.empty()) return Status(StatusCode::kEmptyInput, prefix + where + " has no segments");
    if (!Finite(c.start)) return Status(StatusCode::kNonFinite, prefix + where + " has a non-finite start point");
    Point2 p = c.start;
    double polygon = 0;
    for (size_t k = 0; k < c.segments.size(); ++k) {
      const CubicBezier& s = c.segments[k];
      if (!Finite(s.c1) || !Finite(s.c2) || !Finite(s.end))
        return Status(StatusCode::kNonFinite, prefix + where + " segment " + std::to_string(k) +
                                                  " has a non-finite point");
      polygon += Dist(p, s.c1) + Dist(s.c1, s.c2) + Dist(s.c2, s.end);
      p = s.end;
    }
    if (c.closed) polygon += Dist(p, c.start);
    if (!std::isfinite(c.sharpness))
      return Status(StatusCode::kNonFinite, prefix + where + " has a non-finite sharpness");
    if (c.sharpness < 0 || c.sharpness > 1)
      return Status(StatusCode::kInvalidArgument, prefix + where + " has sharpness " + std::to_string(c.sharpness) +
                                                      " outside [0, 1]");
    SDVI_RETURN_IF_ERROR(ValidateStops(c.left, where, "left"));
    SDVI_RETURN_IF_ERROR(ValidateStops(c.right, where, "right"));
    // The control polygon's length bounds the arc length from above: shorter than
    // kMinLength, the curve has zero length for us.
    if (polygon < kMinLength)
      return Status(StatusCode::kInvalidArgument, prefix + where + " has zero length");
    length += polygon;
    if (length > o.max_length)
      return Status(StatusCode::kLimitExceeded, prefix + "the curves are longer than max_length " +
                                                    std::to_string(o.max_length) + " px (at " + where + ")");
  }
  return Status::Ok();
}

// ---- Sampling: the path as points about kSampleSpacing apart along its arc length ----

// A whole path, or after clipping a run of it inside the drawing.
struct SampledPath {
  std::vector<Point2> points;        // closed: the start is not repeated
  std::vector<double> arc;           // arc length from the path's start at each point
                                     // (increasing; a run of a closed path may pass length)
  double length = 0;                 // total arc length of the whole path (closed:
                                     // including the way back)
  std::vector<uint32_t> corners;     // sample indices of kinked segment joins
  bool closed = false;               // this run is the whole closed path
  bool periodic = false;             // the whole path is closed (colours wrap around)
  bool clipped_start = false, clipped_end = false;  // the run starts / ends at the frame
};

// Direction leaving a segment's start, or arriving at its end (the first non-zero of the
// control-point differences); zero for a degenerate segment.
Point2 StartTangent(Point2 p0, const CubicBezier& s) {
  for (Point2 q : {s.c1, s.c2, s.end})
    if (Dist(q, p0) > 1e-9) return {q.x - p0.x, q.y - p0.y};
  return {0, 0};
}
Point2 EndTangent(Point2 p0, const CubicBezier& s) {
  for (Point2 q : {s.c2, s.c1, p0})
    if (Dist(q, s.end) > 1e-9) return {s.end.x - q.x, s.end.y - q.y};
  return {0, 0};
}

bool Kinked(Point2 in, Point2 out, double corner_angle_deg) {
  double li = std::hypot(in.x, in.y), lo = std::hypot(out.x, out.y);
  if (li == 0 || lo == 0) return false;
  double c = std::clamp((in.x * out.x + in.y * out.y) / (li * lo), -1.0, 1.0);
  return std::acos(c) * 180 / kPi > corner_angle_deg;
}

// The path as points kSampleSpacing apart (per segment, so every segment join is a
// sample), with the joins that turn by more than corner_angle_deg as corners.
SampledPath SamplePath(const ColoredCurve& curve, double corner_angle_deg) {
  std::vector<CubicBezier> segs = curve.segments;
  Point2 last_end = segs.back().end;
  if (curve.closed && Dist(last_end, curve.start) > 1e-6) {  // the closing straight segment
    Point2 a = last_end, b = curve.start;
    segs.push_back({{a.x + (b.x - a.x) / 3, a.y + (b.y - a.y) / 3},
                    {a.x + 2 * (b.x - a.x) / 3, a.y + 2 * (b.y - a.y) / 3},
                    b});
  }
  SampledPath out;
  out.closed = out.periodic = curve.closed;
  out.points.push_back(curve.start);
  out.arc.push_back(0);
  Point2 p0 = curve.start;
  Point2 prev_tangent{0, 0};
  Point2 first_tangent{0, 0};
  for (const CubicBezier& s : segs) {
    // Dense evaluation, then points at equal arc length.
    const double polygon = Dist(p0, s.c1) + Dist(s.c1, s.c2) + Dist(s.c2, s.end);
    if (polygon < 1e-9) {
      p0 = s.end;
      continue;
    }
    const Point2 tin = StartTangent(p0, s);
    if (first_tangent.x == 0 && first_tangent.y == 0) first_tangent = tin;
    else if (Kinked(prev_tangent, tin, corner_angle_deg)) out.corners.push_back(uint32_t(out.points.size() - 1));
    prev_tangent = EndTangent(p0, s);
    const int fine = std::clamp(int(std::ceil(polygon / 0.05)), 16, 1 << 20);
    std::vector<Point2> f(fine + 1);
    std::vector<double> fl(fine + 1, 0);
    for (int k = 0; k <= fine; ++k) f[k] = EvaluateBezier(p0, s, double(k) / fine);
    f[fine] = s.end;
    for (int k = 1; k <= fine; ++k) fl[k] = fl[k - 1] + Dist(f[k - 1], f[k]);
    const double len = fl[fine];
    const int pieces = std::max(1, int(std::lround(len / kSampleSpacing)));
    const double base = out.arc.back();
    int j = 0;
    for (int k = 1; k <= pieces; ++k) {
      double target = len * k / pieces;
      if (k == pieces) {
        out.points.push_back(s.end);
        out.arc.push_back(base + len);
        break;
      }
      while (j + 1 < fine && fl[j + 1] < target) ++j;
      double span = fl[j + 1] - fl[j];
      double t = span > 0 ? (target - fl[j]) / span : 0;
      out.points.push_back({f[j].x + t * (f[j + 1].x - f[j].x), f[j].y + t * (f[j + 1].y - f[j].y)});
      out.arc.push_back(base + target);
    }
    p0 = s.end;
  }
  out.length = out.arc.back();
  if (out.closed) {
    // The last point is the start again: drop it; the join there may be a kink.
    out.points.pop_back();
    out.arc.pop_back();
    if (Kinked(prev_tangent, first_tangent, corner_angle_deg)) out.corners.insert(out.corners.begin(), 0u);
  }
  return out;
}

// The runs of path inside the rectangle [margin, width - margin] x [margin, height - margin],
// each starting and ending at its crossing of that rectangle's edge (the whole path when it
// is inside). Runs with fewer than 2 points are dropped.
std::vector<SampledPath> ClipToFrame(const SampledPath& path, double width, double height, double margin) {
  auto inside = [&](Point2 p) {
    return p.x >= margin && p.y >= margin && p.x <= width - margin && p.y <= height - margin;
  };
  const size_t n = path.points.size();
  size_t first_out = n;
  for (size_t i = 0; i < n && first_out == n; ++i)
    if (!inside(path.points[i])) first_out = i;
  if (first_out == n) return {path};
  std::vector<bool> corner(n, false);
  for (uint32_t c : path.corners) corner[c] = true;
  // Walk the samples once (a closed path from its first outside sample, around to it
  // again), unwrapping the arc length.
  std::vector<size_t> order;
  std::vector<double> arc;
  const size_t start = path.closed ? first_out : 0, count = path.closed ? n + 1 : n;
  for (size_t k = 0; k < count; ++k) {
    size_t i = (start + k) % n;
    order.push_back(i);
    arc.push_back(path.arc[i] + (path.closed && start + k >= n ? path.length : 0));
  }
  // The point where segment a -> b (a inside, b outside or the reverse) meets the edge.
  auto crossing = [&](size_t ka, size_t kb) {
    Point2 a = path.points[order[ka]], b = path.points[order[kb]];
    double lo = 0, hi = 1;  // a + t (b - a): inside at lo
    for (int it = 0; it < 40; ++it) {
      double mid = (lo + hi) / 2;
      (inside({a.x + mid * (b.x - a.x), a.y + mid * (b.y - a.y)}) ? lo : hi) = mid;
    }
    return std::pair<Point2, double>{{a.x + lo * (b.x - a.x), a.y + lo * (b.y - a.y)},
                                     arc[ka] + lo * (arc[kb] - arc[ka])};
  };
  std::vector<SampledPath> runs;
  SampledPath run;
  auto finish = [&]() {
    if (run.points.size() >= 2) runs.push_back(std::move(run));
    run = SampledPath{};
  };
  for (size_t k = 0; k < order.size(); ++k) {
    const Point2 p = path.points[order[k]];
    if (!inside(p)) {
      if (!run.points.empty()) {
        run.clipped_end = true;
        auto [q, s] = crossing(k - 1, k);
        if (Dist(q, run.points.back()) > 1e-6) {
          run.points.push_back(q);
          run.arc.push_back(s);
        }
        finish();
      }
      continue;
    }
    if (run.points.empty()) {
      run.length = path.length;
      run.periodic = path.periodic;
      if (k > 0) {
        run.clipped_start = true;
        auto [q, s] = crossing(k, k - 1);
        if (Dist(q, p) > 1e-6) {
          run.points.push_back(q);
          run.arc.push_back(s);
        }
      }
    }
    if (corner[order[k]] && !run.points.empty()) run.corners.push_back(uint32_t(run.points.size()));
    run.points.push_back(p);
    run.arc.push_back(arc[k]);
  }
  finish();
  return runs;
}

// The drawing's rectangle as the domain boundary curve: corners tagged, sides split at most
// max_segment apart, and graded finer (1.5, 3, 6, ... px) around the feet of the points
// where curves were clipped, so that the two sides of a clipped curve do not meet across
// one long frame edge (the harmonic colours would mix over that whole edge).
FeatureCurve FrameBoundary(double width, double height, const std::vector<Point2>& clip_points,
                           double max_segment) {
  const Point2 corner[4] = {{0, 0}, {width, 0}, {width, height}, {0, height}};
  std::vector<std::vector<double>> cuts(4);  // positions along each side, 0..side length
  for (Point2 p : clip_points) {
    const double dist[4] = {p.y, width - p.x, height - p.y, p.x};
    const int side = int(std::min_element(dist, dist + 4) - dist);
    const double t = side == 0 ? p.x : side == 1 ? p.y : side == 2 ? width - p.x : height - p.y;
    cuts[side].push_back(t);
    for (double step = 1.5; step < max_segment; step *= 2) {
      cuts[side].push_back(t - step);
      cuts[side].push_back(t + step);
    }
  }
  FeatureCurve frame;
  frame.closed = true;
  frame.boundary = true;
  for (int side = 0; side < 4; ++side) {
    const Point2 a = corner[side], b = corner[(side + 1) % 4];
    const double len = Dist(a, b);
    std::vector<double> t{0, len};
    for (double c : cuts[side])
      if (c > 0.5 && c < len - 0.5) t.push_back(c);
    std::sort(t.begin(), t.end());
    std::vector<double> kept{0};  // no two cuts closer than 0.5 px
    for (size_t i = 1; i < t.size(); ++i)
      if (t[i] - kept.back() >= 0.5) kept.push_back(t[i]);
    kept.back() = len;
    frame.corners.push_back(uint32_t(frame.points.size()));
    for (size_t i = 0; i + 1 < kept.size(); ++i) {
      const int pieces = std::max(1, int(std::ceil((kept[i + 1] - kept[i]) / max_segment)));
      for (int k = 0; k < pieces; ++k) {
        const double u = (kept[i] + (kept[i + 1] - kept[i]) * k / pieces) / len;
        frame.points.push_back({a.x + u * (b.x - a.x), a.y + u * (b.y - a.y)});
      }
    }
  }
  return frame;
}

// ---- B-spline fit: the control polygon of the feature curve ----

// Fits the sampled path and makes every control-polygon segment at most max_segment long
// (points inserted evenly, as the feature placement would), dropping repeated points.
FeatureCurve FitCurve(const SampledPath& path, float sharpness, const CreateOptions& options, double max_segment) {
  BSplineFitOptions fit;
  fit.tolerance = options.fit_tolerance;
  fit.max_spacing = std::min(options.max_spacing, max_segment);
  fit.initial_spacing = std::min(fit.initial_spacing, fit.max_spacing);
  FeatureCurve fitted = FitChain(path.points, path.closed, path.corners, fit);
  const size_t n = fitted.points.size();
  std::vector<bool> is_corner(n, false);
  for (uint32_t c : fitted.corners) is_corner[c] = true;
  FeatureCurve out;
  out.closed = fitted.closed;
  out.sharpness = sharpness;
  const size_t segs = out.closed ? n : n - 1;
  for (size_t i = 0; i < n; ++i) {
    if (!out.points.empty() && Dist(out.points.back(), fitted.points[i]) < 2e-3) {
      if (is_corner[i] && (out.corners.empty() || out.corners.back() != out.points.size() - 1))
        out.corners.push_back(uint32_t(out.points.size() - 1));
    } else {
      if (is_corner[i]) out.corners.push_back(uint32_t(out.points.size()));
      out.points.push_back(fitted.points[i]);
    }
    if (i >= segs) continue;
    Point2 a = fitted.points[i], b = fitted.points[(i + 1) % n];
    int pieces = int(std::ceil(Dist(a, b) / max_segment));
    for (int k = 1; k < pieces; ++k) {
      double t = double(k) / pieces;
      out.points.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  if (out.closed && out.points.size() > 1 && Dist(out.points.back(), out.points.front()) < 2e-3) {
    if (!out.corners.empty() && out.corners.back() == out.points.size() - 1) {
      out.corners.pop_back();
      if (out.corners.empty() || out.corners.front() != 0) out.corners.insert(out.corners.begin(), 0u);
    }
    out.points.pop_back();
  }
  return out;
}

// Arc-length fraction (of the path) of each control point's limit point on the spline:
// the limit point (crease limit masks) projected onto the path's samples, searching
// forward along the path from the previous control point.
std::vector<double> ArcFractions(const FeatureCurve& curve, const SampledPath& path) {
  const size_t n = curve.points.size(), ns = path.points.size();
  std::vector<bool> corner(n, false);
  for (uint32_t c : curve.corners) corner[c] = true;
  if (!curve.closed) corner.front() = corner.back() = true;
  std::vector<double> u(n, 0);
  size_t at = 0;  // sample index of the previous projection (unwrapped for closed paths)
  for (size_t i = 0; i < n; ++i) {
    Point2 limit = curve.points[i];
    if (!corner[i]) {
      size_t i0 = (i + n - 1) % n, i1 = (i + 1) % n;
      rules::CreaseVertexMask m = rules::CreaseLimitRule(corner[i0], corner[i1]);
      const Point2 &c0 = curve.points[i0], &v = curve.points[i], &c1 = curve.points[i1];
      limit = {m.c0 * c0.x + m.self * v.x + m.c1 * c1.x, m.c0 * c0.y + m.self * v.y + m.c1 * c1.y};
    }
    size_t lo = at, hi;
    if (i == 0) {
      lo = 0;
      hi = curve.closed ? ns - 1 : std::min(ns - 1, size_t(8));
    } else {
      double step = Dist(curve.points[i - 1], curve.points[i]);
      hi = at + size_t(std::ceil((2 * step + 4) / kSampleSpacing));
      if (!curve.closed) hi = std::min(hi, ns - 1);
    }
    double best = 1e300;
    size_t best_k = lo;
    for (size_t k = lo; k <= hi; ++k) {
      double dd = Dist(limit, path.points[k % ns]);
      if (dd < best) {
        best = dd;
        best_k = k;
      }
    }
    if (!curve.closed && i + 1 == n) best_k = ns - 1;  // open ends interpolate the path ends
    at = best_k;
    double laps = double(best_k / ns);
    u[i] = (path.arc[best_k % ns] + laps * path.length) / path.length;
  }
  if (path.periodic)
    for (double& x : u) x -= std::floor(x);
  else
    for (double& x : u) x = std::clamp(x, 0.0, 1.0);
  return u;
}

// The colour of stops at arc-length fraction u (spec/CURVES.md: linear between stops,
// clamped on open curves, cyclic on closed ones).
CurveColor ColorAt(const std::vector<CurveColorStop>& stops, double u, bool closed) {
  auto mix = [](const CurveColor& a, const CurveColor& b, double t) {
    return CurveColor{float(a.r + t * (b.r - a.r)), float(a.g + t * (b.g - a.g)), float(a.b + t * (b.b - a.b))};
  };
  const CurveColorStop &first = stops.front(), &last = stops.back();
  if (u < first.offset || u > last.offset) {
    if (!closed) return u < first.offset ? first.color : last.color;
    double span = 1 + first.offset - last.offset;
    double t = u > last.offset ? u - last.offset : u + 1 - last.offset;
    return span > 0 ? mix(last.color, first.color, t / span) : first.color;
  }
  size_t k = 0;
  while (k + 1 < stops.size() && stops[k + 1].offset <= u) ++k;
  if (k + 1 == stops.size()) return last.color;
  double span = stops[k + 1].offset - stops[k].offset;
  return span > 0 ? mix(stops[k].color, stops[k + 1].color, (u - stops[k].offset) / span) : stops[k + 1].color;
}

// ---- Pair colours ----

// A drawing curve after fitting: its control polygon and the colours there.
struct FittedCurve {
  FeatureCurve feature;
  std::vector<CurveColor> left, right;  // per control point
};

// Sets the colours of both polylines of every pair of image: its midpoints are the
// control points of one fitted curve, in order (BuildControlMesh offsets them by +-d/2,
// may keep only a run of them and drops a point where a side would turn back along
// itself, from both sides); the first polyline is on the +normal side (-dy, dx), which on
// screen (y down) is the right side. Returns which vertices are fixed.
StatusOr<std::vector<bool>> ColorPairs(Image& image, const std::vector<FittedCurve>& curves) {
  constexpr double kTolerance = 0.02;  // float32 positions of offset points, px
  auto key = [](Point2 p) { return std::pair<int64_t, int64_t>(std::llround(p.x * 8), std::llround(p.y * 8)); };
  std::map<std::pair<int64_t, int64_t>, std::vector<std::pair<uint32_t, uint32_t>>> where;  // (curve, point)
  for (uint32_t c = 0; c < curves.size(); ++c)
    for (uint32_t i = 0; i < curves[c].feature.points.size(); ++i)
      where[key(curves[c].feature.points[i])].push_back({c, i});
  std::vector<bool> fixed(image.vertices.size(), false);
  for (size_t p = 0; p < image.pairs.size(); ++p) {
    const auto& right = image.polylines[image.pairs[p].first].vertices;
    const auto& left = image.polylines[image.pairs[p].second].vertices;
    auto mid = [&](size_t i) {
      const Vertex &a = image.vertices[right[i]], &b = image.vertices[left[i]];
      return Point2{(double(a.x) + b.x) / 2, (double(a.y) + b.y) / 2};
    };
    const Point2 m0 = mid(0);
    std::vector<std::pair<uint32_t, uint32_t>> candidates;
    auto [kx, ky] = key(m0);
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) {
        auto it = where.find({kx + dx, ky + dy});
        if (it != where.end()) candidates.insert(candidates.end(), it->second.begin(), it->second.end());
      }
    std::sort(candidates.begin(), candidates.end());
    bool matched = false;
    for (const auto& candidate : candidates) {
      const size_t start = candidate.second;  // a plain variable: lambdas below capture it
      const FittedCurve& fc = curves[candidate.first];
      const size_t n = fc.feature.points.size();
      if (right.size() > n || left.size() != right.size()) continue;
      // The control point of each pair vertex: the first at start, each next one the
      // nearest following point that matches (skipping dropped ones), within one lap.
      auto in_lap = [&](size_t j) { return j < start + n && (j < n || fc.feature.closed); };
      auto matches = [&](size_t i, size_t j) { return Dist(mid(i), fc.feature.points[j % n]) < kTolerance; };
      std::vector<size_t> at(right.size());
      bool ok = true;
      size_t j = start;
      for (size_t i = 0; i < right.size() && ok; ++i) {
        if (i > 0)
          for (++j; in_lap(j) && !matches(i, j);) ++j;
        ok = in_lap(j) && matches(i, j);
        at[i] = j % n;
      }
      if (!ok) continue;
      for (size_t i = 0; i < right.size(); ++i) {
        const size_t j = at[i];
        Vertex& r = image.vertices[right[i]];
        Vertex& l = image.vertices[left[i]];
        r.r = fc.right[j].r, r.g = fc.right[j].g, r.b = fc.right[j].b;
        l.r = fc.left[j].r, l.g = fc.left[j].g, l.b = fc.left[j].b;
        fixed[right[i]] = fixed[left[i]] = true;
      }
      matched = true;
      break;
    }
    if (!matched)
      return Status(StatusCode::kInternal, "CreateFromCurves: feature pair " + std::to_string(p) +
                                               " matches no fitted curve");
  }
  return fixed;
}

// ---- Harmonic interpolation ----

// Colours of the vertices that are not fixed: the solution of the discrete Laplace
// equation sum_j w_ij (c_j - c_i) = 0 with cotangent weights w_ij = (cot a + cot b) / 2,
// floored at a small positive value (constrained triangulations can make them negative),
// the fixed vertices as Dirichlet constraints; edges of the domain get no constraint
// (natural boundary condition).
Status HarmonicColors(Image& image, const std::vector<bool>& fixed) {
  const size_t n = image.vertices.size();
  std::vector<int> free_index(n, -1);
  int nf = 0;
  for (size_t i = 0; i < n; ++i)
    if (!fixed[i]) free_index[i] = nf++;
  if (nf == 0) return Status::Ok();
  std::map<Edge, double> weight;
  for (const Triangle& t : image.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Vertex &a = image.vertices[t.v[k]], &b = image.vertices[t.v[(k + 1) % 3]],
                   &c = image.vertices[t.v[(k + 2) % 3]];
      // Angle at a, opposite edge (b, c).
      double ux = double(b.x) - a.x, uy = double(b.y) - a.y, vx = double(c.x) - a.x, vy = double(c.y) - a.y;
      double cross = std::fabs(ux * vy - uy * vx), dot = ux * vx + uy * vy;
      double cot = cross > 1e-12 ? dot / cross : 0;
      weight[Edge::Of(t.v[(k + 1) % 3], t.v[(k + 2) % 3])] += 0.5 * cot;
    }
  }
  constexpr double kMinWeight = 1e-3;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nf, 3);
  std::vector<double> diagonal(nf, 0);
  auto add = [&](uint32_t i, uint32_t j, double w) {  // row of free vertex i, neighbour j
    int fi = free_index[i];
    diagonal[fi] += w;
    if (fixed[j]) {
      const Vertex& v = image.vertices[j];
      rhs(fi, 0) += w * v.r;
      rhs(fi, 1) += w * v.g;
      rhs(fi, 2) += w * v.b;
    } else {
      triplets.emplace_back(fi, free_index[j], -w);
    }
  };
  for (const auto& [e, w0] : weight) {
    double w = std::max(w0, kMinWeight);
    if (!fixed[e.a]) add(e.a, e.b, w);
    if (!fixed[e.b]) add(e.b, e.a, w);
  }
  for (int i = 0; i < nf; ++i) triplets.emplace_back(i, i, diagonal[i]);
  Eigen::SparseMatrix<double> L(nf, nf);
  L.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
  if (solver.info() != Eigen::Success)
    return Status(StatusCode::kInternal, "CreateFromCurves: the harmonic system is singular (a region of the "
                                         "mesh touches no curve)");
  Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite())
    return Status(StatusCode::kInternal, "CreateFromCurves: the harmonic solve failed");
  for (size_t i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    Vertex& v = image.vertices[i];
    int fi = free_index[i];
    v.r = float(x(fi, 0));
    v.g = float(x(fi, 1));
    v.b = float(x(fi, 2));
  }
  return Status::Ok();
}

}  // namespace

StatusOr<Image> CreateFromCurves(const CurveDrawing& drawing, const CreateOptions& options) {
  SDVI_RETURN_IF_ERROR(ValidateDrawing(drawing, options));
  const double max_edge = options.max_edge > 0 ? options.max_edge
                                               : std::max(8.0, std::sqrt(double(drawing.width) * drawing.height) / 12.0);
  // Control-polygon segments shorter than the placement's split length (0.7 max_edge), so
  // the placed polylines are exactly our control polygons.
  const double max_segment = 0.69 * max_edge;

  std::vector<FittedCurve> fitted;
  std::vector<FeatureCurve> features;
  std::vector<Point2> clip_points;
  for (const ColoredCurve& c : drawing.curves) {
    // Clip where the pair would leave the frame (less the placement's clearance): the
    // pair then runs up to the frame instead of being trimmed a whole segment short.
    const double d = std::max<double>(options.min_distance, options.rho * (1.0 - c.sharpness));
    const double margin = options.clearance + 0.5 * d + options.fit_tolerance + 0.25;
    for (const SampledPath& path :
         ClipToFrame(SamplePath(c, options.corner_angle_deg), drawing.width, drawing.height, margin)) {
      const size_t need = path.closed ? 3 : 2;
      if (path.points.size() < need) continue;  // shorter than a sample spacing: nothing to draw
      if (path.clipped_start) clip_points.push_back(path.points.front());
      if (path.clipped_end) clip_points.push_back(path.points.back());
      FittedCurve f;
      f.feature = FitCurve(path, c.sharpness, options, max_segment);
      if (f.feature.points.size() < need) continue;
      std::vector<double> u = ArcFractions(f.feature, path);
      for (double x : u) {
        f.left.push_back(ColorAt(c.left, x, c.closed));
        f.right.push_back(ColorAt(c.right, x, c.closed));
      }
      features.push_back(f.feature);
      fitted.push_back(std::move(f));
    }
  }
  features.push_back(FrameBoundary(drawing.width, drawing.height, clip_points, max_segment));

  ControlMeshOptions mesh_options;
  mesh_options.rho = options.rho;
  mesh_options.min_distance = options.min_distance;
  mesh_options.min_angle_deg = options.min_angle_deg;
  mesh_options.max_edge = float(max_edge);
  mesh_options.clearance = options.clearance;
  mesh_options.fine_cuts = false;  // ColorPairs finds each pair vertex among the control points
  mesh_options.junctions = false;  // and pairs vertex by vertex, which a junction would shift
  SDVI_ASSIGN_OR_RETURN(Image image, BuildControlMesh(drawing.width, drawing.height, features, {}, mesh_options));
  if (image.pairs.empty())
    return Status(StatusCode::kEmptyInput, "CreateFromCurves: no curve lies inside the " +
                                               std::to_string(drawing.width) + "x" + std::to_string(drawing.height) +
                                               " drawing");
  SDVI_ASSIGN_OR_RETURN(std::vector<bool> fixed, ColorPairs(image, fitted));
  SDVI_RETURN_IF_ERROR(HarmonicColors(image, fixed));
  return image;
}

}  // namespace sdvi
