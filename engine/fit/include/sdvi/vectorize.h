// SPDX-License-Identifier: GPL-3.0-or-later
// Vectorizing a raster (paper section IV, spec/METHOD.md section 6): curvilinear features,
// B-spline fitting, feature pairs, constrained Delaunay triangulation (features.h), then the
// colour fit (color_fit.h) and the refinement loop below.
//
// Refinement (spec/METHOD.md section 6 step 6). After each fit the per-pixel error e(p) = sum over R, G, B of
// (I(p) - reconstruction(p))^2 is averaged over a small Gaussian window (sigma
// error_blur_sigma px) so that single noisy pixels do not attract vertices. Pixels whose
// averaged RMS error exceeds error_threshold, and that lie farther than feature_clearance
// from every crease edge (features, image border), are candidates; they are visited in order of
// decreasing error (ties by pixel index) and a candidate becomes a new interior sample when
// it lies farther than the current spacing from every control vertex and from every
// sample chosen before it. The spacing is spacing_factor * sqrt(domain pixels / target
// vertex count), floored at min_spacing. The new samples are added, the domain
// re-triangulated (BuildControlMesh) and the colours re-fitted. The loop stops when the
// PSNR reaches target_psnr, when the budget is spent (less than 3% of it left), after
// `iterations` rounds, when no candidate is left, or at the tail stop (few candidates
// chosen after a round that gained little; min_round_growth below).
//
// Data-dependent triangulation. After every triangulation (the initial mesh and each
// refinement round) FlipEdgesToData re-decides the diagonals of the non-crease edges by the
// image data (flip_passes sweeps, flips never create an angle under flip_min_angle); the
// vertices, triangle count and creases stay, so the budget rules below are unchanged.
//
// Budget. max_triangles (when > 0) is a hard cap: a round that would exceed it is redone
// with fewer (the worst-error) samples; an initial mesh over it is rebuilt with fewer grid
// samples, then fewer (the shorter) features, then a looser CDT size bound, and when even
// the boundary alone needs more triangles the result is kLimitExceeded. The CDT size
// bound (mesh.max_edge = 0) is 4 x sqrt(domain pixels / vertex budget). Without it the budget is the vertex count
// domain pixels / compression_ratio, i.e. about twice as many triangles. The quality stop
// (content_block > 0): the initial grid and the size bound apply only in blocks where the
// colour varies by more than error_threshold (FindContentBlocks), so flat regions get few
// vertices whatever the budget (spec/METHOD.md section 6 step 4).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdvi/color_fit.h"
#include "sdvi/features.h"
#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

class Progress;

struct VectorizeOptions {
  double target_psnr = 0;          // dB; 0 = no PSNR target
  int max_triangles = 0;           // hard triangle cap; 0 = from compression_ratio
  double compression_ratio = 64;   // pixels per vertex when max_triangles is 0
  int iterations = 8;              // refinement rounds at most (0 = initial fit only)
  // Refinement constants (header comment).
  double error_threshold = 1.5;    // RMS over R, G, B, 8-bit units
  double error_blur_sigma = 1.0;   // px
  double spacing_factor = 0.35;
  double min_spacing = 2.0;        // px
  double spacing_exponent = 0;     // SpacingRule::exponent (0: fixed spacing)
  double feature_clearance = 1.0;  // px: no interior sample this close to a crease edge
  // The quality stop: the CDT size bound and the initial grid apply only in blocks of this
  // many px where the colour varies by more than error_threshold (FindContentBlocks);
  // 0: everywhere.
  int content_block = 16;
  double initial_fraction = 0.05;  // share of the vertex budget placed as the initial grid
  double growth = 0.2;             // a round adds at most growth x the current vertex count
  // The tail stop: a round whose selected samples are fewer than min_round_growth x the
  // current vertex count, after a round that raised the fit's PSNR by less than
  // min_round_gain dB, is not run and the loop stops (an image whose error is under
  // error_threshold almost everywhere gets a few samples a round, each round a whole fit:
  // on a 4K photo that is most of the time, for hundredths of a dB). 0: every round runs.
  double min_round_growth = 0.01;
  double min_round_gain = 0.05;    // dB
  // The features' share of the vertex budget on the busy part of the domain (all of it on
  // the flat part); within it they are kept, coarsened or dropped by value per vertex
  // (FitFeaturesToBudget, sdvi/feature_budget.h; spec/METHOD.md section 6 step 3).
  double max_feature_fraction = 0.5;
  // VectorizeWithFeatures: the given features' own cost (FeatureVertexCost plus junctions,
  // as the feature budget counts them) is added to the vertex budget and to the features'
  // share of it, up to this many times the budget from compression_ratio, so that exact
  // features (an importer's outlines) do not take the interior's vertices; the interior's
  // density (grid, size bound, refinement spacing) still follows compression_ratio. 0: the
  // given features share the budget as detected ones do. Not applied under max_triangles
  // (a hard cap). spec/METHOD.md section 6 step 3.
  double given_features_extra = 0;
  // Data-dependent edge flips after every triangulation (FlipEdgesToData; beyond the
  // paper, which keeps the CDT as it is).
  int flip_passes = 16;            // sweeps at most (0: none)
  double flip_min_angle = 1.0;     // deg, smallest angle a flip may create
  FeatureOptions features;         // its `threads` is replaced by `threads` below
  ControlMeshOptions mesh;        // the CDT (its angle bound: ControlMeshOptions::min_angle_deg)
  ColorFitOptions fit;             // its `threads` is replaced by `threads` below
  int threads = 1;                 // worker threads (features, colour fit assembly, final render)
  Progress* progress = nullptr;    // optional terminal progress (not owned)
  // false: no final render and CompareImages (the report's psnr, mssim and mean_error stay 0,
  // levels 0, reconstruction empty), for a caller that measures the file it writes instead
  // (`sdvi vectorize`, spec/RATE.md 1).
  bool final_metrics = true;
};

// Seconds per phase, summed over iterations.
struct VectorizeTimings {
  double load = 0;          // filled by callers that load the file
  double features = 0;      // DetectFeatures
  double triangulate = 0;   // BuildControlMesh
  double flips = 0;         // FlipEdgesToData
  double surface = 0;       // BuildLimitSurface + EvaluateSurface (inside the fit)
  double coverage = 0;      // MapPixels (inside the fit)
  double assemble = 0;      // normal equations (inside the fit)
  double solve = 0;         // sparse factorisation + solve
  double refine = 0;        // error map and sample selection
  double metrics = 0;       // final render + CompareImages
  double total = 0;
};

// a - b phase by phase (a round's share of the running sums); total is the sum of the
// differences from features to metrics, load left out.
VectorizeTimings operator-(const VectorizeTimings& a, const VectorizeTimings& b);

struct VectorizeIteration {
  uint32_t vertices = 0, triangles = 0;
  uint32_t added_samples = 0;  // samples added before this fit
  double psnr = 0;             // of the fit's reconstruction
  VectorizeTimings seconds;    // this round's share of the phases (refine: the error map and
                               // selection before it; total: the round's sum)
};

// The paper's Table I fields for one result.
struct VectorizeReport {
  int iterations = 0;              // refinement rounds done
  uint32_t vertices = 0, triangles = 0;
  uint64_t paper_size = 0;         // 20 V + 6 T + 8 bytes
  uint64_t pixels = 0;             // domain pixels
  double compression_ratio = 0;    // pixels / vertices
  double psnr = 0, mssim = 0, mean_error = 0;  // of Render8() at the fit level r vs the input
                                               // (CompareImages): what `sdvi render --levels r`
                                               // writes to a PNG, as `sdvi compare` measures it
  int levels = 0;                  // the subdivision level r of those metrics' render
  double fit_psnr = 0;             // of the last colour fit's reconstruction, before rounding
                                   // to 8 bits (its own error sum; history.back().psnr)
  uint32_t feature_curves = 0;     // curves used (after the budget filter)
  VectorizeTimings seconds;
  std::vector<VectorizeIteration> history;
};

struct VectorizeResult {
  Image image;                        // the fitted sdvi image
  VectorizeReport report;
  std::vector<FeatureCurve> features; // the curves used
  Raster8 reconstruction;             // Render8() of image at the identity viewport, level r
                                      // of the fit (RGBA): what the report's metrics measured
};

// Vectorizes raster (grey / RGB, with alpha or a mask for object images: see FitColors for
// the domain rule). Deterministic: equal inputs and options give equal images.
// Errors: kEmptyInput, kInvalidArgument (options), errors of the phases it runs;
// kLimitExceeded when memory runs out (no exception escapes: dependencies' ones become
// kInternal).
StatusOr<VectorizeResult> Vectorize(const Raster& raster, const Raster* mask,
                                    const VectorizeOptions& options);

// Vectorize with the interior features given instead of detected, for importers that know
// the exact curves (SVG artwork): edge detection is skipped, the domain contours of an
// object image are still found from alpha / mask, and `features` (non-boundary curves in
// source pixels) are added after them; the rest (budget filter, mesh, fit, refinement) is
// Vectorize's. Errors: those of Vectorize and of BuildControlMesh for bad curves.
StatusOr<VectorizeResult> VectorizeWithFeatures(const Raster& raster, const Raster* mask,
                                                const std::vector<FeatureCurve>& features,
                                                const VectorizeOptions& options);

// A per-pixel error picture for people (paper Fig. 10): |difference| summed over R, G, B,
// amplified 4x, drawn black (exact) to white; pixels outside the domain are mid grey.
Raster ErrorImage(const Raster8& reconstruction, const Raster& reference);

// ---- Building blocks of the refinement (spec/METHOD.md section 6 steps 4 and 6), used by Vectorize ----

// Pixels where no interior sample may go: outside the domain, or within `clearance` px of a
// crease edge of mesh (the pairs' strips and the feature polylines themselves), or of a
// feature curve when mesh is null. One byte per pixel, 1 = blocked.
std::vector<uint8_t> BlockedPixels(const Raster& target, const Raster* mask, const Image* mesh,
                                   const std::vector<FeatureCurve>& curves, double clearance);

// Interior samples on a staggered (hexagonal) grid of the given spacing, at unblocked pixel
// centres only.
std::vector<Point2> GridSamples(int width, int height, double spacing,
                                const std::vector<uint8_t>& blocked);

// The quality stop's content blocks (ContentBlocks, features.h; spec/METHOD.md section 6):
// blocks of `block` px, busy when some channel (R, G, B; grey: one) of the block's domain
// pixels spans more than `tolerance` (max - min, 0..255 units). Blocks without a domain
// pixel are flat. block <= 0 gives no blocks (everything busy).
ContentBlocks FindContentBlocks(const Raster& raster, const Raster* mask, int block, double tolerance);

// Per-pixel squared error sum over R, G, B between the reconstruction (RGBA) and target,
// averaged by a Gaussian of sigma px (sigma <= 0: none); -1 outside the fitting domain.
std::vector<float> ErrorMap(const Raster& reconstruction, const Raster& target, const Raster* mask,
                            double sigma);

// ErrorMap(ReconstructRaster(fit), target, mask, sigma), the same floats, computed from the
// fit's pixel samples without the RGBA reconstruction, on `threads` threads.
std::vector<float> ErrorMap(const ColorFit& fit, const Raster& target, const Raster* mask, double sigma,
                            int threads);

// Data-dependent edge flips (spec/METHOD.md section 6 step 4, after the CDT): in up to `passes` sweeps over the
// non-crease interior edges (sorted; a triangle flips at most once a sweep), an edge whose
// quadrilateral is strictly convex is flipped when the piecewise-linear interpolation of the
// image (Gaussian sigma 1 px) sampled at the four vertices has a squared error over the
// quadrilateral's pixels below 0.98 x that of the current diagonal, and neither new triangle
// has an angle under min_angle_deg. Orientation is kept. Returns the number of flips. The
// errors are computed on `threads` threads; the result is the same for any thread count.
//
// A triangle's error is computed with its corners in one canonical order (ascending x, then
// y), so it depends on the three positions only, not on how a mesh lists them.
// `cache` (optional) carries the triangle errors from one call to the next on meshes of the same raster and mask (the vectorizer's rounds re-triangulate,
// and most triangles come back): an error is keyed by its triangle's three vertex positions
// in the canonical order, so a cached value is the value the call would compute. It keeps
// the errors of the last call only.
class FlipErrorCache {
 public:
  struct Entry {
    std::array<uint32_t, 6> key;  // x, y of the three vertices, float bits, canonical order
    double error;
  };
  // The cached error of key, or nullptr. Safe to call from several threads.
  const double* Find(const std::array<uint32_t, 6>& key) const;
  // Lookups Find has answered so far.
  size_t hits() const { return hits_.load(); }
  // Records an error computed or found by the current call.
  void Add(const std::array<uint32_t, 6>& key, double error) { current_.push_back({key, error}); }
  // Appends n entries for the caller to fill (several threads may fill their own ones), as
  // n calls of Add would in the same order.
  Entry* Extend(size_t n) {
    const size_t at = current_.size();
    current_.resize(at + n);
    return current_.data() + at;
  }
  // Ends a call: what it recorded becomes what later calls find.
  void EndCall();
  size_t size() const { return previous_.size(); }

 private:
  // The last call's errors, each key once, and a hash table over them (open addressing,
  // linear probing, a power of two at least 1.5 times the entries; a slot holds an entry's
  // index + 1, 0 when empty): a lookup reads a slot or two and one entry however many
  // triangles the mesh has, and the table adds 6 to 12 bytes an entry to the entries' 32.
  std::vector<Entry> previous_;
  std::vector<uint32_t> slots_;
  std::vector<Entry> current_;
  mutable std::atomic<size_t> hits_{0};
};

int FlipEdgesToData(Image& mesh, const Raster& raster, const Raster* mask, int passes,
                    double min_angle_deg, int threads = 1, FlipErrorCache* cache = nullptr);

// The minimum distance of a new sample, as a function of the error e at its pixel:
// clamp(base * (reference_error / e)^exponent, min, max). exponent 0: a fixed spacing;
// exponent > 0: closer samples where the error is larger (density grows with the error).
struct SpacingRule {
  double base = 2, min = 2, max = 2;
  double exponent = 0;
  double reference_error = 1;
  double At(double error) const;
};

// Greedy far-apart selection (spec/METHOD.md section 6 step 6): visits pixels with error > threshold in order
// of decreasing error (ties: lower pixel index first) and keeps a pixel centre when it is
// farther than spacing.At(its error) from every vertex in `existing` and every pixel kept
// before; stops after max_count. Blocked pixels are skipped.
std::vector<Point2> SelectRefinementSamples(const std::vector<float>& error, int width, int height,
                                            double threshold, const SpacingRule& spacing,
                                            const std::vector<Vertex>& existing,
                                            const std::vector<uint8_t>& blocked,
                                            size_t max_count);

// The built-in sample image (`sdvi sample`): smooth gradients, a sharp and a blurred
// curved edge, a corner, RGB 0..255. Deterministic.
Raster MakeSampleImage(int width, int height);

}  // namespace sdvi
