// SPDX-License-Identifier: GPL-3.0-or-later
// Feature placement: boundary, feature pairs, no crossings (rules in pairs.h).
#include "pairs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

namespace sdvi {
namespace {

double Dist(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

double PointSegmentDistance(Point2 p, Point2 a, Point2 b) {
  double vx = b.x - a.x, vy = b.y - a.y;
  double l2 = vx * vx + vy * vy;
  double t = l2 > 0 ? ((p.x - a.x) * vx + (p.y - a.y) * vy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * vx), p.y - (a.y + t * vy));
}

double Cross(Point2 o, Point2 a, Point2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

bool SegmentsCross(Point2 a, Point2 b, Point2 c, Point2 d) {
  double d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

double SegmentDistance(Point2 a, Point2 b, Point2 c, Point2 d) {
  if (SegmentsCross(a, b, c, d)) return 0;
  return std::min({PointSegmentDistance(a, c, d), PointSegmentDistance(b, c, d),
                   PointSegmentDistance(c, a, b), PointSegmentDistance(d, a, b)});
}

// Uniform grid over the (slightly enlarged) frame holding placed segments.
class SegmentGrid {
 public:
  SegmentGrid(double width, double height, double cell) : cell_(cell) {
    nx_ = std::max(1, int(std::ceil((width + 2 * kPad) / cell)));
    ny_ = std::max(1, int(std::ceil((height + 2 * kPad) / cell)));
    cells_.resize(size_t(nx_) * ny_);
  }
  void Add(Point2 a, Point2 b) {
    int id = int(segs_.size());
    segs_.push_back({a, b});
    ForCells(a, b, 0, [&](std::vector<int>& c) { c.push_back(id); });
  }
  // Smallest distance from segment (a, b) to a placed segment, capped at `reach`.
  double Distance(Point2 a, Point2 b, double reach) const {
    double best = reach;
    const_cast<SegmentGrid*>(this)->ForCells(a, b, reach, [&](std::vector<int>& c) {
      for (int id : c) best = std::min(best, SegmentDistance(a, b, segs_[id].first, segs_[id].second));
    });
    return best;
  }
  const std::vector<std::pair<Point2, Point2>>& segments() const { return segs_; }

 private:
  static constexpr double kPad = 16;
  template <typename F>
  void ForCells(Point2 a, Point2 b, double margin, F&& f) {
    auto cx = [&](double x) { return std::clamp(int(std::floor((x + kPad) / cell_)), 0, nx_ - 1); };
    auto cy = [&](double y) { return std::clamp(int(std::floor((y + kPad) / cell_)), 0, ny_ - 1); };
    int x0 = cx(std::min(a.x, b.x) - margin), x1 = cx(std::max(a.x, b.x) + margin);
    int y0 = cy(std::min(a.y, b.y) - margin), y1 = cy(std::max(a.y, b.y) + margin);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(cells_[size_t(y) * nx_ + x]);
  }
  double cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<std::pair<Point2, Point2>> segs_;
};

// Removes consecutive (near-)duplicate points, keeping corner tags; splits segments
// longer than max_len evenly.
PlacedPolyline Prepare(const FeatureCurve& c, double max_len) {
  PlacedPolyline out;
  out.closed = c.closed;
  out.boundary = c.boundary;
  const size_t n = c.points.size();
  std::vector<bool> is_corner(n, false);
  for (uint32_t k : c.corners)
    if (k < n) is_corner[k] = true;
  std::vector<Point2> pts;
  std::vector<bool> corner;
  for (size_t i = 0; i < n; ++i) {
    if (!pts.empty() && Dist(pts.back(), c.points[i]) < 1e-3) {
      corner.back() = corner.back() || is_corner[i];
      continue;
    }
    pts.push_back(c.points[i]);
    corner.push_back(is_corner[i]);
  }
  if (out.closed && pts.size() > 1 && Dist(pts.back(), pts.front()) < 1e-3) {
    corner.front() = corner.front() || corner.back();
    pts.pop_back();
    corner.pop_back();
  }
  const size_t m = pts.size();
  const size_t segs = out.closed ? m : (m ? m - 1 : 0);
  for (size_t i = 0; i < m; ++i) {
    if (corner[i]) out.corners.push_back(uint32_t(out.points.size()));
    out.points.push_back(pts[i]);
    if (i >= segs) continue;
    Point2 a = pts[i], b = pts[(i + 1) % m];
    int pieces = int(std::ceil(Dist(a, b) / max_len));
    for (int k = 1; k < pieces; ++k) {
      double t = double(k) / pieces;
      out.points.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  return out;
}

// Splits each segment i of l with split[i] set, longer than max_len and on a straight part
// of the polygon evenly into pieces of at most max_len (corners kept); true when some
// segment was split. Straight: the points before and after it (up to a corner or an open
// end) lie within 0.01 px of its line, so the cubic B-spline's spans through the segment
// stay on that line (the next ones change by the last basis function's small weight);
// elsewhere new points would pull the curve towards its control polygon (measured: photos
// -0.1 to -0.8 dB when every bad segment was split).
// *inserted (l's new size) marks the points added.
bool SplitSegments(PlacedPolyline& l, std::vector<bool> split, double max_len, std::vector<bool>* inserted) {
  const size_t m = l.points.size();
  const size_t segs = l.closed ? m : m - 1;
  std::vector<bool> corner(m, false);
  for (uint32_t c : l.corners) corner[c] = true;
  auto off_line = [&](Point2 p, Point2 a, Point2 b) {
    const double len = Dist(a, b);
    return std::fabs((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / len > 0.01;
  };
  bool any = false;
  for (size_t i = 0; i < segs; ++i) {
    const Point2 a = l.points[i], b = l.points[(i + 1) % m];
    if (!split[i] || !(Dist(a, b) > max_len)) {
      split[i] = false;
      continue;
    }
    const bool has_before = !corner[i] && (l.closed || i > 0);
    const bool has_after = !corner[(i + 1) % m] && (l.closed || i + 2 < m);
    if ((has_before && off_line(l.points[(i + m - 1) % m], a, b)) || (has_after && off_line(l.points[(i + 2) % m], a, b)))
      split[i] = false;
    any = any || split[i];
  }
  inserted->assign(m, false);
  if (!any) return false;
  PlacedPolyline out;
  out.closed = l.closed;
  out.boundary = l.boundary;
  inserted->clear();
  for (size_t i = 0; i < m; ++i) {
    if (corner[i]) out.corners.push_back(uint32_t(out.points.size()));
    out.points.push_back(l.points[i]);
    inserted->push_back(false);
    if (i >= segs || !split[i]) continue;
    const Point2 a = l.points[i], b = l.points[(i + 1) % m];
    const int pieces = int(std::ceil(Dist(a, b) / max_len));
    for (int k = 1; k < pieces; ++k) {
      const double t = double(k) / pieces;
      out.points.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      inserted->push_back(true);
    }
  }
  l = std::move(out);
  return true;
}

// Point-in-domain test for object mode: even-odd rule over all boundary polylines (a
// horizontal ray to the right), with the segments bucketed by pixel row.
class DomainTest {
 public:
  DomainTest(const std::vector<PlacedPolyline>& boundary, int height) : rows_(size_t(height) + 1) {
    for (const PlacedPolyline& b : boundary) {
      const size_t m = b.points.size();
      for (size_t i = 0, j = m - 1; i < m; j = i++) {
        Point2 a = b.points[i], c = b.points[j];
        if (a.y == c.y) continue;
        segs_.push_back({a, c});
        int r0 = Row(std::min(a.y, c.y)), r1 = Row(std::max(a.y, c.y));
        for (int r = r0; r <= r1; ++r) rows_[r].push_back(int(segs_.size() - 1));
      }
    }
  }
  bool Inside(Point2 p) const {
    bool inside = false;
    for (int id : rows_[Row(p.y)]) {
      const auto& [a, c] = segs_[id];
      if ((a.y > p.y) != (c.y > p.y)) {
        double x = a.x + (p.y - a.y) * (c.x - a.x) / (c.y - a.y);
        if (p.x < x) inside = !inside;
      }
    }
    return inside;
  }

 private:
  int Row(double y) const { return std::clamp(int(std::floor(y)), 0, int(rows_.size()) - 1); }
  std::vector<std::vector<int>> rows_;
  std::vector<std::pair<Point2, Point2>> segs_;
};

Status ValidateCurve(const FeatureCurve& c, size_t index, int width, int height) {
  auto bad = [&](const std::string& what) {
    return Status(StatusCode::kInvalidArgument, "BuildControlMesh: curve " + std::to_string(index) + " " + what);
  };
  if (c.points.size() < (c.closed ? 3u : 2u))
    return bad("has " + std::to_string(c.points.size()) + " points, needs at least " + (c.closed ? "3" : "2"));
  for (const Point2& p : c.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return bad("has a non-finite point");
    if (c.boundary && (p.x < 0 || p.y < 0 || p.x > width || p.y > height))
      return bad("is a boundary curve with a point outside the frame [0," + std::to_string(width) + "]x[0," +
                 std::to_string(height) + "]");
  }
  for (uint32_t k : c.corners)
    if (k >= c.points.size()) return bad("has corner index " + std::to_string(k) + " out of range");
  if (!(c.sharpness >= 0 && c.sharpness <= 1)) return bad("has sharpness outside [0, 1]");
  if (c.boundary && !c.closed) return bad("is a boundary curve that is not closed");
  return Status::Ok();
}

// Tags segments of a candidate (one or two polylines with equal segment count) that
// conflict with placed segments, with each other, or leave the domain.
// check_domain: also tag segments whose end points leave the domain (the frame shrunk by
// the clearance, or the inside of the boundary polylines when given).
std::vector<bool> BadSegments(const std::vector<const PlacedPolyline*>& lines, const SegmentGrid& placed,
                              double clearance, double self_clearance, bool check_domain, int width,
                              int height, const DomainTest* domain) {
  const PlacedPolyline& first = *lines[0];
  const int m = int(first.points.size());
  const int segs = first.closed ? m : m - 1;
  std::vector<bool> bad(std::max(segs, 0), false);
  for (const PlacedPolyline* l : lines) {
    for (int i = 0; i < m && check_domain; ++i) {
      Point2 p = l->points[i];
      bool inside = domain ? domain->Inside(p)
                             : (p.x >= clearance && p.y >= clearance && p.x <= width - clearance &&
                                p.y <= height - clearance);
      if (!inside) {
        if (i < segs) bad[i] = true;
        if (i > 0 || first.closed) bad[(i - 1 + segs) % segs] = true;
      }
    }
    for (int i = 0; i < segs; ++i) {
      if (bad[i]) continue;
      Point2 a = l->points[i], b = l->points[(i + 1) % m];
      if (placed.Distance(a, b, clearance) < clearance) bad[i] = true;
    }
  }
  // Self and mutual conflicts of the candidate's own segments: every pair closer than
  // self_clearance (neighbours along one polyline excepted). A uniform grid over the
  // segments' boxes, grown by self_clearance, finds the pairs whose boxes meet; the same
  // pairs as testing all of them, in O(n) for a curve that does not fold onto itself.
  const int total = int(lines.size()) * segs;
  auto segment = [&](int id) {
    const auto& p = lines[id / segs]->points;
    const int i = id % segs;
    return std::pair<Point2, Point2>{p[i], p[(i + 1) % m]};
  };
  double mean_length = 0;
  for (int id = 0; id < total; ++id) mean_length += Dist(segment(id).first, segment(id).second);
  const double cell = std::max({1.0, mean_length / std::max(1, total), 4 * self_clearance});
  auto for_cells = [&](int id, auto&& f) {
    const auto [a, b] = segment(id);
    const auto x0 = int64_t(std::floor((std::min(a.x, b.x) - self_clearance) / cell));
    const auto x1 = int64_t(std::floor((std::max(a.x, b.x) + self_clearance) / cell));
    const auto y0 = int64_t(std::floor((std::min(a.y, b.y) - self_clearance) / cell));
    const auto y1 = int64_t(std::floor((std::max(a.y, b.y) + self_clearance) / cell));
    for (int64_t y = y0; y <= y1; ++y)
      for (int64_t x = x0; x <= x1; ++x) f((uint64_t(uint32_t(x)) << 32) | uint32_t(y));
  };
  // A segment of (nearly) no length would give coinciding vertices: it is cut out with its
  // neighbours, so that no run ends or starts on it.
  for (size_t l = 0; l < lines.size(); ++l) {
    for (int i = 0; i < segs; ++i) {
      const auto [a, b] = segment(int(l) * segs + i);
      if (Dist(a, b) >= 0.01) continue;
      for (int k = i - 1; k <= i + 1; ++k) {
        if (first.closed) bad[size_t((k + segs) % segs)] = true;
        else if (k >= 0 && k < segs) bad[size_t(k)] = true;
      }
    }
  }
  // Polygon length strictly between segments i < j of line l (the shorter way round when closed).
  std::vector<std::vector<double>> cumulative(lines.size(), std::vector<double>(size_t(segs) + 1, 0.0));
  for (size_t l = 0; l < lines.size(); ++l) {
    for (int i = 0; i < segs; ++i) {
      const auto [a, b] = segment(int(l) * segs + i);
      cumulative[l][size_t(i) + 1] = cumulative[l][size_t(i)] + Dist(a, b);
    }
  }
  auto ArcBetween = [&](int l, int i, int j) {
    const std::vector<double>& c = cumulative[size_t(l)];
    const double inside = c[size_t(j)] - c[size_t(i) + 1];
    return first.closed ? std::min(inside, c[size_t(segs)] - (c[size_t(j) + 1] - c[size_t(i)])) : inside;
  };
  std::unordered_map<uint64_t, std::vector<int>> cells;
  for (int id = 0; id < total; ++id) for_cells(id, [&](uint64_t key) { cells[key].push_back(id); });
  std::vector<int> tested_with(total, -1);  // the last id this segment was tested against
  for (int ida = 0; ida < total; ++ida) {
    for_cells(ida, [&](uint64_t key) {
      for (int idb : cells[key]) {
        if (idb <= ida || tested_with[idb] == ida) continue;
        tested_with[idb] = ida;
        const int i = ida % segs, j = idb % segs;
        const bool same_line = ida / segs == idb / segs;
        if (same_line) {
          int gap = std::abs(i - j);
          if (first.closed) gap = std::min(gap, segs - gap);
          if (gap <= 1) continue;
        }
        const auto [a, b] = segment(ida);
        const auto [c, d] = segment(idb);
        const double distance = SegmentDistance(a, b, c, d);
        // Along one polyline, segments joined by 0.01 to 2 x self_clearance px of polygon
        // (a short segment at a corner) are near because they are neighbours, not a fold;
        // unless they touch. (Joined by less, they would give coinciding vertices.)
        if (same_line && distance > 0) {
          const double arc = ArcBetween(ida / segs, std::min(i, j), std::max(i, j));
          if (arc >= 0.01 && arc < 2 * self_clearance) continue;
        }
        if (distance < self_clearance) {
          bad[i] = true;
          bad[j] = true;
        }
      }
    });
  }
  return bad;
}

// Sub-polyline of points [a, b] (indices mod m) keeping the corners strictly inside and
// leaving out the points strictly inside marked in `skip`.
PlacedPolyline SubPolyline(const PlacedPolyline& l, int a, int b, const std::vector<bool>& skip) {
  PlacedPolyline out;
  out.closed = false;
  out.boundary = l.boundary;
  const int m = int(l.points.size());
  std::vector<bool> corner(m, false);
  for (uint32_t c : l.corners) corner[c] = true;
  for (int k = a; k <= b; ++k) {
    int i = k % m;
    if (k != a && k != b && skip[size_t(i)]) continue;
    if (corner[i] && k != a && k != b) out.corners.push_back(uint32_t(out.points.size()));
    out.points.push_back(l.points[i]);
  }
  return out;
}

// The closed polyline without the points marked in `skip` (never corners).
PlacedPolyline WithoutPoints(const PlacedPolyline& l, const std::vector<bool>& skip) {
  PlacedPolyline out;
  out.closed = l.closed;
  out.boundary = l.boundary;
  std::vector<bool> corner(l.points.size(), false);
  for (uint32_t c : l.corners) corner[c] = true;
  for (size_t i = 0; i < l.points.size(); ++i) {
    if (skip[i]) continue;
    if (corner[i]) out.corners.push_back(uint32_t(out.points.size()));
    out.points.push_back(l.points[i]);
  }
  return out;
}

double PolylineArea(const PlacedPolyline& l) {
  double a = 0;
  const size_t m = l.points.size();
  for (size_t i = 0, j = m - 1; i < m; j = i++)
    a += l.points[j].x * l.points[i].y - l.points[i].x * l.points[j].y;
  return std::fabs(a) / 2;
}

double Length(const FeatureCurve& c) {
  double len = 0;
  for (size_t i = 1; i < c.points.size(); ++i) len += Dist(c.points[i - 1], c.points[i]);
  return len;
}

// Unit normal offsets (mitred, limit 2) of a polygon's vertices.
std::vector<Point2> PairNormals(const std::vector<Point2>& p, bool closed) {
  const int m = int(p.size());
  auto seg_normal = [&](int i) {  // normal of segment i -> i+1 (left of the direction)
    Point2 a = p[i], b = p[(i + 1) % m];
    double dx = b.x - a.x, dy = b.y - a.y, l = std::hypot(dx, dy);
    return l > 0 ? Point2{-dy / l, dx / l} : Point2{0, 0};
  };
  std::vector<Point2> out(m);
  for (int i = 0; i < m; ++i) {
    bool has_prev = closed || i > 0, has_next = closed || i + 1 < m;
    Point2 n1 = has_prev ? seg_normal((i - 1 + m) % m) : seg_normal(i);
    Point2 n2 = has_next ? seg_normal(i) : n1;
    if (!has_prev) n1 = n2;
    double sx = n1.x + n2.x, sy = n1.y + n2.y, l = std::hypot(sx, sy);
    if (l < 1e-6) {
      out[i] = n1;
      continue;
    }
    sx /= l;
    sy /= l;
    double c = sx * n1.x + sy * n1.y;
    double scale = 1.0 / std::max(0.5, c);
    out[i] = {sx * scale, sy * scale};
  }
  return out;
}

// The centre polygon moved by each offset along its mitred unit normals (+ is the +n side).
std::vector<std::vector<Point2>> OffsetPolygon(const std::vector<Point2>& centre, bool closed,
                                               const std::vector<double>& offsets) {
  const std::vector<Point2> nrm = PairNormals(centre, closed);
  std::vector<std::vector<Point2>> out(offsets.size(), centre);
  for (size_t k = 0; k < offsets.size(); ++k) {
    for (size_t i = 0; i < centre.size(); ++i) {
      out[k][i].x += offsets[k] * nrm[i].x;
      out[k][i].y += offsets[k] * nrm[i].y;
    }
  }
  return out;
}

// The polylines of one feature, as offsets of its centre polygon, and the pairs among them
// (indices into offsets), by the rules in pairs.h.
struct FeatureLayout {
  std::vector<double> offsets;
  std::vector<std::array<int, 2>> pairs;
};

FeatureLayout LayoutOf(const FeatureCurve& curve, const ControlMeshOptions& options) {
  const double d = PairDistance(curve.sharpness, options);
  if (!(curve.width > 0)) {
    if (!options.pairs) return {{0.0}, {}};
    return {{0.5 * d, -0.5 * d}, {{0, 1}}};
  }
  const double half = 0.5 * curve.width;
  if (!options.pairs) return curve.width >= options.clearance ? FeatureLayout{{half, -half}, {}} : FeatureLayout{{0.0}, {}};
  const double outer = half + 0.5 * d, inner = half - 0.5 * d;
  if (2 * inner >= 0.5 * options.min_distance) return {{outer, inner, -inner, -outer}, {{0, 1}, {2, 3}}};
  return {{outer, 0.0, -outer}, {{0, 1}, {1, 2}}};
}

}  // namespace

double PairDistance(float sharpness, const ControlMeshOptions& options) {
  return options.use_sharpness ? std::max<double>(options.min_distance, options.rho * (1.0 - sharpness))
                               : std::max<double>(options.min_distance, options.rho);
}

std::array<std::vector<Point2>, 2> OffsetPairSides(const std::vector<Point2>& centre, bool closed, double distance) {
  std::vector<std::vector<Point2>> sides = OffsetPolygon(centre, closed, {+1.0 * 0.5 * distance, -1.0 * 0.5 * distance});
  return {std::move(sides[0]), std::move(sides[1])};
}

StatusOr<PlacedFeatures> PlaceFeatures(int width, int height, const std::vector<FeatureCurve>& curves,
                                       const std::vector<Point2>& interior_samples,
                                       const ControlMeshOptions& options) {
  if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
    return Status(StatusCode::kInvalidArgument, "BuildControlMesh: image size " + std::to_string(width) + "x" +
                                                    std::to_string(height) + " is out of range (1..65536)");
  if (!(options.rho >= 0 && options.rho < 1000) || !(options.min_distance > 0 && options.min_distance < 1000) ||
      !(options.min_angle_deg >= 0 && options.min_angle_deg <= 30) || !(options.max_edge >= 0) ||
      !(options.clearance > 0 && options.clearance < 1000))
    return Status(StatusCode::kInvalidArgument,
                  "BuildControlMesh: options out of range (rho >= 0, min_distance > 0, min_angle_deg in [0, 30], "
                  "max_edge >= 0, clearance > 0)");
  for (size_t i = 0; i < curves.size(); ++i) SDVI_RETURN_IF_ERROR(ValidateCurve(curves[i], i, width, height));
  for (const Point2& p : interior_samples)
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      return Status(StatusCode::kInvalidArgument, "BuildControlMesh: an interior sample is not finite");

  PlacedFeatures out;
  out.max_edge = options.max_edge > 0 ? options.max_edge
                                      : std::max(8.0, std::sqrt(double(width) * height) / 12.0);
  const double max_len = 0.7 * out.max_edge;
  const double clearance = options.clearance;
  SegmentGrid grid(width, height, std::max(4.0, std::min(32.0, out.max_edge)));
  auto place = [&](PlacedPolyline l) {
    const size_t m = l.points.size();
    const size_t segs = l.closed ? m : m - 1;
    for (size_t i = 0; i < segs; ++i) grid.Add(l.points[i], l.points[(i + 1) % m]);
    out.polylines.push_back(std::move(l));
    return uint32_t(out.polylines.size() - 1);
  };

  // Domain boundary.
  std::vector<size_t> boundary_idx;
  for (size_t i = 0; i < curves.size(); ++i)
    if (curves[i].boundary) boundary_idx.push_back(i);
  out.object_mode = !boundary_idx.empty();
  if (!out.object_mode) {
    PlacedPolyline rect;
    rect.closed = true;
    rect.boundary = true;
    const Point2 corner[4] = {{0, 0}, {double(width), 0}, {double(width), double(height)}, {0, double(height)}};
    for (int s = 0; s < 4; ++s) {
      Point2 a = corner[s], b = corner[(s + 1) % 4];
      int pieces = std::max(1, int(std::ceil(Dist(a, b) / max_len)));
      rect.corners.push_back(uint32_t(rect.points.size()));
      auto at = [&](int k) {
        const double t = double(k) / pieces;
        return Point2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
      };
      // With content blocks a split point is kept only next to a piece that meets a busy
      // block: along flat stretches the side stays one long edge.
      auto busy = [&](int k) {  // piece [k, k + 1]
        const Point2 p = at(k), q = at(k + 1);
        return options.content == nullptr ||
               options.content->AnyBusy(std::min(p.x, q.x), std::min(p.y, q.y), std::max(p.x, q.x),
                                        std::max(p.y, q.y));
      };
      for (int k = 0; k < pieces; ++k) {
        if (k == 0 || busy(k - 1) || busy(k)) rect.points.push_back(at(k));
      }
    }
    place(std::move(rect));
  } else {
    std::vector<PlacedPolyline> prepared;
    for (size_t i : boundary_idx) prepared.push_back(Prepare(curves[i], max_len));
    std::stable_sort(prepared.begin(), prepared.end(),
                     [](const PlacedPolyline& a, const PlacedPolyline& b) { return PolylineArea(a) > PolylineArea(b); });
    for (PlacedPolyline& l : prepared) {
      if (l.points.size() < 3) continue;
      // Kept whole or not at all: it may touch the frame, not a placed curve or itself.
      std::vector<bool> bad =
          BadSegments({&l}, grid, clearance, std::min(0.25, clearance), false, width, height, nullptr);
      if (std::find(bad.begin(), bad.end(), true) == bad.end()) place(std::move(l));
    }
    if (out.polylines.empty())
      return Status(StatusCode::kInvalidMesh, "BuildControlMesh: no boundary curve can bound the domain "
                                              "(all cross each other or themselves)");
  }
  const DomainTest object_domain(out.object_mode ? out.polylines : std::vector<PlacedPolyline>{}, height);
  const DomainTest* domain_test = out.object_mode ? &object_domain : nullptr;

  // Features, longest first.
  std::vector<size_t> order;
  for (size_t i = 0; i < curves.size(); ++i)
    if (!curves[i].boundary) order.push_back(i);
  std::vector<double> length(curves.size());
  for (size_t i : order) length[i] = Length(curves[i]);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return length[a] > length[b]; });
  // One feature: its polylines (LayoutOf) cut together; true when some segment was cut.
  auto place_feature = [&](const FeatureCurve& curve) {
    PlacedPolyline centre = Prepare(curve, max_len);
    if (centre.points.size() < (centre.closed ? 3u : 2u)) return false;
    const float sharpness = options.use_sharpness ? curve.sharpness : 0.0f;
    const FeatureLayout layout = LayoutOf(curve, options);
    double self_clearance = std::min(0.25, clearance);
    for (size_t k = 1; k < layout.offsets.size(); ++k)
      self_clearance = std::min(self_clearance, 0.4 * std::fabs(layout.offsets[k - 1] - layout.offsets[k]));
    std::vector<PlacedPolyline> lines;
    std::vector<bool> bad;
    auto test = [&] {
      lines.clear();
      for (std::vector<Point2>& points : OffsetPolygon(centre.points, centre.closed, layout.offsets)) {
        PlacedPolyline l = centre;
        l.points = std::move(points);
        lines.push_back(std::move(l));
      }
      std::vector<const PlacedPolyline*> ptrs;
      for (const PlacedPolyline& l : lines) ptrs.push_back(&l);
      bad = BadSegments(ptrs, grid, clearance, self_clearance, true, width, height, domain_test);
    };
    test();
    // Fine cuts: bad segments are split into pieces of at most 2 x clearance and tested
    // again, so that a crossing cuts out its neighbourhood, not whole polygon segments.
    std::vector<bool> inserted(centre.points.size(), false);
    if (options.fine_cuts && SplitSegments(centre, bad, 2 * clearance, &inserted)) test();
    // The pieces are kept where they end a run (next to a cut); inside a run the points
    // inserted on a straight segment are left out again: they add vertices, not shape.
    const int m = int(centre.points.size());
    const int segs = int(bad.size());
    auto emit = [&](int a, int b, bool closed) {  // points a..b (mod m)
      std::vector<uint32_t> ids;
      for (const PlacedPolyline& line : lines)
        ids.push_back(place(closed ? WithoutPoints(line, inserted) : SubPolyline(line, a, b, inserted)));
      for (const auto& [first, second] : layout.pairs) out.pairs.push_back({ids[first], ids[second], sharpness});
    };
    const bool any_bad = std::find(bad.begin(), bad.end(), true) != bad.end();
    if (!any_bad && centre.closed) {
      emit(0, m - 1, true);
      return false;
    }
    // Runs of good segments; a closed curve starts after its first bad segment.
    int start = 0;
    if (centre.closed) {
      while (!bad[start]) ++start;
      start += 1;
    }
    int run_begin = -1;
    for (int k = 0; k <= segs; ++k) {
      const bool good = k < segs && !bad[(start + k) % segs];
      if (good && run_begin < 0) run_begin = k;
      if (!good && run_begin >= 0) {
        const int run_segs = k - run_begin;
        if (run_segs >= 2 || (run_segs == 1 && !any_bad)) emit(start + run_begin, start + k, false);
        run_begin = -1;
      }
    }
    return any_bad;
  };
  for (size_t ci : order) {
    const FeatureCurve& curve = curves[ci];
    if (!place_feature(curve) || !(curve.width > 0) || !options.pairs) continue;
    // A thin structure cut somewhere: its two outlines, as features of their own, where
    // they still fit (beside a placed piece they do not: they lie on its polylines).
    const std::vector<std::vector<Point2>> outlines =
        OffsetPolygon(curve.points, curve.closed, {0.5 * curve.width, -0.5 * curve.width});
    for (const std::vector<Point2>& points : outlines) {
      FeatureCurve outline = curve;
      outline.points = points;
      outline.width = 0;
      place_feature(outline);
    }
  }

  // Interior samples: inside, clear of polylines, at least clearance apart.
  SegmentGrid sample_grid(width, height, std::max(4.0, 4 * clearance));
  for (const Point2& p : interior_samples) {
    bool inside = domain_test ? domain_test->Inside(p)
                              : (p.x > clearance && p.y > clearance && p.x < width - clearance &&
                                 p.y < height - clearance);
    if (!inside) continue;
    if (grid.Distance(p, p, clearance) < clearance) continue;
    if (sample_grid.Distance(p, p, clearance) < clearance) continue;
    sample_grid.Add(p, p);
    out.samples.push_back(p);
  }
  return out;
}

}  // namespace sdvi
