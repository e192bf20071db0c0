// SPDX-License-Identifier: GPL-3.0-or-later
// Internals shared by the SVG importer's sources.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sdvi/svg.h"

struct _xmlDoc;
typedef struct _xmlDoc xmlDoc;

namespace sdvi {

struct SvgCheck {
  size_t elements = 0;
  std::vector<std::string> unsupported;  // approximated elements, with their lines
  std::vector<std::string> warnings;     // references that are not loaded
  double shortest_dash = 0;              // SvgDocument::shortest_dash
  bool flat_shapes = false;              // a line, or a path/polyline/polygon without area
  struct Image {
    int line = 0;
    std::string url;  // data:image/...
  };
  std::vector<Image> images;             // raster images in data: URLs (sizes checked by LoadSvg)
};

// The mean dash + gap length of a stroke-dasharray value in user units (relative units
// count as 1/100 of a unit); 0 when the value draws no dashes.
double MeanDashPair(std::string_view value);

// Renames or removes every stroke-dasharray of a tree (attributes, style attributes,
// <style> text): librsvg then draws no dashes.
void RemoveDashes(xmlDoc* doc);

// SvgDocument::traced: the document after RemoveDashes, with every shape without area (line,
// and path, polyline, polygon whose points are collinear) unfilled by an inline
// "fill:none !important", serialised by libxml2; empty if it cannot be read.
std::string TracedDocument(const std::string& bytes);

// True when every point of path data d (ends and controls) or of a points list lies on
// one straight line: the shape has no area. Arcs with both radii count as area.
bool PathIsFlat(const std::string& d);
bool PointsAreFlat(const std::string& points);

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

// kTooManyDashes when geometry.dashes exceeds document.limits.max_dashes.
Status CheckDashes(const SvgDocument& document, const SvgGeometry& geometry, SvgError* error);

// RenderSvg without the dash check (the caller has made it).
StatusOr<Raster> RenderSvgUnchecked(const SvgDocument& document, int width, int height);

// The samples ArtworkFeatures takes on shapes at reference's size (a stroke outline counts
// twice), counted without making them; ImportSvgArtwork checks it against max_outline_samples.
double OutlineSampleCount(const std::vector<SvgShape>& shapes, const Raster& reference, double spacing);

// The painted shapes in a cairo script (svg_trace.cpp has the grammar it reads); when
// glyph_runs is non-null it receives the number of show-glyphs / show-text-glyphs
// operators (text drawn from a font, whose outlines the script does not have). width x
// height: the surface's size, which bounds where pattern tiles are copied (0: unbounded);
// patterns_not_copied: SvgGeometry::patterns_not_copied.
std::vector<SvgShape> ReadCairoScript(const std::string& script, size_t* glyph_runs = nullptr, int width = 0,
                                      int height = 0, size_t* patterns_not_copied = nullptr);

// The same for a polyline's or polygon's points (pairs of numbers).
bool CountPolylinePoints(const std::string& points, size_t* count, std::string* what);

}  // namespace sdvi
