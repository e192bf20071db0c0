// SPDX-License-Identifier: GPL-3.0-or-later
// The artwork mode (spec/SVG.md): exact outlines -> sharp features -> the vectorizer's mesh,
// colour fit and refinement against librsvg's raster.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sdvi/bspline.h"
#include "sdvi/features.h"
#include "svg_internal.h"

namespace sdvi {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kProbe = 1.5;  // px either side of an outline where the colours are compared
constexpr double kClaimRadius = 2.0;  // px around a feature where no lower outline becomes one
// Strokes thinner than this (px) are thin structures: one feature on the centreline with the
// stroke's width (FeatureCurve::width), whose two outlines the vectorizer places as one unit;
// two separate sides would come within the claim radius of each other.
constexpr double kThinStroke = 3.0;

struct Sample {
  Point2 p;
  Point2 normal;        // unit, left of the direction of travel
  bool corner = false;  // a segment joint that keeps a kink
};

Point2 Sub(Point2 a, Point2 b) { return {a.x - b.x, a.y - b.y}; }
double Norm(Point2 a) { return std::hypot(a.x, a.y); }

Point2 Bezier(const Point2* q, double t) {
  const double u = 1 - t;
  const double b0 = u * u * u, b1 = 3 * u * u * t, b2 = 3 * u * t * t, b3 = t * t * t;
  return {b0 * q[0].x + b1 * q[1].x + b2 * q[2].x + b3 * q[3].x,
          b0 * q[0].y + b1 * q[1].y + b2 * q[2].y + b3 * q[3].y};
}

// Direction leaving q[0] (first of q1, q2, q3 distinct from q0) and arriving at q[3].
Point2 StartTangent(const Point2* q) {
  for (int k = 1; k <= 3; ++k) {
    const Point2 d = Sub(q[k], q[0]);
    if (Norm(d) > 1e-9) return d;
  }
  return {0, 0};
}
Point2 EndTangent(const Point2* q) {
  for (int k = 2; k >= 0; --k) {
    const Point2 d = Sub(q[3], q[k]);
    if (Norm(d) > 1e-9) return d;
  }
  return {0, 0};
}

double TurnDegrees(Point2 a, Point2 b) {
  const double na = Norm(a), nb = Norm(b);
  if (na <= 0 || nb <= 0) return 0;
  const double c = std::clamp((a.x * b.x + a.y * b.y) / (na * nb), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

// The part of the plane where samples matter: the raster grown by a margin (the probe and
// half a stroke). Outlines may reach far outside it (coordinates up to cairo's limits).
struct Window {
  double x0, y0, x1, y1;
};

Window WindowOf(const Raster& r, double margin) { return {-margin, -margin, r.width + margin, r.height + margin}; }

constexpr double kPieceLength = 64;  // px of control polygon: a piece sampled uniformly
constexpr int kMaxSplits = 1100;     // halvings from 1e308 down to kPieceLength

double HullLength(const Point2* q) {
  return Norm(Sub(q[1], q[0])) + Norm(Sub(q[2], q[1])) + Norm(Sub(q[3], q[2]));
}

bool HullOutside(const Point2* q, const Window& w) {
  double x0 = q[0].x, x1 = q[0].x, y0 = q[0].y, y1 = q[0].y;
  for (int k = 1; k < 4; ++k) {
    x0 = std::min(x0, q[k].x), x1 = std::max(x1, q[k].x);
    y0 = std::min(y0, q[k].y), y1 = std::max(y1, q[k].y);
  }
  return x1 < w.x0 || x0 > w.x1 || y1 < w.y0 || y0 > w.y1;
}

Point2 Mid(Point2 a, Point2 b) { return {a.x / 2 + b.x / 2, a.y / 2 + b.y / 2}; }

// Splits the cubic q in halves (de Casteljau) until each piece lies outside the window or
// is at most kPieceLength long; visit(piece, inside) in order along the curve.
template <class Visit>
void Pieces(const Point2* q, const Window& w, Visit visit) {
  struct Piece {
    std::array<Point2, 4> p;
    int depth;
  };
  std::vector<Piece> stack{{{q[0], q[1], q[2], q[3]}, 0}};
  while (!stack.empty()) {
    const Piece piece = stack.back();
    stack.pop_back();
    const Point2* p = piece.p.data();
    if (HullOutside(p, w)) {
      visit(p, false);
      continue;
    }
    if (!(HullLength(p) > kPieceLength) || piece.depth >= kMaxSplits) {
      visit(p, true);
      continue;
    }
    const Point2 a = Mid(p[0], p[1]), b = Mid(p[1], p[2]), c = Mid(p[2], p[3]);
    const Point2 ab = Mid(a, b), bc = Mid(b, c), m = Mid(ab, bc);
    stack.push_back({{m, bc, c, p[3]}, piece.depth + 1});
    stack.push_back({{p[0], a, ab, m}, piece.depth + 1});
  }
}

// Samples of a piece inside the window, `spacing` apart (at least one).
int PieceSamples(const Point2* p, double spacing) {
  const double n = std::ceil(HullLength(p) / spacing);
  return n >= 1 && n < 1e9 ? int(n) : 1;
}

// Samples of one outline about `spacing` apart (closed: the start is not repeated), with
// corner flags at joints turning by more than corner_deg and normals from the samples.
// Parts outside the window give one sample each (outside the raster: no feature there).
std::vector<Sample> Flatten(const SvgOutline& outline, double spacing, double corner_deg, const Window& window) {
  std::vector<Sample> out;
  const size_t segments = (outline.points.size() - 1) / 3;
  std::vector<size_t> kept;  // non-degenerate segments
  for (size_t s = 0; s < segments; ++s) {
    const Point2* q = &outline.points[3 * s];
    if (Norm(StartTangent(q)) > 1e-9) kept.push_back(s);
  }
  if (kept.empty()) return out;
  auto add = [&out](const Sample& s) {
    if (!out.empty() && Norm(Sub(s.p, out.back().p)) < 1e-6) {
      out.back().corner = out.back().corner || s.corner;
      return;
    }
    out.push_back(s);
  };
  for (size_t k = 0; k < kept.size(); ++k) {
    const Point2* q = &outline.points[3 * kept[k]];
    bool corner = false;
    if (k > 0 || outline.closed) {
      const Point2* prev = &outline.points[3 * kept[k > 0 ? k - 1 : kept.size() - 1]];
      corner = TurnDegrees(EndTangent(prev), StartTangent(q)) > corner_deg;
    }
    bool first = true;
    Pieces(q, window, [&](const Point2* p, bool inside) {
      const int n = inside ? PieceSamples(p, spacing) : 1;
      for (int i = 0; i < n; ++i) {
        Sample s;
        s.p = Bezier(p, double(i) / n);
        s.corner = first && corner;
        first = false;
        add(s);
      }
    });
  }
  if (!outline.closed) {
    Sample end;
    end.p = outline.points.back();
    if (out.empty() || Norm(Sub(end.p, out.back().p)) > 1e-6) out.push_back(end);
  } else if (out.size() > 1 && Norm(Sub(out.front().p, out.back().p)) < 1e-6) {
    out.pop_back();
  }
  const size_t m = out.size();
  for (size_t i = 0; i < m; ++i) {
    const bool has_prev = i > 0 || outline.closed, has_next = i + 1 < m || outline.closed;
    const Point2 a = has_prev ? out[(i + m - 1) % m].p : out[i].p;
    const Point2 b = has_next ? out[(i + 1) % m].p : out[i].p;
    Point2 d = Sub(b, a);
    const double len = Norm(d);
    out[i].normal = len > 0 ? Point2{-d.y / len, d.x / len} : Point2{0, 0};
  }
  return out;
}

// Bilinear sample of channel c at (x, y) in pixel-centre coordinates (pixel i covers
// [i, i + 1)); false outside the raster.
bool Bilinear(const Raster& r, double x, double y, float out[4]) {
  const double fx = x - 0.5, fy = y - 0.5;
  if (!(fx >= 0 && fy >= 0 && fx <= r.width - 1 && fy <= r.height - 1)) return false;
  const int x0 = std::min(int(fx), r.width - 1), y0 = std::min(int(fy), r.height - 1);
  const int x1 = std::min(x0 + 1, r.width - 1), y1 = std::min(y0 + 1, r.height - 1);
  const double ax = fx - x0, ay = fy - y0;
  for (int c = 0; c < r.channels; ++c) {
    out[c] = float((1 - ay) * ((1 - ax) * r.at(x0, y0, c) + ax * r.at(x1, y0, c)) +
                   ay * ((1 - ax) * r.at(x0, y1, c) + ax * r.at(x1, y1, c)));
  }
  return true;
}

// RMS colour step over R, G, B between a and b; -1 when either lies outside the domain.
double Contrast(const Raster& reference, Point2 a, Point2 b) {
  float ca[4] = {0, 0, 0, 1}, cb[4] = {0, 0, 0, 1};
  if (!Bilinear(reference, a.x, a.y, ca) || !Bilinear(reference, b.x, b.y, cb)) return -1;
  if (reference.channels == 4 && (ca[3] <= 0.5f || cb[3] <= 0.5f)) return -1;
  double sum = 0;
  for (int c = 0; c < 3; ++c) sum += double(ca[c] - cb[c]) * (ca[c] - cb[c]);
  return std::sqrt(sum / 3.0);
}

// The pixels around placed features. A thin structure's claim (FeatureCurve::width > 0)
// keeps its direction (degrees mod 180): a sample is claimed there where it runs along it
// (within kCrossingDeg); crossing it at kCrossingDeg or more it is not, since the crossed
// outline shows again on the other side of the thin structure (the vectorizer makes such
// crossings junctions, spec/METHOD.md section 6 step 3). A wider shape's outline claims
// every direction: what crosses it ends under the shape. A pixel claimed in different
// directions (a corner, a crossing) claims every direction.
constexpr double kCrossingDeg = 30.0;

double DirectionDeg(Point2 d) {
  double a = std::atan2(d.y, d.x) * 180.0 / kPi;
  a = std::fmod(a + 360.0, 180.0);
  return a >= 180.0 ? 0.0 : a;
}

bool SameDirection(double a, double b) {
  const double diff = std::fabs(a - b);
  return std::min(diff, 180.0 - diff) < kCrossingDeg;
}

class ClaimMap {
 public:
  ClaimMap(int w, int h) : w_(w), h_(h), dir_(size_t(w) * h, kFree) {}
  bool Claimed(Point2 p, double direction) const {
    const uint8_t d = At(p);
    return d != kFree && (d == kAll || SameDirection(d, direction));
  }
  // Claimed by a feature this direction crosses.
  bool Crossed(Point2 p, double direction) const { return At(p) != kFree && !Claimed(p, direction); }
  // direction < 0: every direction.
  void Claim(Point2 p, double radius, double direction) {
    const auto dir = direction < 0 ? kAll : uint8_t(std::min(179.0, std::floor(direction)));
    const int r = int(std::ceil(radius));
    const int cx = int(std::floor(p.x)), cy = int(std::floor(p.y));
    for (int y = cy - r; y <= cy + r; ++y) {
      for (int x = cx - r; x <= cx + r; ++x) {
        if (x < 0 || y < 0 || x >= w_ || y >= h_) continue;
        if (std::hypot(x + 0.5 - p.x, y + 0.5 - p.y) > radius) continue;
        uint8_t& d = dir_[size_t(y) * w_ + x];
        if (d == kFree) d = dir;
        else if (d != kAll && (dir == kAll || !SameDirection(d, dir))) d = kAll;
      }
    }
  }
  // Claims around every sample of a fitted feature curve, in its direction when directional.
  void ClaimCurve(const FeatureCurve& c, double radius, bool directional) {
    const std::vector<Point2> p = SampleFeatureCurve(c, 8);
    for (size_t i = 0; i < p.size(); ++i) {
      const Point2 a = p[i > 0 ? i - 1 : i], b = p[i + 1 < p.size() ? i + 1 : i];
      Claim(p[i], radius, directional ? DirectionDeg(Sub(b, a)) : -1.0);
    }
  }

 private:
  static constexpr uint8_t kFree = 255, kAll = 254;
  uint8_t At(Point2 p) const {
    const int x = int(std::floor(p.x)), y = int(std::floor(p.y));
    return x >= 0 && y >= 0 && x < w_ && y < h_ ? dir_[size_t(y) * w_ + x] : kFree;
  }
  int w_, h_;
  std::vector<uint8_t> dir_;
};

// One candidate polyline: a fill outline, or one side of a stroke (offset along the normal).
struct Side {
  std::vector<Sample> samples;
  bool closed = false;
  double inner_probe = kProbe;  // how far inside the colour is read (thin strokes: less)
  double outward = 0;           // +1 / -1: the outside is along +normal / -normal; 0: either
  double width = 0;             // > 0: the centreline of a thin stroke this wide
  // A thin fill's centreline: each sample's width across (empty otherwise); a run's feature
  // gets the median of its samples' widths.
  std::vector<double> widths;
  // The edges of a pattern's tiles chained into lines (SvgShape::tiled): its claim keeps
  // its direction, as a thin structure's does, since the lines cross at the tiles' corners.
  bool crossing = false;
};

// The window of an outline: the raster grown by the probe, half the stroke and a pixel.
Window OutlineWindow(const SvgShape& shape, const Raster& reference) {
  return WindowOf(reference, kProbe + 1 + (shape.paint == SvgPaint::kStroke ? shape.stroke_width / 2 : 0));
}

// The sides of one outline: a fill's outline itself; a thin stroke's centreline (width);
// a wider stroke's two sides at +-half the width, or, open with round caps, its whole
// outline (centre samples `spacing` apart, the caps' likewise).
std::vector<Side> SidesOf(const SvgShape& shape, const SvgOutline& outline, std::vector<Sample> centre,
                          double spacing) {
  std::vector<Side> sides;
  if (centre.size() < 2) return sides;
  if (shape.paint != SvgPaint::kStroke) {
    sides.push_back({std::move(centre), outline.closed, kProbe, 0, 0, {}});
    return sides;
  }
  const double half = shape.stroke_width / 2;
  if (half <= 0) return sides;
  if (shape.stroke_width < kThinStroke) {
    sides.push_back({std::move(centre), outline.closed, kProbe, 0, shape.stroke_width, {}});
    return sides;
  }
  if (!outline.closed && shape.line_cap == SvgLineCap::kRound) {
    // An open stroke with round caps: its whole outline as one closed side, outside on the
    // left of travel (normal = outward): the +normal side forward, the half circle around
    // the end, the -normal side backward, the half circle around the start. The caps meet
    // the sides tangentially, so one feature can run through them.
    Side side;
    side.closed = true;
    side.inner_probe = std::clamp(half, 0.5, kProbe);
    side.outward = 1;
    auto cap = [&](Point2 c, Point2 n, Point2 t) {  // from c + half n through c + half t to c - half n
      const int pieces = std::max(2, int(std::ceil(kPi * half / spacing)));
      for (int k = 1; k < pieces; ++k) {
        const double a = kPi * k / pieces;
        const Point2 r{std::cos(a) * n.x + std::sin(a) * t.x, std::cos(a) * n.y + std::sin(a) * t.y};
        Sample q;
        q.p = {c.x + half * r.x, c.y + half * r.y};
        q.normal = r;
        side.samples.push_back(q);
      }
    };
    const size_t m = centre.size();
    for (size_t i = 0; i < m; ++i) {
      Sample t = centre[i];
      t.p = {t.p.x + half * t.normal.x, t.p.y + half * t.normal.y};
      side.samples.push_back(t);
    }
    const Point2 end_n = centre[m - 1].normal, start_n = centre[0].normal;
    cap(centre[m - 1].p, end_n, {end_n.y, -end_n.x});
    for (size_t i = m; i-- > 0;) {
      Sample t = centre[i];
      t.p = {t.p.x - half * t.normal.x, t.p.y - half * t.normal.y};
      t.normal = {-t.normal.x, -t.normal.y};
      side.samples.push_back(t);
    }
    cap(centre[0].p, {-start_n.x, -start_n.y}, {-start_n.y, start_n.x});
    sides.push_back(std::move(side));
    return sides;
  }
  for (double sign : {1.0, -1.0}) {
    Side side;
    side.closed = outline.closed;
    side.inner_probe = std::clamp(half, 0.5, kProbe);
    side.outward = sign;
    for (const Sample& s : centre) {
      Sample t = s;
      t.p = {s.p.x + sign * half * s.normal.x, s.p.y + sign * half * s.normal.y};
      side.samples.push_back(t);
    }
    sides.push_back(std::move(side));
  }
  return sides;
}

double CountOutlineSamples(const std::vector<SvgShape>& shapes, const Raster& reference, double spacing) {
  double count = 0;
  for (const SvgShape& shape : shapes) {
    const Window window = OutlineWindow(shape, reference);
    const double sides = shape.paint == SvgPaint::kStroke ? 2 : 1;
    for (const SvgOutline& outline : shape.outlines) {
      for (size_t k = 0; k + 3 < outline.points.size(); k += 3) {
        Pieces(&outline.points[k], window, [&](const Point2* p, bool inside) {
          count += sides * (inside ? std::max(1.0, std::ceil(HullLength(p) / spacing)) : 1);
        });
      }
    }
  }
  return count;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Fits one run of accepted samples (indices into side.samples, in order) and appends it.
void EmitRun(const Side& side, const std::vector<size_t>& run, bool closed, const std::vector<double>& contrast,
             bool stroke_side, const SvgArtworkOptions& o, std::vector<FeatureCurve>* out) {
  std::vector<Point2> points;
  std::vector<uint32_t> corners;
  std::vector<double> steps;
  double length = 0;
  for (size_t k = 0; k < run.size(); ++k) {
    const Sample& s = side.samples[run[k]];
    if (!points.empty()) length += Norm(Sub(s.p, points.back()));
    // A stroke side is offset from the centreline: at a kink it jumps (the join fills the
    // gap), so stroke sides are cut at corners instead of kept as kinks.
    if (s.corner && !stroke_side && k > 0 && (closed || k + 1 < run.size())) corners.push_back(uint32_t(points.size()));
    points.push_back(s.p);
    steps.push_back(contrast[run[k]]);
  }
  if (closed && points.size() > 1) length += Norm(Sub(points.front(), points.back()));
  if (length < o.min_length || points.size() < (closed ? 4u : 2u)) return;
  BSplineFitOptions fit;
  fit.tolerance = o.tolerance;
  // The control polygon near its curve, where the features' cost comes on top of the budget
  // (no triangle cap): spec/SVG.md section 4 step 2.
  if (o.vectorize.max_triangles == 0) fit.max_polygon_offset = o.polygon_offset;
  FeatureCurve curve = FitChain(points, closed, corners, fit);
  if (curve.points.size() < 2) return;
  curve.sharpness = 1.0f;
  curve.boundary = false;
  curve.contrast = float(Median(steps));
  if (side.widths.empty()) {
    curve.width = float(side.width);
  } else {
    std::vector<double> widths;
    for (size_t i : run) widths.push_back(side.widths[i]);
    curve.width = float(Median(widths));
  }
  out->push_back(std::move(curve));
}

// Share of the drawn pixels (alpha > 0.5) that a morphological opening with a 3 x 3 square
// removes: parts thinner than 3 px.
double ThinShare(const Raster& reference) {
  const int w = reference.width, h = reference.height;
  auto in = [&](const std::vector<uint8_t>& m, int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && m[size_t(y) * w + x];
  };
  std::vector<uint8_t> mask(size_t(w) * h), eroded(size_t(w) * h, 0);
  size_t drawn = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      mask[size_t(y) * w + x] = reference.at(x, y, 3) > 0.5f ? 1 : 0;
      drawn += mask[size_t(y) * w + x];
    }
  }
  if (drawn == 0) return 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      bool all = true;
      for (int dy = -1; dy <= 1 && all; ++dy) {
        for (int dx = -1; dx <= 1 && all; ++dx) all = in(mask, x + dx, y + dy);
      }
      eroded[size_t(y) * w + x] = all ? 1 : 0;
    }
  }
  size_t lost = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!mask[size_t(y) * w + x]) continue;
      bool opened = false;
      for (int dy = -1; dy <= 1 && !opened; ++dy) {
        for (int dx = -1; dx <= 1 && !opened; ++dx) opened = in(eroded, x + dx, y + dy);
      }
      lost += opened ? 0 : 1;
    }
  }
  return double(lost) / double(drawn);
}

void CompositeOverWhite(Raster& r) {
  for (size_t i = 0; i < size_t(r.width) * r.height; ++i) {
    const float a = r.data[4 * i + 3];
    for (int c = 0; c < 3; ++c) r.data[4 * i + c] = r.data[4 * i + c] * a + 255.f * (1 - a);
    r.data[4 * i + 3] = 1.f;
  }
}

// Edges of the reference that no outline feature explains (text librsvg draws as glyphs
// it does not trace, patterns, images, filters, a trace cut short): the vectorizer's edge
// detection on the fitted raster, without the domain contours, each curve cut where it
// comes within kClaimRadius px (plus half a thin stroke) of an outline feature (ClaimMap:
// not where it crosses a thin one) and the pieces of at least min_length px refitted.
std::vector<FeatureCurve> UncoveredEdges(const Raster& fitted, const std::vector<FeatureCurve>& outline_features,
                                         const SvgArtworkOptions& o) {
  std::vector<FeatureCurve> out;
  StatusOr<std::vector<FeatureCurve>> detected = DetectFeatures(fitted, nullptr, o.vectorize.features);
  if (!detected.ok()) return out;
  ClaimMap claimed(fitted.width, fitted.height);
  for (const FeatureCurve& c : outline_features) claimed.ClaimCurve(c, kClaimRadius + c.width / 2, c.width > 0);
  BSplineFitOptions fit;
  fit.tolerance = o.vectorize.features.fit_tolerance;
  fit.max_spacing = o.vectorize.features.max_spacing;
  for (const FeatureCurve& curve : *detected) {
    if (curve.boundary) continue;
    const std::vector<Point2> samples = SampleFeatureCurve(curve, 8);
    std::vector<uint8_t> free(samples.size());
    bool all = true;
    for (size_t i = 0; i < samples.size(); ++i) {
      const Point2 a = samples[i > 0 ? i - 1 : i], b = samples[i + 1 < samples.size() ? i + 1 : i];
      free[i] = claimed.Claimed(samples[i], DirectionDeg(Sub(b, a))) ? 0 : 1;
      all = all && free[i];
    }
    if (all) {
      out.push_back(curve);
      continue;
    }
    std::vector<Point2> run;
    double length = 0;
    for (size_t i = 0; i <= samples.size(); ++i) {
      if (i < samples.size() && free[i]) {
        if (!run.empty()) length += Norm(Sub(samples[i], run.back()));
        run.push_back(samples[i]);
        continue;
      }
      if (run.size() >= 2 && length >= o.min_length) {
        FeatureCurve piece = FitChain(run, false, {}, fit);
        if (piece.points.size() >= 2) {
          piece.sharpness = curve.sharpness;
          piece.contrast = curve.contrast;
          out.push_back(std::move(piece));
        }
      }
      run.clear();
      length = 0;
    }
  }
  return out;
}

// Where a fill is thinner than kThinFill (glyph stems and the gaps between them at text
// sizes, slivers), its two facing outlines come within the claim radius of each other and
// the probes kProbe px either side of one outline reach past the other: neither would be a
// feature. Such parts are thin structures, as thin strokes are: for each outline sample the
// nearest crossing of the same shape's outline along the normal, either way, facing it
// (tangents within kFacingDeg of opposite) and under kThinFill px away gives a centreline
// sample halfway across with that width. Of two facing samples only the one earlier in the
// shape's outline order gives it, so a stem gives one centreline, not two. Segments are
// found through a sorted index of kCell px cells.
// kThinFill is the claim radius: a wider part keeps both outlines as features of their own
// (the second is not claimed by the first). Measured on the W3C suite (spec/SVG.md): 3 px,
// the thin stroke's limit, costs 0.4 dB of the mean against 2 px.
constexpr double kThinFill = kClaimRadius;
constexpr double kFacingDeg = 35;
constexpr double kCell = 4;
// A cell crossed by more segments than this (a shape drawn over itself many times; text
// puts a few dozen in one) is crowded: samples looking through it find no thin part, so
// the search stays linear in the samples whatever the input.
constexpr long kMaxCellSegments = 256;

class SegmentIndex {
 public:
  struct Ref {
    uint32_t outline, index;  // the segment from sample index to the next one
  };
  SegmentIndex(const std::vector<std::vector<Sample>>& flat, const std::vector<bool>& closed, const Window& w)
      : flat_(flat), w_(w) {
    for (size_t o = 0; o < flat.size(); ++o) {
      const size_t n = flat[o].size();
      const size_t segments = closed[o] ? n : (n > 0 ? n - 1 : 0);
      for (size_t i = 0; i < segments && n > 1; ++i) {
        const Point2 a = flat[o][i].p, b = flat[o][(i + 1) % n].p;
        // Samples inside the window are sample_spacing apart; longer segments join the
        // single samples that stand for pieces outside it.
        if (Norm(Sub(b, a)) > kCell || !Inside(a) || !Inside(b)) continue;
        const int x0 = Cell(std::min(a.x, b.x) - w.x0), x1 = Cell(std::max(a.x, b.x) - w.x0);
        const int y0 = Cell(std::min(a.y, b.y) - w.y0), y1 = Cell(std::max(a.y, b.y) - w.y0);
        for (int y = y0; y <= y1; ++y) {
          for (int x = x0; x <= x1; ++x) entries_.push_back({Key(x, y), {uint32_t(o), uint32_t(i)}});
        }
      }
    }
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
      return a.key != b.key ? a.key < b.key
                            : (a.ref.outline != b.ref.outline ? a.ref.outline < b.ref.outline : a.ref.index < b.ref.index);
    });
  }

  bool empty() const { return entries_.empty(); }

  // The nearest crossing of the ray from sample (o, i) along dir (unit) within reach, not
  // on the segments next to the sample: its distance and segment; false if none.
  bool Nearest(size_t o, size_t i, Point2 dir, double reach, double* t_out, Ref* hit) const {
    const Point2 p = flat_[o][i].p;
    const Point2 q{p.x + reach * dir.x, p.y + reach * dir.y};
    if (!Inside(p) || !Inside(q)) return false;
    const int x0 = Cell(std::min(p.x, q.x) - w_.x0), x1 = Cell(std::max(p.x, q.x) - w_.x0);
    const int y0 = Cell(std::min(p.y, q.y) - w_.y0), y1 = Cell(std::max(p.y, q.y) - w_.y0);
    const size_t n = flat_[o].size();
    double best = reach;
    bool found = false;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const uint64_t key = Key(x, y);
        auto it = std::lower_bound(entries_.begin(), entries_.end(), key,
                                   [](const Entry& e, uint64_t k) { return e.key < k; });
        const auto end = std::upper_bound(it, entries_.end(), key, [](uint64_t k, const Entry& e) { return k < e.key; });
        if (end - it > kMaxCellSegments) return false;  // crowded: no thin part found here
        for (; it != end; ++it) {
          const Ref r = it->ref;
          if (r.outline == o) {
            const size_t d = (r.index + n - i) % n;  // the four segments around the sample
            if (d <= 1 || d >= n - 2) continue;
          }
          const std::vector<Sample>& line = flat_[r.outline];
          const Point2 a = line[r.index].p, b = line[(r.index + 1) % line.size()].p;
          const Point2 e = Sub(b, a), w = Sub(a, p);
          const double denom = dir.x * e.y - dir.y * e.x;
          if (std::abs(denom) < 1e-12) continue;
          const double t = (w.x * e.y - w.y * e.x) / denom, u = (w.x * dir.y - w.y * dir.x) / denom;
          if (u < 0 || u > 1 || !(t > 1e-6) || t >= best) continue;
          best = t;
          *hit = r;
          found = true;
        }
      }
    }
    *t_out = best;
    return found;
  }

 private:
  struct Entry {
    uint64_t key;
    Ref ref;
  };
  bool Inside(Point2 p) const { return p.x >= w_.x0 && p.y >= w_.y0 && p.x <= w_.x1 && p.y <= w_.y1; }
  static int Cell(double v) { return int(std::floor(v / kCell)); }
  static uint64_t Key(int x, int y) { return (uint64_t(uint32_t(y)) << 32) | uint32_t(x); }

  const std::vector<std::vector<Sample>>& flat_;
  Window w_;
  std::vector<Entry> entries_;
};

// One Side per outline with a thin part: every sample of the outline, moved to the
// centreline where it faces the shape's outline thinly (widths[i] > 0), widths[i] = 0
// (never accepted) elsewhere.
std::vector<Side> ThinFillSides(const std::vector<std::vector<Sample>>& flat, const std::vector<bool>& closed,
                                const Window& window) {
  std::vector<Side> sides;
  const SegmentIndex index(flat, closed, window);
  if (index.empty()) return sides;
  const double facing = std::cos(kFacingDeg * kPi / 180);
  for (size_t o = 0; o < flat.size(); ++o) {
    const std::vector<Sample>& line = flat[o];
    Side side;
    side.closed = closed[o];
    side.samples = line;
    side.widths.assign(line.size(), 0);
    bool any = false;
    for (size_t i = 0; i < line.size() && line.size() >= 4; ++i) {
      const Point2 nrm = line[i].normal;
      if (Norm(nrm) < 0.5) continue;
      const Point2 tangent{nrm.y, -nrm.x};
      double best = kThinFill, sign = 0;
      SegmentIndex::Ref across{};
      for (double s : {1.0, -1.0}) {
        double t = 0;
        SegmentIndex::Ref hit{};
        if (!index.Nearest(o, i, {s * nrm.x, s * nrm.y}, kThinFill, &t, &hit) || t >= best) continue;
        const std::vector<Sample>& other = flat[hit.outline];
        const Point2 e = Sub(other[(hit.index + 1) % other.size()].p, other[hit.index].p);
        const double len = Norm(e);
        // Facing: the other side runs back along this one.
        if (!(len > 0) || (e.x * tangent.x + e.y * tangent.y) / len > -facing) continue;
        best = t, sign = s, across = hit;
      }
      // The earlier of the two facing samples gives the centreline sample.
      if (sign == 0 || across.outline < o || (across.outline == o && across.index < i)) continue;
      side.samples[i].p = {line[i].p.x + sign * best / 2 * nrm.x, line[i].p.y + sign * best / 2 * nrm.y};
      side.widths[i] = best;
      any = true;
    }
    if (any) sides.push_back(std::move(side));
  }
  return sides;
}

// A run of a thin fill's centreline ends where the width changes by more than this from the
// run's first sample, or where consecutive centre samples are further apart than kThinJump.
constexpr double kThinWidthStep = 0.75;
constexpr double kThinJump = 1.5;
constexpr uint8_t kBridge = 2;  // accept[] of a sample that bridges a crossing

// The features of one side: samples accepted where the reference changes colour across them
// and nothing above claims them, runs of them fitted (EmitRun), then claimed.
void AddSideFeatures(const Side& side, bool stroke_side, const Raster& reference, const SvgArtworkOptions& o,
                     ClaimMap* claimed, std::vector<FeatureCurve>* curves) {
  const size_t n = side.samples.size();
  std::vector<double> contrast(n, -1);
  std::vector<uint8_t> accept(n, 0);
  const bool thin_fill = !side.widths.empty();
  for (size_t i = 0; i < n; ++i) {
    const Sample& s = side.samples[i];
    const double width = thin_fill ? side.widths[i] : side.width;
    const double direction = DirectionDeg({s.normal.y, -s.normal.x});
    if ((thin_fill && width <= 0) || claimed->Claimed(s.p, direction)) continue;
    const Point2 nrm = s.normal;
    if (width > 0) {
      // A thin structure: its centre against kProbe px beyond either outline; the larger step.
      const double out_d = width / 2 + kProbe;
      const Point2 a{s.p.x + out_d * nrm.x, s.p.y + out_d * nrm.y};
      const Point2 b{s.p.x - out_d * nrm.x, s.p.y - out_d * nrm.y};
      contrast[i] = std::max(Contrast(reference, a, s.p), Contrast(reference, b, s.p));
      accept[i] = contrast[i] >= o.min_contrast ? 1 : 0;
    } else {
      double out_d = kProbe, in_d = side.inner_probe;
      const double dir = side.outward != 0 ? side.outward : 1.0;
      const Point2 a{s.p.x + dir * out_d * nrm.x, s.p.y + dir * out_d * nrm.y};
      const Point2 b{s.p.x - dir * in_d * nrm.x, s.p.y - dir * in_d * nrm.y};
      contrast[i] = Contrast(reference, a, b);
      accept[i] = contrast[i] >= o.min_contrast && !(stroke_side && s.corner) ? 1 : 0;
    }
    // Where it crosses a feature above, the probes read that feature: the sample bridges the
    // crossing (kept inside a run, never at its ends).
    if (!accept[i] && !(stroke_side && s.corner) && claimed->Crossed(s.p, direction)) accept[i] = kBridge;
  }
  // A thin structure crossing another one (drawn above or below it, in any colour): where
  // the probes lie on the other structure the step is lost for up to its width. A gap of at
  // most kThinStroke px between accepted samples, along which something is drawn (the
  // centre differs by min_contrast from the colour beyond both outlines next to the gap; a
  // dash's gap shows the background), is bridged.
  for (size_t i = 0; i < n && (thin_fill || side.width > 0); ++i) {
    if (accept[i] != 1) continue;
    size_t j = i + 1;
    while (j < n && accept[j] == 0 && contrast[j] >= 0) ++j;
    if (j >= n || accept[j] != 1 || j == i + 1) continue;
    if (Norm(Sub(side.samples[j].p, side.samples[i].p)) > kThinStroke + 0.5 * o.sample_spacing) continue;
    std::vector<Point2> beyond;  // the colour beyond both outlines at the gap's two ends
    for (size_t e : {i, j}) {
      const double out_d = (thin_fill ? side.widths[e] : side.width) / 2 + kProbe;
      const Sample& s = side.samples[e];
      beyond.push_back({s.p.x + out_d * s.normal.x, s.p.y + out_d * s.normal.y});
      beyond.push_back({s.p.x - out_d * s.normal.x, s.p.y - out_d * s.normal.y});
    }
    bool drawn = true;
    for (size_t k = i + 1; k < j && drawn; ++k)
      for (const Point2& b : beyond) drawn = drawn && Contrast(reference, side.samples[k].p, b) >= o.min_contrast;
    if (drawn)
      for (size_t k = i + 1; k < j; ++k) accept[k] = kBridge;
  }
  // A thin fill's run is cut where its width steps or its centre jumps.
  auto cut = [&](size_t first, size_t prev, size_t i) {
    return thin_fill && (std::abs(side.widths[i] - side.widths[first]) > kThinWidthStep ||
                         Norm(Sub(side.samples[i].p, side.samples[prev].p)) > kThinJump);
  };
  // Runs of accepted samples; a closed side accepted everywhere stays closed.
  bool all = std::all_of(accept.begin(), accept.end(), [](uint8_t a) { return a != 0; });
  for (size_t i = 1; i <= n && all && side.closed && thin_fill; ++i) all = !cut(0, i - 1, i % n);
  std::vector<size_t> run;
  const size_t before = curves->size();
  // Without its bridging ends; a pattern's lines keep them: a line that ends on another
  // feature (a tile's edge at the fill's outline) then crosses it, and the vectorizer joins
  // the two at a junction.
  auto emit_open = [&](std::vector<size_t> r) {
    const bool keep_ends = side.crossing;
    while (!keep_ends && !r.empty() && accept[r.back()] == kBridge) r.pop_back();
    size_t lead = 0;
    while (!keep_ends && lead < r.size() && accept[r[lead]] == kBridge) ++lead;
    r.erase(r.begin(), r.begin() + std::ptrdiff_t(lead));
    if (!r.empty() && std::any_of(r.begin(), r.end(), [&](size_t i) { return accept[i] == 1; }))
      EmitRun(side, r, false, contrast, stroke_side, o, curves);
  };
  if (all && side.closed && std::find(accept.begin(), accept.end(), 1) != accept.end()) {
    for (size_t i = 0; i < n; ++i) run.push_back(i);
    EmitRun(side, run, true, contrast, stroke_side, o, curves);
  } else {
    size_t start = 0;
    if (side.closed) {
      while (start < n && accept[start]) ++start;  // begin after a rejected sample
    }
    for (size_t k = 0; k <= n; ++k) {
      const size_t i = (start + k) % n;
      const bool open_end = !side.closed && k == n;
      if (k < n && !open_end && accept[i] && (side.closed || i >= start)) {
        if (!run.empty() && cut(run.front(), run.back(), i)) {
          emit_open(run);
          run.clear();
        }
        run.push_back(i);
        continue;
      }
      if (!run.empty()) emit_open(run);
      run.clear();
      if (!side.closed && k >= n) break;
    }
  }
  for (size_t c = before; c < curves->size(); ++c) {
    claimed->ClaimCurve((*curves)[c], kClaimRadius + (*curves)[c].width / 2, (*curves)[c].width > 0 || side.crossing);
  }
}

}  // namespace

double OutlineSampleCount(const std::vector<SvgShape>& shapes, const Raster& reference, double spacing) {
  return CountOutlineSamples(shapes, reference, spacing);
}

std::vector<FeatureCurve> ArtworkFeatures(const std::vector<SvgShape>& shapes, const Raster& reference,
                                          const SvgArtworkOptions& o) {
  std::vector<FeatureCurve> curves;
  ClaimMap claimed(reference.width, reference.height);
  // Top-most first: where two outlines coincide, the visible (upper) one is kept.
  for (auto shape = shapes.rbegin(); shape != shapes.rend(); ++shape) {
    const Window window = OutlineWindow(*shape, reference);
    std::vector<std::vector<Sample>> flat;
    std::vector<bool> closed;
    for (const SvgOutline& outline : shape->outlines) {
      flat.push_back(Flatten(outline, o.sample_spacing, o.corner_angle_deg, window));
      closed.push_back(outline.closed);
    }
    // A fill's parts thinner than kThinFill first (their centrelines claim both outlines),
    // then every outline as it is.
    if (shape->paint == SvgPaint::kFill && o.thin_fills && !shape->tiled) {
      for (const Side& side : ThinFillSides(flat, closed, window)) AddSideFeatures(side, false, reference, o, &claimed, &curves);
    }
    for (size_t k = 0; k < flat.size(); ++k) {
      const bool stroke = shape->paint == SvgPaint::kStroke;
      for (Side& side : SidesOf(*shape, shape->outlines[k], std::move(flat[k]), o.sample_spacing)) {
        side.crossing = shape->tiled && shape->paint == SvgPaint::kFill;  // the lines and the fill they end at
        AddSideFeatures(side, stroke && side.width == 0, reference, o, &claimed, &curves);
      }
    }
  }
  return curves;
}

StatusOr<SvgArtworkResult> ImportSvgArtwork(const SvgDocument& document, const SvgArtworkOptions& options,
                                            SvgError* error) {
  if (!(options.tolerance > 0) || !(options.sample_spacing > 0) || !(options.min_contrast >= 0) ||
      !(options.min_length >= 0) || !(options.polygon_offset >= 0)) {
    return Status(StatusCode::kInvalidArgument, document.name + ": artwork options out of range");
  }
  SDVI_ASSIGN_OR_RETURN(SvgSize size, ChooseSvgSize(document, options.width, options.scale, options.limits, error));
  SvgArtworkResult result;
  // The geometry first: its dash estimate bounds what rendering the reference costs.
  SDVI_ASSIGN_OR_RETURN(SvgGeometry geometry, TraceSvgGeometry(document, size.width, size.height));
  SDVI_RETURN_IF_ERROR(CheckDashes(document, geometry, error));
  SDVI_ASSIGN_OR_RETURN(result.reference, RenderSvgUnchecked(document, size.width, size.height));
  const double samples = OutlineSampleCount(geometry.shapes, result.reference, options.sample_spacing);
  if (!(samples <= double(options.limits.max_outline_samples))) {
    char estimate[32];
    std::snprintf(estimate, sizeof estimate, "%.3g", samples);
    return SvgFailure(SvgError::kTooManyOutlineSamples, document.name,
                      "the outlines need " + std::string(estimate) + " samples at " + std::to_string(size.width) +
                          " x " + std::to_string(size.height) + " px, over the limit of " +
                          std::to_string(options.limits.max_outline_samples) +
                          " (max_outline_samples; a smaller output size needs fewer)",
                      error);
  }
  if (geometry.glyph_runs > 0) {
    result.warnings.push_back("approximate: " + std::to_string(geometry.glyph_runs) +
                              " text runs are drawn from a font without their outlines; their edges are detected "
                              "in librsvg's rendering");
    result.approximate = true;
  }
  if (geometry.patterns_not_copied > 0) {
    result.warnings.push_back("approximate: " + std::to_string(geometry.patterns_not_copied) +
                              " paintings with a pattern have no copies of its tile's shapes (a stroke, a nested "
                              "pattern, too many or too small tiles); their edges are detected in librsvg's rendering");
    result.approximate = true;
  }
  if (!geometry.incomplete.empty()) {
    result.warnings.push_back("approximate: librsvg stopped tracing the outlines (" + geometry.incomplete +
                              "); only the " + std::to_string(geometry.shapes.size()) +
                              " shapes traced before that give exact features");
    result.approximate = true;
  }

  // An opaque drawing is a plain image; a transparent background makes an object image,
  // unless it is made of thin structures (then it is composited over white).
  Raster& ref = result.reference;
  bool opaque = true, any = false;
  for (size_t i = 0; i < size_t(ref.width) * ref.height; ++i) {
    opaque = opaque && ref.data[4 * i + 3] >= 0.999f;
    any = any || ref.data[4 * i + 3] > 0.5f;
  }
  if (!any && options.background != SvgBackground::kWhite) {
    return Status(StatusCode::kEmptyInput, document.name + ": nothing is drawn (the rendering is transparent)");
  }
  bool white = options.background == SvgBackground::kWhite;
  if (!opaque && options.background == SvgBackground::kAuto) {
    const double thin = ThinShare(ref);
    if (thin > 0.02) {
      white = true;
      result.warnings.push_back("the transparent drawing is " + std::to_string(int(std::lround(100 * thin))) +
                                "% structures thinner than 3 px (text, hairlines): composited over white instead "
                                "of an object image");
    }
  }
  if (white) CompositeOverWhite(ref);
  result.object_image = !opaque && !white;
  std::vector<FeatureCurve> curves = ArtworkFeatures(geometry.shapes, ref, options);
  result.outline_features = uint32_t(curves.size());
  Raster rgb;
  const Raster* fitted = &ref;
  if (!result.object_image) {
    rgb = Raster(ref.width, ref.height, 3);
    for (size_t i = 0; i < size_t(ref.width) * ref.height; ++i) {
      for (int c = 0; c < 3; ++c) rgb.data[3 * i + c] = ref.data[4 * i + c];
    }
    fitted = &rgb;
  }
  if (options.detect_uncovered_edges) {
    std::vector<FeatureCurve> detected = UncoveredEdges(*fitted, curves, options);
    result.detected_features = uint32_t(detected.size());
    curves.insert(curves.end(), std::make_move_iterator(detected.begin()), std::make_move_iterator(detected.end()));
  }
  StatusOr<VectorizeResult> vectorized = VectorizeWithFeatures(*fitted, nullptr, curves, options.vectorize);
  if (!vectorized.ok()) {
    return Status(vectorized.status().code(), document.name + ": " + vectorized.status().message());
  }
  result.vectorized = std::move(vectorized).value();
  result.warnings.insert(result.warnings.begin(), document.warnings.begin(), document.warnings.end());
  if (!document.unsupported.empty()) {
    std::string list;
    for (const std::string& u : document.unsupported) list += (list.empty() ? "" : ", ") + u;
    result.warnings.push_back("approximate: no exact features for " + list +
                              " (their colours are fitted to librsvg's rendering)");
    result.approximate = true;
  }
  return result;
}

}  // namespace sdvi
