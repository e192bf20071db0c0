// SPDX-License-Identifier: GPL-3.0-or-later
// engine/edit: sharpness, identity edits, file round trips, validity, rotation, deformation.
#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "edit_fixtures.h"
#include "sdvi/codec.h"
#include "sdvi/edit.h"
#include "sdvi/format.h"
#include "sdvi/render.h"

namespace {

using namespace sdvi;
using edit_test::Area2;

Raster RenderAt(const Image& image) {
  RenderOptions options;
  options.viewport = Viewport::Identity(int(image.width), int(image.height));
  options.threads = 1;
  return Render(image, options).value();
}

// 10%-90% width (px) of the rising grey edge along row y of picture, by linear interpolation.
double TransitionWidth(const Raster& picture, int y) {
  const float lo = picture.at(0, y, 0), hi = picture.at(picture.width - 1, y, 0);
  auto crossing = [&](double level) {
    for (int x = 1; x < picture.width; ++x) {
      const double a = picture.at(x - 1, y, 0), b = picture.at(x, y, 0);
      if (a < level && b >= level) return (x - 1) + (level - a) / (b - a);
    }
    return -1.0;
  };
  return crossing(lo + 0.9 * (hi - lo)) - crossing(lo + 0.1 * (hi - lo));
}

EditStep Step(EditOp op) { return {EditOpName(op), std::move(op)}; }

}  // namespace

TEST_CASE("a sharpness change places the pair where the vectorizer places it", "[edit][sharpness]") {
  const FeatureCurve arc = edit_test::Arc(40, 40, 22, 0.3, 2.6, 10, 0.2f);
  FeatureCurve sharp = arc;
  sharp.sharpness = 0.9f;
  const Image soft_mesh = BuildControlMesh(80, 72, {arc}, {}, ControlMeshOptions{}).value();
  const Image sharp_mesh = BuildControlMesh(80, 72, {sharp}, {}, ControlMeshOptions{}).value();
  REQUIRE(soft_mesh.pairs.size() == 1);
  REQUIRE(sharp_mesh.pairs.size() == 1);
  auto edited = ApplyEdits(soft_mesh, {Step(SetSharpnessOp{0, 0.9})});
  REQUIRE(edited.ok());
  CHECK(edited->pairs[0].sharpness == 0.9f);
  for (uint32_t side : {sharp_mesh.pairs[0].first, sharp_mesh.pairs[0].second}) {
    const auto& want = sharp_mesh.polylines[side].vertices;
    const auto& got = edited->polylines[side].vertices;
    REQUIRE(want.size() == got.size());
    for (size_t i = 0; i < want.size(); ++i) {
      CHECK(edited->vertices[got[i]].x == Approx(sharp_mesh.vertices[want[i]].x).margin(1e-4));
      CHECK(edited->vertices[got[i]].y == Approx(sharp_mesh.vertices[want[i]].y).margin(1e-4));
    }
  }
  // The pair distance is the paper's rho (1 - s) = 0.5 px... floored at 1 px.
  const auto& a = edited->polylines[edited->pairs[0].first].vertices;
  const auto& b = edited->polylines[edited->pairs[0].second].vertices;
  const Vertex &p = edited->vertices[a[a.size() / 2]], &q = edited->vertices[b[b.size() / 2]];
  CHECK(std::hypot(p.x - q.x, p.y - q.y) == Approx(1.0).margin(0.05));
}

TEST_CASE("a sharper pair narrows the rendered transition", "[edit][sharpness]") {
  const Image soft = edit_test::StraightEdge(64, 48, 0.0f);
  auto sharp = ApplyEdits(soft, {Step(SetSharpnessOp{0, 1.0})});
  INFO(sharp.status().ToString());
  REQUIRE(sharp.ok());
  const Raster before = RenderAt(soft), after = RenderAt(*sharp);
  for (int y : {16, 24, 32}) {
    const double w0 = TransitionWidth(before, y), w1 = TransitionWidth(after, y);
    INFO("row " << y << ": width " << w0 << " px -> " << w1 << " px");
    CHECK(w0 > 3.0);   // rho (1 - 0) = 5 px between the sides
    CHECK(w1 < 1.5);   // the 1 px floor
    CHECK(w1 < 0.4 * w0);
  }
  // And back: the soft sharpness restores the positions (to float rounding).
  auto back = ApplyEdits(*sharp, {Step(SetSharpnessOp{0, 0.0})});
  REQUIRE(back.ok());
  for (size_t i = 0; i < soft.vertices.size(); ++i) {
    CHECK(back->vertices[i].x == Approx(soft.vertices[i].x).margin(1e-4));
    CHECK(back->vertices[i].y == Approx(soft.vertices[i].y).margin(1e-4));
  }
}

TEST_CASE("a sharper pair narrows the transition of a vectorized blurred edge", "[edit][sharpness]") {
  // The sample image's blurred edge, vectorized: its softest long pair, made sharp. The width
  // is measured across the pair at its middle, on a 4x render, 10%-90% of the colour step.
  const Image image = edit_test::VectorizedSample(256, 192);
  const std::vector<FeatureInfo> features = ListFeatures(image);
  const FeatureInfo* soft = nullptr;
  for (const FeatureInfo& f : features)
    if (f.kind == FeatureKind::kPair && f.length > 20 && (!soft || f.sharpness < soft->sharpness)) soft = &f;
  REQUIRE(soft != nullptr);
  INFO("pair " << soft->id << ", sharpness " << soft->sharpness << ", length " << soft->length);
  REQUIRE(soft->sharpness < 0.5f);
  auto sharp = ApplyEdits(image, {Step(SetSharpnessOp{soft->id, 1.0})});
  REQUIRE(sharp.ok());
  const auto& a = image.polylines[soft->first].vertices;
  const auto& b = image.polylines[soft->second].vertices;
  const Vertex &p = image.vertices[a[a.size() / 2]], &q = image.vertices[b[b.size() / 2]];
  const double cx = (p.x + q.x) / 2.0, cy = (p.y + q.y) / 2.0, len = std::hypot(q.x - p.x, q.y - p.y);
  const double nx = (q.x - p.x) / len, ny = (q.y - p.y) / len;
  auto width = [&](const Image& im) {
    RenderOptions o;
    o.viewport = {int(im.width) * 4, int(im.height) * 4, 4, 4, 0, 0};
    o.threads = 1;
    const Raster r = Render(im, o).value();
    // Colour along the normal, t in [-4, 4] px, projected on the step between the ends.
    std::vector<std::array<double, 3>> c;
    for (int k = 0; k <= 320; ++k) {
      const double t = -4 + k * 0.025;
      const int x = std::clamp(int((cx + t * nx) * 4), 0, r.width - 1), y = std::clamp(int((cy + t * ny) * 4), 0, r.height - 1);
      c.push_back({r.at(x, y, 0), r.at(x, y, 1), r.at(x, y, 2)});
    }
    std::array<double, 3> d{};
    double d2 = 0;
    for (int ch = 0; ch < 3; ++ch) d[ch] = c.back()[ch] - c.front()[ch], d2 += d[ch] * d[ch];
    std::vector<double> s;
    for (const auto& col : c)
      s.push_back(((col[0] - c.front()[0]) * d[0] + (col[1] - c.front()[1]) * d[1] + (col[2] - c.front()[2]) * d[2]) / d2);
    auto first_above = [&](double level) {
      for (size_t k = 0; k < s.size(); ++k)
        if (s[k] >= level) return -4 + k * 0.025;
      return 4.0;
    };
    return first_above(0.9) - first_above(0.1);
  };
  const double before = width(image), after = width(*sharp);
  INFO("transition " << before << " px -> " << after << " px");
  CHECK(after < 0.5 * before);
}

TEST_CASE("identity edits give byte-identical files", "[edit][roundtrip]") {
  const Image image = edit_test::VectorizedSample();
  REQUIRE(!image.pairs.empty());
  const std::vector<uint8_t> raw = EncodeImage(image, nullptr).value();
  const Image decoded = DecodeImage(raw, "raw").value();
  DeformOp still;
  still.handles = {{std::nullopt, {30, 20}, {30, 20}}, {std::nullopt, {60, 40}, {60, 40}}};
  const std::vector<EditStep> identity = {
      Step(TranslateOp{Selection{}, 0, 0}),
      Step(ScaleColorOp{Selection{}, {1, 1, 1}}),
      Step(AddColorOp{Selection{}, {0, 0, 0}}),
      Step(HslShiftOp{Selection{}, 0, 0, 0}),
      Step(SetSharpnessOp{0, decoded.pairs[0].sharpness}),
      Step(AffineOp{}),
      Step(still),
  };
  auto edited = ApplyEdits(decoded, identity);
  REQUIRE(edited.ok());
  CHECK(EncodeImage(*edited, nullptr).value() == raw);
  // Through a Draco payload: decode, identity edits, the same image; encoded again with the
  // payload's own settings (and its vertex order) it decodes to that image again. (The bytes
  // differ: Draco renumbers vertices along its traversal, so `sdvi edit` copies the input
  // when nothing changed; see spec/EDIT.md.)
  CompressOptions draco;
  const std::vector<uint8_t> compressed = EncodeImage(image, &draco).value();
  const Image from_draco = DecodeImage(compressed, "draco").value();
  auto edited_draco = ApplyEdits(from_draco, identity);
  REQUIRE(edited_draco.ok());
  CHECK(*edited_draco == from_draco);
  const SdviFile file = DecodeSdvi(compressed, "draco").value();
  const DracoPayloadInfo info = InspectDracoPayload(file.compressed_payload, "draco").value();
  CompressOptions same;
  same.position_bits = info.position_bits;
  same.color_bits = info.color_bits;
  same.speed = info.speed;
  same.keep_vertex_order = true;
  CHECK(DecodeImage(EncodeImage(*edited_draco, &same).value(), "again").value() == from_draco);
}

TEST_CASE("edits round trip through the file and its Draco payload", "[edit][roundtrip]") {
  const Image image = edit_test::VectorizedSample();
  DeformOp warp;
  warp.handles = {{std::nullopt, {48, 32}, {50, 33}}};
  Selection region;
  region.kind = Selection::Kind::kRegion;
  region.region = {{10, 10}, {40, 10}, {40, 40}, {10, 40}};
  auto edited = ApplyEdits(image, {Step(SetSharpnessOp{0, 1.0}), Step(HslShiftOp{region, 90, 0.1, 0}), Step(warp)});
  REQUIRE(edited.ok());
  REQUIRE(!(*edited == image));
  // Raw: exact.
  const std::vector<uint8_t> raw = EncodeImage(*edited, nullptr).value();
  CHECK(DecodeImage(raw, "raw").value() == CanonicalizeImage(*edited));
  // Draco: topology, feature layer and sharpness exact; positions and colours within the bound.
  CompressOptions options;
  options.keep_vertex_order = true;
  const Image back = DecodeImage(EncodeImage(*edited, &options).value(), "draco").value();
  REQUIRE(back.vertices.size() == edited->vertices.size());
  CHECK(back.pairs == edited->pairs);
  CHECK(back.polylines == edited->polylines);
  const ErrorBound bound = CompressionErrorBound(*edited, DefaultPositionBits(*edited), DefaultColorBits(*edited));
  for (size_t i = 0; i < back.vertices.size(); ++i) {
    const Vertex &a = back.vertices[i], &b = edited->vertices[i];
    CHECK(std::fabs(a.x - b.x) <= bound.position + 1e-6);
    CHECK(std::fabs(a.y - b.y) <= bound.position + 1e-6);
    CHECK(std::fabs(a.r - b.r) <= bound.color + 1e-4);
  }
}

TEST_CASE("an edit that folds a triangle is refused, naming it", "[edit][validity]") {
  const Image image = edit_test::StraightEdge(64, 48, 0.5f);
  // An interior vertex far from the pair, moved 12 px right: over its neighbours.
  uint32_t v = 0;
  double best = 1e9;
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const double d = std::hypot(image.vertices[i].x - 12, image.vertices[i].y - 24);
    if (d < best) best = d, v = uint32_t(i);
  }
  SetPositionsOp move{{v}, {{image.vertices[v].x + 12.0, image.vertices[v].y}}};
  Image moved = image;
  REQUIRE(ApplyEditOp(move, {}, &moved).ok());
  size_t first_flip = moved.triangles.size();
  for (size_t t = 0; t < moved.triangles.size() && first_flip == moved.triangles.size(); ++t)
    if ((Area2(image, image.triangles[t]) > 0) != (Area2(moved, moved.triangles[t]) > 0)) first_flip = t;
  REQUIRE(first_flip < moved.triangles.size());
  auto refused = ApplyEdits(image, {{"ops[0] (set_positions)", move}});
  REQUIRE(!refused.ok());
  CHECK(refused.status().code() == StatusCode::kEditRefused);
  const std::string m = refused.status().message();
  INFO(m);
  CHECK(m.find("ops[0] (set_positions)") == 0);
  CHECK(m.find("fold") != std::string::npos);
  CHECK(m.find("triangle " + std::to_string(first_flip) + " (vertices") != std::string::npos);
}

TEST_CASE("edits that degenerate a triangle or cross features are refused", "[edit][validity]") {
  // Degenerate: a vertex of triangle 0 moved onto the line of its other two.
  const Image image = edit_test::StraightEdge(64, 48, 0.5f);
  const Triangle t = image.triangles[0];
  const Vertex &a = image.vertices[t.v[1]], &b = image.vertices[t.v[2]];
  auto flat = ApplyEdits(image, {Step(SetPositionsOp{{t.v[0]}, {{(a.x + b.x) / 2.0, (a.y + b.y) / 2.0}}})});
  REQUIRE(!flat.ok());
  CHECK(flat.status().code() == StatusCode::kEditRefused);
  INFO(flat.status().message());
  CHECK((flat.status().message().find("degenerate") != std::string::npos ||
         flat.status().message().find("fold") != std::string::npos));
  CHECK(flat.status().message().find("triangle 0 (vertices") != std::string::npos);

  // Crossing without a fold: two separate triangles, each edge a crease; one slides over the other.
  Image two;
  two.width = two.height = 20;
  two.vertices = {{2, 2}, {8, 2}, {2, 8}, {12, 2}, {18, 2}, {12, 8}};
  two.triangles = {{{0, 1, 2}}, {{3, 4, 5}}};
  two.polylines = {{{0, 1, 2}, true}, {{3, 4, 5}, true}};
  two.crease_edges = {Edge::Of(0, 1), Edge::Of(1, 2), Edge::Of(0, 2), Edge::Of(3, 4), Edge::Of(4, 5), Edge::Of(3, 5)};
  Selection second;
  second.kind = Selection::Kind::kPolyline;
  second.id = 1;
  auto crossed = ApplyEdits(two, {Step(TranslateOp{second, -7, 1})});
  REQUIRE(!crossed.ok());
  CHECK(crossed.status().code() == StatusCode::kEditRefused);
  INFO(crossed.status().message());
  CHECK(crossed.status().message().find("cross") != std::string::npos);
  CHECK(crossed.status().message().find("of polyline 0") != std::string::npos);
  CHECK(crossed.status().message().find("of polyline 1") != std::string::npos);
  // Moved apart instead: fine.
  CHECK(ApplyEdits(two, {Step(TranslateOp{second, 1, 1})}).ok());
}

TEST_CASE("a fold is re-triangulated by edge flips when asked", "[edit][validity]") {
  // A square split along (0, 2); vertex 1 pulled over the diagonal folds triangle 0.
  Image square;
  square.width = square.height = 10;
  square.vertices = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  square.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  const std::vector<EditStep> pull = {Step(SetPositionsOp{{1}, {{4, 6}}})};
  auto refused = ApplyEdits(square, pull);
  REQUIRE(!refused.ok());
  CHECK(refused.status().code() == StatusCode::kEditRefused);
  EditOptions repair;
  repair.repair_folds = true;
  auto repaired = ApplyEdits(square, pull, repair);
  REQUIRE(repaired.ok());
  // The diagonal is now (1, 3), both triangles counter-clockwise like the input's.
  CHECK(repaired->triangles[0] == Triangle{{1, 2, 3}});
  CHECK(repaired->triangles[1] == Triangle{{3, 0, 1}});
  for (const Triangle& t : repaired->triangles) CHECK(Area2(*repaired, t) > 0);
  // A crease diagonal is never flipped: still refused.
  square.crease_edges = {Edge::Of(0, 2)};
  CHECK(ApplyEdits(square, pull, repair).status().code() == StatusCode::kEditRefused);
}

TEST_CASE("a rotation by 90 degrees renders as the rotated render", "[edit][affine]") {
  const Image image = edit_test::VectorizedSample(96, 64);
  const int w = int(image.width), h = int(image.height);
  AffineOp rotate;  // (x, y) -> (h - y, x): pixel (i, j) goes to (h - 1 - j, i)
  rotate.matrix = {0, -1, double(h), 1, 0, 0};
  rotate.new_width = uint32_t(h);
  rotate.new_height = uint32_t(w);
  auto rotated = ApplyEdits(image, {Step(rotate)});
  REQUIRE(rotated.ok());
  const Raster original = RenderAt(image), turned = RenderAt(*rotated);
  REQUIRE(turned.width == h);
  REQUIRE(turned.height == w);
  Raster expected(h, w, original.channels);
  for (int j = 0; j < original.height; ++j)
    for (int i = 0; i < original.width; ++i)
      for (int c = 0; c < original.channels; ++c) expected.at(h - 1 - j, i, c) = original.at(i, j, c);
  const ImageMetrics m = CompareImages(turned, expected).value();
  INFO("PSNR " << m.psnr << " dB");
  CHECK(m.psnr >= 45.0);
}

TEST_CASE("a deformation keeps every triangle's orientation and hits its handles", "[edit][deform]") {
  const Image image = edit_test::VectorizedSample();
  // Move three deBoor points of the longest pair's first polyline by 3 px.
  const std::vector<FeatureInfo> features = ListFeatures(image);
  const FeatureInfo* longest = nullptr;
  for (const FeatureInfo& f : features)
    if (f.kind == FeatureKind::kPair && (!longest || f.length > longest->length)) longest = &f;
  REQUIRE(longest != nullptr);
  const auto& deboor = image.polylines[longest->first].vertices;
  REQUIRE(deboor.size() >= 3);
  DeformOp warp;
  for (size_t k : {size_t(0), deboor.size() / 2, deboor.size() - 1}) {
    const Vertex& v = image.vertices[deboor[k]];
    warp.handles.push_back({deboor[k], {}, {v.x + 3.0, v.y - 2.0}});
  }
  auto warped = ApplyEdits(image, {Step(warp)});
  REQUIRE(warped.ok());
  size_t flips = 0, moved = 0;
  for (size_t t = 0; t < image.triangles.size(); ++t)
    if ((Area2(image, image.triangles[t]) > 0) != (Area2(*warped, warped->triangles[t]) > 0)) ++flips;
  for (size_t i = 0; i < image.vertices.size(); ++i)
    if (!(image.vertices[i] == warped->vertices[i])) ++moved;
  CHECK(flips == 0);
  CHECK(moved > 10);
  for (const DeformHandle& h : warp.handles) {
    CHECK(warped->vertices[*h.vertex].x == float(h.to.x));
    CHECK(warped->vertices[*h.vertex].y == float(h.to.y));
  }
  // Boundary vertices are pinned by default: the frame's corners stay.
  size_t corners = 0;
  for (const Vertex& v : image.vertices)
    if ((v.x == 0 || v.x == 96) && (v.y == 0 || v.y == 64)) ++corners;
  size_t kept = 0;
  for (const Vertex& v : warped->vertices)
    if ((v.x == 0 || v.x == 96) && (v.y == 0 || v.y == 64)) ++kept;
  CHECK(corners == 4);
  CHECK(kept == 4);
}

TEST_CASE("colour operations: set, add, scale, HSL", "[edit][colour]") {
  Image image;
  image.width = image.height = 4;
  image.vertices = {{0, 0, 255, 0, 0}, {4, 0, 100, 50, 25}, {0, 4, 300, -10, 128}};
  image.triangles = {{{0, 1, 2}}};
  Selection v0;
  v0.kind = Selection::Kind::kVertices;
  v0.vertices = {0};
  auto hue = ApplyEdits(image, {Step(HslShiftOp{v0, 120, 0, 0})});
  REQUIRE(hue.ok());
  CHECK(hue->vertices[0].r == Approx(0).margin(1e-3));
  CHECK(hue->vertices[0].g == Approx(255).margin(1e-3));
  CHECK(hue->vertices[0].b == Approx(0).margin(1e-3));
  CHECK(hue->vertices[1] == image.vertices[1]);  // not selected
  // Lightness +0.5 of pure red: l 0.5 -> 1: white.
  auto light = ApplyEdits(image, {Step(HslShiftOp{v0, 0, 0, 0.5})});
  REQUIRE(light.ok());
  CHECK(light->vertices[0].g == Approx(255).margin(1e-3));
  // Overshoot outside 0..255 survives a zero shift exactly.
  auto zero = ApplyEdits(image, {Step(HslShiftOp{Selection{}, 0, 0, 0})});
  REQUIRE(zero.ok());
  CHECK(zero->vertices == image.vertices);
  auto arithmetic = ApplyEdits(image, {Step(SetColorOp{v0, {1, 2, 3}}), Step(AddColorOp{Selection{}, {10, 0, 0}}),
                                       Step(ScaleColorOp{Selection{}, {2, 1, 0.5}})});
  REQUIRE(arithmetic.ok());
  CHECK(arithmetic->vertices[0].r == 22.f);
  CHECK(arithmetic->vertices[0].g == 2.f);
  CHECK(arithmetic->vertices[0].b == 1.5f);
  CHECK(arithmetic->vertices[1].r == 220.f);
  // Positions untouched.
  for (size_t i = 0; i < 3; ++i) CHECK(arithmetic->vertices[i].x == image.vertices[i].x);
}

TEST_CASE("selections: vertices, polyline, pair, region, all; unknown ids are named", "[edit][selection]") {
  const Image image = edit_test::StraightEdge(64, 48, 0.5f);
  Selection s;
  CHECK(ResolveSelection(image, s)->size() == image.vertices.size());
  s.kind = Selection::Kind::kPair;
  s.id = 0;
  const auto pair = ResolveSelection(image, s).value();
  CHECK(pair.size() == image.polylines[image.pairs[0].first].vertices.size() * 2);
  s.id = 5;
  auto missing = ResolveSelection(image, s);
  REQUIRE(!missing.ok());
  CHECK(missing.status().message() == "pair 5 does not exist (the image has 1 pairs)");
  s.kind = Selection::Kind::kRegion;  // the left half, strictly inside
  s.region = {{-1, -1}, {32, -1}, {32, 49}, {-1, 49}};
  const std::vector<uint32_t> left = ResolveSelection(image, s).value();
  CHECK(!left.empty());
  for (uint32_t v : left) CHECK(image.vertices[v].x < 32);
  s.kind = Selection::Kind::kVertices;
  s.vertices = {3, 1, 3};
  CHECK(ResolveSelection(image, s).value() == std::vector<uint32_t>{1, 3});
  s.vertices = {uint32_t(image.vertices.size())};
  CHECK(ResolveSelection(image, s).status().code() == StatusCode::kInvalidArgument);
  auto bad_pair = ApplyEdits(image, {{"ops[3] (set_sharpness)", SetSharpnessOp{7, 1}}});
  REQUIRE(!bad_pair.ok());
  CHECK(bad_pair.status().message() == "ops[3] (set_sharpness): pair 7 does not exist (the image has 1 pairs)");
}

TEST_CASE("the feature list and the overlay show every feature", "[edit][features]") {
  const Image image = edit_test::StraightEdge(64, 48, 0.25f);
  const std::vector<FeatureInfo> list = ListFeatures(image);
  REQUIRE(list.size() == image.pairs.size() + image.polylines.size());
  CHECK(list[0].kind == FeatureKind::kPair);
  CHECK(list[0].sharpness == 0.25f);
  CHECK(list[0].length == Approx(44).margin(1e-3));  // the centre polygon: y from 2 to 46
  CHECK(list[0].box.min_x == Approx(32 - 5 * 0.75 / 2).margin(1e-4));
  size_t boundaries = 0, sides = 0;
  for (const FeatureInfo& f : list) {
    boundaries += f.kind == FeatureKind::kBoundary;
    sides += f.kind == FeatureKind::kPairSide;
  }
  CHECK(boundaries == 1);  // the image rectangle
  CHECK(sides == 2);
  const Raster render = RenderAt(image);
  const Raster overlay = DrawFeatureOverlay(render, image, Viewport::Identity(64, 48));
  REQUIRE(overlay.width == 64);
  REQUIRE(overlay.channels == 3);
  // The pair's lines are drawn: pixels on its left side are no longer the flat 40 grey.
  const int x = int(std::lround(32 - 5 * 0.75 / 2));
  CHECK(std::fabs(overlay.at(x, 30, 0) - overlay.at(x, 30, 1)) > 20);
}

TEST_CASE("an edit that leaves values no file holds is refused, naming the vertex", "[edit][validity]") {
  // The fuzzer's find: a frame change whose matrix moves vertices far outside the new frame
  // succeeded, and the result could not be written (spec/FORMAT.md section 9, check 20).
  const Image image = edit_test::StraightEdge(64, 48, 0.5f);
  AffineOp stretch;
  stretch.matrix = {8, -2, 48, 1, 0, 0};  // x' = 8x - 2y + 48 reaches 560 in a 48 px frame
  stretch.new_width = 48;
  stretch.new_height = 64;
  auto far = ApplyEdits(image, {Step(stretch)});
  REQUIRE(!far.ok());
  CHECK(far.status().code() == StatusCode::kEditRefused);
  INFO(far.status().message());
  CHECK(far.status().message().find("out of range: vertex ") != std::string::npos);
  CHECK(far.status().message().find("more than one image size outside the 48 x 64 image") != std::string::npos);
  // The same frame change without the stretch is fine, and so is every value it leaves.
  AffineOp turn = stretch;
  turn.matrix = {0, -1, 48, 1, 0, 0};
  auto turned = ApplyEdits(image, {Step(turn)});
  REQUIRE(turned.ok());
  CHECK(CheckImageValues(*turned, "turned").ok());
  // Colours: scaled 8 times, the light side (200) goes to 1600, past 255 + 1024.
  ScaleColorOp bright;
  bright.factor = {8, 8, 8};
  auto glare = ApplyEdits(image, {Step(bright)});
  REQUIRE(!glare.ok());
  CHECK(glare.status().code() == StatusCode::kEditRefused);
  CHECK(glare.status().message().find("has colour (1600, 1600, 1600)") != std::string::npos);
  bright.factor = {6, 6, 6};  // 1200 <= 1279: allowed
  CHECK(ApplyEdits(image, {Step(bright)}).ok());
}
