// SPDX-License-Identifier: GPL-3.0-or-later
// Rate control over the whole chain (spec/RATE.md): from a vectorized image to the smallest
// .sdvi file worth its bytes.
//
// Quantisation by rate-distortion. A vectorized image is a point on the budget's RD curve;
// the codec's position and colour steps move it along another. Both trade the same way:
// the Lagrangian cost of a file is J = ln(bytes) - PSNR / s, where s (dB per natural-log
// unit of bytes) is the slope of the vectorizer's own RD curve at this budget: the PSNR its
// last refinement rounds gained per log of vertices added (VectorizeReport::history), or
// RateOptions::slope_db. Starting from the conservative steps (1% of the fit's MSE,
// DefaultPositionBits / DefaultColorBits), position bits and then colour bits are lowered
// one at a time while J falls. Every candidate is measured, not modelled: encode, decode,
// (refit colours), render at x1, PSNR. Positions that fold a triangle at a candidate's bits
// are mended on the codec's grid (SnapPositionsToGrid: a few vertices move to nearby grid
// points) rather than given more bits (spec/RATE.md 3).
//
// Colours refitted on quantised positions. The colour fit is linear least squares for fixed
// positions, so after the positions are quantised the colours can be fitted again on the
// decoded positions (FitColors with the vectorizer's options, vertex order and triangles
// kept) and only then quantised: the fit absorbs what moving the positions cost. Each
// candidate is measured with the vectorizer's colours and with the refitted ones; the one of
// lower J is kept (the refit wins only where positions moved by more than the fit's own
// tolerance, spec/RATE.md 3).
//
// The PSNR of a result (one number, reported everywhere): CompareImages of the file as a
// reader decodes it, rendered at x1 (Render, default levels) and rounded to 8 bits as a PNG
// stores it, against the source (CompareImages: pixels where both alphas are > 0.5).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/render.h"
#include "sdvi/status.h"
#include "sdvi/vectorize.h"

namespace sdvi {

struct RateOptions {
  double slope_db = 0;        // s of the header comment; 0 = from the vectorizer's history
  double min_psnr = 0;        // the search never accepts a candidate below this PSNR (dB)
  bool refit_colors = true;   // also try colours refitted on the quantised positions
  bool search_bits = true;    // false: the conservative steps only (v1 `--compress`)
  int max_steps = 8;          // bit reductions tried per attribute at most
  // How each candidate codes its colours (sdvi/codec.h): by default RGB or decorrelated,
  // whichever file is smaller (spec/RATE.md 5).
  ColorCoding color_coding = ColorCoding::kSmallest;
  bool features_first = true;  // the feature layer first (payload 1.2; false: 1.1), sdvi/codec.h
  bool neighbour_mean = true;  // kSmallest also tries neighbour-mean colours (payload 1.3), sdvi/codec.h
  bool stream_positions = true;  // kSmallest also tries positions in the tag stream (payload 1.4), sdvi/codec.h
  bool stream_colors = true;  // ... and the colours there too (payload 1.5), sdvi/codec.h
  bool stream_grey_colors = true;  // ... and a grey image's one component there (payload 1.6), sdvi/codec.h
  int threads = 1;
};

struct RateResult {
  std::vector<uint8_t> file;  // the .sdvi container (Draco payload)
  Image decoded;              // what a reader of file gets
  double psnr = 0;            // FileQualityPsnr of decoded
  int position_bits = 0, color_bits = 0;
  bool colors_refitted = false;  // the file holds colours refitted on its positions
  int mended_vertices = 0;     // vertices moved off their nearest grid point to unfold triangles
  bool colors_decorrelated = false;  // the file codes its colours as L, C1, C2 (sdvi/codec.h)
  double slope_db = 0;        // s used
  int evaluations = 0;        // candidates measured
};

// The slope s (dB per natural-log unit of vertices) of a vectorizer run: over the last
// refinement rounds that added at least 5% vertices, clamped to [1, 12]; 4 when the history
// has no such round.
double SlopeFromHistory(const VectorizeReport& report);

// The PSNR of the header comment for an image (as decoded) against its source: exactly what
// `sdvi compare` prints for the file or for its x1 PNG render.
StatusOr<double> FileQualityPsnr(const Image& decoded, const Raster& source, int threads);

// FileQualityPsnr with the MSSIM and mean error of the same render (CompareImages): the
// figures `sdvi compare` prints for the file; psnr is FileQualityPsnr's, bit for bit.
StatusOr<ImageMetrics> FileQuality(const Image& decoded, const Raster& source, int threads);

// The smallest file worth its bytes for a vectorized image (header comment). source and mask
// are what Vectorize was given, fit its colour-fit options.
StatusOr<RateResult> CompressForRate(const VectorizeResult& vectorized, const Raster& source,
                                     const Raster* mask, const ColorFitOptions& fit,
                                     const RateOptions& options);

// CompressForRate for an image without its vectorizer run (a raw .sdvi file and the image it
// was made from: `sdvi compress --reference`): the fit's PSNR is FileQualityPsnr of image,
// the slope options.slope_db or, with no history, 4 dB; the colours are refitted with the
// default colour-fit options (the vectorizer's). Errors: kInvalidArgument when source's size
// is not image's, those of CompressForRate.
StatusOr<RateResult> CompressImageForRate(const Image& image, const Raster& source, const RateOptions& options);

// ---- Targets a user sets (spec/RATE.md 4) ---------------------------------------------

// Pixels per vertex for a quality 0..100: 400 x (1/100)^(quality/100), i.e. 400 at 0, 40 at
// 50, 4 at 100; strictly decreasing, so a higher quality never gets fewer vertices.
double BudgetForQuality(double quality);

struct RateTarget {
  double quality = -1;        // 0..100; < 0: unset
  uint64_t bytes = 0;         // the file must not exceed this; 0: unset
  double psnr = 0;            // dB the file's PSNR (section 1) must reach; 0: unset
};

struct TargetResult {
  VectorizeResult vectorized;
  RateResult file;
  bool reached = true;        // the target was met
  std::string note;           // why not, for the warning and the report
  int vectorize_runs = 0;
};

// Vectorizes source and compresses it to meet target (exactly one of its fields set):
//  quality: the budget BudgetForQuality(q), then CompressForRate;
//  bytes: bisection on the budget (log pixels per vertex in [2, 2000], 7 runs) for the most
//    vertices whose file fits; not reached when even 2000 pixels per vertex does not fit (the
//    smallest file is returned);
//  psnr: Vectorize with target_psnr, CompressForRate with min_psnr; when the file falls short
//    the vectorizer runs again aiming higher by the shortfall (at most 3 runs); not reached
//    when the last file is still short (it is returned).
// options.compression_ratio / target_psnr are replaced as above. Errors: kInvalidArgument
// (no target, several, or out of range), the errors of Vectorize and CompressForRate.
StatusOr<TargetResult> VectorizeForTarget(const Raster& source, const Raster* mask,
                                          const VectorizeOptions& options, const RateTarget& target,
                                          const RateOptions& rate);

// ---- The file `sdvi vectorize` writes (spec/RATE.md 1) ----------------------------------

struct VectorizedFile {
  // The fit; its report's psnr, mssim and mean_error are the file's (FileQuality of decoded,
  // what `sdvi compare FILE.sdvi SOURCE` prints), their time in seconds.metrics and .total.
  VectorizeResult vectorized;
  std::vector<uint8_t> bytes;  // the .sdvi file: raw payload, or Draco when compressed
  Image decoded;               // what a reader of bytes gets
  bool compressed = false;
  RateResult choices;          // compressed: the choices made (its file and decoded moved out)
  bool targeted = false;       // a target was set (or VectorizeOptions::target_psnr)
  bool reached = true;         // ... and met
  std::string note;            // why not
  int vectorize_runs = 1;
};

// Vectorizes source into the file `sdvi vectorize` writes, the one path of the command and
// the Python binding: with a target (one of its fields set; with compress,
// options.target_psnr is one too) VectorizeForTarget, which implies compress; with compress
// alone Vectorize then CompressForRate; else Vectorize and the raw payload (EncodeImage). The file is then decoded and measured once (FileQuality); the
// vectorizer's own final render (options.final_metrics) is needed only for debug pictures.
// name is for messages.
StatusOr<VectorizedFile> VectorizeToFile(const Raster& source, const Raster* mask, const VectorizeOptions& options,
                                         bool compress, const RateTarget& target, const RateOptions& rate,
                                         const std::string& name);

// The report of made as JSON text (nlohmann's dump with indent; -1: one line): the fields of
// `sdvi vectorize --report`, which the Python binding returns too (one list for both). input
// and output are the names as given; seconds.load of made's report counts in time_s.
std::string VectorizedFileReportJson(const VectorizedFile& made, const std::string& input, const std::string& output,
                                     int indent);
// The rate control's choices as the report's `rate` object (also `sdvi compress --json`'s).
std::string RateChoicesJson(const RateResult& choices, int indent);

}  // namespace sdvi
