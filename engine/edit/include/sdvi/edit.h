// SPDX-License-Identifier: GPL-3.0-or-later
// Editing a vectorized image (paper section VI.D; spec/EDIT.md): selections, operations on
// the control mesh, and the validity rule every edit must pass.
//
// The image is edited in place of its control mesh: the deBoor points of a feature are the
// vertices of its polyline, so moving them moves the B-spline the crease limit draws;
// colours are the vertices' R, G, B (0..255 units, the file's scale); a pair's sharpness is
// the distance of its two polylines, rho (1 - s) with the vectorizer's floor, placed by the
// same code that places pairs when vectorizing (OffsetPairSides in sdvi/features.h).
// Topology (triangles, creases, corners, the feature layer's vertex lists) never changes
// (unless EditOptions::repair_folds flips edges), so an edit keeps the triangle and vertex
// order and the file stays comparable byte for byte.
//
// Validity (checked after every operation; the first failure refuses the whole script):
//  - fold: a triangle whose signed area changes sign (unless every triangle does: a
//    mirror image is no fold);
//  - degenerate: a triangle whose smallest height falls below kMinTriangleHeight px
//    (and was not below it before);
//  - crossing: two crease edges (feature polylines, the boundary) that cross each other
//    where they did not before;
//  - non-finite: a position or colour that is NaN or infinite;
//  - out of range: a value outside what a file holds (CheckImageValues of
//    sdvi/mesh_rules.h: vertices within one image size of the frame, colours within
//    kColorMargin of 0..255).
// The error (kEditRefused) names the operation, the rule and the first elements that break
// it (triangle ids with their vertices, or the two edges). EditOptions::repair_folds may
// first re-triangulate folds by edge flips; then a fold is checked against the mesh's
// orientation, and every re-made triangle must pass the degenerate rule.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/render.h"
#include "sdvi/status.h"

namespace sdvi {

// ---- Features as a person picks them (`sdvi info --features`, the overlay) ----

struct FeatureBox {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

enum class FeatureKind {
  kPair,      // a feature pair (id = index into Image::pairs)
  kBoundary,  // a polyline all of whose edges lie on the mesh boundary
  kPairSide,  // a polyline that is one side of a pair
  kPolyline,  // any other feature polyline (a single crease curve)
};
const char* FeatureKindName(FeatureKind kind);  // "pair", "boundary", "pair_side", "polyline"

struct FeatureInfo {
  FeatureKind kind = FeatureKind::kPolyline;
  uint32_t id = 0;              // pair index (kPair) or polyline index (the others)
  int64_t pair = -1;            // kPairSide: its pair; -1 otherwise
  uint32_t first = 0, second = 0;  // kPair: its polylines
  bool closed = false;
  float sharpness = -1;         // kPair and kPairSide: the pair's; -1 otherwise
  double length = 0;            // control polygon length, px (kPair: of its centre polygon)
  FeatureBox box;               // of the control points (kPair: of both sides)
  uint32_t vertex_count = 0;    // deBoor points (kPair: of both sides)
};

// Pairs first (by id), then polylines (by id).
std::vector<FeatureInfo> ListFeatures(const Image& image);

// ---- Selections ----

struct Selection {
  enum class Kind { kAll, kVertices, kPolyline, kPair, kRegion };
  Kind kind = Kind::kAll;
  std::vector<uint32_t> vertices;  // kVertices
  uint32_t id = 0;                 // kPolyline, kPair (both of its polylines)
  std::vector<Point2> region;      // kRegion: a polygon (>= 3 points); vertices strictly
                                   // inside by the even-odd rule
};

// The selected vertex ids, sorted and unique. kInvalidArgument for an id out of range or
// a region with fewer than 3 points or a non-finite point.
StatusOr<std::vector<uint32_t>> ResolveSelection(const Image& image, const Selection& selection);

// ---- Operations ----

struct TranslateOp {  // positions += (dx, dy)
  Selection select;
  double dx = 0, dy = 0;
};
struct SetPositionsOp {  // vertex vertices[i] moves to positions[i]
  std::vector<uint32_t> vertices;
  std::vector<Point2> positions;
};
struct SetColorOp {  // colour = rgb
  Selection select;
  std::array<double, 3> rgb{};
};
struct AddColorOp {  // colour += rgb
  Selection select;
  std::array<double, 3> rgb{};
};
struct ScaleColorOp {  // colour *= factor (per channel)
  Selection select;
  std::array<double, 3> factor{1, 1, 1};
};
// Hue, saturation, lightness shift (spec/EDIT.md): the colour clamped to 0..255 goes to HSL,
// h += hue_deg (mod 360), s += saturation and l += lightness (each clamped to [0, 1]), back
// to RGB; what the clamp removed (overshoot of the control colours) is added back.
struct HslShiftOp {
  Selection select;
  double hue_deg = 0, saturation = 0, lightness = 0;
};
// New sharpness of a pair: its centre polygon (the midpoints of corresponding vertices of
// its two polylines) is offset again by PairDistance(sharpness) with OffsetPairSides. A
// sharpness equal to the recorded one changes nothing. Vertices strictly inside the strip
// between the two polylines (Steiner points of the triangulation) keep their barycentric
// coordinates in the strip's quads (each split along the diagonal (a_i, b_i+1)), so a
// narrower strip never folds; a wider one may overrun its neighbours and is then refused.
// Needs both polylines to have the same vertex count and closedness (as every vectorized
// pair has).
struct SetSharpnessOp {
  uint32_t pair = 0;
  double sharpness = 1;
};
// p -> (m[0] x + m[1] y + m[2], m[3] x + m[4] y + m[5]) on the selection. With
// new_width/new_height > 0 (selection all only) the image frame becomes that size (a
// rotation by 90 degrees swaps it).
struct AffineOp {
  Selection select;
  std::array<double, 6> matrix{1, 0, 0, 0, 1, 0};
  uint32_t new_width = 0, new_height = 0;
};
// A handle of a freeform deformation: the point `from` (or vertex `vertex`'s position when
// set) goes to `to`.
struct DeformHandle {
  std::optional<uint32_t> vertex;
  Point2 from, to;
};
// Freeform deformation by moving least squares, rigid variant (Schaefer, McPhail, Warren,
// "Image deformation using moving least squares", SIGGRAPH 2006; spec/EDIT.md): every
// selected vertex v goes to f(v) = |v - p*| (R(v) (v - p*)) / |...| + q*, the rotation R(v)
// that best maps the handles' sources p_i onto their targets q_i under weights
// w_i = 1 / |p_i - v|^(2 alpha). A vertex at a source goes exactly to its target. With
// pin_boundary the mesh boundary vertices do not move and act as fixed handles (p = q),
// so the deformation fades towards the frame and the domain stays covered.
struct DeformOp {
  Selection select;                  // vertices that move (default all)
  std::vector<DeformHandle> handles; // >= 1
  double alpha = 1;
  bool pin_boundary = true;
};

using EditOp = std::variant<TranslateOp, SetPositionsOp, SetColorOp, AddColorOp, ScaleColorOp,
                            HslShiftOp, SetSharpnessOp, AffineOp, DeformOp>;

// The operation's name as the script spells it ("translate", "set_sharpness", ...).
const char* EditOpName(const EditOp& op);

struct EditStep {
  std::string label;  // how errors name the step, e.g. "ops[2] (translate)"
  EditOp op;
};

struct EditOptions {
  ControlMeshOptions placement;  // rho, min_distance, use_sharpness for SetSharpnessOp
  bool check_validity = true;    // false: no validity rule (for tests of the rule itself)
  // Re-triangulate folds: when an operation folds triangles, non-crease edges of the folded
  // triangles are flipped (each flip only when both new triangles have the mesh's
  // orientation and a height >= kMinTriangleHeight; sweeps in triangle order) and the
  // rule is checked again. Vertices, creases and the triangle count stay; the triangles
  // change, so the file is no longer comparable vertex-triple for vertex-triple.
  bool repair_folds = false;
};

// Smallest triangle height an edit may leave (px); see the validity rule above.
inline constexpr double kMinTriangleHeight = 1e-3;

// Applies one operation in place (no validity check). kInvalidArgument for unknown ids,
// non-finite or out-of-range parameters (sharpness outside [0, 1], a deformation without
// handles, a frame change with a partial selection), naming the parameter.
Status ApplyEditOp(const EditOp& op, const EditOptions& options, Image* image);

// Checks after against before (same vertex and triangle counts) by the validity rule; ok
// or kEditRefused naming the elements.
Status CheckEditValidity(const Image& before, const Image& after);

// Applies the steps in order, checking validity after each (EditOptions::check_validity).
// Errors are prefixed with the step's label; the input is never modified.
StatusOr<Image> ApplyEdits(const Image& image, const std::vector<EditStep>& steps,
                           const EditOptions& options = {});

// ---- A picture for picking features ----

// picture (a render of image through viewport, RGB or RGBA 0..255; pixels outside the
// domain, alpha 0, show mid grey) with every feature polyline drawn over it (pair sides red
// when the pair's sharpness is >= 0.5, else green; boundary blue; other polylines yellow),
// deBoor points as dots, and each feature's id at its middle vertex: "P<id>" for a pair,
// "L<id>" for an unpaired, non-boundary polyline. Returns RGB of picture's size.
Raster DrawFeatureOverlay(const Raster& picture, const Image& image, const Viewport& viewport);

}  // namespace sdvi
