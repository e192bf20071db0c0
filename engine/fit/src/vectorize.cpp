// SPDX-License-Identifier: GPL-3.0-or-later
// The vectorizer's driver (paper section IV): features -> control mesh -> colour fit ->
// refinement rounds; see vectorize.h for the rules and the budget.
#include "sdvi/vectorize.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <numeric>
#include <string>
#include <unordered_map>

#include <opencv2/core.hpp>

#if defined(__GLIBC__)
#include <malloc.h>  // malloc_trim
#endif

#include "sdvi/feature_budget.h"
#include "sdvi/progress.h"
#include "sdvi/render.h"

namespace sdvi {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double PsnrOf(double sum_squared_error, uint64_t pixels) {
  if (pixels == 0) return 0;
  const double mse = sum_squared_error / (3.0 * double(pixels));
  return mse <= 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

// Drops the shorter half of the non-boundary curves (at least one); false if none is left.
bool DropShorterHalf(std::vector<FeatureCurve>& curves) {
  std::vector<size_t> interior;
  for (size_t i = 0; i < curves.size(); ++i) {
    if (!curves[i].boundary) interior.push_back(i);
  }
  if (interior.empty()) return false;
  std::stable_sort(interior.begin(), interior.end(), [&](size_t a, size_t b) {
    return PolygonLength(curves[a]) > PolygonLength(curves[b]);
  });
  std::vector<uint8_t> drop(curves.size(), 0);
  for (size_t k = interior.size() / 2; k < interior.size(); ++k) drop[interior[k]] = 1;
  std::vector<FeatureCurve> kept;
  for (size_t i = 0; i < curves.size(); ++i) {
    if (!drop[i]) kept.push_back(curves[i]);
  }
  curves.swap(kept);
  return true;
}

Status CheckOptions(const VectorizeOptions& o) {
  auto bad = [](const std::string& what) {
    return Status(StatusCode::kInvalidArgument, "vectorize: " + what);
  };
  if (!(o.target_psnr >= 0) || !std::isfinite(o.target_psnr)) return bad("target PSNR must be >= 0");
  if (o.max_triangles < 0) return bad("max triangles must be >= 0");
  if (!(o.compression_ratio >= 1) || !std::isfinite(o.compression_ratio)) {
    return bad("compression ratio must be >= 1 pixel per vertex");
  }
  if (o.iterations < 0) return bad("iterations must be >= 0");
  if (!(o.error_threshold >= 0) || !(o.error_blur_sigma >= 0) || !(o.spacing_factor > 0) ||
      !(o.min_spacing > 0) || !(o.initial_fraction >= 0 && o.initial_fraction <= 1) ||
      !(o.growth > 0) || !(o.min_round_growth >= 0 && o.min_round_growth < 1) ||
      !(o.min_round_gain >= 0) || o.content_block < 0 ||
      !(o.max_feature_fraction >= 0 && o.max_feature_fraction <= 1) ||
      !(o.given_features_extra >= 0 && std::isfinite(o.given_features_extra))) {
    return bad("refinement constants out of range");
  }
  if (o.flip_passes < 0 || !(o.flip_min_angle >= 0 && o.flip_min_angle < 60)) {
    return bad("flip passes must be >= 0 and the flip angle in [0, 60) degrees");
  }
  if (o.threads < 1) return bad("threads must be >= 1");
  return Status::Ok();
}

void AddFitTimes(const ColorFit& fit, VectorizeTimings& t) {
  t.surface += fit.seconds_surface;
  t.coverage += fit.seconds_coverage;
  t.assemble += fit.seconds_assemble;
  t.solve += fit.seconds_solve;
}

// The colour fit's starting point (its conjugate gradients start from the vertices'
// colours): a vertex at the position of one of previous's vertices keeps that vertex's
// fitted colour, any other takes the raster's colour at its nearest pixel.
void SeedColors(Image& mesh, const Raster& raster, const Image* previous) {
  auto key = [](const Vertex& v) {
    uint32_t x, y;
    std::memcpy(&x, &v.x, 4);
    std::memcpy(&y, &v.y, 4);
    return (uint64_t(x) << 32) | y;
  };
  std::unordered_map<uint64_t, uint32_t> fitted;
  if (previous != nullptr) {
    fitted.reserve(previous->vertices.size());
    for (uint32_t i = 0; i < previous->vertices.size(); ++i) fitted.emplace(key(previous->vertices[i]), i);
  }
  for (Vertex& v : mesh.vertices) {
    const auto it = fitted.find(key(v));
    if (it != fitted.end()) {
      const Vertex& old = previous->vertices[it->second];
      v.r = old.r, v.g = old.g, v.b = old.b;
      continue;
    }
    const int x = std::clamp(int(std::floor(v.x)), 0, raster.width - 1);
    const int y = std::clamp(int(std::floor(v.y)), 0, raster.height - 1);
    const bool grey = raster.channels <= 2;
    v.r = raster.at(x, y, 0);
    v.g = raster.at(x, y, grey ? 0 : 1);
    v.b = raster.at(x, y, grey ? 0 : 2);
  }
}

// The driver; `given` (when non-null) replaces edge detection (VectorizeWithFeatures).
StatusOr<VectorizeResult> VectorizeFrom(const Raster& raster, const Raster* mask,
                                        const std::vector<FeatureCurve>* given,
                                        const VectorizeOptions& options) {
  const Clock::time_point all_start = Clock::now();
  if (raster.empty() || raster.data.size() != size_t(raster.width) * raster.height * raster.channels) {
    return Status(StatusCode::kEmptyInput, "vectorize: the input raster is empty or malformed");
  }
  if (raster.channels < 1 || raster.channels > 4) {
    return Status(StatusCode::kInvalidArgument,
                  "vectorize: input has " + std::to_string(raster.channels) + " channels, expected 1..4");
  }
  if (mask != nullptr && (mask->width != raster.width || mask->height != raster.height ||
                          mask->channels < 1)) {
    return Status(StatusCode::kInvalidArgument,
                  "vectorize: mask is " + std::to_string(mask->width) + "x" +
                      std::to_string(mask->height) + ", the image " + std::to_string(raster.width) +
                      "x" + std::to_string(raster.height));
  }
  SDVI_RETURN_IF_ERROR(CheckOptions(options));
  const int width = raster.width, height = raster.height;
  Progress* progress = options.progress;
  auto phase = [&](const std::string& name) {
    if (progress != nullptr) progress->Phase(name);
  };

  VectorizeResult result;
  VectorizeReport& report = result.report;
  VectorizeTimings& seconds = report.seconds;

  uint64_t domain_pixels = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) domain_pixels += InDomain(raster, mask, x, y) ? 1 : 0;
  }
  if (domain_pixels == 0) {
    return Status(StatusCode::kEmptyInput, "vectorize: no pixel of the image is in the domain "
                                           "(alpha or mask is zero everywhere)");
  }
  report.pixels = domain_pixels;
  // base_budget: from max_triangles or compression_ratio; vertex_budget adds the given
  // features' own cost when given_features_extra allows (below): the interior's density
  // follows the base, the totals the sum.
  const double base_budget =
      options.max_triangles > 0 ? options.max_triangles / 2.0
                                : double(domain_pixels) / options.compression_ratio;
  double vertex_budget = base_budget;
  const size_t triangle_cap = options.max_triangles > 0 ? size_t(options.max_triangles) : 0;

  // 1-2. Curvilinear features and their B-splines.
  phase("features");
  Clock::time_point start = Clock::now();
  FeatureOptions feature_options = options.features;
  feature_options.threads = options.threads;
  if (given != nullptr) feature_options.detect_edges = false;  // domain contours only
  SDVI_ASSIGN_OR_RETURN(std::vector<FeatureCurve> detected,
                        DetectFeatures(raster, mask, feature_options));
  if (given != nullptr) detected.insert(detected.end(), given->begin(), given->end());
  if (given != nullptr && triangle_cap == 0 && options.given_features_extra > 0) {
    // The given features' cost as the feature budget counts it (pairs, junctions), on top.
    FeatureBudgetOptions cost_options;
    cost_options.vertex_budget = std::numeric_limits<double>::infinity();
    cost_options.pairs = options.mesh.pairs;
    cost_options.junctions = options.mesh.junctions;
    cost_options.threads = options.threads;
    FeatureBudgetStats cost;
    (void)FitFeaturesToBudget(*given, cost_options, &cost);
    vertex_budget += std::min(cost.vertices_detected, options.given_features_extra * base_budget);
  }
  const double extra_budget = vertex_budget - base_budget;
  // The quality stop's blocks: interior samples go to busy blocks only.
  const ContentBlocks content =
      FindContentBlocks(raster, mask, options.content_block, options.error_threshold);
  // The feature budget: the interior's share (1 - max_feature_fraction) applies to the busy
  // part of the domain; what the flat part would have had goes to the features.
  FeatureBudgetOptions budget_options;
  budget_options.vertex_budget =
      (1.0 - (1.0 - options.max_feature_fraction) * content.BusyShare()) * base_budget + extra_budget;
  budget_options.interior_spacing = std::sqrt(double(domain_pixels) / base_budget);
  budget_options.pairs = options.mesh.pairs;
  budget_options.junctions = options.mesh.junctions;
  budget_options.threads = options.threads;
  FeatureBudgetStats budget_stats;
  std::vector<FeatureCurve> curves = FitFeaturesToBudget(detected, budget_options, &budget_stats);
#if defined(__GLIBC__)
  // The memory the features' worker threads freed stays with their malloc arenas, where
  // the main thread's allocations cannot reuse it: back to the system.
  if (options.threads > 1) malloc_trim(0);
#endif
  seconds.features += SecondsSince(start);

  // 3-4. Initial interior samples and the control mesh.
  phase("mesh");
  const double clearance = std::max(1.0, options.feature_clearance);
  const double initial_count = std::max(4.0, options.initial_fraction * base_budget);
  const double grid_spacing = std::sqrt(2.0 * double(domain_pixels) / (std::sqrt(3.0) * initial_count));
  std::vector<uint8_t> blocked;
  std::vector<Point2> samples;
  auto place_samples = [&] {
    const Clock::time_point samples_start = Clock::now();
    blocked = BlockedPixels(raster, mask, nullptr, curves, clearance);
    samples = GridSamples(width, height, grid_spacing, blocked);
    // The quality stop: no grid sample and no size bound where the colour is flat.
    std::erase_if(samples, [&](const Point2& p) { return !content.AnyBusy(p.x, p.y, p.x, p.y); });
    seconds.refine += SecondsSince(samples_start);
  };
  place_samples();

  ControlMeshOptions mesh_options = options.mesh;
  if (options.content_block > 0) mesh_options.content = &content;
  if (mesh_options.max_edge <= 0) {
    // CDT size bound from the budget: a few times the mean vertex spacing, so that the
    // interior samples, not the size bound, decide the density.
    mesh_options.max_edge = float(4.0 * std::sqrt(double(domain_pixels) / base_budget));
  }
  const double diagonal = std::hypot(double(width), double(height));
  FlipErrorCache flip_cache;  // the rounds' triangulations share most triangles
  Image mesh;
  start = Clock::now();
  for (int feature_rounds = 0;; ++feature_rounds) {
    SDVI_ASSIGN_OR_RETURN(mesh, BuildControlMesh(width, height, curves, samples, mesh_options));
    const double overshoot = double(mesh.vertices.size()) - 0.97 * vertex_budget;
    const double floor_budget = options.max_feature_fraction * base_budget + extra_budget;
    if (triangle_cap == 0 && overshoot > 0 && budget_stats.vertices_kept < budget_stats.vertices_detected &&
        budget_options.vertex_budget > floor_budget && feature_rounds < 4) {
      // The features were cut to their budget and the mesh (with the mesher's Steiner
      // points around them) is over the vertex budget: a smaller feature budget, down to
      // max_feature_fraction of the budget at least.
      budget_options.vertex_budget =
          std::max(floor_budget, std::min(budget_options.vertex_budget, budget_stats.vertices_kept) - 1.25 * overshoot);
      curves = FitFeaturesToBudget(detected, budget_options, &budget_stats);
      place_samples();
      continue;
    }
    if (triangle_cap == 0 || mesh.triangles.size() <= triangle_cap) break;
    // Over budget before any refinement: fewer grid samples first, then fewer features,
    // then a looser size bound.
    if (!samples.empty()) {
      samples.resize(samples.size() / 2);
    } else if (!DropShorterHalf(curves)) {
      if (mesh_options.max_edge >= diagonal) {
        return Status(StatusCode::kLimitExceeded,
                      "vectorize: max triangles " + std::to_string(triangle_cap) +
                          " is below what the domain boundary alone needs (" +
                          std::to_string(mesh.triangles.size()) + " triangles)");
      }
      mesh_options.max_edge *= 2;
    }
  }
  seconds.triangulate += SecondsSince(start);
  start = Clock::now();
  FlipEdgesToData(mesh, raster, mask, options.flip_passes, options.flip_min_angle, options.threads,
                  &flip_cache);
  seconds.flips += SecondsSince(start);
  std::vector<uint8_t>().swap(blocked);  // the initial samples' map: not needed by the fit

  ColorFitOptions fit_options = options.fit;
  fit_options.threads = options.threads;
  fit_options.warm_start = true;  // SeedColors below: the previous round's colours
  phase("fit");
  SeedColors(mesh, raster, nullptr);
  ColorFitBuffers fit_buffers;  // storage handed from one round's fit to the next
  SDVI_ASSIGN_OR_RETURN(ColorFit fit, FitColors(mesh, raster, mask, fit_options, &fit_buffers));
  AddFitTimes(fit, seconds);
  double psnr = PsnrOf(fit.sum_squared_error, fit.domain_pixels);
  report.history.push_back({uint32_t(mesh.vertices.size()), uint32_t(mesh.triangles.size()),
                            uint32_t(samples.size()), psnr, seconds - VectorizeTimings()});
  if (progress != nullptr) {
    progress->Update(1.0, std::to_string(mesh.triangles.size()) + " triangles, " +
                              std::to_string(psnr).substr(0, 5) + " dB");
  }

  // 6. Refinement rounds.
  SpacingRule spacing;
  spacing.base = std::max(options.min_spacing,
                          options.spacing_factor * std::sqrt(double(domain_pixels) / base_budget));
  spacing.min = options.min_spacing;
  spacing.max = 4 * spacing.base;
  spacing.exponent = options.spacing_exponent;
  const double threshold = 3.0 * options.error_threshold * options.error_threshold;
  double last_gain = std::numeric_limits<double>::infinity();  // the last round's PSNR gain, dB
  for (int round = 1; round <= options.iterations; ++round) {
    if (options.target_psnr > 0 && psnr >= options.target_psnr) break;
    double room = vertex_budget - double(mesh.vertices.size());
    if (triangle_cap > 0) {
      room = std::min(room, (double(triangle_cap) - double(mesh.triangles.size())) / 2.0);
    }
    if (room < std::max(1.0, 0.03 * vertex_budget)) break;  // within 3% of the budget
    const size_t want =
        size_t(std::min(room, std::max(64.0, options.growth * double(mesh.vertices.size()))));

    phase("refine " + std::to_string(round));
    const VectorizeTimings round_start = seconds;
    start = Clock::now();
    std::vector<float> error =
        ErrorMap(fit, raster, mask, options.error_blur_sigma, options.threads);
    double error_sum = 0;
    for (float e : error) error_sum += std::max(0.f, e);
    spacing.reference_error = error_sum / double(domain_pixels);
    // Only the error map is needed from here on: release the fit's memory but the
    // coverage's, which the next fit writes into.
    fit_buffers.coverage = std::move(fit.coverage.owner);
    fit = ColorFit();
    blocked = BlockedPixels(raster, mask, &mesh, curves, clearance);
    std::vector<Point2> added = SelectRefinementSamples(error, width, height, threshold, spacing,
                                                        mesh.vertices, blocked, want);
    // The per-pixel maps are not needed by the triangulation and the fit: release them.
    std::vector<float>().swap(error);
    std::vector<uint8_t>().swap(blocked);
    seconds.refine += SecondsSince(start);
    if (added.empty()) break;
    if (double(added.size()) < options.min_round_growth * double(mesh.vertices.size()) &&
        last_gain < options.min_round_gain) {
      break;  // the tail stop
    }

    start = Clock::now();
    Image candidate;
    std::vector<Point2> next;
    bool accepted = false;
    // The triangulation may add Steiner points: a round that overshoots the budget (the
    // triangle cap, or the vertex budget by more than 3%) is redone with fewer samples,
    // cut in proportion to the overshoot (the worst-error samples stay).
    const double vertices_before = double(mesh.vertices.size());
    const double triangles_before = double(mesh.triangles.size());
    for (int attempt = 0; attempt < 6 && !added.empty(); ++attempt) {
      next = samples;
      next.insert(next.end(), added.begin(), added.end());
      SDVI_ASSIGN_OR_RETURN(candidate, BuildControlMesh(width, height, curves, next, mesh_options));
      double allowed = 0, grown = 0;
      if (triangle_cap > 0) {
        if (candidate.triangles.size() <= triangle_cap) {
          accepted = true;
          break;
        }
        allowed = double(triangle_cap) - triangles_before;
        grown = double(candidate.triangles.size()) - triangles_before;
      } else {
        if (double(candidate.vertices.size()) <= 1.03 * vertex_budget + 1) {
          accepted = true;
          break;
        }
        allowed = vertex_budget - vertices_before;
        grown = double(candidate.vertices.size()) - vertices_before;
      }
      const double keep = grown > 0 ? 0.95 * double(added.size()) * std::max(0.0, allowed) / grown : 0;
      added.resize(std::min(added.size() - 1, size_t(keep)));
    }
    seconds.triangulate += SecondsSince(start);
    if (!accepted) break;
    start = Clock::now();
    FlipEdgesToData(candidate, raster, mask, options.flip_passes, options.flip_min_angle, options.threads,
                    &flip_cache);
    seconds.flips += SecondsSince(start);

    phase("fit " + std::to_string(round));
    SeedColors(candidate, raster, &mesh);
    SDVI_ASSIGN_OR_RETURN(ColorFit refit, FitColors(candidate, raster, mask, fit_options, &fit_buffers));
    AddFitTimes(refit, seconds);
    mesh = std::move(candidate);
    fit = std::move(refit);
    samples = std::move(next);
    const double previous_psnr = psnr;
    psnr = PsnrOf(fit.sum_squared_error, fit.domain_pixels);
    last_gain = psnr - previous_psnr;
    report.iterations = round;
    report.history.push_back({uint32_t(mesh.vertices.size()), uint32_t(mesh.triangles.size()),
                              uint32_t(added.size()), psnr, seconds - round_start});
    if (progress != nullptr) {
      progress->Update(1.0, std::to_string(mesh.triangles.size()) + " triangles, " +
                                std::to_string(psnr).substr(0, 5) + " dB");
    }
  }

  // Final metrics (unless the caller measures its file): Render8 at the fitted level r +
  // CompareImages, as `sdvi render --levels r` + `sdvi compare` measure them (spec/RATE.md 1).
  fit = ColorFit();  // the fit's arrays are not needed by the metrics
  fit_buffers = ColorFitBuffers();
  report.fit_psnr = psnr;
  if (options.final_metrics) {
    phase("metrics");
    start = Clock::now();
    RenderOptions render_options;
    render_options.viewport = Viewport::Identity(width, height);
    render_options.levels = std::max(2, options.fit.surface.levels);  // the fitted level r
    render_options.threads = options.threads;
    SDVI_ASSIGN_OR_RETURN(result.reconstruction, Render8(mesh, render_options));
    Raster reference_with_domain;
    const Raster* reference = &raster;
    if (mask != nullptr) {
      reference_with_domain = Raster(width, height, 4);
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          for (int c = 0; c < 3; ++c) {
            reference_with_domain.at(x, y, c) = raster.channels <= 2 ? raster.at(x, y, 0) : raster.at(x, y, c);
          }
          reference_with_domain.at(x, y, 3) = InDomain(raster, mask, x, y) ? 1.f : 0.f;
        }
      }
      reference = &reference_with_domain;
    }
    SDVI_ASSIGN_OR_RETURN(ImageMetrics metrics, CompareImages(result.reconstruction, *reference, options.threads));
    seconds.metrics += SecondsSince(start);
    report.psnr = metrics.psnr;
    report.mssim = metrics.mssim;
    report.mean_error = metrics.mean_error;
    report.levels = render_options.levels;
  }

  report.vertices = uint32_t(mesh.vertices.size());
  report.triangles = uint32_t(mesh.triangles.size());
  report.paper_size = uint64_t(report.vertices) * 20 + uint64_t(report.triangles) * 6 + 8;
  report.compression_ratio = double(domain_pixels) / std::max<double>(1, report.vertices);
  report.feature_curves = uint32_t(curves.size());
  result.image = std::move(mesh);
  result.features = std::move(curves);
  seconds.total = SecondsSince(all_start);
  if (progress != nullptr) progress->Done();
  return result;
}

// VectorizeFrom with no exception escaping: running out of memory (std::bad_alloc, or
// OpenCV's out-of-memory error) is kLimitExceeded, any other exception from a dependency
// kInternal, each with what it said.
StatusOr<VectorizeResult> VectorizeGuarded(const Raster& raster, const Raster* mask,
                                           const std::vector<FeatureCurve>* given,
                                           const VectorizeOptions& options) {
  const std::string size = std::to_string(raster.width) + "x" + std::to_string(raster.height);
  try {
    return VectorizeFrom(raster, mask, given, options);
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, "vectorize: out of memory on the " + size + " image");
  } catch (const cv::Exception& e) {
    // OpenCV's own text (e.err), without its multi-line what().
    if (e.code == cv::Error::StsNoMem)
      return Status(StatusCode::kLimitExceeded, "vectorize: out of memory on the " + size + " image (" + e.err + ")");
    return Status(StatusCode::kInternal,
                  "vectorize: OpenCV failed on the " + size + " image: " + e.err + " (in " + e.func + ")");
  } catch (const std::exception& e) {
    return Status(StatusCode::kInternal, "vectorize: a dependency failed on the " + size + " image: " + e.what());
  }
}

}  // namespace

VectorizeTimings operator-(const VectorizeTimings& a, const VectorizeTimings& b) {
  VectorizeTimings d;
  d.load = a.load - b.load;
  d.features = a.features - b.features;
  d.triangulate = a.triangulate - b.triangulate;
  d.flips = a.flips - b.flips;
  d.surface = a.surface - b.surface;
  d.coverage = a.coverage - b.coverage;
  d.assemble = a.assemble - b.assemble;
  d.solve = a.solve - b.solve;
  d.refine = a.refine - b.refine;
  d.metrics = a.metrics - b.metrics;
  d.total = d.features + d.triangulate + d.flips + d.surface + d.coverage + d.assemble + d.solve + d.refine +
            d.metrics;
  return d;
}

StatusOr<VectorizeResult> Vectorize(const Raster& raster, const Raster* mask,
                                    const VectorizeOptions& options) {
  return VectorizeGuarded(raster, mask, nullptr, options);
}

StatusOr<VectorizeResult> VectorizeWithFeatures(const Raster& raster, const Raster* mask,
                                                const std::vector<FeatureCurve>& features,
                                                const VectorizeOptions& options) {
  return VectorizeGuarded(raster, mask, &features, options);
}

Raster ErrorImage(const Raster8& reconstruction, const Raster& reference) {
  const int width = reference.width, height = reference.height;
  Raster out(width, height, 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool in_reference = !reference.has_alpha() || reference.at(x, y, reference.channels - 1) > 0.5f;
      const bool in_reconstruction =
          x < reconstruction.width && y < reconstruction.height &&
          (!reconstruction.has_alpha() || reconstruction.at(x, y, reconstruction.channels - 1) >= 128);
      float value = 128.f;
      if (in_reference && in_reconstruction) {
        float sum = 0;
        for (int c = 0; c < 3; ++c) {
          const float ref = reference.channels <= 2 ? reference.at(x, y, 0) : reference.at(x, y, c);
          const float rec = reconstruction.channels <= 2 ? reconstruction.at(x, y, 0)
                                                         : reconstruction.at(x, y, c);  // 0..255
          sum += std::abs(rec - ref);
        }
        value = std::min(255.f, 4.f * sum);
      }
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = value;
    }
  }
  return out;
}

}  // namespace sdvi
