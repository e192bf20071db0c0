// SPDX-License-Identifier: GPL-3.0-or-later
// Cubic B-spline feature curves (spec/METHOD.md section 2 and section 6 step 2).
//
// A feature polyline of the control mesh is the deBoor (control) polygon of a cubic
// B-spline, and Loop crease subdivision converges to exactly that spline:
//  - closed, no corner: the uniform periodic cubic B-spline of P0..P(n-1); for t in
//    [i, i+1), u = t - i, C(t) = sum_k b_k(u) P((i - 1 + k) mod n) with the uniform
//    basis b0 = (1-u)^3/6, b1 = (3u^3 - 6u^2 + 4)/6, b2 = (-3u^3 + 3u^2 + 3u + 1)/6,
//    b3 = u^3/6; so C(i) = (P(i-1) + 4 P(i) + P(i+1)) / 6 (the crease limit mask).
//  - open P0..Pn: the end-interpolating cubic B-spline with deBoor points
//    P0, P0, P1, ..., Pn, Pn and knots {0,0,0,0,1,2,...,n-1,n,n,n,n}; t in [0, n],
//    C(0) = P0, C(n) = Pn.
//  - a corner inside a polyline splits it into open pieces that share the corner point.
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/features.h"

namespace sdvi {

// Point of the open end-interpolating spline of polygon at parameter t in [0, n]
// (clamped), n = polygon.size() - 1 >= 1.
Point2 EvaluateOpenBSpline(const std::vector<Point2>& polygon, double t);

// Point of the uniform periodic spline of polygon (>= 3 points) at t (taken mod n).
Point2 EvaluateClosedBSpline(const std::vector<Point2>& polygon, double t);

// Dense samples of the spline of curve (open, closed, with corners), about `per_span`
// points per control-polygon segment; the curve drawn by the mesh's crease limit.
std::vector<Point2> SampleFeatureCurve(const FeatureCurve& curve, int per_span = 8);

struct BSplineFitOptions {
  double tolerance = 0.75;     // max distance in px from a chain sample to the spline
  double initial_spacing = 8;  // initial deBoor count = max(4, length / spacing) (paper)
  double max_spacing = 12;     // no control-polygon segment spans more arc length than this
  int max_iterations = 8;      // rounds of "add deBoor points, refit"
  // > 0: deBoor points are also added until every deBoor point lies within this many px of
  // the spline (PolygonOffset), so the control polygon, which the control mesh places
  // (src/pairs.h), keeps to the curve it stands for; 0: no such bound.
  double max_polygon_offset = 0;
};

struct BSplineFit {
  std::vector<Point2> polygon;  // deBoor points
  double max_error = 0;         // max distance from a sample to the spline (after
                                // parameter correction), px
};

// The largest distance from a deBoor point to its spline (the open end-interpolating one,
// or the uniform periodic one when closed), sampled 16 times per span over the spans the
// point shapes: how far the control polygon strays from the curve; 0 for fewer than 3 points.
double PolygonOffset(const std::vector<Point2>& polygon, bool closed);

// Least-squares end-interpolating fit to an open chain of samples (>= 2); the first and
// last deBoor points are the first and last samples. Adds deBoor points until the max
// error is under options.tolerance or a deBoor point per ~2 samples is reached.
BSplineFit FitOpenBSpline(const std::vector<Point2>& samples, const BSplineFitOptions& options);

// Least-squares uniform periodic fit to a closed chain (>= 3 samples, first not repeated).
BSplineFit FitClosedBSpline(const std::vector<Point2>& samples, const BSplineFitOptions& options);

// Fits a chain whose samples at the given indices (sorted, unique) must keep a kink: open
// pieces between corners joined at the corner points (for a closed chain with corners
// the polygon starts at the first corner). Returns the curve (sharpness/boundary unset)
// and the max error in *max_error when non-null.
FeatureCurve FitChain(const std::vector<Point2>& samples, bool closed,
                      const std::vector<uint32_t>& corner_samples,
                      const BSplineFitOptions& options, double* max_error = nullptr);

}  // namespace sdvi
