// SPDX-License-Identifier: GPL-3.0-or-later
// `sdvi vectorize` (raster -> .sdvi, paper section IV) and `sdvi sample` (the built-in
// sample image).
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/codec.h"
#include "sdvi/features.h"
#include "sdvi/file_util.h"
#include "sdvi/parallel.h"
#include "sdvi/progress.h"
#include "sdvi/raster_io.h"
#include "sdvi/rate.h"
#include "sdvi/vectorize.h"

namespace sdvi::cli {
namespace {

using Clock = std::chrono::steady_clock;

Status WriteDebugPictures(const std::string& dir, const Raster& raster, const VectorizeResult& result) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    return Status(StatusCode::kIoError, dir + ": cannot create the debug directory: " + ec.message());
  }
  const std::filesystem::path base(dir);
  SDVI_RETURN_IF_ERROR(
      SaveRasterPng((base / "features.png").string(), DrawFeatures(raster, result.features)));
  SDVI_RETURN_IF_ERROR(
      SaveRasterPng((base / "mesh.png").string(), DrawControlMesh(raster, result.image)));
  SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "reconstruction.png").string(), result.reconstruction));
  SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "error.png").string(),
                                     ErrorImage(result.reconstruction, raster)));
  return Status::Ok();
}

// The options of `sdvi vectorize`.
struct VectorizeArgs {
  std::string input, output, mask, report, debug_dir;
  VectorizeOptions options;
  double quality = -1;
  uint64_t target_bytes = 0;
  CLI::Option *quality_opt = nullptr, *target_bytes_opt = nullptr;
  bool compress = false, strict = false, quiet = false, json = false;
};

Status VectorizeCommand(VectorizeArgs& args) {
  VectorizeOptions& options = args.options;
  options.fit.threads = options.threads;
  const std::string& input = args.input;
  const std::string& output = args.output;

  const Clock::time_point load_start = Clock::now();
  RasterSource source;
  SDVI_ASSIGN_OR_RETURN(Raster raster, LoadRaster(input, &source));
  // What the user should know about the input (spec/RASTER_INPUT.md), even with --quiet.
  for (const std::string& warning : source.warnings) std::fprintf(stderr, "sdvi vectorize: warning: %s\n", warning.c_str());
  Raster mask;
  const bool has_mask = !args.mask.empty();
  if (has_mask) {
    SDVI_ASSIGN_OR_RETURN(mask, LoadRaster(args.mask));
    if (mask.width != raster.width || mask.height != raster.height) {
      return Status(StatusCode::kInvalidArgument,
                    args.mask + ": mask is " + std::to_string(mask.width) + "x" +
                        std::to_string(mask.height) + " but " + input + " is " +
                        std::to_string(raster.width) + "x" + std::to_string(raster.height));
    }
  }
  const double load_seconds = std::chrono::duration<double>(Clock::now() - load_start).count();

  // Rate targets (spec/RATE.md 4): --quality and --target-bytes imply --compress.
  RateTarget target;
  const bool has_quality = args.quality_opt->count() > 0, has_bytes = args.target_bytes_opt->count() > 0;
  target.quality = has_quality ? args.quality : -1;
  target.bytes = has_bytes ? args.target_bytes : 0;
  const bool compress = args.compress || has_quality || has_bytes;
  const Raster* mask_ptr = has_mask ? &mask : nullptr;

  Progress progress(args.quiet);
  options.progress = &progress;
  RateOptions rate;
  rate.threads = options.threads;
  // The file and its one PSNR (spec/RATE.md 1): the x1 render of what a reader decodes.
  // The report's PSNR, MSSIM and mean error are the file's, measured here once: the
  // vectorizer's own final render is made only for --debug-dir.
  options.final_metrics = !args.debug_dir.empty();
  StatusOr<VectorizedFile> made = VectorizeToFile(raster, mask_ptr, options, compress, target, rate, output);
  if (!made.ok()) return Status(made.status().code(), input + ": " + made.status().message());
  VectorizeResult& result = made->vectorized;
  const std::vector<uint8_t>& bytes = made->bytes;
  result.report.seconds.load = load_seconds;
  if (!made->reached) {
    if (args.strict) return Status(StatusCode::kLimitExceeded, input + ": " + made->note + "; nothing written");
    std::fprintf(stderr, "sdvi vectorize: warning: %s: %s\n", input.c_str(), made->note.c_str());
  }
  SDVI_RETURN_IF_ERROR(WriteFileAtomic(output, bytes));
  const uint64_t file_size = bytes.size();

  const std::string report = VectorizedFileReportJson(*made, input, output, 2) + "\n";
  if (!args.report.empty()) SDVI_RETURN_IF_ERROR(WriteFileAtomic(args.report, report.data(), report.size()));
  if (!args.debug_dir.empty()) {
    SDVI_RETURN_IF_ERROR(WriteDebugPictures(args.debug_dir, raster, result));
  }
  if (args.json) {
    std::fputs(report.c_str(), stdout);
  } else if (!args.quiet) {
    const VectorizeReport& r = result.report;
    std::fprintf(SummaryStream(output),
                 "%s: %u triangles, %u vertices, %llu bytes (paper size %llu), PSNR %.2f dB, "
                 "MSSIM %.4f, mean error %.2f, %.2f s\n",
                 output.c_str(), r.triangles, r.vertices, static_cast<unsigned long long>(file_size),
                 static_cast<unsigned long long>(r.paper_size), r.psnr, r.mssim, r.mean_error,
                 r.seconds.total + r.seconds.load);
  }
  return Status::Ok();
}

// The options of `sdvi sample`.
struct SampleArgs {
  std::string output;
  int width = 512, height = 384;
};

}  // namespace

void RegisterVectorize(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<VectorizeArgs>();
  VectorizeOptions& o = a->options;
  o.threads = DefaultThreads();
  CLI::App* c = AddCommand(
      app, "vectorize",
      "turn a raster image into a .sdvi subdivision surface (feature curves, CDT, colour fit, refinement)",
      {"sdvi vectorize photo.jpg -o photo.sdvi",
       "sdvi vectorize photo.png -o photo.sdvi --compression-ratio 25 --report report.json",
       "sdvi vectorize logo.png -o logo.sdvi --target-psnr 40 --compress",
       "cat photo.png | sdvi vectorize - -o - > photo.sdvi",
       "sdvi vectorize photos/ -O out/ -j 2 --batch-report report.jsonl   # every image in photos/"});
  AddOutput(c, a->output, "the .sdvi file to write");
  AddInputs(c, a->input, "the image: PNG, JPEG, TIFF, BMP (8/16-bit; grey, RGB, RGBA); '-' reads standard input",
            {{"png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "pnm", "pbm", "pgm", "ppm", "tga", "exr", "hdr"},
             "sdvi", "", {"--debug-dir"}});
  auto* target_psnr = c->add_option("--target-psnr", o.target_psnr, "stop refining at this PSNR in dB (0: no target); reached or reported (spec/RATE.md)")
      ->check(CLI::Range(0.0, 200.0));
  c->add_option("--max-triangles", o.max_triangles, "triangle budget (0: from --compression-ratio)")
      ->check(CLI::Range(0, 1 << 30));
  c->add_option("--compression-ratio", o.compression_ratio,
                "pixels per vertex when --max-triangles is 0 (the vertex budget)")
      ->check(CLI::Range(1.0, 1e6));
  c->add_option("--iterations", o.iterations, "refinement rounds at most (0: the initial fit only)")
      ->check(CLI::Range(0, 1000));
  MarkInput(c, a->mask);
  UsesRasterCodecs(c);
  c->add_option("--mask", a->mask, "an image of the same size whose non-zero pixels bound the domain (object image)")
      ->type_name("IMG");
  MarkOutput(c, a->report);
  c->add_option("--report", a->report, "write the report (sizes, PSNR, MSSIM, timings, history) as JSON")
      ->type_name("R.json");
  c->add_option("--debug-dir", a->debug_dir, "write features.png, mesh.png, reconstruction.png, error.png here")
      ->type_name("DIR");
  c->add_option("--threads", o.threads, "worker threads")->check(CLI::Range(1, 256));
  c->add_flag("--compress", a->compress,
              "write a Draco payload: quantisation chosen by rate-distortion, colours refitted (spec/RATE.md)");
  a->quality_opt = c->add_option("--quality", a->quality, "one knob 0 (smallest) .. 100 (best), monotone in rate and distortion; implies --compress")
                       ->check(CLI::Range(0.0, 100.0));
  a->target_bytes_opt = c->add_option("--target-bytes", a->target_bytes, "the largest file that fits this many bytes; implies --compress")
                            ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 50))->excludes(a->quality_opt)->excludes(target_psnr);
  a->quality_opt->excludes(target_psnr);
  c->add_flag("--strict", a->strict, "fail (exit 1, nothing written) when --target-psnr is not reached instead of warning");
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] {
    if (a->json && IsStdStream(a->output)) return ReportUsage("vectorize", "--json and -o - both use standard output");
    const Status status = VectorizeCommand(*a);
    return status.ok() ? kExitOk : ReportError("vectorize", status);
  });
}

void RegisterSample(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<SampleArgs>();
  CLI::App* c = AddCommand(
      app, "sample",
      "write the built-in sample image (smooth gradients, sharp and blurred curved edges, corners)",
      {"sdvi sample -o sample.png", "sdvi sample -o wide.png --width 1024 --height 512"});
  AddOutput(c, a->output, "the PNG to write");
  c->add_option("--width", a->width, "width in pixels")->check(CLI::Range(8, 16384));
  c->add_option("--height", a->height, "height in pixels")->check(CLI::Range(8, 16384));
  SetAction(c, outcome, [a] {
    const Status status = SaveRasterPng(a->output, MakeSampleImage(a->width, a->height));
    return status.ok() ? kExitOk : ReportError("sample", status);
  });
}

}  // namespace sdvi::cli
