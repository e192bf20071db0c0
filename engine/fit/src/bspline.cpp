// SPDX-License-Identifier: GPL-3.0-or-later
// Cubic B-spline evaluation and least-squares fitting of feature chains (spec/METHOD.md section 2 and section 6 step 2).
#include "sdvi/bspline.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdvi {
namespace {

// Basis of the open spline of an n-segment polygon at t: the polygon indices and weights
// of its (at most 4) deBoor points. Knots k[i] = clamp(i - 3, 0, n); deBoor index j maps
// to polygon index clamp(j - 1, 0, n) (P0 and Pn are doubled).
struct Basis4 {
  int index[4];
  double weight[4];
};

Basis4 OpenBasis(int n, double t) {
  t = std::clamp(t, 0.0, double(n));
  int span = std::min(int(std::floor(t)), n - 1) + 3;  // k[span] <= t < k[span + 1]
  auto knot = [n](int i) { return double(std::clamp(i - 3, 0, n)); };
  // Cox-de Boor triangle (Piegl & Tiller, BasisFuns), degree 3.
  double N[4] = {1, 0, 0, 0}, left[4], right[4];
  for (int j = 1; j <= 3; ++j) {
    left[j] = t - knot(span + 1 - j);
    right[j] = knot(span + j) - t;
    double saved = 0;
    for (int r = 0; r < j; ++r) {
      double denom = right[r + 1] + left[j - r];
      double temp = denom > 0 ? N[r] / denom : 0;
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
  Basis4 b;
  for (int r = 0; r < 4; ++r) {
    int j = span - 3 + r;
    b.index[r] = std::clamp(j - 1, 0, n);
    b.weight[r] = N[r];
  }
  return b;
}

Basis4 ClosedBasis(int n, double t) {
  double f = std::floor(t);
  double u = t - f;
  int i = int(f) % n;
  if (i < 0) i += n;
  Basis4 b;
  double u2 = u * u, u3 = u2 * u;
  b.weight[0] = (1 - u) * (1 - u) * (1 - u) / 6;
  b.weight[1] = (3 * u3 - 6 * u2 + 4) / 6;
  b.weight[2] = (-3 * u3 + 3 * u2 + 3 * u + 1) / 6;
  b.weight[3] = u3 / 6;
  for (int k = 0; k < 4; ++k) b.index[k] = ((i - 1 + k) % n + n) % n;
  return b;
}

Point2 Combine(const std::vector<Point2>& p, const Basis4& b) {
  Point2 r;
  for (int k = 0; k < 4; ++k) {
    r.x += b.weight[k] * p[b.index[k]].x;
    r.y += b.weight[k] * p[b.index[k]].y;
  }
  return r;
}

// Cumulative chord length of samples (closed: the closing segment is included in total).
std::vector<double> ChordLengths(const std::vector<Point2>& s, bool closed, double* total) {
  std::vector<double> c(s.size(), 0.0);
  for (size_t i = 1; i < s.size(); ++i) c[i] = c[i - 1] + Distance(s[i - 1], s[i]);
  *total = c.back() + (closed ? Distance(s.back(), s.front()) : 0.0);
  return c;
}

// One least-squares solve: polygon (size count) minimising sum |q_j - C(t_j)|^2 plus a
// small second-difference regulariser; open polygons keep their end points fixed.
std::vector<Point2> SolvePolygon(const std::vector<Point2>& q, const std::vector<double>& t,
                                 int count, bool closed) {
  const int n = closed ? count : count - 1;  // spans
  std::vector<Point2> poly(count);
  if (!closed) {
    poly.front() = q.front();
    poly.back() = q.back();
  }
  const int first_free = closed ? 0 : 1;
  const int num_free = closed ? count : count - 2;
  if (num_free <= 0) return poly;
  auto free_index = [&](int i) { return i - first_free; };
  auto is_free = [&](int i) { return closed || (i > 0 && i < count - 1); };

  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd bx = Eigen::VectorXd::Zero(num_free), by = Eigen::VectorXd::Zero(num_free);
  auto add_row = [&](const int* idx, const double* w, int m, double qx, double qy, double scale) {
    // Row r(P) = sum w_k P_idx_k - q; fixed points move to the right-hand side.
    double rx = qx, ry = qy;
    for (int k = 0; k < m; ++k)
      if (!is_free(idx[k])) {
        rx -= w[k] * poly[idx[k]].x;
        ry -= w[k] * poly[idx[k]].y;
      }
    for (int a = 0; a < m; ++a) {
      if (!is_free(idx[a])) continue;
      int fa = free_index(idx[a]);
      bx[fa] += scale * w[a] * rx;
      by[fa] += scale * w[a] * ry;
      for (int b = 0; b < m; ++b)
        if (is_free(idx[b])) trip.emplace_back(fa, free_index(idx[b]), scale * w[a] * w[b]);
    }
  };
  for (size_t j = 0; j < q.size(); ++j) {
    Basis4 b = closed ? ClosedBasis(n, t[j]) : OpenBasis(n, t[j]);
    add_row(b.index, b.weight, 4, q[j].x, q[j].y, 1.0);
  }
  // Regulariser: P(i-1) - 2 P(i) + P(i+1) ~ 0, weak (keeps spans without samples tame).
  const double lambda = 1e-3;
  for (int i = closed ? 0 : 1; i < (closed ? count : count - 1); ++i) {
    int idx[3] = {(i - 1 + count) % count, i, (i + 1) % count};
    double w[3] = {1, -2, 1};
    add_row(idx, w, 3, 0, 0, lambda);
  }
  Eigen::SparseMatrix<double> A(num_free, num_free);
  A.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) return poly;
  Eigen::VectorXd x = solver.solve(bx), y = solver.solve(by);
  for (int i = 0; i < count; ++i)
    if (is_free(i)) poly[i] = {x[free_index(i)], y[free_index(i)]};
  return poly;
}

Point2 Eval(const std::vector<Point2>& poly, bool closed, double t) {
  return closed ? EvaluateClosedBSpline(poly, t) : EvaluateOpenBSpline(poly, t);
}

// Moves each t to the foot of q on the curve (Newton steps); returns the max distance.
double CorrectParameters(const std::vector<Point2>& q, std::vector<double>& t,
                         const std::vector<Point2>& poly, bool closed) {
  const int n = closed ? int(poly.size()) : int(poly.size()) - 1;
  const double h = 1e-4;
  double max_error = 0;
  for (size_t j = 0; j < q.size(); ++j) {
    bool fixed_end = !closed && (j == 0 || j + 1 == q.size());
    for (int it = 0; it < 2 && !fixed_end; ++it) {
      Point2 c = Eval(poly, closed, t[j]);
      Point2 a = Eval(poly, closed, t[j] - h), b = Eval(poly, closed, t[j] + h);
      double dx = (b.x - a.x) / (2 * h), dy = (b.y - a.y) / (2 * h);
      double d2 = dx * dx + dy * dy;
      if (d2 < 1e-12) break;
      double step = ((q[j].x - c.x) * dx + (q[j].y - c.y) * dy) / d2;
      step = std::clamp(step, -0.5, 0.5);
      t[j] += step;
      if (!closed) t[j] = std::clamp(t[j], 0.0, double(n));
    }
    max_error = std::max(max_error, Distance(q[j], Eval(poly, closed, t[j])));
  }
  return max_error;
}

}  // namespace

double PolygonOffset(const std::vector<Point2>& polygon, bool closed) {
  const int m = int(polygon.size());
  if (m < 3) return 0;
  const int spans = closed ? m : m - 1;
  constexpr int kPerSpan = 16;
  double worst = 0;
  for (int i = 0; i < m; ++i) {
    // Point i shapes spans i - 2 .. i + 1 (closed: mod m; open: those that exist).
    double nearest = std::numeric_limits<double>::infinity();
    for (int s = i - 2; s <= i + 1; ++s) {
      if (!closed && (s < 0 || s >= spans)) continue;
      for (int k = 0; k <= kPerSpan; ++k) {
        const double t = s + double(k) / kPerSpan;
        nearest = std::min(nearest, Distance(polygon[i], Eval(polygon, closed, t)));
      }
    }
    worst = std::max(worst, nearest);
  }
  return worst;
}

namespace {

BSplineFit FitSpline(const std::vector<Point2>& q, bool closed, const BSplineFitOptions& o) {
  BSplineFit fit;
  if (q.empty()) return fit;
  if (!closed && q.size() <= 2) {
    fit.polygon = q;
    if (fit.polygon.size() == 1) fit.polygon.push_back(q[0]);
    return fit;
  }
  double total = 0;
  std::vector<double> chord = ChordLengths(q, closed, &total);
  const int max_count = std::max(closed ? 3 : 2, int(q.size()) / 2);
  int count = std::max(4, int(std::lround(total / std::max(1.0, o.initial_spacing))));
  count = std::max(count, int(std::ceil(total / std::max(1.0, o.max_spacing))) + (closed ? 0 : 1));
  count = std::min(count, std::max(closed ? 3 : 2, int(q.size())));
  for (int round = 0;; ++round) {
    const int n = closed ? count : count - 1;
    std::vector<double> t(q.size());
    for (size_t j = 0; j < q.size(); ++j) t[j] = total > 0 ? n * chord[j] / total : 0;
    std::vector<Point2> poly = SolvePolygon(q, t, count, closed);
    double err = CorrectParameters(q, t, poly, closed);
    for (int k = 0; k < 2 && err > o.tolerance * 0.5; ++k) {
      poly = SolvePolygon(q, t, count, closed);
      err = CorrectParameters(q, t, poly, closed);
    }
    // Done when within the tolerance and (max_polygon_offset) the polygon near its curve;
    // else the smallest error so far is kept.
    const bool done = err <= o.tolerance &&
                      (!(o.max_polygon_offset > 0) || PolygonOffset(poly, closed) <= o.max_polygon_offset);
    if (round == 0 || done || err < fit.max_error) {
      fit.polygon = poly;
      fit.max_error = err;
    }
    if (done || count >= max_count || round + 1 >= o.max_iterations) break;
    count = std::min(max_count, int(std::ceil(count * 1.3)) + 1);
  }
  return fit;
}

}  // namespace

Point2 EvaluateOpenBSpline(const std::vector<Point2>& polygon, double t) {
  if (polygon.empty()) return {};
  if (polygon.size() == 1) return polygon[0];
  return Combine(polygon, OpenBasis(int(polygon.size()) - 1, t));
}

Point2 EvaluateClosedBSpline(const std::vector<Point2>& polygon, double t) {
  if (polygon.size() < 3) return polygon.empty() ? Point2{} : polygon[0];
  return Combine(polygon, ClosedBasis(int(polygon.size()), t));
}

std::vector<Point2> SampleFeatureCurve(const FeatureCurve& curve, int per_span) {
  std::vector<Point2> out;
  const auto& p = curve.points;
  per_span = std::max(1, per_span);
  if (p.size() < 2) return p;
  std::vector<uint32_t> corners;
  for (uint32_t c : curve.corners)
    if (c < p.size()) corners.push_back(c);
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  if (curve.closed && corners.empty() && p.size() >= 3) {
    int n = int(p.size());
    for (int i = 0; i < n * per_span; ++i) out.push_back(EvaluateClosedBSpline(p, double(i) / per_span));
    return out;
  }
  // Open pieces between corners (a closed curve with corners wraps around).
  std::vector<uint32_t> cuts;
  const uint32_t n = uint32_t(p.size());
  if (curve.closed) {
    cuts = corners;
    cuts.push_back(corners.front() + n);
  } else {
    cuts.push_back(0);
    for (uint32_t c : corners)
      if (c > 0 && c + 1 < n) cuts.push_back(c);
    cuts.push_back(n - 1);
  }
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    std::vector<Point2> piece;
    for (uint32_t i = cuts[k]; i <= cuts[k + 1]; ++i) piece.push_back(p[i % n]);
    int spans = int(piece.size()) - 1;
    if (spans < 1) continue;
    for (int i = 0; i < spans * per_span; ++i)
      out.push_back(EvaluateOpenBSpline(piece, double(i) / per_span));
    if (!curve.closed && k + 2 == cuts.size()) out.push_back(piece.back());
  }
  return out;
}

BSplineFit FitOpenBSpline(const std::vector<Point2>& samples, const BSplineFitOptions& options) {
  return FitSpline(samples, false, options);
}

BSplineFit FitClosedBSpline(const std::vector<Point2>& samples, const BSplineFitOptions& options) {
  return FitSpline(samples, true, options);
}

FeatureCurve FitChain(const std::vector<Point2>& samples, bool closed,
                      const std::vector<uint32_t>& corner_samples,
                      const BSplineFitOptions& options, double* max_error) {
  FeatureCurve curve;
  curve.closed = closed;
  double err = 0;
  const uint32_t m = uint32_t(samples.size());
  std::vector<uint32_t> corners;
  for (uint32_t c : corner_samples)
    if (c < m && (closed || (c > 0 && c + 1 < m))) corners.push_back(c);
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  if (closed && corners.empty()) {
    BSplineFit fit = FitClosedBSpline(samples, options);
    curve.points = std::move(fit.polygon);
    if (max_error) *max_error = fit.max_error;
    return curve;
  }
  std::vector<uint32_t> cuts;
  if (closed) {
    cuts = corners;
    cuts.push_back(corners.front() + m);
  } else {
    cuts.push_back(0);
    cuts.insert(cuts.end(), corners.begin(), corners.end());
    cuts.push_back(m - 1);
  }
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    std::vector<Point2> piece;
    for (uint32_t i = cuts[k]; i <= cuts[k + 1]; ++i) piece.push_back(samples[i % m]);
    BSplineFit fit = FitOpenBSpline(piece, options);
    err = std::max(err, fit.max_error);
    if (!curve.points.empty()) {
      curve.corners.push_back(uint32_t(curve.points.size() - 1));
      fit.polygon.erase(fit.polygon.begin());  // shared corner point
    }
    curve.points.insert(curve.points.end(), fit.polygon.begin(), fit.polygon.end());
  }
  if (closed) {
    curve.points.pop_back();  // equals the first corner
    curve.corners.insert(curve.corners.begin(), 0u);
  }
  if (max_error) *max_error = err;
  return curve;
}

}  // namespace sdvi
