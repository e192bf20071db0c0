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

  Progress progress(args.flag("--quiet"));
  options.progress = &progress;
  StatusOr<VectorizeResult> vectorized = sdvi::Vectorize(raster, mask_path ? &mask : nullptr, options);
  if (!vectorized.ok()) {
    const Status& s = vectorized.status();
    return Status(s.code(), input + ": " + s.message());
  }
  VectorizeResult& result = *vectorized;
  result.report.seconds.load = load_seconds;

  // The file and its one PSNR (spec/RATE.md): the x1 render of what a reader decodes.
  const double fit_psnr = result.report.psnr;
  nlohmann::json rate_report;
  if (args.flag("--compress")) {
    // Quantisation chosen by rate-distortion, colours refitted on the quantised positions.
    RateOptions rate;
    rate.threads = options.threads;
    SDVI_ASSIGN_OR_RETURN(RateResult compressed,
                          CompressForRate(result, raster, mask_path ? &mask : nullptr, options.fit, rate));
    SDVI_RETURN_IF_ERROR(WriteFileAtomic(*output, compressed.file.data(), compressed.file.size()));
    result.report.psnr = compressed.psnr;
    rate_report = {{"position_bits", compressed.position_bits},
                   {"color_bits", compressed.color_bits},
                   {"slope_db", compressed.slope_db},
                   {"candidates", compressed.evaluations}};
  } else {
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, EncodeImage(result.image, nullptr, *output));
    SDVI_ASSIGN_OR_RETURN(Image decoded, DecodeImage(bytes, *output));
    SDVI_RETURN_IF_ERROR(WriteFileAtomic(*output, bytes));
    SDVI_ASSIGN_OR_RETURN(result.report.psnr, FileQualityPsnr(decoded, raster, options.threads));
  }
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(*output, ec);

  if (const std::optional<std::string> report_path = args.get("--report")) {
    nlohmann::json report = ReportJson(input, *output, raster, result.report, ec ? 0 : file_size);
    report["fit_psnr_db"] = fit_psnr;
    if (!rate_report.is_null()) report["rate"] = rate_report;
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
                      "--report", "--debug-dir", "--threads", "--compression-ratio"},
                     {"--quiet", "--compress"}};
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
