// SPDX-License-Identifier: GPL-3.0-or-later
// Syntax check and command count of SVG path data (SVG 1.1 section 8.3.9 grammar). The
// geometry itself is librsvg's; this pass only refuses malformed data and counts segments
// for SvgLimits::max_path_commands before librsvg parses anything.
#include <cctype>
#include <cstring>
#include <string>

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

}  // namespace

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
