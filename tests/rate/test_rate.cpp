// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/color_fit.h"
#include "sdvi/rate.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/vectorize.h"
#include "sliver_mesh.h"

namespace {

// A small vectorized sample (fast: 96 x 72 pixels).
const sdvi::VectorizeResult& Sample(sdvi::Raster* source = nullptr) {
  static const sdvi::Raster raster = sdvi::MakeSampleImage(96, 72);
  static const sdvi::VectorizeResult result = [] {
    sdvi::VectorizeOptions options;
    options.compression_ratio = 20;
    auto r = sdvi::Vectorize(raster, nullptr, options);
    REQUIRE(r.ok());
    return std::move(r).value();
  }();
  if (source) *source = raster;
  return result;
}

double Mse(double psnr) { return 255.0 * 255.0 / std::pow(10.0, psnr / 10.0); }

// spec/RATE.md 3 step by step: the positions a reader decodes at these bits (the vertex
// order kept), the colours fitted to them.
sdvi::Image QuantisedRefit(const sdvi::Image& image, const sdvi::Raster& source, const sdvi::CompressOptions& bits) {
  sdvi::CompressOptions ordered = bits;
  ordered.keep_vertex_order = true;
  auto file = sdvi::EncodeImage(image, &ordered);
  REQUIRE(file.ok());
  auto decoded = sdvi::DecodeImage(*file, "ordered");
  REQUIRE(decoded.ok());
  REQUIRE(decoded->vertices.size() == image.vertices.size());
  sdvi::Image out = image;
  for (size_t i = 0; i < out.vertices.size(); ++i) {
    REQUIRE(std::abs(decoded->vertices[i].x - image.vertices[i].x) < 0.5f);  // the same vertex
    out.vertices[i].x = decoded->vertices[i].x;
    out.vertices[i].y = decoded->vertices[i].y;
  }
  REQUIRE(sdvi::FitColors(out, source, nullptr, {}).ok());
  return out;
}

// The vertex positions of an image, sorted (independent of the vertex numbering).
std::vector<std::pair<float, float>> Positions(const sdvi::Image& image) {
  std::vector<std::pair<float, float>> out;
  for (const sdvi::Vertex& v : image.vertices) out.push_back({v.x, v.y});
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("RoundTo8Bit rounds colours to 0..255 integers and alpha to 1/255 steps", "[rate]") {
  sdvi::Raster r(2, 1, 4);
  const float values[8] = {-3.f, 12.5f, 300.f, 0.4999f, 254.49f, 0.2f, 1e9f, 1.5f};
  std::copy(values, values + 8, r.data.begin());
  sdvi::RoundTo8Bit(r);
  CHECK(r.data[0] == 0.f);
  CHECK(r.data[1] == 13.f);  // half away from zero
  CHECK(r.data[2] == 255.f);
  CHECK(r.data[3] == std::round(0.4999f * 255.f) / 255.f);
  CHECK(r.data[4] == 254.f);
  CHECK(r.data[5] == 0.f);
  CHECK(r.data[6] == 255.f);
  CHECK(r.data[7] == 1.f);  // alpha clamped to 1
}

TEST_CASE("SlopeFromHistory takes the last round that grew the mesh by 5%", "[rate]") {
  sdvi::VectorizeReport report;
  CHECK(sdvi::SlopeFromHistory(report) == 4.0);
  report.history = {{100, 0, 0, 20.0, {}}, {200, 0, 0, 23.0, {}}, {205, 0, 0, 23.1, {}}};
  // 205 / 200 < 1.05: the slope is that of 100 -> 200 vertices.
  CHECK(sdvi::SlopeFromHistory(report) == Approx(3.0 / std::log(2.0)));
  report.history = {{100, 0, 0, 20.0, {}}, {110, 0, 0, 30.0, {}}};
  CHECK(sdvi::SlopeFromHistory(report) == 12.0);  // clamped
  report.history = {{100, 0, 0, 20.0, {}}, {200, 0, 0, 19.0, {}}};
  CHECK(sdvi::SlopeFromHistory(report) == 1.0);
}

TEST_CASE("without the search the file is v1's conservative Draco file, byte for byte", "[rate]") {
  sdvi::Raster source;
  const sdvi::VectorizeResult& v = Sample(&source);
  sdvi::RateOptions options;
  options.search_bits = false;
  options.refit_colors = false;
  auto r = sdvi::CompressForRate(v, source, nullptr, {}, options);
  REQUIRE(r.ok());
  sdvi::CompressOptions v1;
  v1.reference_mse = Mse(v.report.psnr);
  v1.color_coding = options.color_coding;  // the smallest coding (which may stream positions, payload 1.4)
  auto expected = sdvi::EncodeImage(v.image, &v1);
  REQUIRE(expected.ok());
  CHECK(r->file == *expected);
  CHECK(r->evaluations == 1);
}

TEST_CASE("one PSNR: the result's, the decoded file's render and its PNG agree exactly", "[rate]") {
  sdvi::Raster source;
  const sdvi::VectorizeResult& v = Sample(&source);
  sdvi::RateOptions options;
  auto r = sdvi::CompressForRate(v, source, nullptr, {}, options);
  REQUIRE(r.ok());
  auto decoded = sdvi::DecodeImage(r->file, "test");
  REQUIRE(decoded.ok());
  CHECK(*decoded == r->decoded);
  // Independently: render at x1 (default levels), write the PNG, read it back, compare.
  sdvi::RenderOptions render;
  render.viewport = sdvi::Viewport::Identity(int(decoded->width), int(decoded->height));
  auto raster = sdvi::Render(*decoded, render);
  REQUIRE(raster.ok());
  const std::string png = (std::filesystem::temp_directory_path() / "sdvi_rate_test.png").string();
  REQUIRE(sdvi::SaveRasterPng(png, *raster).ok());
  auto loaded = sdvi::LoadRaster(png);
  REQUIRE(loaded.ok());
  auto from_png = sdvi::CompareImages(*loaded, source);
  REQUIRE(from_png.ok());
  CHECK(r->psnr == from_png->psnr);
  auto file_psnr = sdvi::FileQualityPsnr(*decoded, source, 1);
  REQUIRE(file_psnr.ok());
  CHECK(*file_psnr == r->psnr);
}

TEST_CASE("the RD search never ends at a higher Lagrangian cost than its start", "[rate]") {
  sdvi::Raster source;
  const sdvi::VectorizeResult& v = Sample(&source);
  sdvi::RateOptions start;
  start.search_bits = false;
  auto first = sdvi::CompressForRate(v, source, nullptr, {}, start);
  REQUIRE(first.ok());
  sdvi::RateOptions search;
  auto best = sdvi::CompressForRate(v, source, nullptr, {}, search);
  REQUIRE(best.ok());
  CHECK(best->slope_db == first->slope_db);
  auto cost = [&](const sdvi::RateResult& r) { return std::log(double(r.file.size())) - r.psnr / r.slope_db; };
  CHECK(cost(*best) <= cost(*first));
  CHECK(best->position_bits <= first->position_bits);
  CHECK(best->color_bits <= first->color_bits);
  // The file is what the rule of spec/RATE.md 3 gives at the chosen bits, computed here
  // without the search's reuse of refits: the vectorized image, or its positions quantised
  // and colours refitted, encoded.
  sdvi::CompressOptions chosen;
  chosen.position_bits = best->position_bits;
  chosen.color_bits = best->color_bits;
  chosen.color_coding = search.color_coding;
  sdvi::Image image = v.image;
  if (best->mended_vertices > 0) {  // plain rounding folds at these bits: the mended grid
    auto mended = sdvi::SnapPositionsToGrid(v.image, chosen.position_bits);
    REQUIRE(mended.ok());
    image = *mended;
  }
  if (best->colors_refitted) {
    image = QuantisedRefit(image, source, chosen);
  }
  auto expected = sdvi::EncodeImage(image, &chosen);
  REQUIRE(expected.ok());
  CHECK(*expected == best->file);
  // Deterministic.
  auto again = sdvi::CompressForRate(v, source, nullptr, {}, search);
  REQUIRE(again.ok());
  CHECK(again->file == best->file);
}

TEST_CASE("MeasureParts: raw parts are exact and both payloads sum to the file", "[rate][codec]") {
  const sdvi::Image& image = Sample().image;
  REQUIRE(!image.polylines.empty());
  auto raw = sdvi::EncodeImage(image, nullptr);
  REQUIRE(raw.ok());
  auto parts = sdvi::MeasureParts(*raw, "raw");
  REQUIRE(parts.ok());
  CHECK(parts->positions == 8 * image.vertices.size());
  CHECK(parts->colors == 12 * image.vertices.size());
  CHECK(parts->connectivity == 6 * image.triangles.size());
  CHECK(parts->tags == 4 * image.corners.size());
  sdvi::Image bare = image;
  bare.polylines.clear();
  bare.pairs.clear();
  auto smaller = sdvi::EncodeImage(bare, nullptr);
  REQUIRE(smaller.ok());
  CHECK(parts->feature_layer == raw->size() - smaller->size());
  auto sum = [](const sdvi::PartBytes& p) {
    return p.connectivity + p.positions + p.colors + p.tags + p.feature_layer + p.container;
  };
  CHECK(sum(*parts) == raw->size());

  sdvi::CompressOptions with_layer, without_layer;
  without_layer.feature_layer = false;
  auto draco = sdvi::EncodeImage(image, &with_layer);
  auto draco_bare = sdvi::EncodeImage(image, &without_layer);
  REQUIRE(draco.ok());
  REQUIRE(draco_bare.ok());
  auto a = sdvi::MeasureParts(*draco, "draco");
  auto b = sdvi::MeasureParts(*draco_bare, "draco without layer");
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(sum(*a) == draco->size());
  CHECK(sum(*b) == draco_bare->size());
  CHECK(a->feature_layer > 0);
  CHECK(b->feature_layer == 0);
  // The feature layer first (payload 1.2): crease edges along its polylines cost less than
  // alone; crease edges first (payload 1.1): the same tag bytes as without the layer.
  CHECK(a->tags < b->tags);
  sdvi::CompressOptions crease_first;
  crease_first.features_first = false;
  auto draco_11 = sdvi::EncodeImage(image, &crease_first);
  REQUIRE(draco_11.ok());
  auto c = sdvi::MeasureParts(*draco_11, "draco 1.1");
  REQUIRE(c.ok());
  CHECK(sum(*c) == draco_11->size());
  CHECK(c->tags == b->tags);
  CHECK(c->feature_layer > 0);
  CHECK(a->connectivity > 0);
  CHECK(a->positions > 0);
  CHECK(a->colors > 0);
  // A damaged file is an error naming it.
  std::vector<uint8_t> cut(draco->begin(), draco->begin() + draco->size() / 2);
  auto bad = sdvi::MeasureParts(cut, "cut.sdvi");
  REQUIRE(!bad.ok());
  CHECK(bad.status().message().find("cut.sdvi") != std::string::npos);
}

TEST_CASE("BudgetForQuality: 400 px per vertex at 0, 40 at 50, 4 at 100, strictly decreasing", "[rate]") {
  CHECK(sdvi::BudgetForQuality(0) == Approx(400));
  CHECK(sdvi::BudgetForQuality(50) == Approx(40));
  CHECK(sdvi::BudgetForQuality(100) == Approx(4));
  for (int q = 1; q <= 100; ++q) CHECK(sdvi::BudgetForQuality(q) < sdvi::BudgetForQuality(q - 1));
}

TEST_CASE("VectorizeForTarget needs exactly one valid target", "[rate]") {
  sdvi::Raster source;
  Sample(&source);
  const sdvi::VectorizeOptions options;
  sdvi::RateTarget none, two, bad;
  two.quality = 50;
  two.bytes = 1000;
  bad.quality = 101;
  for (const auto& t : {none, two, bad}) {
    auto r = sdvi::VectorizeForTarget(source, nullptr, options, t, {});
    REQUIRE(!r.ok());
    CHECK(r.status().code() == sdvi::StatusCode::kInvalidArgument);
  }
}

TEST_CASE("a byte target is met by the file, or reported as not reached", "[rate]") {
  sdvi::Raster source;
  Sample(&source);
  sdvi::VectorizeOptions options;
  sdvi::RateTarget target;
  target.bytes = 2500;
  auto r = sdvi::VectorizeForTarget(source, nullptr, options, target, {});
  REQUIRE(r.ok());
  CHECK(r->reached);
  CHECK(r->file.file.size() <= target.bytes);
  CHECK(r->vectorize_runs >= 2);
  target.bytes = 10;  // below any file
  auto tiny = sdvi::VectorizeForTarget(source, nullptr, options, target, {});
  REQUIRE(tiny.ok());
  CHECK(!tiny->reached);
  CHECK(tiny->file.file.size() > 10);
  CHECK(tiny->note.find("more than 10") != std::string::npos);
}

TEST_CASE("a PSNR target is reached by the file's PSNR, or reported as not reached", "[rate]") {
  sdvi::Raster source;
  Sample(&source);
  sdvi::VectorizeOptions options;
  options.compression_ratio = 10;
  sdvi::RateTarget target;
  target.psnr = 28;
  auto r = sdvi::VectorizeForTarget(source, nullptr, options, target, {});
  REQUIRE(r.ok());
  CHECK(r->reached);
  CHECK(r->file.psnr >= 28);
  auto again = sdvi::FileQualityPsnr(r->file.decoded, source, 1);
  REQUIRE(again.ok());
  CHECK(*again == r->file.psnr);
  target.psnr = 95;
  auto high = sdvi::VectorizeForTarget(source, nullptr, options, target, {});
  REQUIRE(high.ok());
  CHECK(!high->reached);
  CHECK(high->file.psnr < 95);
  CHECK(high->note.find("not reached") != std::string::npos);
}

TEST_CASE("colours refitted on the quantised positions: at equal bits the file's PSNR is at least the unrefitted one's",
          "[rate]") {
  sdvi::Raster source;
  const sdvi::VectorizeResult& v = Sample(&source);
  const double mse = Mse(v.report.psnr);
  const int color_bits = sdvi::DefaultColorBits(v.image, mse);
  int tried = 0;
  // From the conservative position step down to coarse ones (where quantisation moves the
  // positions by up to a pixel and the refit has something to absorb); bits that fold a
  // triangle give no file and are skipped.
  for (int drop = 0; drop <= 6; drop += 2) {
    sdvi::CompressOptions bits;
    bits.position_bits = sdvi::DefaultPositionBits(v.image, mse) - drop;
    bits.color_bits = color_bits;
    auto plain = sdvi::EncodeImage(v.image, &bits);
    if (!plain.ok() && plain.status().code() == sdvi::StatusCode::kFoldedTriangle) continue;
    REQUIRE(plain.ok());
    auto plain_decoded = sdvi::DecodeImage(*plain, "plain");
    REQUIRE(plain_decoded.ok());
    auto refit = sdvi::EncodeImage(QuantisedRefit(v.image, source, bits), &bits);
    REQUIRE(refit.ok());
    auto refit_decoded = sdvi::DecodeImage(*refit, "refit");
    REQUIRE(refit_decoded.ok());
    // The positions are those of the unrefitted file (re-encoding keeps them on their grid;
    // edgebreaker may number them differently).
    CHECK(Positions(*refit_decoded) == Positions(*plain_decoded));
    auto plain_psnr = sdvi::FileQualityPsnr(*plain_decoded, source, 1);
    auto refit_psnr = sdvi::FileQualityPsnr(*refit_decoded, source, 1);
    REQUIRE(plain_psnr.ok());
    REQUIRE(refit_psnr.ok());
    INFO("position bits " << bits.position_bits << ": " << *plain_psnr << " dB unrefitted, " << *refit_psnr
                          << " dB refitted");
    // The refit minimises the fit's least squares (with its regulariser) before colour
    // quantisation and clamping, which may cost it a few thousandths of a dB where the
    // positions barely moved (the conservative step).
    CHECK(*refit_psnr >= *plain_psnr - 0.01);
    ++tried;
  }
  CHECK(tried >= 2);

  // CompressForRate at the conservative steps (no search), refit on and off: the same bits,
  // the result with the refit at no higher cost J (it keeps the better of the two files),
  // and byte-identical when run again or on more threads.
  sdvi::RateOptions on, off;
  on.search_bits = off.search_bits = false;
  off.refit_colors = false;
  auto with = sdvi::CompressForRate(v, source, nullptr, {}, on);
  auto without = sdvi::CompressForRate(v, source, nullptr, {}, off);
  REQUIRE(with.ok());
  REQUIRE(without.ok());
  CHECK(with->position_bits == without->position_bits);
  CHECK(with->color_bits == without->color_bits);
  auto cost = [&](const sdvi::RateResult& r) { return std::log(double(r.file.size())) - r.psnr / r.slope_db; };
  CHECK(cost(*with) <= cost(*without));
  if (!with->colors_refitted) CHECK(with->file == without->file);
  auto again = sdvi::CompressForRate(v, source, nullptr, {}, on);
  REQUIRE(again.ok());
  CHECK(again->file == with->file);
  on.threads = 2;
  auto threaded = sdvi::CompressForRate(v, source, nullptr, {}, on);
  REQUIRE(threaded.ok());
  CHECK(threaded->file == with->file);
}

TEST_CASE("a sliver that folds at the start's bits is mended there: the whole mesh keeps its bits", "[rate]") {
  // The sliver mesh of tests/support/sliver_mesh.h, at a step where it folds.
  sdvi::VectorizeResult v;
  v.report.psnr = 30;  // the start: a coarse position step (DefaultPositionBits of this MSE)
  const double mse = Mse(v.report.psnr);
  const int bits = sdvi::DefaultPositionBits(sdvi::testing::SliverImage(32, 32, 0), mse);
  const float step = 64.f / float((1 << bits) - 1);
  auto folds = [&](const sdvi::Image& image, int b) {
    sdvi::CompressOptions options;
    options.position_bits = b;
    auto file = sdvi::EncodeImage(image, &options);
    return !file.ok() && file.status().code() == sdvi::StatusCode::kFoldedTriangle;
  };
  auto found = sdvi::testing::FindFoldingSliver(step, [&](const sdvi::Image& image) { return folds(image, bits); });
  REQUIRE(found);
  v.image = *found;
  REQUIRE(sdvi::DefaultPositionBits(v.image, mse) == bits);
  sdvi::RenderOptions render;
  render.viewport = sdvi::Viewport::Identity(64, 64);
  auto source = sdvi::Render(v.image, render);
  REQUIRE(source.ok());

  sdvi::RateOptions start;
  start.search_bits = false;
  auto r = sdvi::CompressForRate(v, *source, nullptr, {}, start);
  REQUIRE(r.ok());
  CHECK(r->position_bits == bits);  // before the mend: raised until plain rounding unfolds
  CHECK(r->mended_vertices >= 1);
  CHECK(r->mended_vertices <= 2);
  auto decoded = sdvi::DecodeImage(r->file, "mended");
  REQUIRE(decoded.ok());
  CHECK(*decoded == r->decoded);
  CHECK(sdvi::ValidateImage(*decoded, "mended").ok());
  int plain_bits = bits;
  while (folds(v.image, plain_bits)) ++plain_bits;
  CHECK(plain_bits > bits);
  // Deterministic.
  auto again = sdvi::CompressForRate(v, *source, nullptr, {}, start);
  REQUIRE(again.ok());
  CHECK(again->file == r->file);
}
