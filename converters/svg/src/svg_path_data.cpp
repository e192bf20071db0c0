// SPDX-License-Identifier: GPL-3.0-or-later
// Syntax check and command count of SVG path data (SVG 1.1 section 8.3.9 grammar). The
// geometry itself is librsvg's; this pass only refuses malformed data and counts segments
// for SvgLimits::max_path_commands before librsvg parses anything. PathIsFlat evaluates
// the points to find shapes without area (spec/SVG.md, "The traced document").
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "svg_internal.h"

namespace sdvi {
namespace {

class Scanner {
 public:
  explicit Scanner(const std::string& s) : s_(s) {}
  void SkipSeparators() {
    while (i_ < s_.size() && (std::isspace(static_cast<unsigned char>(s_[i_])) || s_[i_] == ',')) ++i_;
  }
  void SkipSpace() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool AtEnd() const { return i_ >= s_.size(); }
  char Peek() const { return s_[i_]; }
  void Advance() { ++i_; }
  size_t Position() const { return i_; }
  bool StartsNumber() const {
    if (AtEnd()) return false;
    const char c = s_[i_];
    return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+';
  }
  // number ::= sign? (digits ("." digits?)? | "." digits) exponent?
  bool Number() {
    size_t j = i_;
    if (j < s_.size() && (s_[j] == '+' || s_[j] == '-')) ++j;
    size_t digits = 0;
    while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) ++j, ++digits;
    if (j < s_.size() && s_[j] == '.') {
      ++j;
      while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) ++j, ++digits;
    }
    if (digits == 0) return false;
    if (j < s_.size() && (s_[j] == 'e' || s_[j] == 'E')) {
      size_t k = j + 1;
      if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
      size_t exp_digits = 0;
      while (k < s_.size() && std::isdigit(static_cast<unsigned char>(s_[k]))) ++k, ++exp_digits;
      if (exp_digits > 0) j = k;
    }
    i_ = j;
    return true;
  }
  // Number() with its value.
  bool Value(double* v) {
    const size_t start = i_;
    if (!Number()) return false;
    *v = std::strtod(s_.substr(start, i_ - start).c_str(), nullptr);
    return true;
  }
  bool Flag() {
    if (i_ < s_.size() && (s_[i_] == '0' || s_[i_] == '1')) {
      ++i_;
      return true;
    }
    return false;
  }

 private:
  const std::string& s_;
  size_t i_ = 0;
};

int ArgumentCount(char command) {
  switch (command) {
    case 'M': case 'm': case 'L': case 'l': case 'T': case 't': return 2;
    case 'H': case 'h': case 'V': case 'v': return 1;
    case 'C': case 'c': return 6;
    case 'S': case 's': case 'Q': case 'q': return 4;
    case 'A': case 'a': return 7;
    case 'Z': case 'z': return 0;
    default: return -1;
  }
}

std::string Near(const std::string& s, size_t at) {
  return "at character " + std::to_string(at) + " (\"" + s.substr(at, 16) + "\")";
}

// True when every point lies on one straight line (so does anything drawn between them).
bool Collinear(const std::vector<double>& xy) {
  const size_t n = xy.size() / 2;
  size_t far = 0;
  double far_d = 0;
  for (size_t k = 1; k < n; ++k) {
    const double d = std::hypot(xy[2 * k] - xy[0], xy[2 * k + 1] - xy[1]);
    if (d > far_d) far_d = d, far = k;
  }
  if (!(far_d > 0)) return std::isfinite(far_d);
  const double ux = (xy[2 * far] - xy[0]) / far_d, uy = (xy[2 * far + 1] - xy[1]) / far_d;
  for (size_t k = 1; k < n; ++k) {
    const double off = (xy[2 * k] - xy[0]) * uy - (xy[2 * k + 1] - xy[1]) * ux;
    if (!(std::abs(off) <= 1e-9 * far_d)) return false;
  }
  return true;
}

}  // namespace

bool PathIsFlat(const std::string& d) {
  Scanner in(d);
  std::vector<double> xy;  // every end and control point, absolute
  double x = 0, y = 0, sx = 0, sy = 0;
  auto add = [&xy](double px, double py) { xy.push_back(px), xy.push_back(py); };
  in.SkipSeparators();
  while (!in.AtEnd()) {
    const char command = in.Peek();
    const int args = ArgumentCount(command);
    if (args < 0) return false;
    in.Advance();
    in.SkipSeparators();
    const bool rel = std::islower(static_cast<unsigned char>(command)) != 0;
    const char upper = char(std::toupper(static_cast<unsigned char>(command)));
    if (args == 0) {
      x = sx, y = sy;
      continue;
    }
    bool first = true;
    while (in.StartsNumber()) {
      double a[7];
      for (int k = 0; k < args; ++k) {
        const bool is_flag = upper == 'A' && (k == 3 || k == 4);
        if (is_flag) {
          if (in.AtEnd()) return false;
          a[k] = in.Peek() == '1' ? 1 : 0;
          if (!in.Flag()) return false;
        } else if (!in.Value(&a[k])) {
          return false;
        }
        in.SkipSeparators();
      }
      const double ox = rel ? x : 0, oy = rel ? y : 0;
      switch (upper) {
        case 'M':
          x = a[0] + ox, y = a[1] + oy;
          if (first) sx = x, sy = y;
          break;
        case 'L': case 'T':
          x = a[0] + ox, y = a[1] + oy;
          break;
        case 'H':
          x = a[0] + ox;
          break;
        case 'V':
          y = a[0] + oy;
          break;
        case 'C':
          add(a[0] + ox, a[1] + oy), add(a[2] + ox, a[3] + oy);
          x = a[4] + ox, y = a[5] + oy;
          break;
        case 'S': case 'Q':
          add(a[0] + ox, a[1] + oy);
          x = a[2] + ox, y = a[3] + oy;
          break;
        case 'A':
          // An arc with both radii has area (a reflected control point of S or T lies on
          // the line through the points already seen, so it needs no entry of its own).
          if (a[0] != 0 && a[1] != 0 && (a[5] + ox != x || a[6] + oy != y)) return false;
          x = a[5] + ox, y = a[6] + oy;
          break;
      }
      add(x, y);
      first = false;
    }
  }
  return Collinear(xy);
}

bool PointsAreFlat(const std::string& points) {
  Scanner in(points);
  std::vector<double> xy;
  in.SkipSeparators();
  double v = 0;
  while (!in.AtEnd() && in.Value(&v)) {
    xy.push_back(v);
    in.SkipSeparators();
  }
  if (xy.size() % 2 != 0) xy.pop_back();
  return Collinear(xy);
}

bool CountPathCommands(const std::string& d, size_t* count, std::string* what, size_t cap) {
  Scanner in(d);
  in.SkipSeparators();
  bool first = true;
  while (!in.AtEnd()) {
    const char command = in.Peek();
    const int args = ArgumentCount(command);
    if (args < 0) {
      *what = "unknown command " + Near(d, in.Position());
      return false;
    }
    if (first && command != 'M' && command != 'm') {
      *what = "path data must start with a moveto (M or m), not '" + std::string(1, command) + "'";
      return false;
    }
    first = false;
    in.Advance();
    in.SkipSeparators();
    if (args == 0) {
      ++*count;
      continue;
    }
    bool one = false;
    while (in.StartsNumber() || !one) {
      for (int k = 0; k < args; ++k) {
        const bool is_flag = (command == 'A' || command == 'a') && (k == 3 || k == 4);
        if (!(is_flag ? in.Flag() : in.Number())) {
          *what = "command '" + std::string(1, command) + "' expects " + std::to_string(args) +
                  " numbers, bad argument " + Near(d, in.Position());
          return false;
        }
        in.SkipSeparators();
      }
      ++*count;
      one = true;
      if (*count > cap) return true;  // over the caller's limit: no need to read on
    }
  }
  return true;
}

bool CountPolylinePoints(const std::string& points, size_t* count, std::string* what) {
  Scanner in(points);
  in.SkipSeparators();
  size_t numbers = 0;
  while (!in.AtEnd()) {
    if (!in.Number()) {
      *what = "not a number " + Near(points, in.Position());
      return false;
    }
    ++numbers;
    in.SkipSeparators();
  }
  if (numbers % 2 != 0) {
    *what = "odd count of coordinates (" + std::to_string(numbers) + ")";
    return false;
  }
  *count += numbers / 2;
  return true;
}

}  // namespace sdvi
