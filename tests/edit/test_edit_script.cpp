// SPDX-License-Identifier: GPL-3.0-or-later
// The JSON edit script and the short flags: what they build, and clean errors naming the key.
#include <catch2/catch.hpp>
#include <string>

#include "sdvi/edit_script.h"

namespace {

using namespace sdvi;

std::string ErrorOf(const std::string& script) {
  auto steps = ParseEditScript(script, "edits.json");
  REQUIRE(!steps.ok());
  INFO(steps.status().ToString());
  return steps.status().ToString();
}

}  // namespace

TEST_CASE("a script with every operation parses into its steps", "[edit][script]") {
  const std::string script = R"({
    "sdvi_edit": 1,
    "ops": [
      {"op": "translate", "select": {"vertices": [1, 2]}, "by": [1.5, -2]},
      {"op": "set_positions", "vertices": [4], "positions": [[10, 11]]},
      {"op": "set_color", "select": {"pair": 2}, "rgb": [255, 0, 0]},
      {"op": "add_color", "select": {"region": [[0, 0], [10, 0], [10, 10]]}, "rgb": [1, 2, 3]},
      {"op": "scale_color", "select": "all", "factor": 0.5},
      {"op": "hsl_shift", "select": {"polyline": 3}, "hue": 30, "lightness": -0.1},
      {"op": "set_sharpness", "pair": 3, "sharpness": 1},
      {"op": "affine", "rotate": 90, "center": [10, 20]},
      {"op": "deform", "handles": [{"vertex": 7, "to": [1, 2]}, {"from": [3, 4], "to": [5, 6]}], "pin_boundary": false}
    ]})";
  auto steps = ParseEditScript(script, "edits.json");
  REQUIRE(steps.ok());
  REQUIRE(steps->size() == 9);
  CHECK((*steps)[0].label == "ops[0] (translate)");
  const auto& t = std::get<TranslateOp>((*steps)[0].op);
  CHECK(t.select.kind == Selection::Kind::kVertices);
  CHECK(t.dx == 1.5);
  CHECK(std::get<SetColorOp>((*steps)[2].op).select.id == 2);
  CHECK(std::get<ScaleColorOp>((*steps)[4].op).factor[2] == 0.5);
  CHECK(std::get<HslShiftOp>((*steps)[5].op).hue_deg == 30);
  CHECK(std::get<SetSharpnessOp>((*steps)[6].op).pair == 3);
  // rotate 90 about (10, 20): (x, y) -> (10 - (y - 20), 20 + (x - 10)), exactly.
  const auto& m = std::get<AffineOp>((*steps)[7].op).matrix;
  CHECK(m == std::array<double, 6>{0, -1, 30, 1, 0, 10});
  const auto& d = std::get<DeformOp>((*steps)[8].op);
  CHECK(*d.handles[0].vertex == 7u);
  CHECK(d.handles[1].from.y == 4);
  CHECK(!d.pin_boundary);
}

TEST_CASE("bad scripts give errors naming the key", "[edit][script]") {
  CHECK(ErrorOf(R"({"ops": [{"op": "translate", "by": [0, 0]}, {"op": "explode"}]})") ==
        "invalid_argument: edits.json: ops[1].op: unknown operation \"explode\" (expected translate, "
        "set_positions, set_color, add_color, scale_color, hsl_shift, set_sharpness, affine, deform)");
  CHECK(ErrorOf(R"({"ops": [{"op": "set_color", "rgb": "red"}]})") ==
        "invalid_argument: edits.json: ops[0].rgb: expected an array of 3 numbers");
  CHECK(ErrorOf(R"({"ops": [{"op": "set_color", "rgb": [1, "2", 3]}]})") ==
        "invalid_argument: edits.json: ops[0].rgb[1]: expected a number, got string");
  CHECK(ErrorOf(R"({"ops": [{"op": "set_sharpness", "pair": -1, "sharpness": 1}]})") ==
        "invalid_argument: edits.json: ops[0].pair: expected a non-negative integer id, got -1");
  CHECK(ErrorOf(R"({"ops": [{"op": "set_sharpness", "pair": 1.5, "sharpness": 1}]})") ==
        "invalid_argument: edits.json: ops[0].pair: expected a non-negative integer id, got 1.5");
  CHECK(ErrorOf(R"({"ops": [{"op": "set_sharpness", "pair": 1, "sharpness": 2}]})") ==
        "invalid_argument: edits.json: ops[0].sharpness: must be in [0, 1]");
  CHECK(ErrorOf(R"({"ops": [{"op": "translate", "by": [1, 1], "colour": 3}]})") ==
        "invalid_argument: edits.json: ops[0].colour: unknown key");
  CHECK(ErrorOf(R"({"ops": [{"op": "translate"}]})") == "invalid_argument: edits.json: ops[0].by: missing");
  CHECK(ErrorOf(R"({"ops": [{"op": "translate", "by": [1e999, 0]}]})") ==
        "decode_failed: edits.json: not valid JSON: [json.exception.out_of_range.406] number overflow parsing "
        "'1e999'");
  CHECK(ErrorOf(R"({"ops": [{"op": "deform", "handles": [{"to": [1, 2]}]}]})") ==
        "invalid_argument: edits.json: ops[0].handles[0]: give exactly one of vertex and from");
  CHECK(ErrorOf(R"({"ops": [{"op": "set_color", "select": {"triangle": 1}, "rgb": [1, 2, 3]}]})") ==
        "invalid_argument: edits.json: ops[0].select.triangle: unknown selection (expected vertices, polyline, pair "
        "or region)");
  CHECK(ErrorOf(R"({"ops": {}})") == "invalid_argument: edits.json: ops: expected an array of operations");
  CHECK(ErrorOf(R"({"sdvi_edit": 2, "ops": []})") ==
        "invalid_argument: edits.json: sdvi_edit: unsupported script version 2 (this build reads 1)");
  CHECK(ErrorOf(R"({"opz": []})") == "invalid_argument: edits.json: script.opz: unknown key");
  // NaN is not JSON: the parser names the line and column.
  const std::string nan = ErrorOf("{\"ops\": [\n  {\"op\": \"translate\", \"by\": [NaN, 0]}]}");
  INFO(nan);
  CHECK(nan.rfind("decode_failed: edits.json: not valid JSON: ", 0) == 0);
  CHECK(nan.find("line 2") != std::string::npos);
}

TEST_CASE("the short flags build one step each", "[edit][script]") {
  auto s = ParseSharpnessFlag("3=0.75");
  REQUIRE(s.ok());
  CHECK(std::get<SetSharpnessOp>(s->op).pair == 3);
  CHECK(std::get<SetSharpnessOp>(s->op).sharpness == 0.75);
  auto m = ParseMoveFlag("pair:2:1,-1");
  REQUIRE(m.ok());
  CHECK(std::get<TranslateOp>(m->op).select.kind == Selection::Kind::kPair);
  CHECK(std::get<TranslateOp>(m->op).dy == -1);
  auto v = ParseMoveFlag("4,5,6:0.5,0");
  REQUIRE(v.ok());
  CHECK(std::get<TranslateOp>(v->op).select.vertices == std::vector<uint32_t>{4, 5, 6});
  auto c = ParseRecolorFlag("polyline:7:10,20,30");
  REQUIRE(c.ok());
  CHECK(std::get<SetColorOp>(c->op).rgb[1] == 20);
  auto t = ParseTransformFlag("1,0,5,0,1,-5");
  REQUIRE(t.ok());
  CHECK(std::get<AffineOp>(t->op).matrix[5] == -5);
  CHECK(ParseSharpnessFlag("3=1.5").status().message() == "--sharpness: expected one sharpness in [0, 1] after '='");
  CHECK(ParseSharpnessFlag("x=1").status().message() == "--sharpness: \"x\" is not an id");
  CHECK(ParseMoveFlag("1,2").status().message() == "--move: expected SELECTION:DX,DY");
  CHECK(ParseRecolorFlag("all:1,2").status().message() == "--recolor: expected R,G,B after ':'");
  CHECK(ParseTransformFlag("1,0,nan,0,1,0").status().message() == "--transform: \"nan\" is not a finite number");
}
