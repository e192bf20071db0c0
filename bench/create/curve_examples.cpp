// SPDX-License-Identifier: GPL-3.0-or-later
// curve_examples: the three example curve drawings of examples/curves, built in code
// through sdvi::CreateFromCurves (spec/CURVES.md).
//
//   curve_examples [--svg-dir DIR] [--out DIR] [--scale S]
//
// cherries4 (the cherries at 4x size), dots (400 circles) and spiral (one 38,000 px curve)
// measure larger drawings; they have no SVG file.
// --svg-dir writes each drawing's SVG form (the sdvi curves namespace; this is how the
// files in examples/curves are made), --out writes NAME.sdvi and NAME.png (rendered at
// scale S, default 2). Prints, per drawing: curves, pairs kept, control vertices and
// triangles, create and render times (ms), and whether a second create is identical.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/create.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"

namespace {

using sdvi::ColoredCurve;
using sdvi::CubicBezier;
using sdvi::CurveColor;
using sdvi::CurveColorStop;
using sdvi::Point2;

CurveColor Mix(CurveColor a, CurveColor b, double t) {
  return {float(a.r + t * (b.r - a.r)), float(a.g + t * (b.g - a.g)), float(a.b + t * (b.b - a.b))};
}

// Catmull-Rom spline through points as cubic Beziers (closed: back to the first point).
ColoredCurve ThroughPoints(const std::vector<Point2>& p, bool closed) {
  const int n = int(p.size());
  auto at = [&](int i) {
    if (closed) return p[(i % n + n) % n];
    return p[std::clamp(i, 0, n - 1)];
  };
  ColoredCurve c;
  c.start = p[0];
  c.closed = closed;
  for (int i = 0; i < (closed ? n : n - 1); ++i) {
    Point2 a = at(i - 1), b = at(i), d = at(i + 1), e = at(i + 2);
    c.segments.push_back({{b.x + (d.x - a.x) / 6, b.y + (d.y - a.y) / 6},
                          {d.x - (e.x - b.x) / 6, d.y - (e.y - b.y) / 6},
                          d});
  }
  return c;
}

// A closed blob around (cx, cy) with radius r(angle), drawn clockwise on screen from its
// rightmost point (like an SVG circle: left = outside).
ColoredCurve Blob(double cx, double cy, const std::function<double(double)>& radius, int points = 12) {
  std::vector<Point2> p;
  for (int i = 0; i < points; ++i) {
    double a = 2 * 3.14159265358979 * i / points;
    double r = radius(a);
    p.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return ThroughPoints(p, true);
}

// Point of the curve at Bezier parameter t of segment k.
Point2 PointOn(const ColoredCurve& c, size_t k, double t) {
  Point2 p0 = k == 0 ? c.start : c.segments[k - 1].end;
  const CubicBezier& s = c.segments[k];
  double u = 1 - t;
  return {u * u * u * p0.x + 3 * u * u * t * s.c1.x + 3 * u * t * t * s.c2.x + t * t * t * s.end.x,
          u * u * u * p0.y + 3 * u * u * t * s.c1.y + 3 * u * t * t * s.c2.y + t * t * t * s.end.y};
}

// Colour stops that follow a background colour field along the curve: one per segment
// join (offset = arc-length fraction, measured on a dense sampling).
std::vector<CurveColorStop> StopsFrom(const ColoredCurve& c, const std::function<CurveColor(Point2)>& field) {
  std::vector<double> arc{0};
  std::vector<Point2> joins{c.start};
  double len = 0;
  for (size_t k = 0; k < c.segments.size(); ++k) {
    Point2 prev = PointOn(c, k, 0);
    for (int i = 1; i <= 64; ++i) {
      Point2 q = PointOn(c, k, i / 64.0);
      len += std::hypot(q.x - prev.x, q.y - prev.y);
      prev = q;
    }
    arc.push_back(len);
    joins.push_back(c.segments[k].end);
  }
  std::vector<CurveColorStop> stops;
  for (size_t i = 0; i < joins.size(); ++i) stops.push_back({arc[i] / len, field(joins[i])});
  return stops;
}

ColoredCurve Colored(ColoredCurve c, std::vector<CurveColorStop> left, std::vector<CurveColorStop> right,
                     float sharpness, std::string name) {
  c.left = std::move(left);
  c.right = std::move(right);
  c.sharpness = sharpness;
  c.name = std::move(name);
  return c;
}

std::vector<CurveColorStop> Const(CurveColor c) { return {{0, c}}; }

// ---- The drawings ----

// In the spirit of the paper's Fig. 11: a picture drawn freehand from a few curves.
// Two cherries on stems with a leaf, in front of a sky and a hill.
sdvi::CurveDrawing Cherries() {
  const CurveColor sky_top{60, 115, 190}, sky_low{200, 222, 240}, grass{120, 175, 70}, grass_dark{45, 95, 40};
  const CurveColor stem{105, 75, 35}, leaf_light{130, 190, 80}, leaf_dark{50, 115, 45};
  const CurveColor highlight{255, 225, 230};
  const double top_y = 12, horizon_y = 242;
  // The sky between the two sky curves is linear in y (harmonic between two lines).
  auto sky = [&](Point2 p) { return Mix(sky_top, sky_low, std::clamp((p.y - top_y) / (horizon_y - top_y), 0.0, 1.0)); };
  sdvi::CurveDrawing d{400, 300, {}};
  d.curves.push_back(Colored(ThroughPoints({{-10, top_y}, {410, top_y}}, false), Const(sky_top), Const(sky_top), 0,
                             "sky"));
  d.curves.push_back(Colored(ThroughPoints({{-10, 248}, {90, 236}, {190, 246}, {290, 234}, {410, 244}}, false),
                             Const(sky_low), Const(grass), 0.3f, "horizon"));
  d.curves.push_back(Colored(ThroughPoints({{-10, 292}, {410, 292}}, false), Const(grass_dark), Const(grass_dark),
                             0, "ground"));
  struct Cherry {
    double x, y, r;
  };
  const Cherry cherries[2] = {{150, 168, 36}, {252, 180, 38}};
  for (int i = 0; i < 2; ++i) {
    const Cherry& ch = cherries[i];
    // A slightly heart-shaped outline: a dimple at the top where the stem goes in.
    ColoredCurve outline = Blob(ch.x, ch.y, [&](double a) {
      double top = std::exp(-std::pow((a - 4.712) / 0.35, 2));
      return ch.r * (1 - 0.12 * top);
    });
    // Inside: light upper left, dark lower right (offsets from the rightmost point, clockwise).
    std::vector<CurveColorStop> inside{{0.0, {150, 15, 30}},  {0.2, {95, 5, 20}},     {0.45, {175, 25, 40}},
                                       {0.65, {205, 45, 55}}, {0.85, {185, 30, 45}}};
    d.curves.push_back(Colored(outline, StopsFrom(outline, sky), inside, 0.85f, "cherry" + std::to_string(i + 1)));
    // A tilted ellipse, 9 x 5 px.
    ColoredCurve shine = Blob(ch.x - 13, ch.y - 14, [&](double a) {
      double u = std::cos(a + 0.7) / 9, v = std::sin(a + 0.7) / 5;
      return 1 / std::sqrt(u * u + v * v);
    }, 10);
    d.curves.push_back(Colored(shine, Const({205, 50, 60}), Const(highlight), 0.0f,
                               "shine" + std::to_string(i + 1)));
    // A soft crescent of shadow along the lower right inside the cherry.
    std::vector<Point2> crescent;
    for (double a : {-0.2, 0.4, 1.0, 1.6, 2.2}) crescent.push_back({ch.x + 0.72 * ch.r * std::cos(a), ch.y + 0.72 * ch.r * std::sin(a)});
    d.curves.push_back(Colored(ThroughPoints(crescent, false), Const({165, 20, 35}), Const({110, 8, 22}), 0.0f,
                               "shadow" + std::to_string(i + 1)));
  }
  // Stems: thin closed ribbons from the twig to each cherry's dimple.
  auto ribbon = [&](std::vector<Point2> centre, double half_width, const std::string& name) {
    ColoredCurve line = ThroughPoints(centre, false);
    std::vector<Point2> side_a, side_b;
    const int n = 24;
    for (int i = 0; i <= n; ++i) {
      double t = double(i) / n * line.segments.size();
      size_t k = std::min(size_t(t), line.segments.size() - 1);
      double tk = t - double(k);
      Point2 p = PointOn(line, k, std::max(0.0, tk - 1e-3)), q = PointOn(line, k, std::min(1.0, tk + 1e-3));
      double dx = q.x - p.x, dy = q.y - p.y, l = std::hypot(dx, dy);
      Point2 c = PointOn(line, k, tk);
      double w = half_width * (1 - 0.3 * i / n);
      side_a.push_back({c.x - w * dy / l, c.y + w * dx / l});
      side_b.push_back({c.x + w * dy / l, c.y - w * dx / l});
    }
    std::vector<Point2> outline = side_b;
    outline.insert(outline.end(), side_a.rbegin(), side_a.rend());
    ColoredCurve shape = ThroughPoints(outline, true);
    // Which way the outline runs depends on the stem: the signed area tells which side
    // of the outline is the inside.
    double area = 0;
    for (size_t i = 0, j = outline.size() - 1; i < outline.size(); j = i++)
      area += outline[j].x * outline[i].y - outline[i].x * outline[j].y;
    bool clockwise_on_screen = area > 0;  // y down: positive shoelace = clockwise on screen
    auto outside = StopsFrom(shape, sky);
    return clockwise_on_screen ? Colored(shape, outside, Const(stem), 0.9f, name)
                               : Colored(shape, Const(stem), outside, 0.9f, name);
  };
  d.curves.push_back(ribbon({{196, 46}, {175, 80}, {158, 112}, {150, 130}}, 2.2, "stem1"));
  d.curves.push_back(ribbon({{200, 47}, {225, 85}, {245, 120}, {251, 140}}, 2.2, "stem2"));
  // The leaf, clockwise on screen (left = outside), lighter at its tip, and its midrib.
  ColoredCurve leaf = ThroughPoints({{210, 40}, {245, 22}, {290, 22}, {330, 38}, {292, 56}, {246, 58}}, true);
  d.curves.push_back(Colored(leaf, StopsFrom(leaf, sky),
                             {{0, leaf_dark}, {0.5, leaf_light}, {1, leaf_dark}}, 0.8f, "leaf"));
  d.curves.push_back(Colored(ThroughPoints({{222, 41}, {270, 38}, {316, 39}}, false), Const(leaf_light),
                             Const(leaf_dark), 0.6f, "midrib"));
  return d;
}

// Five wavy curves with sharpness 1, 0.75, 0.5, 0.25, 0 between six colour bands.
sdvi::CurveDrawing Sharpness() {
  const CurveColor band[6] = {{30, 40, 90},    {60, 95, 165},   {90, 155, 205},
                              {150, 205, 160}, {225, 210, 110}, {240, 140, 60}};
  sdvi::CurveDrawing d{400, 200, {}};
  for (int k = 0; k < 5; ++k) {
    double x = 60 + 70 * k;
    std::vector<Point2> p;
    for (int i = 0; i <= 6; ++i) p.push_back({x + 9 * std::sin(i * 1.3 + k), -12 + i * 224.0 / 6});
    // Downward on screen: left is +x, the next band.
    float s = 1.0f - 0.25f * k;
    std::string name = "s";
    name += std::to_string(int(s * 100));
    d.curves.push_back(Colored(ThroughPoints(p, false), Const(band[k + 1]), Const(band[k]), s, name));
  }
  return d;
}

// Colour varying along curves: a ring with cyclic rainbow stops on both sides and an
// S-curve whose sides go from white to black in opposite directions.
sdvi::CurveDrawing Rainbow() {
  const CurveColor hue[6] = {{230, 40, 40}, {235, 210, 40}, {50, 190, 60}, {40, 200, 210}, {50, 70, 220}, {200, 50, 200}};
  sdvi::CurveDrawing d{300, 300, {}};
  std::vector<CurveColorStop> outside, inside;
  for (int i = 0; i < 6; ++i) {
    outside.push_back({i / 6.0, hue[i]});
    inside.push_back({i / 6.0, Mix(hue[(i + 3) % 6], {20, 20, 20}, 0.4)});
  }
  ColoredCurve ring = Blob(150, 150, [](double) { return 95.0; });
  d.curves.push_back(Colored(ring, outside, inside, 0.9f, "ring"));
  ColoredCurve s = ThroughPoints({{100, 150}, {125, 120}, {150, 150}, {175, 180}, {200, 150}}, false);
  d.curves.push_back(Colored(s, {{0, {250, 250, 250}}, {1, {10, 10, 10}}}, {{0, {10, 10, 10}}, {1, {250, 250, 250}}},
                             0.3f, "wave"));
  return d;
}

// The drawing with every coordinate multiplied by k (a larger picture of the same thing).
sdvi::CurveDrawing Scaled(sdvi::CurveDrawing d, double k) {
  auto sc = [&](Point2& p) { p = {p.x * k, p.y * k}; };
  d.width = int(d.width * k);
  d.height = int(d.height * k);
  for (ColoredCurve& c : d.curves) {
    sc(c.start);
    for (CubicBezier& s : c.segments) {
      sc(s.c1);
      sc(s.c2);
      sc(s.end);
    }
  }
  return d;
}

// A 20 x 20 grid of small circles with colours from a fixed sequence, on 1024 x 1024: many
// curves, for timing.
sdvi::CurveDrawing Dots() {
  sdvi::CurveDrawing d{1024, 1024, {}};
  uint32_t state = 2463534242u;
  auto next = [&]() {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return float(state % 256);
  };
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const double r = 12 + (i + j) % 5 * 2;
      ColoredCurve c = Blob(30 + 51 * i, 30 + 51 * j, [&](double) { return r; }, 8);
      d.curves.push_back(Colored(c, Const({next(), next(), next()}), Const({next(), next(), next()}),
                                 float((i * 7 + j * 3) % 11) / 10, "dot"));
    }
  return d;
}

// One long curve: a spiral of 24 turns (about 38,000 px) on 1024 x 1024, colours varying
// along it, for timing the fit and the placement of long curves.
sdvi::CurveDrawing Spiral() {
  sdvi::CurveDrawing d{1024, 1024, {}};
  std::vector<Point2> p;
  const int turns = 24, per_turn = 16;
  for (int i = 0; i <= turns * per_turn; ++i) {
    double a = 2 * 3.14159265358979 * i / per_turn, r = 20 + 480.0 * i / (turns * per_turn);
    p.push_back({512 + r * std::cos(a), 512 + r * std::sin(a)});
  }
  d.curves.push_back(Colored(ThroughPoints(p, false), {{0, {250, 220, 60}}, {1, {200, 30, 60}}},
                             {{0, {20, 40, 120}}, {1, {40, 160, 200}}}, 0.7f, "spiral"));
  return d;
}

// ---- SVG form (spec/CURVES.md section 2) ----

std::string Hex(CurveColor c) {
  auto b = [](float v) { return std::clamp(int(std::lround(v)), 0, 255); };
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", b(c.r), b(c.g), b(c.b));
  return buf;
}

std::string ColorList(const std::vector<CurveColorStop>& stops) {
  if (stops.size() == 1) return Hex(stops[0].color);
  std::string s;
  for (size_t i = 0; i < stops.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g ", stops[i].offset);
    if (i) s += "; ";
    s += buf;
    s += Hex(stops[i].color);
  }
  return s;
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

std::string Svg(const sdvi::CurveDrawing& d, const std::string& title) {
  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:sdvi=\"https://sdvi.dev/ns/curves/1\"\n"
    << "     width=\"" << d.width << "\" height=\"" << d.height << "\" viewBox=\"0 0 " << d.width << " " << d.height
    << "\">\n"
    << "  <title>" << title << "</title>\n"
    << "  <desc>An sdvi curve drawing (spec/CURVES.md): each path carries the colours on its left and right\n"
    << "  and a sharpness; render it with: sdvi import-svg FILE -o OUT.sdvi --mode curves</desc>\n";
  for (const ColoredCurve& c : d.curves) {
    o << "  <path id=\"" << c.name << "\" d=\"M " << Num(c.start.x) << " " << Num(c.start.y);
    for (const CubicBezier& s : c.segments)
      o << " C " << Num(s.c1.x) << " " << Num(s.c1.y) << " " << Num(s.c2.x) << " " << Num(s.c2.y) << " "
        << Num(s.end.x) << " " << Num(s.end.y);
    if (c.closed) o << " Z";
    o << "\"\n        fill=\"none\" stroke=\"" << Hex(Mix(c.left[0].color, c.right[0].color, 0.5))
      << "\" stroke-width=\"0.5\"\n"
      << "        sdvi:left-color=\"" << ColorList(c.left) << "\"\n"
      << "        sdvi:right-color=\"" << ColorList(c.right) << "\"\n"
      << "        sdvi:sharpness=\"" << Num(c.sharpness) << "\"/>\n";
  }
  o << "</svg>\n";
  return o.str();
}

double Ms(std::chrono::steady_clock::time_point a) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string svg_dir, out_dir;
  double scale = 2;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--svg-dir" && i + 1 < argc) svg_dir = argv[++i];
    else if (a == "--out" && i + 1 < argc) out_dir = argv[++i];
    else if (a == "--scale" && i + 1 < argc) scale = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "usage: curve_examples [--svg-dir DIR] [--out DIR] [--scale S]\n");
      return 2;
    }
  }
  if (!(scale > 0 && scale <= 16)) {
    std::fprintf(stderr, "curve_examples: --scale must be in (0, 16]\n");
    return 2;
  }
  struct Example {
    const char* name;
    const char* title;
    sdvi::CurveDrawing drawing;
  };
  const Example examples[] = {
      {"cherries", "Cherries: a picture drawn from curves (in the spirit of Fig. 11 of Zhou, Zheng, Wei 2014)",
       Cherries()},
      {"sharpness", "Sharpness 1, 0.75, 0.5, 0.25, 0 from left to right", Sharpness()},
      {"rainbow", "Colour stops along curves", Rainbow()},
      {"cherries4", "The cherries drawn 4x larger (1600x1200)", Scaled(Cherries(), 4)},
      {"dots", "400 circles on 1024x1024", Dots()},
      {"spiral", "One spiral curve of 38,000 px on 1024x1024", Spiral()},
  };
  std::printf("%-10s %6s %6s %8s %9s %10s %10s %9s\n", "drawing", "curves", "pairs", "vertices", "triangles",
              "create_ms", "render_ms", "identical");
  int failures = 0;
  for (const Example& e : examples) {
    const bool timing_only = std::string(e.name) == "cherries4" || std::string(e.name) == "dots" ||
                             std::string(e.name) == "spiral";
    if (!svg_dir.empty() && !timing_only) {
      std::ofstream f(svg_dir + "/" + e.name + ".svg", std::ios::binary);
      f << Svg(e.drawing, e.title);
      if (!f) {
        std::fprintf(stderr, "curve_examples: cannot write %s/%s.svg\n", svg_dir.c_str(), e.name);
        return 1;
      }
    }
    auto t0 = std::chrono::steady_clock::now();
    auto image = sdvi::CreateFromCurves(e.drawing, {});
    double create_ms = Ms(t0);
    if (!image.ok()) {
      std::fprintf(stderr, "curve_examples: %s: %s\n", e.name, image.status().ToString().c_str());
      ++failures;
      continue;
    }
    auto again = sdvi::CreateFromCurves(e.drawing, {});
    bool identical = again.ok() && *again == *image;
    sdvi::RenderOptions ro;
    ro.viewport = {int(e.drawing.width * scale), int(e.drawing.height * scale), scale, scale, 0, 0};
    t0 = std::chrono::steady_clock::now();
    auto raster = sdvi::Render(*image, ro);
    double render_ms = Ms(t0);
    if (!raster.ok()) {
      std::fprintf(stderr, "curve_examples: %s: render: %s\n", e.name, raster.status().ToString().c_str());
      ++failures;
      continue;
    }
    std::printf("%-10s %6zu %6zu %8zu %9zu %10.1f %10.1f %9s\n", e.name, e.drawing.curves.size(),
                image->pairs.size(), image->vertices.size(), image->triangles.size(), create_ms, render_ms,
                identical ? "yes" : "NO");
    if (!identical) ++failures;
    if (!out_dir.empty()) {
      sdvi::Status s = sdvi::WriteImage(out_dir + "/" + e.name + ".sdvi", *image, nullptr);
      if (s.ok()) s = sdvi::SaveRasterPng(out_dir + "/" + e.name + ".png", *raster);
      if (!s.ok()) {
        std::fprintf(stderr, "curve_examples: %s: %s\n", e.name, s.ToString().c_str());
        ++failures;
      }
    }
  }
  return failures ? 1 : 0;
}
