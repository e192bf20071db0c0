// `sdvi vectorize` (raster -> .sdvi, paper section IV) and `sdvi sample` (the built-in
// sample image).
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/codec.h"
#include "sdvi/features.h"
#include "sdvi/file_util.h"
#include "sdvi/progress.h"
#include "sdvi/raster_io.h"
#include "sdvi/rate.h"
#include "sdvi/vectorize.h"

namespace sdvi::cli {
namespace {

using Clock = std::chrono::steady_clock;

nlohmann::json ReportJson(const std::string& input, const std::string& output, const Raster& raster,
                          const VectorizeReport& r, uint64_t file_size) {
  const VectorizeTimings& s = r.seconds;
  nlohmann::json history = nlohmann::json::array();
  for (const VectorizeIteration& it : r.history) {
    history.push_back({{"vertices", it.vertices},
                       {"triangles", it.triangles},
                       {"added_samples", it.added_samples},
                       {"psnr_db", it.psnr}});
  }
  return {{"input", input},
          {"output", output},
          {"width", raster.width},
          {"height", raster.height},
          {"time_s", s.total + s.load},
          {"iterations", r.iterations},
          {"triangles", r.triangles},
          {"vertices", r.vertices},
          {"paper_size_bytes", r.paper_size},
          {"file_size_bytes", file_size},
          {"pixels", r.pixels},
          {"mean_error", r.mean_error},
          {"compression_ratio", r.compression_ratio},
          {"psnr_db", r.psnr},
          {"mssim", r.mssim},
          {"mssim_channels", "mean over R, G, B"},
          {"feature_curves", r.feature_curves},
          {"phases_s",
           {{"load", s.load},
            {"features", s.features},
            {"triangulate", s.triangulate},
            {"limit_surface", s.surface},
            {"coverage", s.coverage},
            {"assemble", s.assemble},
            {"solve", s.solve},
            {"refine", s.refine},
            {"metrics", s.metrics}}},
          {"history", history}};
}

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

Status VectorizeCommand(const Args& args) {
  if (args.positional().size() != 1) {
    return Status(StatusCode::kInvalidArgument, "expected one input image, got " +
                                                    std::to_string(args.positional().size()));
  }
  const std::string input = args.positional()[0];
  const std::optional<std::string> output = args.get("-o");
  if (!output) return Status(StatusCode::kInvalidArgument, "missing -o OUT.sdvi");
  VectorizeOptions options;
  SDVI_ASSIGN_OR_RETURN(options.target_psnr, args.GetDouble("--target-psnr", 0));
  SDVI_ASSIGN_OR_RETURN(options.max_triangles, args.GetInt("--max-triangles", 0));
  SDVI_ASSIGN_OR_RETURN(options.iterations, args.GetInt("--iterations", options.iterations));
  SDVI_ASSIGN_OR_RETURN(options.compression_ratio,
                        args.GetDouble("--compression-ratio", options.compression_ratio));
  const int hardware = int(std::max(1u, std::thread::hardware_concurrency()));
  SDVI_ASSIGN_OR_RETURN(options.threads, args.GetInt("--threads", std::min(hardware, 8)));
  if (options.threads < 1 || options.threads > 256) {
    return Status(StatusCode::kInvalidArgument, "--threads must be in 1..256");
  }
  options.fit.threads = options.threads;

  const Clock::time_point load_start = Clock::now();
  SDVI_ASSIGN_OR_RETURN(Raster raster, LoadRaster(input));
  Raster mask;
  const std::optional<std::string> mask_path = args.get("--mask");
  if (mask_path) {
    SDVI_ASSIGN_OR_RETURN(mask, LoadRaster(*mask_path));
    if (mask.width != raster.width || mask.height != raster.height) {
      return Status(StatusCode::kInvalidArgument,
                    *mask_path + ": mask is " + std::to_string(mask.width) + "x" +
                        std::to_string(mask.height) + " but " + input + " is " +
                        std::to_string(raster.width) + "x" + std::to_string(raster.height));
    }
  }
  const double load_seconds = std::chrono::duration<double>(Clock::now() - load_start).count();

  // Rate targets (spec/RATE.md 4): --quality and --target-bytes imply --compress.
  RateTarget target;
  SDVI_ASSIGN_OR_RETURN(target.quality, args.GetDouble("--quality", -1));
  SDVI_ASSIGN_OR_RETURN(const double target_bytes, args.GetDouble("--target-bytes", 0));
  if (args.get("--quality") && !(target.quality >= 0 && target.quality <= 100))
    return Status(StatusCode::kInvalidArgument, "--quality must be in 0..100");
  if (args.get("--target-bytes") && !(target_bytes >= 1 && target_bytes < 1e15))
    return Status(StatusCode::kInvalidArgument, "--target-bytes must be a positive byte count");
  target.bytes = uint64_t(target_bytes);
  if (int(args.get("--quality").has_value()) + int(args.get("--target-bytes").has_value()) +
          int(options.target_psnr > 0) > 1)
    return Status(StatusCode::kInvalidArgument, "choose one of --quality, --target-bytes, --target-psnr");
  const bool compress = args.flag("--compress") || args.get("--quality") || args.get("--target-bytes");
  const Raster* mask_ptr = mask_path ? &mask : nullptr;

  Progress progress(args.flag("--quiet"));
  options.progress = &progress;
  RateOptions rate;
  rate.threads = options.threads;
  // The file and its one PSNR (spec/RATE.md 1): the x1 render of what a reader decodes.
  VectorizeResult result;
  std::vector<uint8_t> bytes;
  double file_psnr = 0;
  bool reached = true;
  std::string note;
  nlohmann::json rate_report;
  auto named = [&](const Status& s) { return s.ok() ? s : Status(s.code(), input + ": " + s.message()); };
  if (compress) {
    RateResult compressed;
    if (args.get("--quality") || args.get("--target-bytes") || options.target_psnr > 0) {
      if (options.target_psnr > 0) target.psnr = options.target_psnr;
      StatusOr<TargetResult> t = VectorizeForTarget(raster, mask_ptr, options, target, rate);
      if (!t.ok()) return named(t.status());
      result = std::move(t->vectorized);
      compressed = std::move(t->file);
      reached = t->reached;
      note = t->note;
      rate_report["vectorize_runs"] = t->vectorize_runs;
    } else {
      StatusOr<VectorizeResult> v = sdvi::Vectorize(raster, mask_ptr, options);
      if (!v.ok()) return named(v.status());
      result = std::move(*v);
      StatusOr<RateResult> c = CompressForRate(result, raster, mask_ptr, options.fit, rate);
      if (!c.ok()) return named(c.status());
      compressed = std::move(*c);
    }
    bytes = std::move(compressed.file);
    file_psnr = compressed.psnr;
    rate_report["position_bits"] = compressed.position_bits;
    rate_report["color_bits"] = compressed.color_bits;
    rate_report["slope_db"] = compressed.slope_db;
    rate_report["candidates"] = compressed.evaluations;
  } else {
    StatusOr<VectorizeResult> v = sdvi::Vectorize(raster, mask_ptr, options);
    if (!v.ok()) return named(v.status());
    result = std::move(*v);
    SDVI_ASSIGN_OR_RETURN(bytes, EncodeImage(result.image, nullptr, *output));
    SDVI_ASSIGN_OR_RETURN(Image decoded, DecodeImage(bytes, *output));
    SDVI_ASSIGN_OR_RETURN(file_psnr, FileQualityPsnr(decoded, raster, options.threads));
    if (options.target_psnr > 0 && file_psnr < options.target_psnr) {
      reached = false;
      char buf[160];
      std::snprintf(buf, sizeof buf, "target PSNR %.2f dB not reached: the file has %.2f dB (%u vertices); raise "
                    "the budget (--compression-ratio lower, --iterations higher)",
                    options.target_psnr, file_psnr, unsigned(result.image.vertices.size()));
      note = buf;
    }
  }
  result.report.seconds.load = load_seconds;
  const double fit_psnr = result.report.psnr;
  result.report.psnr = file_psnr;
  if (!reached) {
    if (args.flag("--strict")) return Status(StatusCode::kLimitExceeded, input + ": " + note + "; nothing written");
    std::fprintf(stderr, "sdvi vectorize: warning: %s: %s\n", input.c_str(), note.c_str());
  }
  SDVI_RETURN_IF_ERROR(WriteFileAtomic(*output, bytes));
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(*output, ec);

  if (const std::optional<std::string> report_path = args.get("--report")) {
    nlohmann::json report = ReportJson(input, *output, raster, result.report, ec ? 0 : file_size);
    report["fit_psnr_db"] = fit_psnr;
    if (!rate_report.is_null()) report["rate"] = rate_report;
    if (args.get("--quality") || args.get("--target-bytes") || options.target_psnr > 0) {
      report["target_reached"] = reached;
      if (!reached) report["target_note"] = note;
    }
    const std::string text = report.dump(2) + "\n";
    SDVI_RETURN_IF_ERROR(WriteFileAtomic(*report_path, text.data(), text.size()));
  }
  if (const std::optional<std::string> debug_dir = args.get("--debug-dir")) {
    SDVI_RETURN_IF_ERROR(WriteDebugPictures(*debug_dir, raster, result));
  }
  if (!args.flag("--quiet")) {
    const VectorizeReport& r = result.report;
    std::printf("%s: %u triangles, %u vertices, %llu bytes (paper size %llu), PSNR %.2f dB, "
                "MSSIM %.4f, mean error %.2f, %.2f s\n",
                output->c_str(), r.triangles, r.vertices,
                static_cast<unsigned long long>(ec ? 0 : file_size),
                static_cast<unsigned long long>(r.paper_size), r.psnr, r.mssim, r.mean_error,
                r.seconds.total + r.seconds.load);
  }
  return Status::Ok();
}

Status SampleCommand(const Args& args) {
  if (!args.positional().empty()) {
    return Status(StatusCode::kInvalidArgument, "unexpected argument '" + args.positional()[0] + "'");
  }
  const std::optional<std::string> output = args.get("-o");
  if (!output) return Status(StatusCode::kInvalidArgument, "missing -o OUT.png");
  SDVI_ASSIGN_OR_RETURN(const int width, args.GetInt("--width", 512));
  SDVI_ASSIGN_OR_RETURN(const int height, args.GetInt("--height", 384));
  if (width < 8 || height < 8 || width > 16384 || height > 16384) {
    return Status(StatusCode::kInvalidArgument, "--width and --height must be in 8..16384");
  }
  return SaveRasterPng(*output, MakeSampleImage(width, height));
}

}  // namespace

int RunVectorize(const CommandArgs& args) {
  const ArgSpec spec{{"-o", "--target-psnr", "--max-triangles", "--iterations", "--mask",
                      "--report", "--debug-dir", "--threads", "--compression-ratio", "--quality",
                      "--target-bytes"},
                     {"--quiet", "--compress", "--strict"}};
  StatusOr<Args> parsed = Args::Parse(args, spec);
  if (!parsed.ok()) return ReportError("vectorize", parsed.status());
  const Status status = VectorizeCommand(*parsed);
  return status.ok() ? 0 : ReportError("vectorize", status);
}

int RunSample(const CommandArgs& args) {
  const ArgSpec spec{{"-o", "--width", "--height"}, {}};
  StatusOr<Args> parsed = Args::Parse(args, spec);
  if (!parsed.ok()) return ReportError("sample", parsed.status());
  const Status status = SampleCommand(*parsed);
  return status.ok() ? 0 : ReportError("sample", status);
}

}  // namespace sdvi::cli
