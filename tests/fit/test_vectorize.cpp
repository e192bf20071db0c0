// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the vectorizer driver (vectorize.h): quality on small synthetic images, the
// budgets, determinism, object images, the refinement helpers and bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sdvi/render.h"
#include "sdvi/vectorize.h"

namespace {

// A smooth image: two gentle ramps and a Gaussian bump; RGB.
sdvi::Raster SmoothImage(int width, int height) {
  sdvi::Raster raster(width, height, 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double u = (x + 0.5) / width, v = (y + 0.5) / height;
      const double bump = std::exp(-((u - 0.4) * (u - 0.4) + (v - 0.6) * (v - 0.6)) * 8);
      raster.at(x, y, 0) = float(40 + 150 * u + 40 * bump);
      raster.at(x, y, 1) = float(60 + 120 * v);
      raster.at(x, y, 2) = float(200 - 90 * u * v + 30 * bump);
    }
  }
  return raster;
}

}  // namespace

TEST_CASE("vectorize reaches a PSNR bound on the built-in sample image", "[vectorize]") {
  const sdvi::Raster sample = sdvi::MakeSampleImage(128, 96);
  sdvi::VectorizeOptions options;
  options.compression_ratio = 16;
  auto result = sdvi::Vectorize(sample, nullptr, options);
  REQUIRE(result.ok());
  const sdvi::VectorizeReport& r = result->report;
  INFO("PSNR " << r.psnr << " dB, " << r.vertices << " vertices, " << r.triangles << " triangles");
  CHECK(r.psnr > 30.0);
  CHECK(r.mssim > 0.9);
  CHECK(r.pixels == 128u * 96u);
  CHECK(r.vertices == result->image.vertices.size());
  CHECK(r.triangles == result->image.triangles.size());
  CHECK(r.paper_size == 20ull * r.vertices + 6ull * r.triangles + 8);
  CHECK(r.feature_curves > 0);  // the disc, the triangle and the soft edge
  // The budget: about pixels / ratio vertices (the features may add a little).
  CHECK(r.vertices <= 1.25 * 128 * 96 / 16.0);
  // The report's reconstruction is what Render8 draws at the fit's level, and its metrics are
  // CompareImages' of those bytes (what `sdvi render --levels r` + `sdvi compare` print).
  REQUIRE(result->reconstruction.width == 128);
  REQUIRE(result->reconstruction.height == 96);
  CHECK(r.levels == 2);
  sdvi::RenderOptions render;
  render.viewport = sdvi::Viewport::Identity(128, 96);
  render.levels = r.levels;
  auto drawn = sdvi::Render8(result->image, render);
  REQUIRE(drawn.ok());
  CHECK(drawn->data == result->reconstruction.data);
  auto metrics = sdvi::CompareImages(*drawn, sample);
  REQUIRE(metrics.ok());
  CHECK(r.psnr == metrics->psnr);
  CHECK(r.mssim == metrics->mssim);
  CHECK(r.mean_error == metrics->mean_error);
  // fit_psnr is the last fit's own (before rounding to 8 bits).
  REQUIRE(!r.history.empty());
  CHECK(r.fit_psnr == r.history.back().psnr);
  CHECK(r.fit_psnr != r.psnr);
}

TEST_CASE("vectorize of a smooth image is accurate with few vertices", "[vectorize]") {
  const sdvi::Raster smooth = SmoothImage(96, 96);
  sdvi::VectorizeOptions options;
  options.compression_ratio = 48;
  auto result = sdvi::Vectorize(smooth, nullptr, options);
  REQUIRE(result.ok());
  INFO("PSNR " << result->report.psnr << " dB, " << result->report.vertices << " vertices");
  CHECK(result->report.psnr > 40.0);
  CHECK(result->report.vertices <= 96 * 96 / 48 + 40);
}

TEST_CASE("vectorize respects max-triangles and stops at a target PSNR", "[vectorize]") {
  const sdvi::Raster sample = sdvi::MakeSampleImage(128, 96);
  sdvi::VectorizeOptions capped;
  capped.max_triangles = 600;
  auto a = sdvi::Vectorize(sample, nullptr, capped);
  REQUIRE(a.ok());
  CHECK(a->report.triangles <= 600u);

  sdvi::VectorizeOptions target;
  target.compression_ratio = 8;
  target.target_psnr = 20;  // reached by the first fit
  auto b = sdvi::Vectorize(sample, nullptr, target);
  REQUIRE(b.ok());
  CHECK(b->report.iterations == 0);
  CHECK(b->report.history.size() == 1);
}

TEST_CASE("the tail stop ends the rounds with an earlier round's result", "[vectorize]") {
  const sdvi::Raster sample = sdvi::MakeSampleImage(128, 96);
  sdvi::VectorizeOptions all;
  all.compression_ratio = 16;
  all.min_round_growth = 0;  // every round runs
  auto full = sdvi::Vectorize(sample, nullptr, all);
  REQUIRE(full.ok());
  REQUIRE(full->report.iterations >= 2);
  // A stop that holds from the second round on (any round adds under 99% of the vertices,
  // and every gain is under 1e9 dB): one round runs, and its result is that of one round.
  sdvi::VectorizeOptions tail = all;
  tail.min_round_growth = 0.99;
  tail.min_round_gain = 1e9;
  auto stopped = sdvi::Vectorize(sample, nullptr, tail);
  REQUIRE(stopped.ok());
  CHECK(stopped->report.iterations == 1);
  sdvi::VectorizeOptions one = all;
  one.iterations = 1;
  auto first = sdvi::Vectorize(sample, nullptr, one);
  REQUIRE(first.ok());
  CHECK(stopped->image == first->image);
  CHECK(stopped->report.psnr == first->report.psnr);
  sdvi::VectorizeOptions bad = all;
  bad.min_round_growth = 1;
  CHECK(sdvi::Vectorize(sample, nullptr, bad).status().code() == sdvi::StatusCode::kInvalidArgument);
}

TEST_CASE("vectorize is deterministic", "[vectorize]") {
  const sdvi::Raster sample = sdvi::MakeSampleImage(112, 80);
  sdvi::VectorizeOptions options;
  options.compression_ratio = 24;
  options.threads = 1;
  auto first = sdvi::Vectorize(sample, nullptr, options);
  options.threads = 2;
  auto second = sdvi::Vectorize(sample, nullptr, options);
  REQUIRE(first.ok());
  REQUIRE(second.ok());
  CHECK(first->image == second->image);
  CHECK(first->report.psnr == second->report.psnr);
}

TEST_CASE("vectorize of an object image fits only the domain", "[vectorize]") {
  // RGBA: an opaque disc on a transparent background.
  sdvi::Raster rgba(96, 96, 4);
  for (int y = 0; y < 96; ++y) {
    for (int x = 0; x < 96; ++x) {
      const double d = std::hypot(x + 0.5 - 48, y + 0.5 - 48);
      rgba.at(x, y, 0) = float(100 + x);
      rgba.at(x, y, 1) = float(80 + y);
      rgba.at(x, y, 2) = 150.f;
      rgba.at(x, y, 3) = d < 36 ? 1.f : 0.f;
    }
  }
  auto result = sdvi::Vectorize(rgba, nullptr, sdvi::VectorizeOptions{});
  REQUIRE(result.ok());
  INFO("PSNR " << result->report.psnr);
  CHECK(result->report.psnr > 30.0);
  // The domain is the disc: about pi 36^2 pixels, not the whole square.
  CHECK(result->report.pixels < 0.85 * 96 * 96);
  CHECK(result->report.pixels > 0.75 * 3.14159 * 36 * 36);
}

TEST_CASE("vectorize rejects empty input and bad options", "[vectorize]") {
  CHECK(sdvi::Vectorize(sdvi::Raster(), nullptr, {}).status().code() == sdvi::StatusCode::kEmptyInput);
  const sdvi::Raster sample = sdvi::MakeSampleImage(32, 32);
  sdvi::VectorizeOptions bad;
  bad.compression_ratio = 0;
  CHECK(sdvi::Vectorize(sample, nullptr, bad).status().code() == sdvi::StatusCode::kInvalidArgument);
  bad = {};
  bad.iterations = -1;
  CHECK(sdvi::Vectorize(sample, nullptr, bad).status().code() == sdvi::StatusCode::kInvalidArgument);
  const sdvi::Raster wrong_mask(16, 16, 1);
  CHECK(sdvi::Vectorize(sample, &wrong_mask, {}).status().code() == sdvi::StatusCode::kInvalidArgument);
  // A mask that excludes everything leaves no domain.
  const sdvi::Raster empty_mask(32, 32, 1);
  CHECK(sdvi::Vectorize(sample, &empty_mask, {}).status().code() == sdvi::StatusCode::kEmptyInput);
}

TEST_CASE("content blocks flag exactly the blocks whose colour varies", "[vectorize]") {
  // 40 x 24 px in blocks of 16: 3 x 2 blocks (the last column and row partial). One pixel
  // of block (2, 1) differs by 2 in green; block (0, 0) by exactly the tolerance.
  sdvi::Raster raster(40, 24, 3);
  for (float& v : raster.data) v = 100;
  raster.at(35, 20, 1) = 102;
  raster.at(3, 3, 2) = 101.5f;
  const sdvi::ContentBlocks blocks = sdvi::FindContentBlocks(raster, nullptr, 16, 1.5);
  REQUIRE(blocks.columns == 3);
  REQUIRE(blocks.rows == 2);
  CHECK(blocks.AnyBusy(33, 17, 39, 23));        // block (2, 1)
  CHECK_FALSE(blocks.AnyBusy(0, 0, 31.9, 15));  // blocks (0, 0) and (1, 0): at most 1.5
  CHECK_FALSE(blocks.AnyBusy(0, 16, 31.9, 23)); // row 1 without the last column
  CHECK(blocks.AnyBusy(0, 16, 32, 23));         // reaches block (2, 1)
  CHECK(blocks.AnyBusy(-100, -100, 1e9, 1e9));  // clamped to the image
  // A mask that leaves the differing pixel out makes its block flat.
  sdvi::Raster mask(40, 24, 1);
  for (float& v : mask.data) v = 255;
  mask.at(35, 20, 0) = 0;
  CHECK_FALSE(sdvi::FindContentBlocks(raster, &mask, 16, 1.5).AnyBusy(0, 0, 39, 23));
  // No blocks: everything is busy.
  CHECK(sdvi::FindContentBlocks(raster, nullptr, 0, 1.5).AnyBusy(0, 0, 1, 1));
}

TEST_CASE("the quality stop: a flat image costs a few triangles, whatever the budget", "[vectorize]") {
  sdvi::Raster flat(512, 384, 3);
  for (size_t i = 0; i < flat.data.size(); ++i) flat.data[i] = float(40 + 80 * (i % 3));
  sdvi::VectorizeOptions options;  // default budget: 512 x 384 / 64 = 3072 vertices
  auto result = sdvi::Vectorize(flat, nullptr, options);
  REQUIRE(result.ok());
  INFO(result->report.vertices << " vertices, " << result->report.triangles << " triangles");
  CHECK(result->report.triangles <= 8);
  CHECK(result->report.psnr > 100);
  // Without the quality stop the budget decides: the size bound and the initial grid fill
  // the rectangle.
  options.content_block = 0;
  auto budgeted = sdvi::Vectorize(flat, nullptr, options);
  REQUIRE(budgeted.ok());
  CHECK(budgeted->report.triangles > 500);
  options.content_block = -1;
  CHECK(sdvi::Vectorize(flat, nullptr, options).status().code() == sdvi::StatusCode::kInvalidArgument);
}

TEST_CASE("the quality stop keeps the size bound where the image varies", "[vectorize]") {
  // Left half flat, right half a smooth ramp: vertices go to the right half.
  sdvi::Raster half(256, 128, 3);
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 256; ++x) {
      const float v = x < 128 ? 60.f : float(60 + (x - 128) * 1.2 + 40 * std::sin(y * 0.08));
      for (int c = 0; c < 3; ++c) half.at(x, y, c) = v;
    }
  }
  sdvi::VectorizeOptions options;
  options.compression_ratio = 32;
  auto result = sdvi::Vectorize(half, nullptr, options);
  REQUIRE(result.ok());
  int left = 0, right = 0;
  for (const sdvi::Vertex& v : result->image.vertices) {
    if (v.x < 120) ++left;
    if (v.x > 136) ++right;
  }
  INFO(left << " vertices left, " << right << " right, PSNR " << result->report.psnr);
  CHECK(right > 4 * left);
  CHECK(result->report.psnr > 40);
}

TEST_CASE("refinement selection keeps samples far apart and worst first", "[vectorize]") {
  const int w = 20, h = 10;
  std::vector<float> error(size_t(w) * h, 0.f);
  error[5 * w + 5] = 100.f;   // worst
  error[5 * w + 6] = 90.f;    // too close to the worst
  error[5 * w + 15] = 50.f;   // far away
  error[1 * w + 1] = 40.f;    // close to an existing vertex
  std::vector<sdvi::Vertex> existing(1);
  existing[0].x = 1.5f;
  existing[0].y = 2.0f;
  const std::vector<uint8_t> blocked(size_t(w) * h, 0);
  sdvi::SpacingRule spacing;
  spacing.base = spacing.min = spacing.max = 3.0;
  const auto chosen = sdvi::SelectRefinementSamples(error, w, h, 10.0, spacing, existing, blocked, 10);
  REQUIRE(chosen.size() == 2);
  CHECK(chosen[0].x == 5.5);
  CHECK(chosen[0].y == 5.5);
  CHECK(chosen[1].x == 15.5);
  // max_count limits the selection.
  CHECK(sdvi::SelectRefinementSamples(error, w, h, 10.0, spacing, existing, blocked, 1).size() == 1);
  // With an exponent, a high error allows closer samples.
  spacing.exponent = 0.5;
  spacing.reference_error = 100.0;
  spacing.min = 0.5;
  spacing.max = 12.0;
  CHECK(spacing.At(400.0) == Approx(1.5));
  CHECK(spacing.At(1.0) == Approx(12.0));
  const auto adaptive = sdvi::SelectRefinementSamples(error, w, h, 10.0, spacing, existing, blocked, 10);
  CHECK(adaptive.size() == 2);  // (6,5) is within 3 px of (5,5); the error-40 pixel is near the vertex
}

TEST_CASE("the sample image has a sharp edge, a soft edge and smooth regions", "[vectorize]") {
  const sdvi::Raster a = sdvi::MakeSampleImage(64, 48);
  const sdvi::Raster b = sdvi::MakeSampleImage(64, 48);
  REQUIRE(a.channels == 3);
  CHECK(a.data == b.data);
  float lo = 255, hi = 0;
  for (float v : a.data) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  CHECK(lo >= 0.f);
  CHECK(hi <= 255.f);
  CHECK(hi - lo > 100.f);
}

TEST_CASE("vectorize handles tiny, grey and grey+alpha images", "[vectorize]") {
  for (const auto& [w, h, channels] : std::vector<std::array<int, 3>>{
           {8, 8, 3}, {5, 17, 3}, {24, 16, 1}, {24, 20, 2}, {40, 30, 4}}) {
    const sdvi::Raster sample = sdvi::MakeSampleImage(w, h);
    sdvi::Raster raster(w, h, channels);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const float grey = sample.at(x, y, 1);
        if (channels <= 2) {
          raster.at(x, y, 0) = grey;
        } else {
          for (int c = 0; c < 3; ++c) raster.at(x, y, c) = sample.at(x, y, c);
        }
        if (channels == 2 || channels == 4) raster.at(x, y, channels - 1) = (x + y) % 7 == 0 ? 0.f : 1.f;
      }
    }
    INFO(w << "x" << h << " with " << channels << " channels");
    auto result = sdvi::Vectorize(raster, nullptr, sdvi::VectorizeOptions{});
    REQUIRE(result.ok());
    CHECK(result->report.vertices >= 3);
    CHECK(std::isfinite(result->report.psnr));
    if (channels <= 2) {
      // Grey stays grey: R = G = B at every control vertex.
      for (const sdvi::Vertex& v : result->image.vertices) {
        CHECK(v.r == v.g);
        CHECK(v.g == v.b);
      }
    }
  }
}

TEST_CASE("the error map from the fit's samples equals the one from its reconstruction", "[vectorize]") {
  // An RGBA image with a transparent hole (outside the domain) and a mask cutting a band,
  // so that uncovered, masked and covered pixels all occur.
  const sdvi::Raster sample = sdvi::MakeSampleImage(150, 110);
  sdvi::Raster rgba(150, 110, 4);
  sdvi::Raster mask(150, 110, 1);
  for (int y = 0; y < 110; ++y) {
    for (int x = 0; x < 150; ++x) {
      for (int c = 0; c < 3; ++c) rgba.at(x, y, c) = sample.at(x, y, c);
      rgba.at(x, y, 3) = std::hypot(x - 40.0, y - 50.0) < 15 ? 0.f : 1.f;
      mask.at(x, y, 0) = x > 120 && y < 30 ? 0.f : 255.f;
    }
  }
  std::vector<sdvi::Point2> samples;
  for (int y = 5; y < 110; y += 9) {
    for (int x = 5 + (y % 2) * 4; x < 150; x += 9) samples.push_back({x + 0.5, y + 0.5});
  }
  auto built = sdvi::BuildControlMesh(150, 110, {}, samples, sdvi::ControlMeshOptions());
  REQUIRE(built.ok());
  const sdvi::Raster* const masks[] = {nullptr, &mask};
  const sdvi::Raster* const targets[] = {&sample, &rgba};
  for (const sdvi::Raster* m : masks) {
    for (const sdvi::Raster* target : targets) {
      sdvi::Image mesh = *built;
      auto fit = sdvi::FitColors(mesh, *target, m, sdvi::ColorFitOptions{});
      REQUIRE(fit.ok());
      for (double sigma : {0.0, 1.5}) {
        const std::vector<float> expected = sdvi::ErrorMap(sdvi::ReconstructRaster(*fit), *target, m, sigma);
        for (int threads : {1, 3}) CHECK(sdvi::ErrorMap(*fit, *target, m, sigma, threads) == expected);
      }
    }
  }
}
