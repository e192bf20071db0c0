// SPDX-License-Identifier: GPL-3.0-or-later
// bench_table1: the paper's Table I analogue for the vectorizer, its ablations, a phase
// timing and a large-image run. Prints Markdown tables; not part of ctest.
//
//   bench_table1 [--data DIR] [IMAGE...] [--ratios 50,250] [--no-ablations] [--no-table]
//                [--timing IMG] [--timing-triangles N] [--large IMG] [--threads N]
//                [--opt name=value ...]   (override a vectorizer constant, for experiments)
//
// Images: the given files, else every file of DIR/photos and DIR/graphics (sorted).
// Table: per image and per budget (compression ratio = pixels / vertices): vertices,
//   triangles, paper size, PSNR, MSSIM, mean error, time.
// Ablations at the first budget, equal triangle budget: (a) full method; (b) the same mesh
//   with piecewise-linear colours (levels 0, no limit; same least squares); (c) no feature
//   pairs; (d) no sharpness (every pair at rho). Averages of (a) - (x) in dB.
// --timing IMG: phase-by-phase seconds at --timing-triangles (default 10000).
// --large IMG: IMG upscaled (bicubic) to 3840x2160, default budget; time and peak RSS.
//   Run it alone: peak RSS is per process.
// --scale IMG (repeatable) [--scale-threads 1,2]: IMG as it is (e.g. a 3840x2160 photo),
//   default budget, once per thread count, each run in its own child process (load +
//   vectorize, as `sdvi vectorize` does): wall and CPU seconds per phase, the child's peak
//   RSS, PSNR, and whether the mesh is the same as with the first thread count; then the
//   speed-up of each thread count over the first.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/color_fit.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/vectorize.h"

namespace {

struct Config {
  std::string data = "/work/shared/data";
  std::vector<std::string> images;
  std::vector<double> ratios = {50, 250};
  bool ablations = true;
  bool table = true;
  std::string timing;
  int timing_triangles = 10000;
  std::string large;
  std::vector<std::string> scale;
  std::vector<int> scale_threads = {1, 2};
  int threads = 2;
  std::vector<std::pair<std::string, double>> overrides;  // --opt name=value
};

// Applies --opt overrides (experiments with the vectorizer's constants).
bool ApplyOverrides(const Config& c, sdvi::VectorizeOptions& o) {
  for (const auto& [name, v] : c.overrides) {
    if (name == "iterations") o.iterations = int(v);
    else if (name == "error_threshold") o.error_threshold = v;
    else if (name == "error_blur_sigma") o.error_blur_sigma = v;
    else if (name == "spacing_factor") o.spacing_factor = v;
    else if (name == "min_spacing") o.min_spacing = v;
    else if (name == "initial_fraction") o.initial_fraction = v;
    else if (name == "growth") o.growth = v;
    else if (name == "min_round_growth") o.min_round_growth = v;
    else if (name == "min_round_gain") o.min_round_gain = v;
    else if (name == "content_block") o.content_block = int(v);
    else if (name == "spacing_exponent") o.spacing_exponent = v;
    else if (name == "feature_clearance") o.feature_clearance = v;
    else if (name == "max_feature_fraction") o.max_feature_fraction = v;
    else if (name == "flip_passes") o.flip_passes = int(v);
    else if (name == "flip_min_angle") o.flip_min_angle = v;
    else if (name == "detect_edges") o.features.detect_edges = v != 0;
    else if (name == "rho") o.mesh.rho = float(v);
    else if (name == "max_edge") o.mesh.max_edge = float(v);
    else if (name == "min_angle") o.mesh.min_angle_deg = float(v);
    else if (name == "regularization") o.fit.regularization = v;
    else if (name == "levels") o.fit.surface.levels = int(v);
    else {
      std::fprintf(stderr, "bench_table1: unknown --opt %s\n", name.c_str());
      return false;
    }
  }
  return true;
}

const Config* g_config = nullptr;

double PeakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: KiB
}

std::vector<std::string> ListImages(const std::string& dir) {
  std::vector<std::string> out;
  for (const char* sub : {"photos", "graphics"}) {
    const std::filesystem::path p = std::filesystem::path(dir) / sub;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(p, ec)) {
      const std::string ext = entry.path().extension().string();
      if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".bmp") {
        out.push_back(entry.path().string());
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string ShortName(const std::string& path) {
  const std::filesystem::path p(path);
  return p.parent_path().filename().string() + "/" + p.filename().string();
}

sdvi::StatusOr<sdvi::VectorizeResult> Run(const sdvi::Raster& raster, sdvi::VectorizeOptions options,
                                          int threads) {
  options.threads = threads;
  options.fit.threads = threads;
  if (g_config != nullptr && !ApplyOverrides(*g_config, options)) std::exit(1);
  return sdvi::Vectorize(raster, nullptr, options);
}

// (b): the same mesh, piecewise-linear colours fitted by the same least squares.
sdvi::StatusOr<sdvi::ImageMetrics> PiecewiseLinear(const sdvi::Image& mesh, const sdvi::Raster& raster,
                                                   int threads) {
  sdvi::Image copy = mesh;
  sdvi::ColorFitOptions options;
  options.surface.levels = 0;
  options.surface.to_limit = false;
  options.threads = threads;
  SDVI_ASSIGN_OR_RETURN(sdvi::ColorFit fit, sdvi::FitColors(copy, raster, nullptr, options));
  return sdvi::CompareImages(sdvi::ReconstructRaster(fit), raster);
}

void PrintPhases(const sdvi::VectorizeReport& r) {
  const sdvi::VectorizeTimings& s = r.seconds;
  std::printf("| phase | seconds |\n|---|---|\n");
  const std::pair<const char*, double> rows[] = {
      {"features (DetectFeatures)", s.features},     {"triangulate (BuildControlMesh)", s.triangulate},
      {"flips (FlipEdgesToData)", s.flips},
      {"limit surface + evaluate", s.surface},       {"coverage (MapPixels)", s.coverage},
      {"assemble normal equations", s.assemble},     {"solve (colour CG)", s.solve},
      {"refine (error map, selection)", s.refine},   {"metrics (Render + Compare)", s.metrics},
      {"total", s.total}};
  for (const auto& [name, sec] : rows) std::printf("| %s | %.3f |\n", name, sec);
  std::printf("\nfits: %zu (iterations %d); per round vertices/triangles/PSNR:", r.history.size(),
              r.iterations);
  for (const sdvi::VectorizeIteration& it : r.history) {
    std::printf(" %u/%u/%.2f", it.vertices, it.triangles, it.psnr);
  }
  std::printf("\n\n");
}

// One --scale run, measured in a child process.
struct ScaleRun {
  int ok = 0;
  int width = 0, height = 0;
  double wall = 0, cpu = 0;  // seconds: load + vectorize; CPU = user + system
  double peak_mib = 0;       // the child's peak RSS
  sdvi::VectorizeTimings seconds;
  uint32_t vertices = 0, triangles = 0;
  double psnr = 0;
  uint64_t mesh_hash = 0;  // FNV-1a of the vertices' and triangles' bytes
  static constexpr int kMaxRounds = 16;
  int rounds = 0;  // fits (history entries), at most kMaxRounds kept
  sdvi::VectorizeIteration history[kMaxRounds];
};

uint64_t HashBytes(uint64_t h, const void* data, size_t size) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

ScaleRun RunScaleChild(const std::string& path, int threads) {
  ScaleRun run;
  int fds[2];
  if (pipe(fds) != 0) return run;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const auto start = std::chrono::steady_clock::now();
    ScaleRun r;
    sdvi::StatusOr<sdvi::Raster> raster = sdvi::LoadRaster(path);
    if (raster.ok()) {
      const double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      r.width = raster->width;
      r.height = raster->height;
      auto result = Run(*raster, sdvi::VectorizeOptions{}, threads);
      if (result.ok()) {
        r.ok = 1;
        r.seconds = result->report.seconds;
        r.seconds.load = load;
        r.vertices = result->report.vertices;
        r.triangles = result->report.triangles;
        r.psnr = result->report.psnr;
        r.rounds = int(std::min<size_t>(ScaleRun::kMaxRounds, result->report.history.size()));
        std::copy_n(result->report.history.begin(), r.rounds, r.history);
        const sdvi::Image& m = result->image;
        r.mesh_hash = HashBytes(1469598103934665603ull, m.vertices.data(), m.vertices.size() * sizeof(sdvi::Vertex));
        r.mesh_hash = HashBytes(r.mesh_hash, m.triangles.data(), m.triangles.size() * sizeof(sdvi::Triangle));
      } else {
        std::fprintf(stderr, "%s: %s\n", path.c_str(), result.status().ToString().c_str());
      }
    } else {
      std::fprintf(stderr, "%s\n", raster.status().ToString().c_str());
    }
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    r.cpu = usage.ru_utime.tv_sec + usage.ru_utime.tv_usec * 1e-6 + usage.ru_stime.tv_sec + usage.ru_stime.tv_usec * 1e-6;
    r.peak_mib = usage.ru_maxrss / 1024.0;
    const bool written = write(fds[1], &r, sizeof(r)) == ssize_t(sizeof(r));
    _exit(written ? 0 : 1);
  }
  close(fds[1]);
  if (pid > 0) {
    if (read(fds[0], &run, sizeof(run)) != ssize_t(sizeof(run))) run = ScaleRun();
    int status = 0;
    waitpid(pid, &status, 0);
  }
  close(fds[0]);
  return run;
}

// --scale: the table of the large-image runs.
void PrintScale(const Config& c) {
  std::printf("## Large images as they are, default budget, one child process per run\n\n");
  std::printf("| image | threads | wall s | CPU s | features | triangulate | flips | surface | coverage | "
              "assemble | solve | refine | metrics | peak RSS MiB | vertices | PSNR dB | same mesh |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& path : c.scale) {
    std::vector<ScaleRun> runs;
    for (int threads : c.scale_threads) {
      const ScaleRun r = RunScaleChild(path, threads);
      runs.push_back(r);
      if (!r.ok) {
        std::printf("| %s | %d | failed |\n", ShortName(path).c_str(), threads);
        continue;
      }
      const sdvi::VectorizeTimings& t = r.seconds;
      std::printf("| %s %dx%d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | "
                  "%u | %.2f | %s |\n",
                  ShortName(path).c_str(), r.width, r.height, threads, r.wall, r.cpu, t.features, t.triangulate,
                  t.flips, t.surface, t.coverage, t.assemble, t.solve, t.refine, t.metrics, r.peak_mib, r.vertices, r.psnr,
                  runs.size() == 1 ? "-" : (runs[0].ok && r.mesh_hash == runs[0].mesh_hash ? "yes" : "NO"));
      std::fflush(stdout);
    }
    for (size_t k = 0; k < runs.size(); ++k) {
      if (!runs[k].ok) continue;
      std::printf("\n%s, %d threads, per round (wall s):\n\n| round | vertices | added | triangulate | flips | "
                  "surface | coverage | assemble | solve | refine | total |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
                  ShortName(path).c_str(), c.scale_threads[k]);
      for (int i = 0; i < runs[k].rounds; ++i) {
        const sdvi::VectorizeIteration& it = runs[k].history[i];
        const sdvi::VectorizeTimings& t = it.seconds;
        std::printf("| %d | %u | %u | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", i, it.vertices,
                    it.added_samples, t.triangulate, t.flips, t.surface, t.coverage, t.assemble, t.solve, t.refine,
                    t.total);
      }
    }
    for (size_t k = 1; k < runs.size(); ++k) {
      if (!runs[0].ok || !runs[k].ok) continue;
      std::printf("\n%s: %d threads vs %d: wall x%.2f, vectorize x%.2f\n", ShortName(path).c_str(),
                  c.scale_threads[k], c.scale_threads[0], runs[0].wall / runs[k].wall,
                  runs[0].seconds.total / runs[k].seconds.total);
    }
    std::printf("\n");
  }
}

int ParseArgs(int argc, char** argv, Config& c) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_table1: %s needs a value\n", a.c_str());
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--data") {
      c.data = value();
    } else if (a == "--ratios") {
      c.ratios.clear();
      std::string list = value();
      size_t start = 0;
      while (start <= list.size()) {
        const size_t comma = list.find(',', start);
        const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!item.empty()) c.ratios.push_back(std::stod(item));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    } else if (a == "--no-ablations") {
      c.ablations = false;
    } else if (a == "--no-table") {
      c.table = false;
    } else if (a == "--timing") {
      c.timing = value();
    } else if (a == "--timing-triangles") {
      c.timing_triangles = std::stoi(value());
    } else if (a == "--large") {
      c.large = value();
    } else if (a == "--scale") {
      c.scale.push_back(value());
    } else if (a == "--scale-threads") {
      c.scale_threads.clear();
      std::string list = value();
      size_t start = 0;
      while (start <= list.size()) {
        const size_t comma = list.find(',', start);
        const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!item.empty()) c.scale_threads.push_back(std::max(1, std::stoi(item)));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    } else if (a == "--opt") {
      const std::string kv = value();
      const size_t eq = kv.find('=');
      if (eq == std::string::npos) {
        std::fprintf(stderr, "bench_table1: --opt expects name=value\n");
        return 1;
      }
      c.overrides.push_back({kv.substr(0, eq), std::stod(kv.substr(eq + 1))});
    } else if (a == "--threads") {
      c.threads = std::max(1, std::stoi(value()));
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "bench_table1: unknown option %s\n", a.c_str());
      return 1;
    } else {
      c.images.push_back(a);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Config config;
  if (ParseArgs(argc, argv, config) != 0) return 1;
  g_config = &config;
  const bool only_special =
      config.images.empty() && (!config.timing.empty() || !config.large.empty() || !config.scale.empty());
  if (config.images.empty() && !only_special) config.images = ListImages(config.data);
  if (!config.table && !config.ablations) config.images.clear();

  struct AblationRow {
    std::string name;
    double a = 0, b = 0, c = 0, d = 0;
  };
  std::vector<AblationRow> ablation_rows;

  if (!config.images.empty() && config.table) {
    std::printf("## Table I analogue (threads %d)\n\n", config.threads);
    std::printf("| image | size | ratio target | vertices | triangles | paper size B | ratio | PSNR dB | "
                "MSSIM | mean err | time s |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  }
  for (const std::string& path : config.images) {
    sdvi::StatusOr<sdvi::Raster> raster = sdvi::LoadRaster(path);
    if (!raster.ok()) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), raster.status().ToString().c_str());
      continue;
    }
    for (size_t k = 0; k < config.ratios.size(); ++k) {
      sdvi::VectorizeOptions options;
      options.compression_ratio = config.ratios[k];
      auto result = Run(*raster, options, config.threads);
      if (!result.ok()) {
        std::printf("| %s | %dx%d | %.0f | failed: %s |\n", ShortName(path).c_str(), raster->width,
                    raster->height, config.ratios[k], result.status().ToString().c_str());
        continue;
      }
      const sdvi::VectorizeReport& r = result->report;
      if (config.table) {
        std::printf("| %s | %dx%d | %.0f | %u | %u | %llu | %.1f | %.2f | %.4f | %.2f | %.2f |\n",
                    ShortName(path).c_str(), raster->width, raster->height, config.ratios[k],
                    r.vertices, r.triangles, static_cast<unsigned long long>(r.paper_size),
                    r.compression_ratio, r.psnr, r.mssim, r.mean_error, r.seconds.total);
        std::fflush(stdout);
      }
      if (k != 0 || !config.ablations) continue;
      AblationRow row{ShortName(path), r.psnr};
      const double failed = std::nan("");
      auto linear = PiecewiseLinear(result->image, *raster, config.threads);
      row.b = linear.ok() ? linear->psnr : failed;
      sdvi::VectorizeOptions equal;
      equal.max_triangles = int(r.triangles);
      equal.mesh.pairs = false;
      auto no_pairs = Run(*raster, equal, config.threads);
      row.c = no_pairs.ok() ? no_pairs->report.psnr : failed;
      if (!no_pairs.ok()) std::fprintf(stderr, "%s (c): %s\n", path.c_str(), no_pairs.status().ToString().c_str());
      equal.mesh.pairs = true;
      equal.mesh.use_sharpness = false;
      auto no_sharpness = Run(*raster, equal, config.threads);
      row.d = no_sharpness.ok() ? no_sharpness->report.psnr : failed;
      if (!no_sharpness.ok()) std::fprintf(stderr, "%s (d): %s\n", path.c_str(), no_sharpness.status().ToString().c_str());
      ablation_rows.push_back(row);
    }
  }
  if (!ablation_rows.empty()) {
    std::printf("\n## Ablations at equal triangle budget (ratio %.0f), PSNR dB\n\n", config.ratios[0]);
    std::printf("| image | (a) full | (b) piecewise linear | (c) no pairs | (d) no sharpness |\n"
                "|---|---|---|---|---|\n");
    // Means over the images where every variant ran (a failed run prints nan).
    double db = 0, dc = 0, dd = 0;
    int n = 0;
    for (const AblationRow& row : ablation_rows) {
      std::printf("| %s | %.2f | %.2f | %.2f | %.2f |\n", row.name.c_str(), row.a, row.b, row.c, row.d);
      if (std::isnan(row.b) || std::isnan(row.c) || std::isnan(row.d)) continue;
      db += row.a - row.b;
      dc += row.a - row.c;
      dd += row.a - row.d;
      ++n;
    }
    if (n > 0) {
      std::printf("\nmean gain of (a) over: (b) %+.2f dB, (c) %+.2f dB, (d) %+.2f dB (%d of %zu images; "
                  "the others had a failed variant)\n\n",
                  db / n, dc / n, dd / n, n, ablation_rows.size());
    }
  }

  if (!config.timing.empty()) {
    sdvi::StatusOr<sdvi::Raster> raster = sdvi::LoadRaster(config.timing);
    if (!raster.ok()) {
      std::fprintf(stderr, "%s\n", raster.status().ToString().c_str());
      return 2;
    }
    sdvi::VectorizeOptions options;
    options.max_triangles = config.timing_triangles;
    auto result = Run(*raster, options, config.threads);
    if (!result.ok()) {
      std::fprintf(stderr, "%s\n", result.status().ToString().c_str());
      return 2;
    }
    const sdvi::VectorizeReport& r = result->report;
    std::printf("## Phase timing: %s %dx%d, max %d triangles, threads %d\n\n", ShortName(config.timing).c_str(),
                raster->width, raster->height, config.timing_triangles, config.threads);
    std::printf("result: %u vertices, %u triangles, PSNR %.2f dB, MSSIM %.4f, mean error %.2f\n\n",
                r.vertices, r.triangles, r.psnr, r.mssim, r.mean_error);
    PrintPhases(r);
  }

  if (!config.scale.empty()) PrintScale(config);

  if (!config.large.empty()) {
    sdvi::StatusOr<sdvi::Raster> small = sdvi::LoadRaster(config.large);
    if (!small.ok()) {
      std::fprintf(stderr, "%s\n", small.status().ToString().c_str());
      return 2;
    }
    const int type = CV_32FC(small->channels);
    cv::Mat src(small->height, small->width, type, small->data.data());
    cv::Mat big;
    cv::resize(src, big, cv::Size(3840, 2160), 0, 0, cv::INTER_CUBIC);
    sdvi::Raster raster(3840, 2160, small->channels);
    std::memcpy(raster.data.data(), big.ptr<float>(), raster.data.size() * sizeof(float));
    big.release();
    *small = sdvi::Raster();
    const double before = PeakRssMiB();
    auto result = Run(raster, sdvi::VectorizeOptions{}, config.threads);
    if (!result.ok()) {
      std::fprintf(stderr, "%s\n", result.status().ToString().c_str());
      return 2;
    }
    const sdvi::VectorizeReport& r = result->report;
    std::printf("## Large image: %s upscaled to 3840x2160, default budget, threads %d\n\n",
                ShortName(config.large).c_str(), config.threads);
    std::printf("result: %u vertices, %u triangles, PSNR %.2f dB, MSSIM %.4f; peak RSS %.0f MiB "
                "(%.0f MiB before vectorizing)\n\n",
                r.vertices, r.triangles, r.psnr, r.mssim, PeakRssMiB(), before);
    PrintPhases(r);
  }
  return 0;
}
