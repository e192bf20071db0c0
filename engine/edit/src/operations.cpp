// SPDX-License-Identifier: GPL-3.0-or-later
// The edit operations on positions, colours and sharpness, and the script driver
// (rules in sdvi/edit.h and spec/EDIT.md).
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include "edit_internal.h"
#include "sdvi/edit.h"

namespace sdvi {
namespace {

using edit_internal::Bad;

bool Finite(std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// Colours -------------------------------------------------------------------------------

struct Hsl {
  double h = 0, s = 0, l = 0;  // h in [0, 360), s and l in [0, 1]
};

// rgb in [0, 1].
Hsl ToHsl(double r, double g, double b) {
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
  Hsl out;
  out.l = (mx + mn) / 2;
  const double c = mx - mn;
  if (c <= 0) return out;
  out.s = c / (1 - std::fabs(2 * out.l - 1));
  double h;
  if (mx == r)
    h = std::fmod((g - b) / c, 6.0);
  else if (mx == g)
    h = (b - r) / c + 2;
  else
    h = (r - g) / c + 4;
  out.h = h * 60;
  if (out.h < 0) out.h += 360;
  return out;
}

std::array<double, 3> FromHsl(const Hsl& x) {
  const double c = (1 - std::fabs(2 * x.l - 1)) * x.s;
  const double hp = x.h / 60;
  const double xx = c * (1 - std::fabs(std::fmod(hp, 2.0) - 1));
  double r = 0, g = 0, b = 0;
  if (hp < 1) r = c, g = xx;
  else if (hp < 2) r = xx, g = c;
  else if (hp < 3) g = c, b = xx;
  else if (hp < 4) g = xx, b = c;
  else if (hp < 5) r = xx, b = c;
  else r = c, b = xx;
  const double m = x.l - c / 2;
  return {r + m, g + m, b + m};
}

void ShiftHsl(const HslShiftOp& op, Vertex* v) {
  const double in[3] = {v->r, v->g, v->b};
  double clamped[3];
  for (int k = 0; k < 3; ++k) clamped[k] = std::clamp(in[k], 0.0, 255.0);
  Hsl hsl = ToHsl(clamped[0] / 255, clamped[1] / 255, clamped[2] / 255);
  hsl.h = std::fmod(hsl.h + op.hue_deg, 360.0);
  if (hsl.h < 0) hsl.h += 360;
  hsl.s = std::clamp(hsl.s + op.saturation, 0.0, 1.0);
  hsl.l = std::clamp(hsl.l + op.lightness, 0.0, 1.0);
  const std::array<double, 3> rgb = FromHsl(hsl);
  v->r = float(rgb[0] * 255 + (in[0] - clamped[0]));
  v->g = float(rgb[1] * 255 + (in[1] - clamped[1]));
  v->b = float(rgb[2] * 255 + (in[2] - clamped[2]));
}

// Sharpness -----------------------------------------------------------------------------

// Barycentric coordinates of p in triangle (a, b, c); false when p is outside or it is flat.
bool Barycentric(Point2 p, Point2 a, Point2 b, Point2 c, double w[3]) {
  const double d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (d == 0) return false;
  w[1] = ((p.x - a.x) * (c.y - a.y) - (p.y - a.y) * (c.x - a.x)) / d;
  w[2] = ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / d;
  w[0] = 1 - w[1] - w[2];
  return w[0] > 0 && w[1] > 0 && w[2] > 0;
}

// Vertices strictly inside the strip between the pair's polylines a and b (Steiner points
// of the triangulation) follow the strip: the quad of segment i, (a_i, a_i+1, b_i+1, b_i),
// split into two triangles, maps each such vertex by its barycentric coordinates onto the
// same triangle between the new sides (before the sides themselves move).
void MoveStripInterior(const FeaturePolyline& a, const FeaturePolyline& b,
                       const std::array<std::vector<Point2>, 2>& sides, Image* out) {
  const Image& image = *out;
  const size_t m = a.vertices.size(), segs = a.closed ? m : m - 1;
  auto at = [&](uint32_t v) { return Point2{image.vertices[v].x, image.vertices[v].y}; };
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  std::vector<uint8_t> on_pair(image.vertices.size(), 0);
  for (const FeaturePolyline* l : {&a, &b})
    for (uint32_t v : l->vertices) {
      on_pair[v] = 1;
      x0 = std::min<double>(x0, image.vertices[v].x), x1 = std::max<double>(x1, image.vertices[v].x);
      y0 = std::min<double>(y0, image.vertices[v].y), y1 = std::max<double>(y1, image.vertices[v].y);
    }
  for (size_t v = 0; v < image.vertices.size(); ++v) {
    const Point2 p = at(uint32_t(v));
    if (on_pair[v] || p.x <= x0 || p.x >= x1 || p.y <= y0 || p.y >= y1) continue;
    for (size_t i = 0; i < segs; ++i) {
      const size_t j = (i + 1) % m;
      const uint32_t tri[2][3] = {{a.vertices[i], a.vertices[j], b.vertices[j]}, {a.vertices[i], b.vertices[j], b.vertices[i]}};
      const Point2 moved[2][3] = {{sides[0][i], sides[0][j], sides[1][j]}, {sides[0][i], sides[1][j], sides[1][i]}};
      double w[3];
      int k = Barycentric(p, at(tri[0][0]), at(tri[0][1]), at(tri[0][2]), w) ? 0
              : Barycentric(p, at(tri[1][0]), at(tri[1][1]), at(tri[1][2]), w) ? 1 : -1;
      if (k < 0) continue;
      out->vertices[v].x = float(w[0] * moved[k][0].x + w[1] * moved[k][1].x + w[2] * moved[k][2].x);
      out->vertices[v].y = float(w[0] * moved[k][0].y + w[1] * moved[k][1].y + w[2] * moved[k][2].y);
      break;
    }
  }
}

Status SetSharpness(const SetSharpnessOp& op, const EditOptions& options, Image* image) {
  if (op.pair >= image->pairs.size())
    return Bad("pair " + std::to_string(op.pair) + " does not exist (the image has " +
               std::to_string(image->pairs.size()) + " pairs)");
  if (!(op.sharpness >= 0 && op.sharpness <= 1))
    return Bad("sharpness " + std::to_string(op.sharpness) + " is outside [0, 1]");
  FeaturePair& pair = image->pairs[op.pair];
  const float sharpness = float(op.sharpness);
  if (sharpness == pair.sharpness) return Status::Ok();
  const FeaturePolyline& a = image->polylines[pair.first];
  const FeaturePolyline& b = image->polylines[pair.second];
  if (a.vertices.size() != b.vertices.size() || a.closed != b.closed || a.vertices.size() < 2)
    return Bad("pair " + std::to_string(op.pair) + ": its polylines " + std::to_string(pair.first) + " and " +
               std::to_string(pair.second) + " have " + std::to_string(a.vertices.size()) + " and " +
               std::to_string(b.vertices.size()) +
               " vertices (or differ in closedness); a sharpness change needs vertex-to-vertex sides");
  const size_t m = a.vertices.size();
  std::vector<Point2> centre(m);
  for (size_t i = 0; i < m; ++i) {
    const Vertex& p = image->vertices[a.vertices[i]];
    const Vertex& q = image->vertices[b.vertices[i]];
    centre[i] = {(double(p.x) + q.x) / 2, (double(p.y) + q.y) / 2};
  }
  std::array<std::vector<Point2>, 2> sides =
      OffsetPairSides(centre, a.closed, PairDistance(sharpness, options.placement));
  // The first polyline keeps its side of the centre.
  double side = 0;
  for (size_t i = 0; i < m; ++i) {
    const Vertex& p = image->vertices[a.vertices[i]];
    side += (p.x - centre[i].x) * (sides[0][i].x - centre[i].x) + (p.y - centre[i].y) * (sides[0][i].y - centre[i].y);
  }
  if (side < 0) std::swap(sides[0], sides[1]);
  MoveStripInterior(a, b, sides, image);
  for (size_t i = 0; i < m; ++i) {
    Vertex& p = image->vertices[a.vertices[i]];
    Vertex& q = image->vertices[b.vertices[i]];
    p.x = float(sides[0][i].x);
    p.y = float(sides[0][i].y);
    q.x = float(sides[1][i].x);
    q.y = float(sides[1][i].y);
  }
  pair.sharpness = sharpness;
  return Status::Ok();
}

// Positions -----------------------------------------------------------------------------

Status Affine(const AffineOp& op, const std::vector<uint32_t>& selected, Image* image) {
  const auto& m = op.matrix;
  if (!Finite({m[0], m[1], m[2], m[3], m[4], m[5]})) return Bad("matrix has a non-finite entry");
  if ((op.new_width > 0) != (op.new_height > 0)) return Bad("frame needs both width and height > 0");
  if (op.new_width > 0) {
    if (op.select.kind != Selection::Kind::kAll) return Bad("frame can only change when the selection is all");
    if (op.new_width > 65536 || op.new_height > 65536) return Bad("frame is larger than 65536 px");
    image->width = op.new_width;
    image->height = op.new_height;
  }
  for (uint32_t i : selected) {
    Vertex& v = image->vertices[i];
    const double x = v.x, y = v.y;
    v.x = float(m[0] * x + m[1] * y + m[2]);
    v.y = float(m[3] * x + m[4] * y + m[5]);
  }
  return Status::Ok();
}

Status SetPositions(const SetPositionsOp& op, Image* image) {
  if (op.vertices.size() != op.positions.size())
    return Bad(std::to_string(op.vertices.size()) + " vertices but " + std::to_string(op.positions.size()) +
               " positions");
  for (size_t i = 0; i < op.vertices.size(); ++i) {
    if (op.vertices[i] >= image->vertices.size())
      return Bad("vertex " + std::to_string(op.vertices[i]) + " does not exist (the image has " +
                 std::to_string(image->vertices.size()) + " vertices)");
    if (!Finite({op.positions[i].x, op.positions[i].y}))
      return Bad("position " + std::to_string(i) + " is not finite");
  }
  for (size_t i = 0; i < op.vertices.size(); ++i) {
    image->vertices[op.vertices[i]].x = float(op.positions[i].x);
    image->vertices[op.vertices[i]].y = float(op.positions[i].y);
  }
  return Status::Ok();
}

// Applies f(Vertex&) to every selected vertex.
template <typename F>
Status ForSelected(const Selection& selection, Image* image, F&& f) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint32_t> selected, ResolveSelection(*image, selection));
  for (uint32_t i : selected) f(image->vertices[i]);
  return Status::Ok();
}

}  // namespace

const char* EditOpName(const EditOp& op) {
  return std::visit(
      [](const auto& o) -> const char* {
        using T = std::decay_t<decltype(o)>;
        if constexpr (std::is_same_v<T, TranslateOp>) return "translate";
        else if constexpr (std::is_same_v<T, SetPositionsOp>) return "set_positions";
        else if constexpr (std::is_same_v<T, SetColorOp>) return "set_color";
        else if constexpr (std::is_same_v<T, AddColorOp>) return "add_color";
        else if constexpr (std::is_same_v<T, ScaleColorOp>) return "scale_color";
        else if constexpr (std::is_same_v<T, HslShiftOp>) return "hsl_shift";
        else if constexpr (std::is_same_v<T, SetSharpnessOp>) return "set_sharpness";
        else if constexpr (std::is_same_v<T, AffineOp>) return "affine";
        else return "deform";
      },
      op);
}

Status ApplyEditOp(const EditOp& op, const EditOptions& options, Image* image) {
  return std::visit(
      [&](const auto& o) -> Status {
        using T = std::decay_t<decltype(o)>;
        if constexpr (std::is_same_v<T, TranslateOp>) {
          if (!Finite({o.dx, o.dy})) return Bad("offset is not finite");
          return ForSelected(o.select, image, [&](Vertex& v) {
            v.x = float(v.x + o.dx);
            v.y = float(v.y + o.dy);
          });
        } else if constexpr (std::is_same_v<T, SetPositionsOp>) {
          return SetPositions(o, image);
        } else if constexpr (std::is_same_v<T, SetColorOp>) {
          if (!Finite({o.rgb[0], o.rgb[1], o.rgb[2]})) return Bad("colour is not finite");
          return ForSelected(o.select, image, [&](Vertex& v) {
            v.r = float(o.rgb[0]);
            v.g = float(o.rgb[1]);
            v.b = float(o.rgb[2]);
          });
        } else if constexpr (std::is_same_v<T, AddColorOp>) {
          if (!Finite({o.rgb[0], o.rgb[1], o.rgb[2]})) return Bad("colour is not finite");
          return ForSelected(o.select, image, [&](Vertex& v) {
            v.r = float(v.r + o.rgb[0]);
            v.g = float(v.g + o.rgb[1]);
            v.b = float(v.b + o.rgb[2]);
          });
        } else if constexpr (std::is_same_v<T, ScaleColorOp>) {
          if (!Finite({o.factor[0], o.factor[1], o.factor[2]})) return Bad("factor is not finite");
          return ForSelected(o.select, image, [&](Vertex& v) {
            v.r = float(v.r * o.factor[0]);
            v.g = float(v.g * o.factor[1]);
            v.b = float(v.b * o.factor[2]);
          });
        } else if constexpr (std::is_same_v<T, HslShiftOp>) {
          if (!Finite({o.hue_deg, o.saturation, o.lightness})) return Bad("shift is not finite");
          return ForSelected(o.select, image, [&](Vertex& v) { ShiftHsl(o, &v); });
        } else if constexpr (std::is_same_v<T, SetSharpnessOp>) {
          return SetSharpness(o, options, image);
        } else if constexpr (std::is_same_v<T, AffineOp>) {
          SDVI_ASSIGN_OR_RETURN(std::vector<uint32_t> selected, ResolveSelection(*image, o.select));
          return Affine(o, selected, image);
        } else {
          return edit_internal::ApplyDeform(o, image);
        }
      },
      op);
}

StatusOr<Image> ApplyEdits(const Image& image, const std::vector<EditStep>& steps, const EditOptions& options) {
  Image current = image;
  for (const EditStep& step : steps) {
    Image before = options.check_validity ? current : Image{};
    Status s = ApplyEditOp(step.op, options, &current);
    if (s.ok() && options.check_validity) s = CheckEditValidity(before, current);
    if (!s.ok() && s.code() == StatusCode::kEditRefused && options.repair_folds) {
      edit_internal::RepairFolds(edit_internal::MeshOrientation(before), &current);
      s = CheckEditValidity(before, current);
    }
    if (!s.ok()) return Status(s.code(), step.label + ": " + s.message());
  }
  return current;
}

}  // namespace sdvi
