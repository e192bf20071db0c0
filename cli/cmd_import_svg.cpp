// SPDX-License-Identifier: GPL-3.0-or-later
// `sdvi import-svg`: SVG -> .sdvi (converters/svg, spec/SVG.md).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/progress.h"
#include "sdvi/raster_io.h"
#include "sdvi/svg.h"

namespace sdvi::cli {
namespace {

struct ImportSvgRequest {
  std::string input, output, mode = "artwork", report, debug_dir;
  int width = 0;
  double scale = 0;
  int max_triangles = 0;
  double target_psnr = 0;
  int threads = 1;
  bool quiet = false;
};

nlohmann::json ArtworkReportJson(const ImportSvgRequest& request, const SvgArtworkResult& result,
                                 uint64_t file_size) {
  const VectorizeReport& r = result.vectorized.report;
  return {{"input", request.input},
          {"output", request.output},
          {"mode", request.mode},
          {"width", result.reference.width},
          {"height", result.reference.height},
          {"triangles", r.triangles},
          {"vertices", r.vertices},
          {"file_size_bytes", file_size},
          {"paper_size_bytes", r.paper_size},
          {"psnr_db", r.psnr},
          {"psnr_reference", "librsvg rendering at the output size, over the domain pixels"},
          {"mssim", r.mssim},
          {"mean_error", r.mean_error},
          {"iterations", r.iterations},
          {"outline_features", result.outline_features},
          {"feature_curves", r.feature_curves},
          {"approximate", result.approximate},
          {"object_image", result.object_image},
          {"warnings", result.warnings},
          {"time_s", r.seconds.total}};
}

Status ImportCurves(const ImportSvgRequest& request) {
  SvgCurvesOptions options;
  options.width = request.width;
  options.scale = request.scale;
  SDVI_ASSIGN_OR_RETURN(SvgDocument document, LoadSvgFile(request.input, options.limits));
  SDVI_ASSIGN_OR_RETURN(SvgCurvesResult result, ImportSvgCurves(document, options));
  for (const std::string& w : result.warnings) {
    std::fprintf(stderr, "sdvi import-svg: %s: warning: %s\n", request.input.c_str(), w.c_str());
  }
  SDVI_RETURN_IF_ERROR(SaveSdvi(request.output, result.image));
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(request.output, ec);
  if (!request.report.empty()) {
    const nlohmann::json report = {{"input", request.input},
                                   {"output", request.output},
                                   {"mode", "curves"},
                                   {"width", result.width},
                                   {"height", result.height},
                                   {"curves", result.curves},
                                   {"vertices", result.image.vertices.size()},
                                   {"triangles", result.image.triangles.size()},
                                   {"file_size_bytes", ec ? 0 : file_size},
                                   {"warnings", result.warnings}};
    const std::string text = report.dump(2) + "\n";
    SDVI_RETURN_IF_ERROR(WriteFileAtomic(request.report, text.data(), text.size()));
  }
  if (!request.quiet) {
    std::printf("%s: %d x %d, %zu curves, %zu triangles, %zu vertices, %llu bytes\n", request.output.c_str(),
                result.width, result.height, result.curves, result.image.triangles.size(),
                result.image.vertices.size(), static_cast<unsigned long long>(ec ? 0 : file_size));
  }
  return Status::Ok();
}

Status ImportSvgCommand(const ImportSvgRequest& request) {
  if (request.mode != "artwork" && request.mode != "curves") {
    return Status(StatusCode::kInvalidArgument, "--mode must be artwork or curves, got '" + request.mode + "'");
  }
  if (request.width < 0 || request.scale < 0 || (request.width > 0 && request.scale > 0)) {
    return Status(StatusCode::kInvalidArgument, "give at most one of --width W (> 0) and --scale S (> 0)");
  }
  if (request.mode == "curves") return ImportCurves(request);
  SvgArtworkOptions options;
  options.width = request.width;
  options.scale = request.scale;
  options.vectorize.max_triangles = request.max_triangles;
  options.vectorize.target_psnr = request.target_psnr;
  options.vectorize.threads = request.threads;
  options.vectorize.fit.threads = request.threads;
  SDVI_ASSIGN_OR_RETURN(SvgDocument document, LoadSvgFile(request.input, options.limits));
  Progress progress(request.quiet);
  options.vectorize.progress = &progress;
  SDVI_ASSIGN_OR_RETURN(SvgArtworkResult result, ImportSvgArtwork(document, options));
  for (const std::string& w : result.warnings) std::fprintf(stderr, "sdvi import-svg: %s: warning: %s\n",
                                                            request.input.c_str(), w.c_str());
  SDVI_RETURN_IF_ERROR(SaveSdvi(request.output, result.vectorized.image));
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(request.output, ec);
  if (!request.report.empty()) {
    const std::string text = ArtworkReportJson(request, result, ec ? 0 : file_size).dump(2) + "\n";
    SDVI_RETURN_IF_ERROR(WriteFileAtomic(request.report, text.data(), text.size()));
  }
  if (!request.debug_dir.empty()) {
    std::error_code dir_error;
    std::filesystem::create_directories(request.debug_dir, dir_error);
    if (dir_error) return Status(StatusCode::kIoError, request.debug_dir + ": cannot create the directory");
    const std::filesystem::path base(request.debug_dir);
    const VectorizeResult& v = result.vectorized;
    SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "reference.png").string(), result.reference));
    SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "features.png").string(), DrawFeatures(result.reference, v.features)));
    SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "mesh.png").string(), DrawControlMesh(result.reference, v.image)));
    SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "reconstruction.png").string(), v.reconstruction));
    SDVI_RETURN_IF_ERROR(SaveRasterPng((base / "error.png").string(), ErrorImage(v.reconstruction, result.reference)));
  }
  if (!request.quiet) {
    const VectorizeReport& r = result.vectorized.report;
    std::printf("%s: %d x %d, %u outline features, %u triangles, %u vertices, %llu bytes, PSNR %.2f dB "
                "against librsvg%s\n",
                request.output.c_str(), result.reference.width, result.reference.height, result.outline_features,
                r.triangles, r.vertices, static_cast<unsigned long long>(ec ? 0 : file_size), r.psnr,
                result.approximate ? " (approximate)" : "");
  }
  return Status::Ok();
}

}  // namespace

int RunImportSvg(const CommandArgs& args) {
  const ArgSpec spec{{"-o", "--mode", "--width", "--scale", "--max-triangles", "--target-psnr", "--report",
                      "--threads", "--debug-dir"},
                     {"--quiet"}};
  StatusOr<Args> parsed = Args::Parse(args, spec);
  if (!parsed.ok()) return ReportError("import-svg", parsed.status());
  const Args& a = *parsed;
  auto run = [&]() -> Status {
    if (a.positional().size() != 1) {
      return Status(StatusCode::kInvalidArgument,
                    "expected one input SVG, got " + std::to_string(a.positional().size()));
    }
    ImportSvgRequest request;
    request.input = a.positional()[0];
    const std::optional<std::string> output = a.get("-o");
    if (!output) return Status(StatusCode::kInvalidArgument, "missing -o OUT.sdvi");
    request.output = *output;
    request.mode = a.get("--mode").value_or("artwork");
    request.report = a.get("--report").value_or("");
    request.debug_dir = a.get("--debug-dir").value_or("");
    SDVI_ASSIGN_OR_RETURN(request.width, a.GetInt("--width", 0));
    SDVI_ASSIGN_OR_RETURN(request.scale, a.GetDouble("--scale", 0));
    SDVI_ASSIGN_OR_RETURN(request.max_triangles, a.GetInt("--max-triangles", 0));
    SDVI_ASSIGN_OR_RETURN(request.target_psnr, a.GetDouble("--target-psnr", 0));
    const int hardware = int(std::max(1u, std::thread::hardware_concurrency()));
    SDVI_ASSIGN_OR_RETURN(request.threads, a.GetInt("--threads", std::min(hardware, 8)));
    request.quiet = a.flag("--quiet");
    return ImportSvgCommand(request);
  };
  const Status status = run();
  return status.ok() ? 0 : ReportError("import-svg", status);
}

}  // namespace sdvi::cli
