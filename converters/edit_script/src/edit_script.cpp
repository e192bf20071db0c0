// SPDX-License-Identifier: GPL-3.0-or-later
// The JSON edit script and the short flags (spec/EDIT.md) -> EditStep.
#include "sdvi/edit_script.h"

#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

namespace sdvi {
namespace {

using Json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// A script error at a key path; turned into a Status at the public functions.
struct ScriptError {
  std::string path, what;
};

[[noreturn]] void Fail(const std::string& path, const std::string& what) { throw ScriptError{path, what}; }

double Number(const Json& j, const std::string& path) {
  if (!j.is_number()) Fail(path, "expected a number, got " + std::string(j.type_name()));
  const double v = j.get<double>();
  if (!std::isfinite(v)) Fail(path, "is not finite");
  return v;
}

uint32_t Id(const Json& j, const std::string& path) {
  if (!j.is_number_integer() || j.get<int64_t>() < 0 || j.get<int64_t>() > int64_t(UINT32_MAX))
    Fail(path, "expected a non-negative integer id, got " + (j.is_number() ? j.dump() : std::string(j.type_name())));
  return uint32_t(j.get<int64_t>());
}

bool Bool(const Json& j, const std::string& path) {
  if (!j.is_boolean()) Fail(path, "expected true or false, got " + std::string(j.type_name()));
  return j.get<bool>();
}

std::vector<double> Numbers(const Json& j, const std::string& path, size_t count) {
  if (!j.is_array() || j.size() != count)
    Fail(path, "expected an array of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (size_t i = 0; i < count; ++i) out.push_back(Number(j[i], path + "[" + std::to_string(i) + "]"));
  return out;
}

Point2 PointAt(const Json& j, const std::string& path) {
  std::vector<double> v = Numbers(j, path, 2);
  return {v[0], v[1]};
}

std::vector<uint32_t> Ids(const Json& j, const std::string& path) {
  if (!j.is_array()) Fail(path, "expected an array of vertex ids");
  std::vector<uint32_t> out;
  for (size_t i = 0; i < j.size(); ++i) out.push_back(Id(j[i], path + "[" + std::to_string(i) + "]"));
  return out;
}

std::vector<Point2> Points(const Json& j, const std::string& path) {
  if (!j.is_array()) Fail(path, "expected an array of [x, y] points");
  std::vector<Point2> out;
  for (size_t i = 0; i < j.size(); ++i) out.push_back(PointAt(j[i], path + "[" + std::to_string(i) + "]"));
  return out;
}

// The object's keys must be among `allowed`; `required` ones must be present.
void Keys(const Json& j, const std::string& path, std::initializer_list<const char*> allowed,
          std::initializer_list<const char*> required = {}) {
  if (!j.is_object()) Fail(path, "expected an object, got " + std::string(j.type_name()));
  const std::set<std::string> known(allowed.begin(), allowed.end());
  for (const auto& item : j.items())
    if (!known.count(item.key())) Fail(path + "." + item.key(), "unknown key");
  for (const char* key : required)
    if (!j.contains(key)) Fail(path + "." + key, "missing");
}

Selection ParseSelection(const Json& j, const std::string& path) {
  Selection s;
  if (j.is_string()) {
    if (j.get<std::string>() != "all") Fail(path, "expected \"all\" or an object, got \"" + j.get<std::string>() + "\"");
    return s;
  }
  if (!j.is_object() || j.size() != 1)
    Fail(path, "expected \"all\" or an object with one of vertices, polyline, pair, region");
  // The one member (items() would hand out a reference into a temporary iterator).
  const auto member = j.begin();
  const std::string key = member.key();
  const Json& value = member.value();
  const std::string sub = path + "." + key;
  if (key == "vertices") {
    s.kind = Selection::Kind::kVertices;
    s.vertices = Ids(value, sub);
  } else if (key == "polyline") {
    s.kind = Selection::Kind::kPolyline;
    s.id = Id(value, sub);
  } else if (key == "pair") {
    s.kind = Selection::Kind::kPair;
    s.id = Id(value, sub);
  } else if (key == "region") {
    s.kind = Selection::Kind::kRegion;
    s.region = Points(value, sub);
    if (s.region.size() < 3) Fail(sub, "a region needs at least 3 points");
  } else {
    Fail(sub, "unknown selection (expected vertices, polyline, pair or region)");
  }
  return s;
}

Selection SelectionOf(const Json& op, const std::string& path) {
  return op.contains("select") ? ParseSelection(op["select"], path + ".select") : Selection{};
}

std::array<double, 3> Rgb(const Json& j, const std::string& path) {
  std::vector<double> v = Numbers(j, path, 3);
  return {v[0], v[1], v[2]};
}

// "matrix": [[a, b, c], [d, e, f]], or rotate/scale/center/translate composed as
// p' = translate + center + R(rotate) S(scale) (p - center).
std::array<double, 6> AffineMatrix(const Json& op, const std::string& path) {
  if (op.contains("matrix")) {
    for (const char* k : {"rotate", "scale", "center", "translate"})
      if (op.contains(k)) Fail(path + "." + k, "cannot be combined with matrix");
    const Json& m = op["matrix"];
    if (!m.is_array() || m.size() != 2) Fail(path + ".matrix", "expected [[a, b, c], [d, e, f]]");
    std::vector<double> r0 = Numbers(m[0], path + ".matrix[0]", 3), r1 = Numbers(m[1], path + ".matrix[1]", 3);
    return {r0[0], r0[1], r0[2], r1[0], r1[1], r1[2]};
  }
  const double angle = op.contains("rotate") ? Number(op["rotate"], path + ".rotate") * kPi / 180 : 0;
  double sx = 1, sy = 1;
  if (op.contains("scale")) {
    if (op["scale"].is_array()) {
      std::vector<double> s = Numbers(op["scale"], path + ".scale", 2);
      sx = s[0], sy = s[1];
    } else {
      sx = sy = Number(op["scale"], path + ".scale");
    }
  }
  const Point2 c = op.contains("center") ? PointAt(op["center"], path + ".center") : Point2{0, 0};
  const Point2 t = op.contains("translate") ? PointAt(op["translate"], path + ".translate") : Point2{0, 0};
  // Exact for the common angles (multiples of 90 degrees).
  const double deg = op.contains("rotate") ? op["rotate"].get<double>() : 0;
  double cs = std::cos(angle), sn = std::sin(angle);
  if (std::fmod(deg, 90.0) == 0) {
    const int q = int(std::lround(std::fmod(std::fmod(deg, 360.0) + 360.0, 360.0) / 90)) % 4;
    const double cq[4] = {1, 0, -1, 0}, sq[4] = {0, 1, 0, -1};
    cs = cq[q];
    sn = sq[q];
  }
  const double a = cs * sx, b = -sn * sy, d = sn * sx, e = cs * sy;
  return {a, b, c.x + t.x - a * c.x - b * c.y, d, e, c.y + t.y - d * c.x - e * c.y};
}

EditOp ParseOp(const Json& op, const std::string& path) {
  if (!op.is_object()) Fail(path, "expected an object, got " + std::string(op.type_name()));
  if (!op.contains("op")) Fail(path + ".op", "missing");
  if (!op["op"].is_string()) Fail(path + ".op", "expected a string");
  const std::string name = op["op"].get<std::string>();
  if (name == "translate") {
    Keys(op, path, {"op", "select", "by"}, {"by"});
    Point2 by = PointAt(op["by"], path + ".by");
    return TranslateOp{SelectionOf(op, path), by.x, by.y};
  }
  if (name == "set_positions") {
    Keys(op, path, {"op", "vertices", "positions"}, {"vertices", "positions"});
    SetPositionsOp o{Ids(op["vertices"], path + ".vertices"), Points(op["positions"], path + ".positions")};
    if (o.vertices.size() != o.positions.size())
      Fail(path + ".positions", "has " + std::to_string(o.positions.size()) + " points for " +
                                    std::to_string(o.vertices.size()) + " vertices");
    return o;
  }
  if (name == "set_color" || name == "add_color") {
    Keys(op, path, {"op", "select", "rgb"}, {"rgb"});
    const std::array<double, 3> rgb = Rgb(op["rgb"], path + ".rgb");
    if (name == "set_color") return SetColorOp{SelectionOf(op, path), rgb};
    return AddColorOp{SelectionOf(op, path), rgb};
  }
  if (name == "scale_color") {
    Keys(op, path, {"op", "select", "factor"}, {"factor"});
    std::array<double, 3> f;
    if (op["factor"].is_array()) {
      f = Rgb(op["factor"], path + ".factor");
    } else {
      const double v = Number(op["factor"], path + ".factor");
      f = {v, v, v};
    }
    return ScaleColorOp{SelectionOf(op, path), f};
  }
  if (name == "hsl_shift") {
    Keys(op, path, {"op", "select", "hue", "saturation", "lightness"});
    HslShiftOp o;
    o.select = SelectionOf(op, path);
    if (op.contains("hue")) o.hue_deg = Number(op["hue"], path + ".hue");
    if (op.contains("saturation")) o.saturation = Number(op["saturation"], path + ".saturation");
    if (op.contains("lightness")) o.lightness = Number(op["lightness"], path + ".lightness");
    return o;
  }
  if (name == "set_sharpness") {
    Keys(op, path, {"op", "pair", "sharpness"}, {"pair", "sharpness"});
    SetSharpnessOp o{Id(op["pair"], path + ".pair"), Number(op["sharpness"], path + ".sharpness")};
    if (o.sharpness < 0 || o.sharpness > 1) Fail(path + ".sharpness", "must be in [0, 1]");
    return o;
  }
  if (name == "affine") {
    Keys(op, path, {"op", "select", "matrix", "rotate", "scale", "center", "translate", "frame"});
    AffineOp o;
    o.select = SelectionOf(op, path);
    o.matrix = AffineMatrix(op, path);
    if (op.contains("frame")) {
      std::vector<double> f = Numbers(op["frame"], path + ".frame", 2);
      if (f[0] < 1 || f[1] < 1 || f[0] > 65536 || f[1] > 65536 || f[0] != std::floor(f[0]) || f[1] != std::floor(f[1]))
        Fail(path + ".frame", "expected two integers in 1..65536");
      o.new_width = uint32_t(f[0]);
      o.new_height = uint32_t(f[1]);
    }
    return o;
  }
  if (name == "deform") {
    Keys(op, path, {"op", "select", "handles", "alpha", "pin_boundary"}, {"handles"});
    DeformOp o;
    o.select = SelectionOf(op, path);
    const Json& hs = op["handles"];
    if (!hs.is_array() || hs.empty()) Fail(path + ".handles", "expected a non-empty array of handles");
    for (size_t i = 0; i < hs.size(); ++i) {
      const std::string hp = path + ".handles[" + std::to_string(i) + "]";
      Keys(hs[i], hp, {"vertex", "from", "to"}, {"to"});
      if (hs[i].contains("vertex") == hs[i].contains("from")) Fail(hp, "give exactly one of vertex and from");
      DeformHandle h;
      if (hs[i].contains("vertex")) h.vertex = Id(hs[i]["vertex"], hp + ".vertex");
      else h.from = PointAt(hs[i]["from"], hp + ".from");
      h.to = PointAt(hs[i]["to"], hp + ".to");
      o.handles.push_back(h);
    }
    if (op.contains("alpha")) {
      o.alpha = Number(op["alpha"], path + ".alpha");
      if (o.alpha <= 0 || o.alpha > 8) Fail(path + ".alpha", "must be in (0, 8]");
    }
    if (op.contains("pin_boundary")) o.pin_boundary = Bool(op["pin_boundary"], path + ".pin_boundary");
    return o;
  }
  Fail(path + ".op", "unknown operation \"" + name +
                         "\" (expected translate, set_positions, set_color, add_color, scale_color, hsl_shift, "
                         "set_sharpness, affine, deform)");
}

Status ToStatus(const ScriptError& e, const std::string& source) {
  return Status(StatusCode::kInvalidArgument, source + ": " + e.path + ": " + e.what);
}

// "a,b,c" -> numbers (all finite).
std::vector<double> SplitNumbers(const std::string& text, const std::string& flag) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v)) Fail(flag, "\"" + item + "\" is not a finite number");
    out.push_back(v);
  }
  return out;
}

// "all", "pair:ID", "polyline:ID" or "V1,V2,...".
Selection FlagSelection(const std::string& text, const std::string& flag) {
  Selection s;
  if (text == "all") return s;
  auto id = [&](const std::string& digits) {
    char* end = nullptr;
    const long long v = std::strtoll(digits.c_str(), &end, 10);
    if (digits.empty() || *end != '\0' || v < 0 || v > UINT32_MAX) Fail(flag, "\"" + digits + "\" is not an id");
    return uint32_t(v);
  };
  for (const char* prefix : {"pair:", "polyline:"}) {
    if (text.rfind(prefix, 0) == 0) {
      s.kind = std::string(prefix) == "pair:" ? Selection::Kind::kPair : Selection::Kind::kPolyline;
      s.id = id(text.substr(std::string(prefix).size()));
      return s;
    }
  }
  s.kind = Selection::Kind::kVertices;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) s.vertices.push_back(id(item));
  if (s.vertices.empty()) Fail(flag, "no vertex given");
  return s;
}

// Splits "SELECTION:VALUES" at the last ':'.
std::pair<std::string, std::string> SplitLast(const std::string& value, const std::string& flag, const char* form) {
  const size_t colon = value.rfind(':');
  if (colon == std::string::npos) Fail(flag, "expected " + std::string(form));
  return {value.substr(0, colon), value.substr(colon + 1)};
}

template <typename F>
StatusOr<EditStep> FlagStep(const std::string& flag, F&& parse) {
  try {
    return EditStep{flag, parse()};
  } catch (const ScriptError& e) {
    return Status(StatusCode::kInvalidArgument, e.path + ": " + e.what);
  }
}

}  // namespace

StatusOr<std::vector<EditStep>> ParseEditScript(std::string_view text, const std::string& source_name) {
  Json root;
  try {
    root = Json::parse(text.begin(), text.end());
  } catch (const Json::exception& e) {  // syntax errors name the line; overflow the number
    return Status(StatusCode::kDecodeFailed, source_name + ": not valid JSON: " + e.what());
  }
  try {
    Keys(root, "script", {"sdvi_edit", "ops"}, {"ops"});
    if (root.contains("sdvi_edit") && (!root["sdvi_edit"].is_number_integer() || root["sdvi_edit"].get<int64_t>() != 1))
      Fail("sdvi_edit", "unsupported script version " + root["sdvi_edit"].dump() + " (this build reads 1)");
    const Json& ops = root["ops"];
    if (!ops.is_array()) Fail("ops", "expected an array of operations");
    std::vector<EditStep> steps;
    for (size_t i = 0; i < ops.size(); ++i) {
      const std::string path = "ops[" + std::to_string(i) + "]";
      EditOp op = ParseOp(ops[i], path);
      steps.push_back({path + " (" + EditOpName(op) + ")", std::move(op)});
    }
    return steps;
  } catch (const ScriptError& e) {
    return ToStatus(e, source_name);
  }
}

StatusOr<EditStep> ParseSharpnessFlag(const std::string& value) {
  return FlagStep("--sharpness", [&]() -> EditOp {
    const size_t eq = value.find('=');
    if (eq == std::string::npos) Fail("--sharpness", "expected PAIR=S, got \"" + value + "\"");
    Selection pair = FlagSelection(value.substr(0, eq), "--sharpness");
    if (pair.kind != Selection::Kind::kVertices || pair.vertices.size() != 1)
      Fail("--sharpness", "expected one pair id before '='");
    std::vector<double> s = SplitNumbers(value.substr(eq + 1), "--sharpness");
    if (s.size() != 1 || s[0] < 0 || s[0] > 1) Fail("--sharpness", "expected one sharpness in [0, 1] after '='");
    return SetSharpnessOp{pair.vertices[0], s[0]};
  });
}

StatusOr<EditStep> ParseMoveFlag(const std::string& value) {
  return FlagStep("--move", [&]() -> EditOp {
    auto [sel, by] = SplitLast(value, "--move", "SELECTION:DX,DY");
    std::vector<double> d = SplitNumbers(by, "--move");
    if (d.size() != 2) Fail("--move", "expected DX,DY after ':'");
    return TranslateOp{FlagSelection(sel, "--move"), d[0], d[1]};
  });
}

StatusOr<EditStep> ParseRecolorFlag(const std::string& value) {
  return FlagStep("--recolor", [&]() -> EditOp {
    auto [sel, rgb] = SplitLast(value, "--recolor", "SELECTION:R,G,B");
    std::vector<double> c = SplitNumbers(rgb, "--recolor");
    if (c.size() != 3) Fail("--recolor", "expected R,G,B after ':'");
    return SetColorOp{FlagSelection(sel, "--recolor"), {c[0], c[1], c[2]}};
  });
}

StatusOr<EditStep> ParseTransformFlag(const std::string& value) {
  return FlagStep("--transform", [&]() -> EditOp {
    std::vector<double> m = SplitNumbers(value, "--transform");
    if (m.size() != 6) Fail("--transform", "expected six numbers A,B,C,D,E,F");
    AffineOp o;
    o.matrix = {m[0], m[1], m[2], m[3], m[4], m[5]};
    return o;
  });
}

}  // namespace sdvi
