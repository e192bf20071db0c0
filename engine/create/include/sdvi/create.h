// SPDX-License-Identifier: GPL-3.0-or-later
// Creating an image from curves (paper section V; like diffusion curves): the user gives
// curves with a colour on each side and a sharpness; the engine fits each curve with a
// cubic B-spline control polygon, places a feature pair at distance
// max(min_distance, rho (1 - sharpness)) carrying the side colours, triangulates the
// rectangle (constrained Delaunay, no Steiner point on a feature polyline), fixes the
// colours of the feature-polyline vertices and gets every other vertex colour by harmonic
// interpolation on the mesh. The subdivision surface of that mesh is the image.
// The SVG form of a drawing (our own attribute namespace) is specified in spec/CURVES.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/features.h"  // Point2
#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

// A colour in the image's units: 8-bit sRGB scale, 0..255 as floats.
struct CurveColor {
  float r = 0, g = 0, b = 0;
  friend bool operator==(const CurveColor&, const CurveColor&) = default;
};

// A colour at a place along a curve: offset = fraction of the curve's arc length from its
// start, in [0, 1].
struct CurveColorStop {
  double offset = 0;
  CurveColor color;
};

// One cubic Bezier segment of a path: from the previous segment's end (or the path's
// start) through control points c1, c2 to end. Device space: pixels of the drawing,
// (0,0) = top-left corner, x right, y down (sdvi::Image units).
struct CubicBezier {
  Point2 c1, c2, end;
};

// A curve of the drawing.
//  - Geometry: start + segments. A straight piece is a cubic with c1, c2 on the line.
//    closed = true: the path returns to start; if the last end is not start (more than
//    1e-6 px away) a straight segment closes it.
//  - Sides: "left" is the side on the left when walking along the path in its direction
//    as seen on screen (y down): for tangent (dx, dy) the left normal is (dy, -dx).
//  - Colours: left and right each hold >= 1 stop, offsets in [0, 1], non-decreasing. The
//    colour at arc-length fraction u is the linear interpolation (in 0..255 sRGB units)
//    of the stops around u; before the first / after the last stop it is that stop's
//    colour on an open curve; on a closed curve it interpolates cyclically from the last
//    stop to the first (through offset 1 == 0). One stop = a constant colour.
//  - sharpness in [0, 1]: 1 = a crisp edge (pair at the floor distance), 0 = the widest
//    transition (pair at rho).
//  - Kinks: where consecutive segments meet at an angle larger than
//    CreateOptions::corner_angle_deg the B-spline keeps a corner.
struct ColoredCurve {
  Point2 start;
  std::vector<CubicBezier> segments;
  bool closed = false;
  std::vector<CurveColorStop> left;
  std::vector<CurveColorStop> right;
  float sharpness = 1.0f;
  std::string name;  // names the curve in error messages (e.g. the SVG element id)
};

// A drawing: a width x height rectangle (the image domain) and its curves. Curves are
// clipped a few pixels inside the rectangle (where their pair would reach the frame's
// clearance; each part inside becomes a curve of its own, its colour offsets still measured
// along the whole path); where two curves cross or come closer than
// CreateOptions::clearance, the longer one is kept whole and the other is cut there (the
// rule of the vectorizer's feature placement). spec/CURVES.md section 1 has the details.
struct CurveDrawing {
  int width = 0, height = 0;
  std::vector<ColoredCurve> curves;
};

struct CreateOptions {
  float rho = 5.0f;            // pair distance rho (1 - sharpness), px (paper: 5)
  float min_distance = 1.0f;   // floor on the pair distance, px (keeps triangles sound)
  double fit_tolerance = 0.5;  // B-spline fit: max distance from the Bezier path, px
  double max_spacing = 12;     // B-spline fit: max arc length per control-polygon segment, px
  double corner_angle_deg = 30;  // a join of Bezier segments turning more than this is a
                                 // corner (smooth editor nodes turn by 0, cusps usually more)
  float min_angle_deg = 20;    // CDT quality bound
  float max_edge = 0;          // CDT size bound, px; 0 = max(8, sqrt(width * height) / 12)
  float clearance = 1.0f;      // min distance between different feature polylines, px
  // Input limits (each breach is kLimitExceeded naming the limit).
  int max_size = 16384;            // width and height
  size_t max_curves = 100000;
  size_t max_segments = 1000000;   // Bezier segments over all curves
  size_t max_color_stops = 100000; // stops over all curves and sides
  double max_length = 2e6;         // arc length over all curves (bounded by the control
                                   // polygons' length), px; sampled every 0.5 px
};

// Builds the image of drawing: a control mesh whose feature layer holds one pair per
// (kept piece of a) curve, with colours from the harmonic interpolation. Deterministic:
// the same drawing and options give the identical Image.
// Errors (the message names the curve by index and name, and the place):
//  - kInvalidArgument: width/height <= 0, sharpness outside [0, 1], a side without colour
//    stops, a stop offset outside [0, 1] or decreasing, a curve of (near) zero length,
//    bad options;
//  - kNonFinite: NaN or infinity in a point, a colour, an offset or the sharpness;
//  - kEmptyInput: no curves, a curve without segments, or no curve left inside the
//    rectangle after clipping;
//  - kLimitExceeded: a CreateOptions limit.
StatusOr<Image> CreateFromCurves(const CurveDrawing& drawing, const CreateOptions& options);

}  // namespace sdvi
