// SPDX-License-Identifier: GPL-3.0-or-later
// Feature placement: boundary, feature pairs, no crossings (rules in pairs.h).
#include "pairs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>

namespace sdvi {
namespace {

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
  // Adds segment (a, b), segment `segment` of placed polyline `polyline` (-1: none).
  void Add(Point2 a, Point2 b, int polyline = -1, int segment = -1) {
    int id = int(segs_.size());
    segs_.push_back({a, b});
    owners_.push_back({polyline, segment});
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
  // Ids of the placed segments in the cells within `reach` of segment (a, b), ascending.
  std::vector<int> Near(Point2 a, Point2 b, double reach) const {
    std::vector<int> ids;
    const_cast<SegmentGrid*>(this)->ForCells(a, b, reach, [&](std::vector<int>& c) {
      ids.insert(ids.end(), c.begin(), c.end());
    });
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
  }
  const std::vector<std::pair<Point2, Point2>>& segments() const { return segs_; }
  const std::pair<int, int>& owner(int id) const { return owners_[size_t(id)]; }

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
  std::vector<std::pair<int, int>> owners_;  // (polyline, segment) of each segment
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
    if (!pts.empty() && Distance(pts.back(), c.points[i]) < 1e-3) {
      corner.back() = corner.back() || is_corner[i];
      continue;
    }
    pts.push_back(c.points[i]);
    corner.push_back(is_corner[i]);
  }
  if (out.closed && pts.size() > 1 && Distance(pts.back(), pts.front()) < 1e-3) {
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
    int pieces = int(std::ceil(Distance(a, b) / max_len));
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
    const double len = Distance(a, b);
    return std::fabs((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / len > 0.01;
  };
  bool any = false;
  for (size_t i = 0; i < segs; ++i) {
    const Point2 a = l.points[i], b = l.points[(i + 1) % m];
    if (!split[i] || !(Distance(a, b) > max_len)) {
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
    const int pieces = int(std::ceil(Distance(a, b) / max_len));
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

// Junctions (rules in pairs.h): a candidate segment crossing a placed feature segment at
// kJunctionMinSin or more, kJunctionGap or more from every vertex and junction of both.
constexpr double kJunctionMinSin = 0.5;  // 30 degrees
constexpr double kJunctionGap = 0.25;    // px
constexpr double kTouch = 0.01;          // px: closer, a contact is never explained by a junction

// A point to insert into a placed polyline: on its segment `segment` (as placed), at
// parameter u along it.
struct Insertion {
  int segment;
  double u;
  Point2 at;
  int vertex = -1;  // >= 0: the junction is this existing vertex (made a corner), nothing inserted
};

// A crossing of candidate line `line` with placed polyline `polyline` that becomes a shared
// corner vertex `at`. On the candidate it is inserted on segment `segment` at parameter t, or
// it is the candidate's vertex `candidate_vertex` (moved onto `at`, at most kJunctionGap); on
// the placed polyline it is inserted on segment `placed_segment` at parameter u, or it is
// the placed vertex `vertex`.
struct Junction {
  int line, segment;
  double t;
  int polyline, placed_segment;
  double u;
  Point2 at;
  double radius;              // the neighbourhood where the two may come closer than the clearance
  int vertex = -1;            // placed vertex, or -1
  int candidate_vertex = -1;  // candidate vertex, or -1
  int other_segment = -1;     // the candidate vertex's other segment (-1: an open end)
};

// What junction tests read of the placed features.
struct JunctionContext {
  const std::vector<PlacedPolyline>* placed;
  const std::vector<std::vector<Insertion>>* pending;  // junctions already on each polyline
};

// The parts of segment (a, b) outside the disc (o, r).
std::vector<std::pair<Point2, Point2>> OutsideDisc(Point2 a, Point2 b, Point2 o, double r) {
  const double vx = b.x - a.x, vy = b.y - a.y, wx = a.x - o.x, wy = a.y - o.y;
  const double qa = vx * vx + vy * vy, qb = 2 * (vx * wx + vy * wy), qc = wx * wx + wy * wy - r * r;
  const double disc = qb * qb - 4 * qa * qc;
  if (qa <= 0 || disc <= 0) return {{a, b}};
  const double s1 = (-qb - std::sqrt(disc)) / (2 * qa), s2 = (-qb + std::sqrt(disc)) / (2 * qa);
  auto at = [&](double s) { return Point2{a.x + s * vx, a.y + s * vy}; };
  std::vector<std::pair<Point2, Point2>> parts;
  if (s1 > 0) parts.push_back({a, at(std::min(s1, 1.0))});
  if (s2 < 1) parts.push_back({at(std::max(s2, 0.0)), b});
  return parts;
}

// Distance between segments (a, b) and (c, d) with the disc (o, r) left out of either.
double DistanceOutsideDisc(Point2 a, Point2 b, Point2 c, Point2 d, Point2 o, double r) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [p, q] : OutsideDisc(a, b, o, r)) best = std::min(best, SegmentDistance(p, q, c, d));
  for (const auto& [p, q] : OutsideDisc(c, d, o, r)) best = std::min(best, SegmentDistance(a, b, p, q));
  return best;
}

// The junction of candidate segment `segment` (a, b) of line `l` with placed segment `id`,
// if their contact is one (rules above); `found` holds the candidate's junctions so far. A
// crossing within kJunctionGap of a vertex is that vertex: the placed polyline's (kept), or
// the candidate's (moved onto the placed segment), when the polylines pass through each
// other there (their neighbours on opposite sides) at kJunctionMinSin or more; a candidate's
// open end within kJunctionGap of a placed segment ends on it (a T).
std::optional<Junction> JunctionAt(const PlacedPolyline& l, int line, int segment, int id, const SegmentGrid& placed,
                                   const JunctionContext& context, const std::vector<Junction>& found,
                                   double clearance) {
  const auto [polyline, placed_segment] = placed.owner(id);
  if (polyline < 0 || (*context.placed)[size_t(polyline)].boundary) return std::nullopt;
  const PlacedPolyline& pl = (*context.placed)[size_t(polyline)];
  const int pm = int(pl.points.size()), m = int(l.points.size());
  const Point2 a = l.points[size_t(segment)], b = l.points[size_t(segment + 1) % size_t(m)];
  const auto& [c, d] = placed.segments()[size_t(id)];
  auto sin_between = [](Point2 p, Point2 q, Point2 r, Point2 s) {
    const double ux = q.x - p.x, uy = q.y - p.y, vx = s.x - r.x, vy = s.y - r.y;
    const double n = std::hypot(ux, uy) * std::hypot(vx, vy);
    return n > 0 ? std::fabs(ux * vy - uy * vx) / n : 0.0;
  };
  // Strictly on opposite sides of the line (p, q).
  auto apart = [](Point2 p, Point2 q, Point2 x, Point2 y) {
    const double cx = Cross(p, q, x), cy = Cross(p, q, y);
    return (cx > 0 && cy < 0) || (cx < 0 && cy > 0);
  };
  auto neighbours = [](const PlacedPolyline& pl, int i, Point2* before, Point2* after) {
    const int n = int(pl.points.size());
    if (!pl.closed && (i == 0 || i == n - 1)) return false;
    *before = pl.points[size_t((i + n - 1) % n)];
    *after = pl.points[size_t((i + 1) % n)];
    return true;
  };
  Junction j{line, segment, 0, polyline, placed_segment, 0, {}, 0};
  double sin_angle = sin_between(a, b, c, d);
  const bool near_a = PointSegmentDistance(a, c, d) < kJunctionGap, near_b = PointSegmentDistance(b, c, d) < kJunctionGap;
  const bool near_c = PointSegmentDistance(c, a, b) < kJunctionGap, near_d = PointSegmentDistance(d, a, b) < kJunctionGap;
  if (SegmentsCross(a, b, c, d) && !near_a && !near_b && !near_c && !near_d) {
    const double rx = b.x - a.x, ry = b.y - a.y, qx = d.x - c.x, qy = d.y - c.y, den = rx * qy - ry * qx;
    j.t = ((c.x - a.x) * qy - (c.y - a.y) * qx) / den;
    j.u = ((c.x - a.x) * ry - (c.y - a.y) * rx) / den;
    j.at = {a.x + j.t * rx, a.y + j.t * ry};
  } else if ((near_a || near_b) != (near_c || near_d)) {
    if (near_c || near_d) {  // a placed vertex on the candidate segment
      const int vi = (placed_segment + (near_d ? 1 : 0)) % pm;
      Point2 before, after;
      if (!neighbours(pl, vi, &before, &after) || !apart(a, b, before, after)) return std::nullopt;
      j.vertex = vi;
      j.at = pl.points[size_t(vi)];
      const double rl2 = (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y);
      j.t = ((j.at.x - a.x) * (b.x - a.x) + (j.at.y - a.y) * (b.y - a.y)) / rl2;
      sin_angle = std::min(sin_between(a, b, before, j.at), sin_between(a, b, j.at, after));
    } else {  // a candidate vertex on the placed segment: moved onto it
      const int wi = (segment + (near_b ? 1 : 0)) % m;
      const Point2 w = l.points[size_t(wi)];
      Point2 before, after;
      if (neighbours(l, wi, &before, &after)) {
        if (!apart(c, d, before, after)) return std::nullopt;
        sin_angle = std::min(sin_between(c, d, before, w), sin_between(c, d, w, after));
        j.other_segment = near_b ? (segment + 1) % m : (segment + m - 1) % m;
        if (!l.closed && j.other_segment >= m - 1) return std::nullopt;
      }
      const double ql2 = (d.x - c.x) * (d.x - c.x) + (d.y - c.y) * (d.y - c.y);
      j.u = std::clamp(((w.x - c.x) * (d.x - c.x) + (w.y - c.y) * (d.y - c.y)) / ql2, 0.0, 1.0);
      j.at = {c.x + j.u * (d.x - c.x), c.y + j.u * (d.y - c.y)};
      j.candidate_vertex = wi;
      j.t = near_b ? 1 : 0;
    }
  } else if (near_a || near_b) {  // a vertex of each, together: the placed one
    const int wi = (segment + (near_b ? 1 : 0)) % m, vi = (placed_segment + (near_d ? 1 : 0)) % pm;
    const Point2 w = l.points[size_t(wi)], v = pl.points[size_t(vi)];
    Point2 lb, la, pb, pa;
    if (Distance(w, v) >= kJunctionGap || !neighbours(pl, vi, &pb, &pa)) return std::nullopt;
    if (neighbours(l, wi, &lb, &la)) {
      if (!apart(pb, pa, lb, la) || !apart(lb, la, pb, pa)) return std::nullopt;
      sin_angle = std::min({sin_between(lb, w, pb, v), sin_between(lb, w, v, pa), sin_between(w, la, pb, v),
                            sin_between(w, la, v, pa)});
      j.other_segment = near_b ? (segment + 1) % m : (segment + m - 1) % m;
      if (!l.closed && j.other_segment >= m - 1) return std::nullopt;
    } else {
      sin_angle = std::min(sin_between(a, b, pb, v), sin_between(a, b, v, pa));
    }
    j.vertex = vi;
    j.candidate_vertex = wi;
    j.at = v;
    j.t = near_b ? 1 : 0;
  } else {
    return std::nullopt;
  }
  if (!(sin_angle >= kJunctionMinSin)) return std::nullopt;
  if (j.candidate_vertex < 0 && (Distance(j.at, a) < kJunctionGap || Distance(j.at, b) < kJunctionGap)) return std::nullopt;
  if (j.vertex < 0 && (Distance(j.at, c) < kJunctionGap || Distance(j.at, d) < kJunctionGap)) return std::nullopt;
  for (const Insertion& k : (*context.pending)[size_t(polyline)])
    if (Distance(j.at, k.at) < kJunctionGap) return std::nullopt;
  for (const Junction& k : found)
    if ((k.line == line || k.polyline == polyline) && Distance(j.at, k.at) < kJunctionGap) return std::nullopt;
  j.radius = 1.5 * clearance / sin_angle;
  return j;
}

// Tags segments of a candidate (one or two polylines with equal segment count) that
// conflict with placed segments, with each other, or leave the domain.
// check_domain: also tag segments whose end points leave the domain (the frame shrunk by
// the clearance, or the inside of the boundary polylines when given).
// With a junction context, crossings of placed features may become junctions (*junctions:
// those whose segment stays good); every other contact closer than the clearance is a
// conflict unless a junction of the same candidate line and placed polyline explains it (the
// two are clear of each other outside the junction's radius), and a segment explained only
// by junctions on cut segments is cut too.
std::vector<bool> BadSegments(const std::vector<const PlacedPolyline*>& lines, const SegmentGrid& placed,
                              double clearance, double self_clearance, bool check_domain, int width,
                              int height, const DomainTest* domain, const JunctionContext* context = nullptr,
                              std::vector<Junction>* junctions = nullptr) {
  const PlacedPolyline& first = *lines[0];
  const int m = int(first.points.size());
  const int segs = first.closed ? m : m - 1;
  std::vector<bool> bad(std::max(segs, 0), false);
  struct Contact {
    int line, segment, placed_id;
    std::vector<size_t> junctions;  // the junctions that explain it
  };
  std::vector<Contact> contacts;
  if (junctions != nullptr) junctions->clear();
  for (const PlacedPolyline* const& l : lines) {
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
      if (context == nullptr) {
        if (placed.Distance(a, b, clearance) < clearance) bad[i] = true;
        continue;
      }
      const int line = int(&l - &lines[0]);
      for (int id : placed.Near(a, b, clearance)) {
        const auto& [c, d] = placed.segments()[size_t(id)];
        if (SegmentDistance(a, b, c, d) >= clearance) continue;
        if (auto j = JunctionAt(*l, line, i, id, placed, *context, *junctions, clearance)) {
          junctions->push_back(*j);
        } else {
          contacts.push_back({line, i, id, {}});
        }
      }
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
  for (int id = 0; id < total; ++id) mean_length += Distance(segment(id).first, segment(id).second);
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
      if (Distance(a, b) >= 0.01) continue;
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
      cumulative[l][size_t(i) + 1] = cumulative[l][size_t(i)] + Distance(a, b);
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
  if (context == nullptr) return bad;
  // Contacts explained by junctions; then, until nothing changes, a contact whose junctions
  // all lie on cut segments is a conflict, and so is a run of one segment (never emitted
  // when some segment is cut).
  for (Contact& k : contacts) {
    const auto& p = lines[size_t(k.line)]->points;
    const Point2 a = p[size_t(k.segment)], b = p[size_t(k.segment + 1) % size_t(m)];
    const auto& [c, d] = placed.segments()[size_t(k.placed_id)];
    const int polyline = placed.owner(k.placed_id).first;
    const int placed_segment = placed.owner(k.placed_id).second;
    const int pm = int((*context->placed)[size_t(polyline)].points.size());
    const bool touching = SegmentDistance(a, b, c, d) < kTouch;
    for (size_t j = 0; j < junctions->size(); ++j) {
      const Junction& x = (*junctions)[j];
      if (x.line != k.line || x.polyline != polyline) continue;
      // A junction at a vertex of this placed segment explains its touching the candidate.
      const bool at_end = (x.vertex >= 0 && (x.vertex == placed_segment || x.vertex == (placed_segment + 1) % pm)) ||
                          (x.candidate_vertex >= 0 &&
                           (x.candidate_vertex == k.segment || x.candidate_vertex == (k.segment + 1) % m));
      // Touching is explained only where the junction lies on the candidate segment: a
      // segment beside it that comes back onto the placed one crosses it a second time.
      const double from_candidate = PointSegmentDistance(x.at, a, b);
      if ((!touching || (at_end && from_candidate < kTouch)) && from_candidate < x.radius &&
          DistanceOutsideDisc(a, b, c, d, x.at, x.radius) >= clearance)
        k.junctions.push_back(j);
    }
    if (k.junctions.empty()) bad[size_t(k.segment)] = true;
  }
  auto dead = [&](const Junction& j) {
    return bad[size_t(j.segment)] && (j.other_segment < 0 || bad[size_t(j.other_segment)]);
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (const Contact& k : contacts) {
      if (bad[size_t(k.segment)]) continue;
      if (std::all_of(k.junctions.begin(), k.junctions.end(), [&](size_t j) { return dead((*junctions)[j]); })) {
        bad[size_t(k.segment)] = true;
        changed = true;
      }
    }
    if (std::find(bad.begin(), bad.end(), true) == bad.end()) break;
    for (int i = 0; i < segs; ++i) {
      if (bad[size_t(i)]) continue;
      const bool before = first.closed ? bad[size_t((i + segs - 1) % segs)] : (i == 0 || bad[size_t(i - 1)]);
      const bool after = first.closed ? bad[size_t((i + 1) % segs)] : (i + 1 == segs || bad[size_t(i + 1)]);
      if (before && after) {
        bad[size_t(i)] = true;
        changed = true;
      }
    }
  }
  junctions->erase(std::remove_if(junctions->begin(), junctions->end(), dead), junctions->end());
  return bad;
}

// The part of candidate line `line` to place: points a..b (indices mod m; closed: the
// whole closed polyline, a and b unused), leaving out the points strictly inside marked in
// `skip` (never corners), keeping the corners strictly inside (closed: all), and with the
// line's junctions inserted on their segments as corners; each junction is also queued
// for insertion into the placed polyline it crosses (*pending).
PlacedPolyline Emitted(const PlacedPolyline& l, int line, int a, int b, bool closed, const std::vector<bool>& skip,
                       const std::vector<Junction>& junctions, std::vector<std::vector<Insertion>>* pending) {
  PlacedPolyline out;
  out.closed = closed;
  out.boundary = l.boundary;
  const int m = int(l.points.size());
  std::vector<bool> corner(size_t(m), false);
  for (uint32_t c : l.corners) corner[c] = true;
  std::vector<const Junction*> on;
  for (const Junction& j : junctions)
    if (j.line == line) on.push_back(&j);
  std::sort(on.begin(), on.end(), [](const Junction* x, const Junction* y) {
    return x->segment != y->segment ? x->segment < y->segment : x->t < y->t;
  });
  const int first = closed ? 0 : a, last = closed ? m - 1 : b;
  for (int k = first; k <= last; ++k) {
    const int i = k % m;
    const bool end = !closed && (k == a || k == b);
    const Junction* at_vertex = nullptr;
    for (const Junction* j : on)
      if (j->candidate_vertex == i) at_vertex = j;
    if (at_vertex != nullptr) {
      if (!end) out.corners.push_back(uint32_t(out.points.size()));
      out.points.push_back(at_vertex->at);
      (*pending)[size_t(at_vertex->polyline)].push_back(
          {at_vertex->placed_segment, at_vertex->u, at_vertex->at, at_vertex->vertex});
    } else if (end || !skip[size_t(i)]) {
      if (corner[size_t(i)] && !end) out.corners.push_back(uint32_t(out.points.size()));
      out.points.push_back(l.points[size_t(i)]);
    }
    if (!closed && k == b) break;
    for (const Junction* j : on) {
      if (j->segment != i || j->candidate_vertex >= 0) continue;
      out.corners.push_back(uint32_t(out.points.size()));
      out.points.push_back(j->at);
      (*pending)[size_t(j->polyline)].push_back({j->placed_segment, j->u, j->at, j->vertex});
    }
  }
  return out;
}

// Inserts the queued junctions into a placed polyline, as corners, in order along each segment.
void InsertJunctions(PlacedPolyline& l, std::vector<Insertion> insertions) {
  std::sort(insertions.begin(), insertions.end(), [](const Insertion& x, const Insertion& y) {
    return x.segment != y.segment ? x.segment < y.segment : x.u < y.u;
  });
  const size_t m = l.points.size();
  std::vector<bool> corner(m, false);
  for (uint32_t c : l.corners) corner[c] = true;
  for (const Insertion& k : insertions)
    if (k.vertex >= 0) corner[size_t(k.vertex)] = true;
  PlacedPolyline out;
  out.closed = l.closed;
  out.boundary = l.boundary;
  size_t next = 0;
  for (size_t i = 0; i < m; ++i) {
    if (corner[i]) out.corners.push_back(uint32_t(out.points.size()));
    out.points.push_back(l.points[i]);
    for (; next < insertions.size() && insertions[next].segment == int(i); ++next) {
      if (insertions[next].vertex >= 0) continue;
      out.corners.push_back(uint32_t(out.points.size()));
      out.points.push_back(insertions[next].at);
    }
  }
  l = std::move(out);
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
  for (size_t i = 1; i < c.points.size(); ++i) len += Distance(c.points[i - 1], c.points[i]);
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

// Removes from the centre polygon every point where one of its offset polylines would turn
// back along itself: the segment after the point runs back over the one before it (within
// 1e-3 of its length from its line). Those two overlapping segments could not both be
// constraints of the triangulation. It happens where a sharp corner is followed by steps
// shorter than the offset's shift along them (the mitred corner point of the inner side
// lies beyond the next point). The point is removed from the centre, so from every offset
// polyline at once: the polylines of a feature keep corresponding vertex by vertex.
// *inserted (parallel to the points) and the corner tags follow the removal.
void DropSpikes(PlacedPolyline* centre, const std::vector<double>& offsets, std::vector<bool>* inserted) {
  std::vector<Point2>& pts = centre->points;
  std::vector<bool> corner(pts.size(), false);
  for (uint32_t c : centre->corners) corner[c] = true;
  bool dropped = false;
  while (pts.size() > (centre->closed ? 3u : 2u)) {
    const size_t m = pts.size();
    size_t tip = m;
    for (const std::vector<Point2>& line : OffsetPolygon(pts, centre->closed, offsets)) {
      for (size_t i = centre->closed ? 0 : 1; i < (centre->closed ? m : m - 1) && i < tip; ++i) {
        const Point2 a = line[(i + m - 1) % m], b = line[i], c = line[(i + 1) % m];
        const bool back = (b.x - a.x) * (c.x - b.x) + (b.y - a.y) * (c.y - b.y) < 0;
        if (back && std::abs(Cross(a, b, c)) < 1e-3 * std::max(Distance(a, b), Distance(b, c))) tip = i;
      }
    }
    if (tip == m) break;
    pts.erase(pts.begin() + std::ptrdiff_t(tip));
    corner.erase(corner.begin() + std::ptrdiff_t(tip));
    inserted->erase(inserted->begin() + std::ptrdiff_t(tip));
    dropped = true;
  }
  if (!dropped) return;
  centre->corners.clear();
  for (size_t i = 0; i < corner.size(); ++i)
    if (corner[i]) centre->corners.push_back(uint32_t(i));
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
  std::vector<std::vector<Insertion>> pending;  // junctions to insert into each placed polyline
  auto place = [&](PlacedPolyline l) {
    const size_t m = l.points.size();
    const size_t segs = l.closed ? m : m - 1;
    const int k = int(out.polylines.size());
    for (size_t i = 0; i < segs; ++i) grid.Add(l.points[i], l.points[(i + 1) % m], k, int(i));
    out.polylines.push_back(std::move(l));
    pending.emplace_back();
    return uint32_t(k);
  };
  const JunctionContext junction_context{&out.polylines, &pending};

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
      int pieces = std::max(1, int(std::ceil(Distance(a, b) / max_len)));
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
    std::vector<Junction> junctions;
    std::vector<bool> inserted(centre.points.size(), false);  // points added by the fine cuts
    auto test = [&] {
      DropSpikes(&centre, layout.offsets, &inserted);
      lines.clear();
      for (std::vector<Point2>& points : OffsetPolygon(centre.points, centre.closed, layout.offsets)) {
        PlacedPolyline l = centre;
        l.points = std::move(points);
        lines.push_back(std::move(l));
      }
      std::vector<const PlacedPolyline*> ptrs;
      for (const PlacedPolyline& l : lines) ptrs.push_back(&l);
      bad = BadSegments(ptrs, grid, clearance, self_clearance, true, width, height, domain_test,
                        options.junctions ? &junction_context : nullptr, &junctions);
    };
    test();
    // Fine cuts: bad segments are split into pieces of at most 2 x clearance and tested
    // again, so that a crossing cuts out its neighbourhood, not whole polygon segments.
    if (options.fine_cuts && SplitSegments(centre, bad, 2 * clearance, &inserted)) test();
    // The pieces are kept where they end a run (next to a cut); inside a run the points
    // inserted on a straight segment are left out again: they add vertices, not shape.
    const int m = int(centre.points.size());
    const int segs = int(bad.size());
    auto emit = [&](int a, int b, bool closed) {  // points a..b (mod m)
      std::vector<uint32_t> ids;
      for (size_t li = 0; li < lines.size(); ++li)
        ids.push_back(place(Emitted(lines[li], int(li), a, b, closed, inserted, junctions, &pending)));
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

  for (size_t k = 0; k < out.polylines.size(); ++k)
    if (!pending[k].empty()) InsertJunctions(out.polylines[k], std::move(pending[k]));

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
