// SPDX-License-Identifier: GPL-3.0-or-later
// Rate control: quantisation by rate-distortion and colours refitted on quantised positions
// (rules in sdvi/rate.h and spec/RATE.md).
#include "sdvi/rate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "sdvi/codec.h"
#include "sdvi/color_fit.h"
#include "sdvi/render.h"

namespace sdvi {
namespace {

constexpr double kMinSlope = 1.0, kMaxSlope = 12.0, kFallbackSlope = 4.0;
constexpr double kMinGrowth = 1.05;  // a round counts for the slope when it adds >= 5% vertices
constexpr int kMinBits = 4;

// The x1 render of a decoded file in 8 bits, what its PNG holds (spec/RATE.md 1 steps 2-3).
StatusOr<Raster8> RenderX1(const Image& decoded, int threads) {
  RenderOptions options;
  options.viewport = Viewport::Identity(int(decoded.width), int(decoded.height));
  options.threads = threads;
  return Render8(decoded, options);
}

StatusOr<double> Psnr(const Image& decoded, const Raster& reference, int threads) {
  SDVI_ASSIGN_OR_RETURN(Raster8 render, RenderX1(decoded, threads));
  // The PSNR needs no MSSIM.
  SDVI_ASSIGN_OR_RETURN(ImageMetrics metrics, ComparePixelErrors(render, reference));
  return metrics.psnr;
}

// One candidate: bits, the file and what it measures.
struct Candidate {
  int position_bits = 0, color_bits = 0;
  std::vector<uint8_t> file;
  Image decoded;
  Image refitted;  // quantised positions, colours refitted, not yet quantised (refit only)
  bool colors_refitted = false;  // file holds the refitted colours (else the vectorizer's)
  double psnr = 0;
  int mended_vertices = 0;  // vertices moved off their nearest grid point to unfold triangles
  double Cost(double slope) const { return std::log(double(file.size())) - psnr / slope; }
};

// image with its positions replaced by those a reader of its file at these bits decodes:
// same vertex order and triangles (the codec keeps the order when asked), so that the file
// of the result is coded in the same traversal as image's own.
StatusOr<Image> QuantisedPositions(const Image& image, const CompressOptions& bits) {
  CompressOptions ordered = bits;
  ordered.keep_vertex_order = true;
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> file, EncodeImage(image, &ordered));
  SDVI_ASSIGN_OR_RETURN(Image decoded, DecodeImage(file, "rate control"));
  if (decoded.vertices.size() != image.vertices.size())
    return Status(StatusCode::kInternal, "rate control: the codec did not keep the vertex order");
  Image out = image;
  for (size_t i = 0; i < out.vertices.size(); ++i) {
    out.vertices[i].x = decoded.vertices[i].x;
    out.vertices[i].y = decoded.vertices[i].y;
  }
  return out;
}

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

StatusOr<ImageMetrics> FileQuality(const Image& decoded, const Raster& source, int threads) {
  SDVI_ASSIGN_OR_RETURN(Raster8 render, RenderX1(decoded, threads));
  return CompareImages(render, source, threads);
}

namespace {

// CompressForRate of an image whose colour fit measured fit_psnr, at the slope s = slope_db
// (both entry points below).
StatusOr<RateResult> CompressFittedImage(const Image& image, double fit_psnr, double slope_db, const Raster& source,
                                         const Raster* mask, const ColorFitOptions& fit,
                                         const RateOptions& options) {
  const double fit_mse = 255.0 * 255.0 / std::pow(10.0, fit_psnr / 10.0);
  RateResult result;
  result.slope_db = slope_db;
  ColorFitOptions refit = fit;
  refit.threads = options.threads;

  // The file of an image at given bits and what it measures.
  const auto folds = [](const Status& s) { return s.code() == StatusCode::kFoldedTriangle; };
  auto measure = [&](const Image& colors_from, const CompressOptions& compress, Candidate& c) -> Status {
    SDVI_ASSIGN_OR_RETURN(c.file, EncodeImage(colors_from, &compress));
    SDVI_ASSIGN_OR_RETURN(c.decoded, DecodeImage(c.file, "rate control"));
    SDVI_ASSIGN_OR_RETURN(c.psnr, Psnr(c.decoded, source, options.threads));
    return Status::Ok();
  };
  // Measures one (position bits, colour bits) pair: the file of the vectorizer's colours and,
  // with the refit, the file of the colours refitted on the quantised positions; the one of
  // lower cost J is the candidate. same_positions: a candidate with the same position bits,
  // whose refitted image is reused (Draco quantises attributes independently, so the
  // quantised positions, and hence the refit, are the same).
  auto evaluate = [&](int position_bits, int color_bits, const Candidate* same_positions) -> StatusOr<Candidate> {
    Candidate c;
    c.position_bits = position_bits;
    c.color_bits = color_bits;
    CompressOptions compress;
    compress.position_bits = position_bits;
    compress.color_bits = color_bits;
    compress.color_coding = options.color_coding;
    compress.features_first = options.features_first;
    compress.neighbour_mean = options.neighbour_mean;
    compress.stream_positions = options.stream_positions;
    compress.stream_colors = options.stream_colors;
    compress.stream_grey_colors = options.stream_grey_colors;
    // Positions that fold a triangle at these bits: the few vertices of the folds move to
    // nearby grid points (spec/RATE.md 3) instead of every vertex getting a finer step.
    const Image* positions = &image;
    Image mended;
    if (Status plain = measure(image, compress, c); !plain.ok()) {
      if (!folds(plain)) return plain;
      SDVI_ASSIGN_OR_RETURN(mended, SnapPositionsToGrid(image, position_bits, &c.mended_vertices));
      positions = &mended;
      SDVI_RETURN_IF_ERROR(measure(mended, compress, c));
    }
    ++result.evaluations;
    if (!options.refit_colors) return c;
    Candidate r = c;
    if (same_positions != nullptr) {
      r.refitted = same_positions->refitted;
    } else {
      SDVI_ASSIGN_OR_RETURN(r.refitted, QuantisedPositions(*positions, compress));
      SDVI_RETURN_IF_ERROR(FitColors(r.refitted, source, mask, refit).status());
    }
    SDVI_RETURN_IF_ERROR(measure(r.refitted, compress, r));
    r.colors_refitted = true;
    if (r.Cost(result.slope_db) < c.Cost(result.slope_db)) return r;
    c.refitted = std::move(r.refitted);  // for the colour steps
    return c;
  };

  // Bits whose quantised positions fold a triangle that mending cannot unfold give no file:
  // the start rises until it encodes, the descent stops there.
  int position_bits = DefaultPositionBits(image, fit_mse);
  const int color_bits = DefaultColorBits(image, fit_mse);
  StatusOr<Candidate> start = evaluate(position_bits, color_bits, nullptr);
  while (!start.ok() && folds(start.status()) && position_bits < kMaxQuantizationBits)
    start = evaluate(++position_bits, color_bits, nullptr);
  SDVI_ASSIGN_OR_RETURN(Candidate best, std::move(start));
  if (options.search_bits) {
    // Coordinate descent: positions, then colours, one bit at a time while J falls.
    for (int attribute = 0; attribute < 2; ++attribute) {
      for (int step = 0; step < options.max_steps; ++step) {
        const int p = best.position_bits - (attribute == 0 ? 1 : 0);
        const int c = best.color_bits - (attribute == 1 ? 1 : 0);
        if (p < kMinBits || c < kMinBits) break;
        StatusOr<Candidate> tried = evaluate(p, c, attribute == 1 ? &best : nullptr);
        if (!tried.ok() && folds(tried.status())) break;
        SDVI_ASSIGN_OR_RETURN(Candidate next, std::move(tried));
        if (next.psnr < options.min_psnr) break;
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
  result.colors_refitted = best.colors_refitted;
  result.mended_vertices = best.mended_vertices;
  {
    SDVI_ASSIGN_OR_RETURN(SdviFile file, DecodeSdvi(result.file, "rate control"));
    SDVI_ASSIGN_OR_RETURN(DracoPayloadInfo info, InspectDracoPayload(file.compressed_payload, "rate control"));
    result.colors_decorrelated = info.decorrelated;
  }
  return result;
}

}  // namespace

StatusOr<RateResult> CompressForRate(const VectorizeResult& vectorized, const Raster& source, const Raster* mask,
                                     const ColorFitOptions& fit, const RateOptions& options) {
  const double slope = options.slope_db > 0 ? options.slope_db : SlopeFromHistory(vectorized.report);
  return CompressFittedImage(vectorized.image, vectorized.report.fit_psnr, slope, source, mask, fit, options);
}

StatusOr<RateResult> CompressImageForRate(const Image& image, const Raster& source, const RateOptions& options) {
  if (uint32_t(source.width) != image.width || uint32_t(source.height) != image.height)
    return Status(StatusCode::kInvalidArgument, "the reference is " + std::to_string(source.width) + "x" +
                                                    std::to_string(source.height) + ", the image " +
                                                    std::to_string(image.width) + "x" + std::to_string(image.height));
  SDVI_ASSIGN_OR_RETURN(const double fit_psnr, FileQualityPsnr(image, source, options.threads));
  ColorFitOptions fit;
  fit.threads = options.threads;
  const double slope = options.slope_db > 0 ? options.slope_db : kFallbackSlope;  // no history
  return CompressFittedImage(image, fit_psnr, slope, source, nullptr, fit, options);
}

double BudgetForQuality(double quality) {
  return 400.0 * std::pow(0.01, std::clamp(quality, 0.0, 100.0) / 100.0);
}

// Why a PSNR target was missed, for the warning and the report.
static std::string PsnrNotReached(double target_psnr, double file_psnr, const Image& image) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "target PSNR %.2f dB not reached: the file has %.2f dB (%u vertices); raise "
                "the budget (--compression-ratio lower, --iterations higher)",
                target_psnr, file_psnr, unsigned(image.vertices.size()));
  return buf;
}

StatusOr<TargetResult> VectorizeForTarget(const Raster& source, const Raster* mask, const VectorizeOptions& options,
                                          const RateTarget& target, const RateOptions& rate) {
  const int set = (target.quality >= 0) + (target.bytes > 0) + (target.psnr > 0);
  if (set != 1)
    return Status(StatusCode::kInvalidArgument, "rate control needs exactly one of quality, bytes, PSNR; got " +
                                                    std::to_string(set));
  if (target.quality > 100)
    return Status(StatusCode::kInvalidArgument, "quality " + std::to_string(target.quality) + " not in 0..100");
  if (target.psnr > 0 && !(target.psnr < 200))
    return Status(StatusCode::kInvalidArgument, "target PSNR must be below 200 dB");
  TargetResult out;
  // One run: vectorize at ppv (and target PSNR aim), compress.
  auto run = [&](double ppv, double aim, double min_psnr) -> Status {
    VectorizeOptions o = options;
    o.compression_ratio = ppv;
    o.max_triangles = options.max_triangles;
    o.target_psnr = aim;
    SDVI_ASSIGN_OR_RETURN(out.vectorized, Vectorize(source, mask, o));
    RateOptions r = rate;
    r.min_psnr = min_psnr;
    SDVI_ASSIGN_OR_RETURN(out.file, CompressForRate(out.vectorized, source, mask, o.fit, r));
    ++out.vectorize_runs;
    return Status::Ok();
  };

  if (target.quality >= 0) {
    SDVI_RETURN_IF_ERROR(run(BudgetForQuality(target.quality), 0, 0));
    return out;
  }
  if (target.bytes > 0) {
    // Bisection on log(ppv): lo fits (or is the coarsest), hi does not (or is the finest).
    constexpr double kFinest = 2, kCoarsest = 2000;
    constexpr int kRuns = 7;
    double lo = std::log(kCoarsest), hi = std::log(kFinest);
    SDVI_RETURN_IF_ERROR(run(kCoarsest, 0, 0));
    if (out.file.file.size() > target.bytes) {
      out.reached = false;
      out.note = "even " + std::to_string(int(kCoarsest)) + " pixels per vertex needs " +
                 std::to_string(out.file.file.size()) + " bytes, more than " + std::to_string(target.bytes);
      return out;
    }
    TargetResult best = out;
    for (int i = 1; i < kRuns; ++i) {
      const double mid = i == 1 ? hi : 0.5 * (lo + hi);
      SDVI_RETURN_IF_ERROR(run(std::exp(mid), 0, 0));
      if (out.file.file.size() <= target.bytes) {
        lo = mid;
        if (out.file.psnr >= best.file.psnr) best = out;
        if (i == 1) break;  // even the finest budget fits
      } else {
        hi = mid;
      }
    }
    best.vectorize_runs = out.vectorize_runs;
    return best;
  }
  // PSNR target: aim the vectorizer higher by the shortfall of the file.
  double aim = target.psnr;
  for (int attempt = 0; attempt < 3; ++attempt) {
    SDVI_RETURN_IF_ERROR(run(options.compression_ratio, aim, target.psnr));
    if (out.file.psnr >= target.psnr) return out;
    if (out.vectorized.report.fit_psnr < aim) break;  // the vectorizer itself fell short: budget spent
    aim += target.psnr - out.file.psnr + 0.05;
  }
  out.reached = false;
  out.note = PsnrNotReached(target.psnr, out.file.psnr, out.vectorized.image);
  return out;
}

StatusOr<VectorizedFile> VectorizeToFile(const Raster& source, const Raster* mask, const VectorizeOptions& options,
                                         bool compress, const RateTarget& target, const RateOptions& rate,
                                         const std::string& name) {
  RateTarget wanted = target;
  if (compress && options.target_psnr > 0) wanted.psnr = options.target_psnr;  // met by the compressed file
  const bool has_target = wanted.quality >= 0 || wanted.bytes > 0 || wanted.psnr > 0;
  VectorizedFile out;
  RateResult compressed;
  if (has_target) {
    SDVI_ASSIGN_OR_RETURN(TargetResult t, VectorizeForTarget(source, mask, options, wanted, rate));
    out.vectorized = std::move(t.vectorized);
    compressed = std::move(t.file);
    out.reached = t.reached;
    out.note = std::move(t.note);
    out.vectorize_runs = t.vectorize_runs;
  } else {
    SDVI_ASSIGN_OR_RETURN(out.vectorized, Vectorize(source, mask, options));
    if (compress) {
      SDVI_ASSIGN_OR_RETURN(compressed, CompressForRate(out.vectorized, source, mask, options.fit, rate));
    }
  }
  out.targeted = has_target || options.target_psnr > 0;
  out.compressed = has_target || compress;
  if (out.compressed) {
    out.bytes = std::move(compressed.file);
    out.decoded = std::move(compressed.decoded);
    out.choices = std::move(compressed);
  } else {
    SDVI_ASSIGN_OR_RETURN(out.bytes, EncodeImage(out.vectorized.image, nullptr, name));
    SDVI_ASSIGN_OR_RETURN(out.decoded, DecodeImage(out.bytes, name));
  }
  const auto start = std::chrono::steady_clock::now();
  SDVI_ASSIGN_OR_RETURN(const ImageMetrics file, FileQuality(out.decoded, source, options.threads));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  VectorizeReport& report = out.vectorized.report;
  report.seconds.metrics += seconds;
  report.seconds.total += seconds;
  report.psnr = file.psnr;
  report.mssim = file.mssim;
  report.mean_error = file.mean_error;
  if (!has_target && options.target_psnr > 0 && file.psnr < options.target_psnr) {
    out.reached = false;
    out.note = PsnrNotReached(options.target_psnr, file.psnr, out.vectorized.image);
  }
  return out;
}

}  // namespace sdvi
