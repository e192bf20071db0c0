// SPDX-License-Identifier: GPL-3.0-or-later
// Internals shared by the SVG importer's sources.
#pragma once

#include <string>
#include <vector>

#include "sdvi/svg.h"

namespace sdvi {

struct SvgCheck {
  size_t elements = 0;
  std::vector<std::string> unsupported;  // approximated elements, with their lines
  std::vector<std::string> warnings;     // references that are not loaded
};

// The Status for a refused SVG: the StatusCode that goes with code, a message naming the
// input and the rule, "[svg error name]" at its end; sets *out when non-null.
Status SvgFailure(SvgError code, const std::string& name, const std::string& what, SvgError* out);

// The safety pass (svg_check.cpp).
Status CheckSvg(const std::string& bytes, const std::string& name, const SvgLimits& limits,
                SvgCheck* check, SvgError* error);

// Checks the grammar of a path's d attribute (SVG 1.1 path data: commands and their
// argument counts, numbers, arc flags) and adds the number of segments (an implicit
// repetition counts as one more) to *count. On a syntax error returns false with *what
// describing it. Stops early (true) once *count exceeds cap.
bool CountPathCommands(const std::string& d, size_t* count, std::string* what, size_t cap);

// The painted shapes in a cairo script (svg_trace.cpp has the grammar it reads).
std::vector<SvgShape> ReadCairoScript(const std::string& script);

// The same for a polyline's or polygon's points (pairs of numbers).
bool CountPolylinePoints(const std::string& points, size_t* count, std::string* what);

}  // namespace sdvi
