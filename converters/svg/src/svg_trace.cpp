// SPDX-License-Identifier: GPL-3.0-or-later
// TraceSvgGeometry: librsvg renders into a cairo script surface (cairo 1.16, ASCII mode);
// the script it writes lists every path in device space followed by the operator that
// used it. This file reads back the few operators that carry geometry:
//   n                      new path          x y m / x y l / x1 y1 x2 y2 x3 y3 c / h
//   x y w h rectangle      a closed box      fill[+] stroke[+] clip[+]   the painting
//   //LINE_CAP_x set-line-cap (the stroke's cap),
//   w set-line-width, [a b c d e f] | identity set-matrix, sx sy scale, [...] transform:
//                          the stroke width in device pixels = width x sqrt(|det CTM|);
//                          the CTM's smaller singular value bounds the dash estimate
//   context ... pop, save ... restore: graphics-state scopes. Between linear / radial /
//   pattern / mesh and the set-source that consumes it, set-matrix is the pattern's.
//   w h //CONTENT similar dup /NAME exch def context ... pop: a surface drawn apart (group
//   opacity, masks, pattern tiles), in device space. NAME pattern [matrix] set-matrix ...
//   //EXTEND_REPEAT set-extend set-source: a tiled pattern (an SVG <pattern>): the tile's
//   shapes are in tile space, not where they are seen, so they are dropped; a fill painted
//   with the pattern gets copies of them in device space, one per tile over the fill,
//   placed by the pattern's matrix (device -> tile) and clipped to their tile, the tiles'
//   fills chained into lines across the tiles (SvgShape::tiled; spec/SVG.md section 1,
//   "Patterns").
// Text: librsvg 2.54 fills the glyphs' outlines (m l c h fill), which are read like any
// path. show-glyphs / show-text-glyphs (text drawn from a font, its outlines not in the
// script) are only counted: the artwork mode then says the result is approximate.
// Everything else (sources, patterns, image data, dictionaries) is skipped token by token:
// strings (...) with escapes, base85 data <~ ... ~> and <| ... ~>, hex <...>, comments.
#include <cairo-script.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <cstdlib>
#include <string>
#include <vector>

#include "svg_internal.h"
#include "svg_rsvg.h"

namespace sdvi {
namespace {

// cairo 1.16's script surface refuses the fill of a path made only of horizontal and
// vertical lines that is not a set of boxes (an L- or T-shaped polygon, straight-edged
// glyphs such as "Hi") with INVALID_PATH_DATA, and then every later operation. A trace that
// stops with an error is made again with the drawing turned by this angle (radians) about
// the origin, and its shapes turned back: turned, no path with an edge of 0.4 px or more is
// rectilinear (the script's coordinates have 1/256 px steps; the shapes come back within
// 0.003 px). Rotation keeps lengths, so stroke widths (sqrt |det| of the CTM) are unchanged.
constexpr double kTraceTurn = 0.01;

// Pattern tiles copied over a fill (spec/SVG.md section 1, "Patterns"): at most this many
// points and this many px of outline (control polygons) in all copies of one trace, and
// tiles at least kMinTile px across; beyond these a pattern is left to the artwork mode's
// edge detection (SvgGeometry::patterns_not_copied).
constexpr double kMaxTilePoints = 1e6;
constexpr double kMaxTileLength = 5e5;
constexpr double kMinTile = 2.0;

// One cubic segment: start, two controls, end.
using Segment = std::array<Point2, 4>;

// A tile's segment is kept when its middle lies in the tile grown by this (tile px).
constexpr double kTileMargin = 0.01;
// At a junction of tile edges a line goes on through the edge turning least, when it
// turns by less than this (degrees): lines cross as the tiles' edges do.
constexpr double kStraightDeg = 30;

Point2 CubicMiddle(const Point2* q) {
  return {(q[0].x + 3 * q[1].x + 3 * q[2].x + q[3].x) / 8, (q[0].y + 3 * q[1].y + 3 * q[2].y + q[3].y) / 8};
}

// Direction leaving q[0] (towards the first control distinct from it).
Point2 Leaving(const Segment& q) {
  for (int k = 1; k <= 3; ++k) {
    const Point2 d{q[k].x - q[0].x, q[k].y - q[0].y};
    if (std::hypot(d.x, d.y) > 1e-9) return d;
  }
  return {0, 0};
}

Segment Reversed(const Segment& q) { return {q[3], q[2], q[1], q[0]}; }

double TurnDeg(Point2 a, Point2 b) {
  const double na = std::hypot(a.x, a.y), nb = std::hypot(b.x, b.y);
  if (!(na > 0) || !(nb > 0)) return 180;
  const double c = std::clamp((a.x * b.x + a.y * b.y) / (na * nb), -1.0, 1.0);
  return std::acos(c) * 180 / 3.14159265358979323846;
}

// The edges of a pattern's tiles over a fill as lines (spec/SVG.md section 1, "Patterns"):
// the segments of every copy's fills, each drawn once (a segment and its reverse, ends
// and controls on a 1/64 px grid, are one), chained end to end: through a point where two
// segments meet, and through a junction of more along the pair that turns least when it
// turns by under kStraightDeg. A chain either crosses junctions or turns corners (by
// kStraightDeg or more), never both, so it never crosses itself; one ending where it began
// is closed. Adjacent tiles' shared sides and a grid's lines thus become single outlines
// that cross at junctions, not squares cut around each other. The order is that of the
// segments.
std::vector<SvgOutline> ChainSegments(std::vector<Segment> segments) {
  using Key = std::pair<int64_t, int64_t>;
  auto key = [](Point2 p) { return Key{std::llround(p.x * 64), std::llround(p.y * 64)}; };
  // Drawn once.
  std::map<std::array<int64_t, 8>, size_t> seen;
  std::vector<Segment> unique;
  for (const Segment& q : segments) {
    std::array<int64_t, 8> a, b;
    for (int k = 0; k < 4; ++k) {
      const Key f = key(q[k]), r = key(q[3 - k]);
      a[2 * k] = f.first, a[2 * k + 1] = f.second, b[2 * k] = r.first, b[2 * k + 1] = r.second;
    }
    if (key(q[0]) == key(q[3]) && key(q[1]) == key(q[0]) && key(q[2]) == key(q[0])) continue;  // a point
    if (seen.emplace(std::min(a, b), unique.size()).second) unique.push_back(q);
  }
  // The segments at each end point: (segment, 0 = starts there, 1 = ends there).
  std::map<Key, std::vector<std::pair<size_t, int>>> at;
  for (size_t s = 0; s < unique.size(); ++s) {
    at[key(unique[s][0])].push_back({s, 0});
    at[key(unique[s][3])].push_back({s, 1});
  }
  std::vector<uint8_t> used(unique.size(), 0);
  // The chain being made: its segments, whether it crossed a junction or turned a corner,
  // whether it may turn.
  std::vector<size_t> taken;
  bool crossed = false, turned = false, may_turn = false;
  // The segment that goes on from the end of q (oriented), or false.
  auto next = [&](const Segment& q, Segment* out) {
    const std::vector<std::pair<size_t, int>>& here = at[key(q[3])];
    const Point2 back = Leaving(Reversed(q));
    const Point2 dir{-back.x, -back.y};  // arriving at q[3]
    double best = 1e9;
    size_t pick = 0;
    Segment oriented{};
    for (const auto& [s, end] : here) {
      if (used[s]) continue;
      const Segment o = end == 0 ? unique[s] : Reversed(unique[s]);
      const double turn = TurnDeg(dir, Leaving(o));
      if (turn < best) best = turn, pick = s, oriented = o;
    }
    if (best > 180 || (here.size() > 2 && best >= kStraightDeg)) return false;
    if (here.size() > 2) {
      if (turned) return false;
      crossed = true;
    } else if (best >= kStraightDeg) {
      if (crossed || !may_turn) return false;
      turned = true;
    }
    used[pick] = 1;
    taken.push_back(pick);
    *out = oriented;
    return true;
  };
  // First the lines that cross junctions, then what is left, turning corners: a grid's
  // lines run from border to border, its border comes in pieces.
  std::vector<SvgOutline> out;
  for (const bool turns : {false, true}) {
    for (size_t s = 0; s < unique.size(); ++s) {
      if (used[s]) continue;
      used[s] = 1;
      taken = {s};
      crossed = turned = false;
      may_turn = turns;
      std::vector<Segment> forward{unique[s]}, backward;
      Segment q;
      while (next(forward.back(), &q)) forward.push_back(q);
      if (key(forward.back()[3]) != key(forward.front()[0])) {
        Segment b = Reversed(unique[s]);
        while (next(b, &q)) backward.push_back(b = q);
      }
      if (!turns && !crossed) {
        for (size_t t : taken) used[t] = 0;
        continue;
      }
      SvgOutline o;
      for (auto it = backward.rbegin(); it != backward.rend(); ++it) {
        const Segment r = Reversed(*it);
        if (o.points.empty()) o.points.push_back(r[0]);
        o.points.insert(o.points.end(), r.begin() + 1, r.end());
      }
      for (const Segment& f : forward) {
        if (o.points.empty()) o.points.push_back(f[0]);
        o.points.insert(o.points.end(), f.begin() + 1, f.end());
      }
      o.closed = backward.empty() && forward.size() > 1 && key(forward.back()[3]) == key(forward.front()[0]);
      out.push_back(std::move(o));
    }
  }
  return out;
}

struct GraphicsState {
  double line_width = 2.0;  // cairo's default
  SvgLineCap line_cap = SvgLineCap::kButt;  // cairo's default
  double det = 1.0;         // |det| of the CTM
  // The CTM's linear part in cairo's order (xx, yx, xy, yy): x' = xx x + xy y, y' = yx x + yy y.
  std::array<double, 4> linear{1, 0, 0, 1};
  // The source, when it is a repeated pattern: its tile surface and the pattern's matrix
  // (device -> tile space; cairo hands patterns to the script surface in device space).
  std::string tiled;
  std::array<double, 6> tile_matrix{1, 0, 0, 1, 0, 0};
};

// p through the cairo matrix m: (m0 x + m2 y + m4, m1 x + m3 y + m5).
Point2 Apply(const std::array<double, 6>& m, Point2 p) {
  return {m[0] * p.x + m[2] * p.y + m[4], m[1] * p.x + m[3] * p.y + m[5]};
}

// The smaller singular value of m's linear part: the fewest output units a user unit
// becomes in any direction (0 for a singular m).
double SmallestScale(double xx, double yx, double xy, double yy) {
  const double sum = xx * xx + yx * yx + xy * xy + yy * yy;
  const double det = xx * yy - yx * xy;
  const double root = std::sqrt(std::max(0.0, sum * sum - 4 * det * det));
  return std::sqrt(std::max(0.0, (sum - root) / 2));
}

// The linear part of m first, then c (cairo_transform and cairo_scale: the CTM c becomes c m).
std::array<double, 4> AfterLinear(const std::array<double, 4>& c, double m0, double m1, double m2, double m3) {
  return {c[0] * m0 + c[2] * m1, c[1] * m0 + c[3] * m1, c[0] * m2 + c[2] * m3, c[1] * m2 + c[3] * m3};
}

// The inverse of m; false when it is singular.
bool Invert(const std::array<double, 6>& m, std::array<double, 6>* out) {
  const double det = m[0] * m[3] - m[1] * m[2];
  if (!std::isfinite(det) || std::abs(det) < 1e-12) return false;
  const double a = m[3] / det, b = -m[1] / det, c = -m[2] / det, d = m[0] / det;
  *out = {a, b, c, d, -(a * m[4] + c * m[5]), -(b * m[4] + d * m[5])};
  return true;
}

class ScriptReader {
 public:
  // width x height: the surface the script draws (0: unknown, tiles are copied over a
  // fill's whole extent).
  ScriptReader(const std::string& text, int width, int height) : s_(text), width_(width), height_(height) {}

  size_t glyph_runs() const { return glyph_runs_; }
  size_t patterns_not_copied() const { return patterns_not_copied_; }

  std::vector<SvgShape> Read() {
    std::string token;
    while (Next(&token)) Handle(token);
    std::vector<SvgShape> kept;
    for (size_t k = 0; k < shapes_.size(); ++k) {
      if (!dropped_[k]) kept.push_back(std::move(shapes_[k]));
    }
    return kept;
  }

 private:
  bool IsSpace(char c) const { return c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == '\f'; }

  void SkipUntil(const char* end) {
    const size_t k = s_.find(end, i_);
    i_ = k == std::string::npos ? s_.size() : k + std::string(end).size();
  }

  // The next token that matters, or false at the end. Data and strings are skipped here.
  bool Next(std::string* token) {
    for (;;) {
      while (i_ < s_.size() && IsSpace(s_[i_])) ++i_;
      if (i_ >= s_.size()) return false;
      const char c = s_[i_];
      if (c == '%') {
        SkipUntil("\n");
        continue;
      }
      if (c == '(') {
        int level = 0;
        while (i_ < s_.size()) {
          const char d = s_[i_++];
          if (d == '\\') {
            ++i_;
          } else if (d == '(') {
            ++level;
          } else if (d == ')' && --level == 0) {
            break;
          }
        }
        *token = "(string)";
        return true;
      }
      if (c == '<') {
        if (i_ + 1 < s_.size() && (s_[i_ + 1] == '~' || s_[i_ + 1] == '|')) {
          SkipUntil("~>");
          *token = "(data)";
          return true;
        }
        if (i_ + 1 < s_.size() && s_[i_ + 1] == '<') {
          i_ += 2;
          *token = "<<";
          return true;
        }
        SkipUntil(">");
        *token = "(data)";
        return true;
      }
      if (c == '[' || c == ']' || c == '{' || c == '}') {
        ++i_;
        *token = std::string(1, c);
        return true;
      }
      const size_t start = i_;
      while (i_ < s_.size() && !IsSpace(s_[i_]) && s_[i_] != '[' && s_[i_] != ']' && s_[i_] != '{' &&
             s_[i_] != '}' && s_[i_] != '(' && s_[i_] != '<' && s_[i_] != '%') {
        ++i_;
      }
      if (i_ == start) {  // a lone '>' or similar
        ++i_;
        continue;
      }
      *token = s_.substr(start, i_ - start);
      return true;
    }
  }

  static bool ParseNumber(const std::string& t, double* v) {
    const char c = t[0];
    if (!((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.')) return false;
    char* end = nullptr;
    *v = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() && std::isfinite(*v);
  }

  bool Take(size_t n, double* out) {
    if (numbers_.size() < n) return false;
    for (size_t k = 0; k < n; ++k) out[k] = numbers_[numbers_.size() - n + k];
    return true;
  }

  SvgOutline* Current() { return path_.empty() ? nullptr : &path_.back(); }

  void LineTo(double x, double y) {
    SvgOutline* o = Current();
    if (o == nullptr) return;
    const Point2 a = o->points.back();
    o->points.push_back({a.x + (x - a.x) / 3, a.y + (y - a.y) / 3});
    o->points.push_back({a.x + 2 * (x - a.x) / 3, a.y + 2 * (y - a.y) / 3});
    o->points.push_back({x, y});
  }

  void Paint(SvgPaint paint) {
    SvgShape shape;
    shape.paint = paint;
    const GraphicsState& g = states_.back();
    shape.scale = std::sqrt(g.det);
    shape.min_scale = SmallestScale(g.linear[0], g.linear[1], g.linear[2], g.linear[3]);
    shape.stroke_width = paint == SvgPaint::kStroke ? g.line_width * shape.scale : 0;
    shape.line_cap = g.line_cap;
    for (const SvgOutline& o : path_) {
      if (o.points.size() >= 4) shape.outlines.push_back(o);
    }
    if (shape.outlines.empty()) return;
    shapes_.push_back(std::move(shape));
    dropped_.push_back(0);
  }

  // A surface drawn apart: its shapes [begin, end) in shapes_, its size in pixels.
  struct Surface {
    size_t begin = 0, end = 0;
    bool open = true;
    double width = 0, height = 0;
    // Its own shapes, set when it is first used as a tile: those not dropped as a nested
    // pattern's tile, not copies of one (a nested pattern is not copied again).
    std::vector<size_t> own;
    bool nested = false;
    bool tile = false;
  };

  // The fill just painted (the last shape) with the repeated pattern g.tiled: copies of the
  // tile's shapes, one per tile that meets the fill's extent (its control points' box,
  // within the surface grown by 2 px), each clipped to its tile; the copies' fills chained
  // into lines (ChainSegments), their strokes and clips as they are, all placed before the
  // fill in painting order so that the artwork mode (top-most first) visits the fill's own
  // outline first. Tiles from a pattern within the tile (a nested pattern) are not copied
  // again.
  void CopyTiles(const GraphicsState& g) {
    const auto it = surfaces_.find(g.tiled);
    std::array<double, 6> to_device;
    if (it == surfaces_.end() || shapes_.empty() || !Invert(g.tile_matrix, &to_device)) return;
    const Surface& tile = it->second;
    const double tw = tile.width, th = tile.height;
    const std::vector<size_t>& sources = tile.own;
    double points = 0, length = 0;
    for (size_t k : sources) {
      for (const SvgOutline& o : shapes_[k].outlines) {
        points += double(o.points.size());
        for (size_t i = 1; i < o.points.size(); ++i) {
          const Point2 a = Apply(to_device, o.points[i - 1]), b = Apply(to_device, o.points[i]);
          length += std::hypot(b.x - a.x, b.y - a.y);
        }
      }
    }
    if (tile.nested) ++patterns_not_copied_;
    if (sources.empty()) return;
    // The tile's sides in device space.
    const double side_x = std::hypot(to_device[0], to_device[1]) * tw;
    const double side_y = std::hypot(to_device[2], to_device[3]) * th;
    const SvgShape& fill = shapes_.back();
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const SvgOutline& o : fill.outlines) {
      for (const Point2& p : o.points) {
        x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
      }
    }
    if (width_ > 0 && height_ > 0) {
      x0 = std::max(x0, -2.0), y0 = std::max(y0, -2.0);
      x1 = std::min(x1, width_ + 2.0), y1 = std::min(y1, height_ + 2.0);
    }
    if (!(x0 <= x1 && y0 <= y1)) return;
    if (!(tw > 0 && th > 0 && side_x >= kMinTile && side_y >= kMinTile)) {
      ++patterns_not_copied_;
      return;
    }
    // The tiles (i, j) that meet the box, from its corners in tile space.
    double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300;
    for (const Point2& c : {Point2{x0, y0}, Point2{x1, y0}, Point2{x0, y1}, Point2{x1, y1}}) {
      const Point2 q = Apply(g.tile_matrix, c);
      u0 = std::min(u0, q.x / tw), u1 = std::max(u1, q.x / tw), v0 = std::min(v0, q.y / th), v1 = std::max(v1, q.y / th);
    }
    const double columns = std::floor(u1) - std::floor(u0) + 1, rows = std::floor(v1) - std::floor(v0) + 1;
    const double copies = columns * rows;
    if (!(copies * points + tile_points_ <= kMaxTilePoints && copies * length + tile_length_ <= kMaxTileLength)) {
      ++patterns_not_copied_;
      return;
    }
    tile_points_ += copies * points;
    tile_length_ += copies * length;
    SvgShape painted = std::move(shapes_.back());
    shapes_.pop_back();
    dropped_.pop_back();
    const double scale = std::sqrt(std::abs(to_device[0] * to_device[3] - to_device[1] * to_device[2]));
    const double min_scale = SmallestScale(to_device[0], to_device[1], to_device[2], to_device[3]);
    std::vector<Segment> fill_segments;  // of every copy's fills, in device space
    std::vector<SvgShape> others;        // copies of the tile's strokes and clips
    for (double j = std::floor(v0); j <= std::floor(v1); ++j) {
      for (double i = std::floor(u0); i <= std::floor(u1); ++i) {
        std::array<double, 6> place = to_device;  // tile space -> device, this tile
        place[4] += to_device[0] * i * tw + to_device[2] * j * th;
        place[5] += to_device[1] * i * tw + to_device[3] * j * th;
        for (size_t k : sources) {
          const SvgShape& source = shapes_[k];
          SvgShape copy;
          copy.tiled = true;
          copy.paint = source.paint;
          copy.scale = source.scale * scale;
          copy.min_scale = source.min_scale * min_scale;  // at most the product's smaller singular value
          copy.stroke_width = source.stroke_width * scale;
          for (const SvgOutline& o : source.outlines) {
            // Segments whose middle lies outside the tile are clipped away by the tile.
            SvgOutline part{{}, false};
            bool whole = true;
            for (size_t s = 0; s + 3 < o.points.size(); s += 3) {
              const Point2 mid = CubicMiddle(&o.points[s]);
              if (!(mid.x >= -kTileMargin && mid.y >= -kTileMargin && mid.x <= tw + kTileMargin &&
                    mid.y <= th + kTileMargin)) {
                whole = false;
                if (part.points.size() >= 4) copy.outlines.push_back(std::move(part));
                part = SvgOutline{{}, false};
                continue;
              }
              Segment d;
              for (int q = 0; q < 4; ++q) d[q] = Apply(place, o.points[s + q]);
              if (source.paint == SvgPaint::kFill) {
                fill_segments.push_back(d);
                continue;
              }
              if (part.points.empty()) part.points.push_back(d[0]);
              part.points.insert(part.points.end(), d.begin() + 1, d.end());
            }
            part.closed = whole && o.closed;
            if (part.points.size() >= 4) copy.outlines.push_back(std::move(part));
          }
          if (!copy.outlines.empty()) others.push_back(std::move(copy));
        }
      }
    }
    // Painting order: the tile's fills (lower), its strokes and clips, the fill itself.
    SvgShape lines;
    lines.paint = SvgPaint::kFill;
    lines.tiled = true;
    lines.scale = painted.scale * scale;
    lines.min_scale = painted.min_scale * min_scale;
    lines.outlines = ChainSegments(std::move(fill_segments));
    if (!lines.outlines.empty()) {
      shapes_.push_back(std::move(lines));
      dropped_.push_back(0);
    }
    for (SvgShape& copy : others) {
      shapes_.push_back(std::move(copy));
      dropped_.push_back(0);
    }
    painted.tiled = true;
    shapes_.push_back(std::move(painted));
    dropped_.push_back(0);
  }

  void Handle(const std::string& t) {
    double v = 0;
    if (ParseNumber(t, &v)) {
      (in_array_ ? array_ : numbers_).push_back(v);
      return;
    }
    if (t == "[") {
      in_array_ = true;
      array_.clear();
      return;
    }
    if (t == "]") {
      in_array_ = false;
      have_array_ = true;
      return;
    }
    if (in_array_) return;  // names inside arrays
    if (t[0] == '/') {  // a literal name: //EXTEND_REPEAT, /s2 (keeps the numbers before it)
      literal_ = t;
      return;
    }
    double a[6];
    GraphicsState& g = states_.back();
    if (t == "similar" && Take(2, a)) {
      similar_width_ = a[0], similar_height_ = a[1];
    } else if (t == "def" && literal_.size() > 1) {
      defined_ = literal_.substr(1);
    } else if (t == "context" && !defined_.empty()) {
      Surface surface;
      surface.begin = shapes_.size();
      surface.width = similar_width_;
      surface.height = similar_height_;
      similar_width_ = similar_height_ = 0;
      surfaces_[defined_] = surface;
      surface_of_state_.resize(states_.size() + 1);
      surface_of_state_[states_.size()] = defined_;  // the state pushed below
      defined_.clear();
    } else if (t == "set-extend") {
      pattern_repeat_ = literal_ == "//EXTEND_REPEAT" || literal_ == "//EXTEND_REFLECT";
    } else if (t == "pattern") {
      pattern_surface_ = surfaces_.count(word_) > 0 ? word_ : std::string();
      pattern_repeat_ = false;
      pattern_matrix_ = {1, 0, 0, 1, 0, 0};
    }
    if (t == "set-source") {
      auto it = surfaces_.find(pattern_surface_);
      g.tiled.clear();
      if (pattern_open_ && pattern_repeat_ && it != surfaces_.end() && !it->second.open) {
        Surface& tile = it->second;
        if (!tile.tile) {
          tile.tile = true;
          for (size_t k = tile.begin; k < tile.end; ++k) {
            if (dropped_[k] || shapes_[k].tiled) {
              tile.nested = true;
            } else {
              tile.own.push_back(k);
            }
          }
        }
        for (size_t k = tile.begin; k < tile.end; ++k) dropped_[k] = 1;
        g.tiled = pattern_surface_;
        g.tile_matrix = pattern_matrix_;
      }
      pattern_surface_.clear();
    }
    if ((t == "pop" || t == "restore") && states_.size() > 1 && surface_of_state_.size() >= states_.size() &&
        !surface_of_state_[states_.size() - 1].empty()) {
      Surface& surface = surfaces_[surface_of_state_[states_.size() - 1]];
      surface.end = shapes_.size();
      surface.open = false;
      surface_of_state_[states_.size() - 1].clear();
    }
    word_ = t;
    if (t == "show-glyphs" || t == "show-text-glyphs") ++glyph_runs_;
    if (t == "n") {
      path_.clear();
    } else if (t == "m" && Take(2, a)) {
      path_.push_back(SvgOutline{{{a[0], a[1]}}, false});
    } else if (t == "l" && Take(2, a)) {
      LineTo(a[0], a[1]);
    } else if (t == "c" && Take(6, a)) {
      if (SvgOutline* o = Current()) {
        o->points.push_back({a[0], a[1]});
        o->points.push_back({a[2], a[3]});
        o->points.push_back({a[4], a[5]});
      }
    } else if (t == "h") {
      if (SvgOutline* o = Current()) {
        const Point2 first = o->points.front(), last = o->points.back();
        if (first.x != last.x || first.y != last.y) LineTo(first.x, first.y);
        o->closed = true;
      }
    } else if (t == "rectangle" && Take(4, a)) {
      path_.push_back(SvgOutline{{{a[0], a[1]}}, false});
      LineTo(a[0] + a[2], a[1]);
      LineTo(a[0] + a[2], a[1] + a[3]);
      LineTo(a[0], a[1] + a[3]);
      LineTo(a[0], a[1]);
      path_.back().closed = true;
    } else if (t == "fill" || t == "fill+") {
      const size_t before = shapes_.size();
      Paint(SvgPaint::kFill);
      if (!g.tiled.empty() && shapes_.size() > before) CopyTiles(g);
    } else if (t == "paint" || t == "paint-with-alpha") {
      if (!g.tiled.empty()) ++patterns_not_copied_;  // painted within a clip: not copied
    } else if (t == "stroke" || t == "stroke+") {
      const size_t before = shapes_.size();
      Paint(SvgPaint::kStroke);
      if (!g.tiled.empty() && shapes_.size() > before) ++patterns_not_copied_;
    } else if (t == "clip" || t == "clip+") {
      Paint(SvgPaint::kClip);
    } else if (t == "set-line-width" && Take(1, a)) {
      g.line_width = std::abs(a[0]);
    } else if (t == "set-line-cap") {
      g.line_cap = literal_ == "//LINE_CAP_ROUND"    ? SvgLineCap::kRound
                   : literal_ == "//LINE_CAP_SQUARE" ? SvgLineCap::kSquare
                                                     : SvgLineCap::kButt;
    } else if (t == "identity") {
      array_ = {1, 0, 0, 1, 0, 0};
      have_array_ = true;
      numbers_.clear();
      return;  // set-matrix follows
    } else if (t == "linear" || t == "radial" || t == "pattern" || t == "mesh") {
      pattern_open_ = true;  // set-matrix now applies to the pattern, until set-source
    } else if (t == "set-source") {
      pattern_open_ = false;
    } else if (t == "set-matrix" && have_array_ && array_.size() == 6 && pattern_open_) {
      std::copy(array_.begin(), array_.end(), pattern_matrix_.begin());
    } else if (t == "set-matrix" && have_array_ && array_.size() == 6) {
      g.det = std::abs(array_[0] * array_[3] - array_[1] * array_[2]);
      g.linear = {array_[0], array_[1], array_[2], array_[3]};
    } else if (t == "transform" && have_array_ && array_.size() == 6) {
      g.det *= std::abs(array_[0] * array_[3] - array_[1] * array_[2]);
      g.linear = AfterLinear(g.linear, array_[0], array_[1], array_[2], array_[3]);
    } else if (t == "scale" && Take(2, a)) {
      g.det *= std::abs(a[0] * a[1]);
      g.linear = AfterLinear(g.linear, a[0], 0, 0, a[1]);
    } else if (t == "context" || t == "save") {
      states_.push_back(t == "save" ? g : GraphicsState());
    } else if ((t == "pop" || t == "restore") && states_.size() > 1) {
      states_.pop_back();
    }
    numbers_.clear();
    have_array_ = false;
  }

  const std::string& s_;
  size_t i_ = 0;
  std::vector<double> numbers_, array_;
  bool in_array_ = false, have_array_ = false;
  bool pattern_open_ = false;  // a pattern is on the stack (its own set-matrix follows)
  std::vector<SvgOutline> path_;
  std::vector<GraphicsState> states_{GraphicsState()};
  std::vector<SvgShape> shapes_;
  std::vector<uint8_t> dropped_;  // per shape: a tile's own shape, replaced by its copies
  std::string literal_, word_, defined_;  // the last literal name, the last word, a new surface's name
  std::map<std::string, Surface> surfaces_;
  std::vector<std::string> surface_of_state_;  // per state depth: the surface it draws
  std::string pattern_surface_;            // the surface of the pattern being made
  bool pattern_repeat_ = false;
  std::array<double, 6> pattern_matrix_{1, 0, 0, 1, 0, 0};  // its matrix (device -> tile)
  double similar_width_ = 0, similar_height_ = 0;            // the size of the next surface
  int width_ = 0, height_ = 0;
  double tile_points_ = 0, tile_length_ = 0;  // in the copies so far (kMaxTilePoints, kMaxTileLength)
  size_t glyph_runs_ = 0;  // show-glyphs / show-text-glyphs seen
  size_t patterns_not_copied_ = 0;
};

}  // namespace

std::vector<SvgShape> ReadCairoScript(const std::string& script, size_t* glyph_runs, int width, int height,
                                      size_t* patterns_not_copied) {
  ScriptReader reader(script, width, height);
  std::vector<SvgShape> shapes = reader.Read();
  if (glyph_runs != nullptr) *glyph_runs = reader.glyph_runs();
  if (patterns_not_copied != nullptr) *patterns_not_copied = reader.patterns_not_copied();
  return shapes;
}

namespace {

// librsvg draws the document into a cairo script surface turned by `turn` radians about the
// origin; the shapes read back are turned back. False when librsvg stopped with an error
// (*message says why; the shapes before it are kept).
bool TraceOnce(const SvgDocument& document, int width, int height, double turn, SvgGeometry* geometry,
               std::string* message) {
  std::string script;
  cairo_device_t* device = cairo_script_create_for_stream(AppendScript, &script);
  cairo_script_set_mode(device, CAIRO_SCRIPT_MODE_ASCII);
  cairo_surface_t* surface = cairo_script_surface_create(device, CAIRO_CONTENT_COLOR_ALPHA, width, height);
  cairo_t* cr = cairo_create(surface);
  if (turn != 0) cairo_rotate(cr, turn);
  Status rendered = RenderWithRsvg(document, cr, width, height, nullptr, /*traced=*/true);
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  cairo_surface_destroy(surface);
  cairo_device_finish(device);
  cairo_device_destroy(device);
  // Turned, the surface is not the box (0, 0, width, height) of the script's coordinates:
  // pattern tiles are then copied over each fill's whole extent.
  geometry->shapes = ReadCairoScript(script, &geometry->glyph_runs, turn == 0 ? width : 0, turn == 0 ? height : 0,
                                     &geometry->patterns_not_copied);
  if (turn != 0) {
    const double c = std::cos(turn), s = std::sin(turn);
    for (SvgShape& shape : geometry->shapes) {
      for (SvgOutline& outline : shape.outlines) {
        for (Point2& p : outline.points) p = {c * p.x + s * p.y, -s * p.x + c * p.y};
      }
    }
  }
  *message = rendered.ok() ? std::string() : rendered.message();
  return rendered.ok();
}

}  // namespace

StatusOr<SvgGeometry> TraceSvgGeometry(const SvgDocument& document, int width, int height) {
  if (width <= 0 || height <= 0) {
    return Status(StatusCode::kInvalidArgument, document.name + ": trace size must be positive");
  }
  SvgGeometry geometry;
  std::string message;
  if (!TraceOnce(document, width, height, 0, &geometry, &message)) {
    // Traced again turned (kTraceTurn); kept when that one completes.
    SvgGeometry turned;
    std::string ignored;
    if (TraceOnce(document, width, height, kTraceTurn, &turned, &ignored)) {
      geometry = std::move(turned);
      message.clear();
    }
  }
  geometry.incomplete = message;
  if (document.shortest_dash > 0) {
    // Upper estimate: every stroke dashed with the shortest dash; the control polygon is at
    // least as long as the curve, and a device length is at most min_scale times the user
    // length (a stroke squashed in one direction is long in user units).
    for (const SvgShape& shape : geometry.shapes) {
      if (shape.paint != SvgPaint::kStroke) continue;
      double length = 0;
      for (const SvgOutline& o : shape.outlines) {
        for (size_t k = 1; k < o.points.size(); ++k) {
          length += std::hypot(o.points[k].x - o.points[k - 1].x, o.points[k].y - o.points[k - 1].y);
        }
      }
      if (length > 0) geometry.dashes += length / (document.shortest_dash * shape.min_scale);
    }
  }
  return geometry;
}

}  // namespace sdvi
