// SPDX-License-Identifier: GPL-3.0-or-later
// SVG import (spec/SVG.md): a safety check of the XML (libxml2), librsvg for the geometry
// and the reference raster, and the artwork mode that turns a drawing into an sdvi image.
//
// Stack. librsvg (Debian librsvg2 2.54) parses and renders the document, loaded from memory
// with no base URI so that nothing outside the bytes is ever read. The geometry is captured
// by rendering the same document, at the same viewport, into a cairo script surface: its
// text is every painted path in device space (viewBox, preserveAspectRatio, units,
// transforms, use/symbol, shapes, arcs already resolved by librsvg) followed by the
// operator that painted it (fill, stroke with its width, clip). So one engine gives both
// the exact outlines and the raster the colours are fitted to.
//
// Safety. Before librsvg sees the bytes, CheckSvg reads them once with libxml2's SAX2
// parser (no network, no DTD loading, no entity substitution) and enforces SvgLimits; every
// breach is its own SvgError, and the Status message names the input and the limit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sdvi/create.h"
#include "sdvi/features.h"
#include "sdvi/raster.h"
#include "sdvi/status.h"
#include "sdvi/vectorize.h"

namespace sdvi {

// The specific reason an SVG was refused (the Status carries the general StatusCode).
enum class SvgError : int {
  kNone = 0,
  kFileTooLarge,         // more bytes than SvgLimits::max_bytes (kLimitExceeded)
  kTooManyElements,      // more elements than max_elements (kLimitExceeded)
  kTooDeep,              // element nesting deeper than max_depth (kLimitExceeded)
  kTooManyPathCommands,  // path/polyline commands in all over max_path_commands (kLimitExceeded)
  kUseExpansion,         // elements after expanding every <use> over max_use_expansion (kLimitExceeded)
  kUseCycle,             // a <use> that references itself, directly or through others (kCorrupt)
  kEntityDeclaration,    // an <!ENTITY> declaration: entities are never expanded (kUnsupportedFormat)
  kExternalEntity,       // an external (SYSTEM / PUBLIC) entity declaration (kUnsupportedFormat)
  kXInclude,             // an element in the XInclude namespace (kUnsupportedFormat)
  kMalformedXml,         // not well-formed XML, or no <svg> root (kDecodeFailed)
  kBadPathData,          // a path's d or a polyline's points that do not parse (kDecodeFailed)
  kSizeTooLarge,         // output width or height over max_dimension, or pixels over max_pixels (kLimitExceeded)
  kNoSize,               // the document has no size and none was given (kInvalidArgument)
  kRenderFailed,         // librsvg refused to load or render the document (kDecodeFailed)
  kBadCurveAttribute,    // curves mode: a malformed sdvi: attribute (kInvalidArgument)
  kNoCurves,             // curves mode: no element carries sdvi colours (kEmptyInput)
  kTooManyDashes,        // dashes librsvg would draw over max_dashes (kLimitExceeded)
  kTooManyOutlineSamples,  // artwork outline samples over max_outline_samples (kLimitExceeded)
  kUnsafeCss,            // a CSS escape, @import, or an xml-stylesheet with a data: URL (kUnsupportedFormat)
  kNestedDocument,       // a data: URL that is not a PNG/JPEG/GIF/WebP raster, e.g. an SVG inside
                         // the SVG that would escape these checks (kUnsupportedFormat)
};

// Stable lower_snake name, e.g. "too_many_elements".
std::string_view SvgErrorName(SvgError error);

// Input limits (defaults suit icons, drawings and the W3C suite with a wide margin).
struct SvgLimits {
  size_t max_bytes = size_t(32) << 20;      // file size
  size_t max_elements = 100000;             // elements in the document
  int max_depth = 128;                      // element nesting (the root is depth 1)
  size_t max_path_commands = 2000000;       // path segments, all paths together
  size_t max_use_expansion = 200000;        // elements drawn after expanding <use>
  int max_dimension = 16384;                // output raster width or height, px
  uint64_t max_pixels = uint64_t(64) << 20; // output raster width x height
  // Dashes librsvg would draw, all dashed strokes together at the output size (an upper
  // estimate: every stroke's device length over the shortest dash found, spec/SVG.md).
  uint64_t max_dashes = 1000000;
  // Artwork mode: outline samples (sample_spacing apart, within the raster and a margin).
  uint64_t max_outline_samples = 4000000;
};

// A checked document, ready for librsvg.
struct SvgDocument {
  std::string name;              // file name used in messages
  std::string bytes;             // the document
  double width = 0, height = 0;  // intrinsic size in px (96 dpi); 0 when it has none
  size_t elements = 0;
  // Elements whose rendering the artwork mode only approximates (no exact features for
  // them; their colours are fitted like a raster): "filter (line 30)", "image (line 12)".
  std::vector<std::string> unsupported;
  std::vector<std::string> warnings;  // references to other files, which are not loaded
  SvgLimits limits;              // the limits it was loaded with (rendering enforces max_dashes)
  // Dashes (spec/SVG.md, "Dashes"): the shortest mean dash + gap of any stroke-dasharray in
  // the document, in user units (0: the document has none).
  double shortest_dash = 0;
  // The document the geometry is traced from (spec/SVG.md, "The traced document"): every
  // stroke-dasharray renamed, shapes without area unfilled; empty: the document itself.
  std::string traced;
};

// Checks bytes against limits and the safety rules (header comment), then loads them with
// librsvg to learn the intrinsic size. On failure *error (when non-null) says which rule.
StatusOr<SvgDocument> LoadSvg(std::string bytes, const std::string& name, const SvgLimits& limits,
                              SvgError* error = nullptr);

// Reads path (size checked before reading) and calls LoadSvg.
StatusOr<SvgDocument> LoadSvgFile(const std::string& path, const SvgLimits& limits,
                                  SvgError* error = nullptr);

// The output raster size: width > 0 (height keeps the aspect ratio), or scale > 0 times
// the intrinsic size, or the intrinsic size; rounded, at least 1 px.
struct SvgSize {
  int width = 0, height = 0;
};
StatusOr<SvgSize> ChooseSvgSize(const SvgDocument& document, int width, double scale,
                                const SvgLimits& limits, SvgError* error = nullptr);

// librsvg's rendering of the document into width x height (viewBox and
// preserveAspectRatio applied to that viewport): RGBA, colours 0..255 not premultiplied,
// alpha 0..1. This is the reference the artwork mode fits. A dashed document is traced
// first: kTooManyDashes when its dash estimate exceeds document.limits.max_dashes.
StatusOr<Raster> RenderSvg(const SvgDocument& document, int width, int height);

// One subpath as painted, in output pixels: points[0] is the start, then three points
// (two Bezier controls and the end) per cubic segment; lines come as cubics with controls
// at thirds.
struct SvgOutline {
  std::vector<Point2> points;
  bool closed = false;
};

enum class SvgPaint { kFill, kStroke, kClip };
// How a stroke's open ends are drawn (cairo's line cap, as librsvg sets it from
// stroke-linecap).
enum class SvgLineCap { kButt, kRound, kSquare };

// One painting operation: a path filled, stroked (stroke_width in output pixels) or used
// as a clip.
struct SvgShape {
  SvgPaint paint = SvgPaint::kFill;
  double stroke_width = 0;
  SvgLineCap line_cap = SvgLineCap::kButt;  // a stroke's
  double scale = 1;  // output pixels per user unit where it was painted (sqrt |det| of the CTM)
  double min_scale = 1;  // ... in the direction it shrinks most (the CTM's smaller singular value)
  std::vector<SvgOutline> outlines;
  // Copied from a pattern's tiles over a fill (spec/SVG.md, section 1, "Patterns"): a copy
  // of a tile's stroke or clip, or (paint kFill) the edges of the tiles' fills chained
  // into lines across the tiles, which may cross one another.
  bool tiled = false;
};

// The painted paths of the document at the same viewport as RenderSvg, in painting order.
// When librsvg stops with an error while drawing into the script surface (it can refuse a
// path there that it draws into an image), the shapes traced before the error are kept and
// `incomplete` holds librsvg's message.
// Dashes are not applied (a dashed stroke is traced whole, from document.traced);
// `dashes` is the estimate RenderSvg checks against max_dashes.
struct SvgGeometry {
  std::vector<SvgShape> shapes;
  std::string incomplete;
  double dashes = 0;
  // Text drawn from a font (cairo show-glyphs) rather than as the glyphs' outlines, which
  // librsvg 2.54 never does: its outlines are not traced (spec/SVG.md, section 1).
  size_t glyph_runs = 0;
  // Paintings with a pattern whose tiles are not copied as shapes (a stroke, a `paint`, a
  // nested pattern, tiles under 2 px or over the bounds of spec/SVG.md section 1, "Patterns").
  size_t patterns_not_copied = 0;
};
StatusOr<SvgGeometry> TraceSvgGeometry(const SvgDocument& document, int width, int height);

// Artwork mode (spec/SVG.md): the outlines that are colour discontinuities in the reference
// become sharp features; colours come from the vectorizer's fit to the reference.
enum class SvgBackground {
  kAuto,         // transparent (an object image) unless the drawn area has structures
                 // thinner than 3 px (text, hairlines) over more than 2% of it: then white
  kTransparent,  // always an object image where the drawing leaves alpha < 1
  kWhite,        // composited over white: a full-rectangle image
};

struct SvgArtworkOptions {
  int width = 0;       // output width (0: from scale or the intrinsic size)
  SvgBackground background = SvgBackground::kAuto;
  double scale = 0;    // output size = scale x intrinsic size (0: 1)
  SvgLimits limits;
  // The vectorizer's options; given_features_extra 1: the exact features' own vertices
  // come on top of the budget, up to once more the budget; mesh.clearance 0.5 px: exact
  // outlines 1-2 px apart (a glyph on a hairline) are both real, so different features'
  // polylines may come as close as a sharp pair's sides to its centre (spec/SVG.md
  // section 4 step 4).
  VectorizeOptions vectorize = [] {
    VectorizeOptions v;
    v.given_features_extra = 1.0;
    v.mesh.clearance = 0.5f;
    return v;
  }();
  double tolerance = 0.5;         // px: max distance from the B-spline to the exact outline
  // px: without vectorize.max_triangles, deBoor points are also added until every one lies
  // within this of its spline (BSplineFitOptions::max_polygon_offset): the mesh places the
  // control polygon, and a small closed outline's few points (a glyph's counter) lie far
  // outside it (spec/SVG.md section 4 step 2). 0: no bound.
  double polygon_offset = 0.5;
  double corner_angle_deg = 25;   // a turn of more than this at a segment joint keeps a kink
  double min_contrast = 16;       // RMS step over R, G, B (0..255) across an outline, 1.5 px
                                  // either side, that makes it a feature
  double min_length = 4;          // px: shorter feature runs are dropped
  double sample_spacing = 0.5;    // px between outline samples
  // Edges of the reference that no outline feature explains (text, patterns, images,
  // filters) are detected as in a raster (vectorize.features) and added (spec/SVG.md).
  bool detect_uncovered_edges = true;
  // Parts of a fill thinner than 3 px (glyph stems and the gaps between them at text sizes,
  // slivers) are thin structures: features on their centreline with their width, as thin
  // strokes are (spec/SVG.md). Off: the fill's outline only, the ablation.
  bool thin_fills = true;
};

struct SvgArtworkResult {
  VectorizeResult vectorized;       // the image, its report, the curves used
  Raster reference;                 // librsvg's rendering the colours were fitted to
  std::vector<std::string> warnings;
  bool approximate = false;         // true when some element has no exact features
  bool object_image = false;        // the domain is the drawing's alpha (transparent background)
  uint32_t outline_features = 0;    // features that came from the SVG's outlines
  uint32_t detected_features = 0;   // features detected where no outline explains an edge
};

// The features of the artwork mode: for each outline (top-most shape first) the samples
// where the reference changes colour across it by min_contrast with both sides inside the
// domain (alpha > 0.5), not already covered by a feature of a shape above (a thin one
// covers only what runs along it: crossings stay, bridged where the contrast is lost,
// spec/SVG.md section 4 "Crossings"); runs of them longer than min_length fitted by
// B-splines within tolerance, kinks kept at segment joints that turn by more than
// corner_angle_deg. Stroke outlines are the two sides of the stroke.
std::vector<FeatureCurve> ArtworkFeatures(const std::vector<SvgShape>& shapes, const Raster& reference,
                                          const SvgArtworkOptions& options);

// The whole artwork import. Errors: those of ChooseSvgSize, RenderSvg, TraceSvgGeometry,
// kTooManyOutlineSamples (options.limits.max_outline_samples) and VectorizeWithFeatures.
StatusOr<SvgArtworkResult> ImportSvgArtwork(const SvgDocument& document, const SvgArtworkOptions& options,
                                            SvgError* error = nullptr);

}  // namespace sdvi

namespace sdvi {

// Curves mode (spec/CURVES.md): every path / line / polyline / polygon / rect / circle /
// ellipse outside defs with sdvi:left-color or sdvi:right-color is a curve (each subpath
// one), in device space at the output size as librsvg draws it; the drawing goes to
// CreateFromCurves. Elements without sdvi attributes are skipped with a warning.
struct SvgCurvesOptions {
  int width = 0;     // output width (0: from scale or the intrinsic size)
  double scale = 0;  // output size = scale x intrinsic size (0: 1)
  SvgLimits limits;
  CreateOptions create;
};

struct SvgCurvesResult {
  Image image;
  int width = 0, height = 0;
  size_t curves = 0;  // curves given to the engine (subpaths)
  std::vector<std::string> warnings;
};

// Errors: kBadCurveAttribute (the message names the element, its line and the attribute),
// kNoCurves, those of ChooseSvgSize and librsvg, and CreateFromCurves' (named by element).
StatusOr<SvgCurvesResult> ImportSvgCurves(const SvgDocument& document, const SvgCurvesOptions& options,
                                          SvgError* error = nullptr);

}  // namespace sdvi
