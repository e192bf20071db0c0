// SPDX-License-Identifier: GPL-3.0-or-later
// TraceSvgGeometry: librsvg renders into a cairo script surface (cairo 1.16, ASCII mode);
// the script it writes lists every path in device space followed by the operator that
// used it. This file reads back the few operators that carry geometry:
//   n                      new path          x y m / x y l / x1 y1 x2 y2 x3 y3 c / h
//   x y w h rectangle      a closed box      fill[+] stroke[+] clip[+]   the painting
//   w set-line-width, [a b c d e f] | identity set-matrix, sx sy scale, [...] transform:
//                          the stroke width in device pixels = width x sqrt(|det CTM|)
//   context ... pop, save ... restore: graphics-state scopes. Between linear / radial /
//   pattern / mesh and the set-source that consumes it, set-matrix is the pattern's.
//   w h //CONTENT similar dup /NAME exch def context ... pop: a surface drawn apart (group
//   opacity, masks, pattern tiles), in device space. NAME pattern ... //EXTEND_REPEAT
//   set-extend set-source: a tiled pattern, whose tile's shapes are in tile space, not
//   where they are seen: they are dropped (the artwork mode detects the pattern's edges,
//   spec/SVG.md; repeating 10 px tiles as outline features costs more of the vertex
//   budget than it gains).
// Text: librsvg 2.54 fills the glyphs' outlines (m l c h fill), which are read like any
// path. show-glyphs / show-text-glyphs (text drawn from a font, its outlines not in the
// script) are only counted: the artwork mode then says the result is approximate.
// Everything else (sources, patterns, image data, dictionaries) is skipped token by token:
// strings (...) with escapes, base85 data <~ ... ~> and <| ... ~>, hex <...>, comments.
#include <cairo-script.h>
#include <cairo.h>

#include <algorithm>
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

cairo_status_t AppendScript(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

struct GraphicsState {
  double line_width = 2.0;  // cairo's default
  double det = 1.0;         // |det| of the CTM
};

class ScriptReader {
 public:
  explicit ScriptReader(const std::string& text) : s_(text) {}

  size_t glyph_runs() const { return glyph_runs_; }

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
    shape.stroke_width = paint == SvgPaint::kStroke ? g.line_width * shape.scale : 0;
    for (const SvgOutline& o : path_) {
      if (o.points.size() >= 4) shape.outlines.push_back(o);
    }
    if (shape.outlines.empty()) return;
    shapes_.push_back(std::move(shape));
    dropped_.push_back(0);
  }

  // A surface drawn apart: its shapes [begin, end) in shapes_.
  struct Surface {
    size_t begin = 0, end = 0;
    bool open = true;
  };

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
    if (t == "def" && literal_.size() > 1) {
      defined_ = literal_.substr(1);
    } else if (t == "context" && !defined_.empty()) {
      Surface surface;
      surface.begin = shapes_.size();
      surfaces_[defined_] = surface;
      surface_of_state_.resize(states_.size() + 1);
      surface_of_state_[states_.size()] = defined_;  // the state pushed below
      defined_.clear();
    } else if (t == "set-extend") {
      pattern_repeat_ = literal_ == "//EXTEND_REPEAT" || literal_ == "//EXTEND_REFLECT";
    } else if (t == "pattern") {
      pattern_surface_ = surfaces_.count(word_) > 0 ? word_ : std::string();
      pattern_repeat_ = false;
    }
    if (t == "set-source") {
      auto it = surfaces_.find(pattern_surface_);
      if (pattern_open_ && pattern_repeat_ && it != surfaces_.end() && !it->second.open) {
        for (size_t k = it->second.begin; k < it->second.end; ++k) dropped_[k] = 1;
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
      Paint(SvgPaint::kFill);
    } else if (t == "stroke" || t == "stroke+") {
      Paint(SvgPaint::kStroke);
    } else if (t == "clip" || t == "clip+") {
      Paint(SvgPaint::kClip);
    } else if (t == "set-line-width" && Take(1, a)) {
      g.line_width = std::abs(a[0]);
    } else if (t == "identity") {
      array_ = {1, 0, 0, 1, 0, 0};
      have_array_ = true;
      numbers_.clear();
      return;  // set-matrix follows
    } else if (t == "linear" || t == "radial" || t == "pattern" || t == "mesh") {
      pattern_open_ = true;  // set-matrix now applies to the pattern, until set-source
    } else if (t == "set-source") {
      pattern_open_ = false;
    } else if (t == "set-matrix" && have_array_ && array_.size() == 6 && !pattern_open_) {
      g.det = std::abs(array_[0] * array_[3] - array_[1] * array_[2]);
    } else if (t == "transform" && have_array_ && array_.size() == 6) {
      g.det *= std::abs(array_[0] * array_[3] - array_[1] * array_[2]);
    } else if (t == "scale" && Take(2, a)) {
      g.det *= std::abs(a[0] * a[1]);
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
  size_t glyph_runs_ = 0;  // show-glyphs / show-text-glyphs seen
};

}  // namespace

std::vector<SvgShape> ReadCairoScript(const std::string& script, size_t* glyph_runs) {
  ScriptReader reader(script);
  std::vector<SvgShape> shapes = reader.Read();
  if (glyph_runs != nullptr) *glyph_runs = reader.glyph_runs();
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
  geometry->shapes = ReadCairoScript(script, &geometry->glyph_runs);
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
    // least as long as the curve.
    for (const SvgShape& shape : geometry.shapes) {
      if (shape.paint != SvgPaint::kStroke) continue;
      double length = 0;
      for (const SvgOutline& o : shape.outlines) {
        for (size_t k = 1; k < o.points.size(); ++k) {
          length += std::hypot(o.points[k].x - o.points[k - 1].x, o.points[k].y - o.points[k - 1].y);
        }
      }
      if (length > 0) geometry.dashes += length / (document.shortest_dash * shape.scale);
    }
  }
  return geometry;
}

}  // namespace sdvi
