// SPDX-License-Identifier: GPL-3.0-or-later
// Rate control: quantisation by rate-distortion and colours refitted on quantised positions
// (rules in sdvi/rate.h and spec/RATE.md).
#include "sdvi/rate.h"

#include <algorithm>
#include <cmath>

#include "sdvi/codec.h"
#include "sdvi/color_fit.h"
#include "sdvi/render.h"

namespace sdvi {
namespace {

constexpr double kMinSlope = 1.0, kMaxSlope = 12.0, kFallbackSlope = 4.0;
constexpr double kMinGrowth = 1.05;  // a round counts for the slope when it adds >= 5% vertices
constexpr int kMinBits = 4;

StatusOr<double> Psnr(const Image& decoded, const Raster& reference, int threads) {
  RenderOptions options;
  options.viewport = Viewport::Identity(int(decoded.width), int(decoded.height));
  options.threads = threads;
  SDVI_ASSIGN_OR_RETURN(Raster render, Render(decoded, options));
  RoundTo8Bit(render);  // what its PNG holds
  SDVI_ASSIGN_OR_RETURN(ImageMetrics metrics, CompareImages(render, reference));
  return metrics.psnr;
}

// One candidate: bits, the file and what it measures.
struct Candidate {
  int position_bits = 0, color_bits = 0;
  std::vector<uint8_t> file;
  Image decoded;
  double psnr = 0;
  double Cost(double slope) const { return std::log(double(file.size())) - psnr / slope; }
};

}  // namespace

double SlopeFromHistory(const VectorizeReport& report) {
  const auto& h = report.history;
  for (size_t i = h.size(); i-- > 1;) {
    // The latest round that grew the mesh by at least kMinGrowth, against the one before.
    if (h[i].vertices >= kMinGrowth * h[i - 1].vertices && h[i - 1].vertices > 0) {
      const double gained = h[i].psnr - h[i - 1].psnr;
      const double slope = gained / std::log(double(h[i].vertices) / double(h[i - 1].vertices));
      return std::clamp(slope, kMinSlope, kMaxSlope);
    }
  }
  return kFallbackSlope;
}

StatusOr<double> FileQualityPsnr(const Image& decoded, const Raster& source, int threads) {
  return Psnr(decoded, source, threads);
}

StatusOr<RateResult> CompressForRate(const VectorizeResult& vectorized, const Raster& source, const Raster* mask,
                                     const ColorFitOptions& fit, const RateOptions& options) {
  const Image& image = vectorized.image;
  const double fit_mse = 255.0 * 255.0 / std::pow(10.0, vectorized.report.psnr / 10.0);
  RateResult result;
  result.slope_db = options.slope_db > 0 ? options.slope_db : SlopeFromHistory(vectorized.report);
  ColorFitOptions refit = fit;
  refit.threads = options.threads;

  // Measures one (position bits, colour bits) pair.
  auto evaluate = [&](int position_bits, int color_bits) -> StatusOr<Candidate> {
    Candidate c;
    c.position_bits = position_bits;
    c.color_bits = color_bits;
    CompressOptions compress;
    compress.position_bits = position_bits;
    compress.color_bits = color_bits;
    SDVI_ASSIGN_OR_RETURN(c.file, EncodeImage(image, &compress));
    SDVI_ASSIGN_OR_RETURN(c.decoded, DecodeImage(c.file, "rate control"));
    if (options.refit_colors) {
      // Positions as decoded, colours fitted to them, then quantised.
      SDVI_RETURN_IF_ERROR(FitColors(c.decoded, source, mask, refit).status());
      SDVI_ASSIGN_OR_RETURN(c.file, EncodeImage(c.decoded, &compress));
      SDVI_ASSIGN_OR_RETURN(c.decoded, DecodeImage(c.file, "rate control"));
    }
    SDVI_ASSIGN_OR_RETURN(c.psnr, Psnr(c.decoded, source, options.threads));
    ++result.evaluations;
    return c;
  };

  int position_bits = DefaultPositionBits(image, fit_mse);
  int color_bits = DefaultColorBits(image, fit_mse);
  SDVI_ASSIGN_OR_RETURN(Candidate best, evaluate(position_bits, color_bits));
  if (options.search_bits) {
    // Coordinate descent: positions, then colours, one bit at a time while J falls.
    for (int attribute = 0; attribute < 2; ++attribute) {
      for (int step = 0; step < options.max_steps; ++step) {
        const int p = best.position_bits - (attribute == 0 ? 1 : 0);
        const int c = best.color_bits - (attribute == 1 ? 1 : 0);
        if (p < kMinBits || c < kMinBits) break;
        SDVI_ASSIGN_OR_RETURN(Candidate next, evaluate(p, c));
        if (!(next.Cost(result.slope_db) < best.Cost(result.slope_db))) break;
        best = std::move(next);
      }
    }
  }
  result.file = std::move(best.file);
  result.decoded = std::move(best.decoded);
  result.psnr = best.psnr;
  result.position_bits = best.position_bits;
  result.color_bits = best.color_bits;
  return result;
}

}  // namespace sdvi
