// SPDX-License-Identifier: GPL-3.0-or-later
// `sdvi import-svg`: SVG -> .sdvi (converters/svg, spec/SVG.md).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/parallel.h"
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
  bool quiet = false, json = false;
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
          {"detected_features", result.detected_features},
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
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, EncodeImage(result.vectorized.image, nullptr, request.input));
  SDVI_RETURN_IF_ERROR(WriteFileAtomic(request.output, bytes));
  const uint64_t file_size = bytes.size();
  const nlohmann::json report = ArtworkReportJson(request, result, file_size);
  if (!request.report.empty()) {
    const std::string text = report.dump(2) + "\n";
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
  if (request.json) {
    std::printf("%s\n", report.dump(2).c_str());
  } else if (!request.quiet) {
    const VectorizeReport& r = result.vectorized.report;
    std::fprintf(SummaryStream(request.output), "%s: %d x %d, %u outline + %u detected features, %u triangles, %u vertices, %llu bytes, PSNR %.2f dB "
                "against librsvg%s\n",
                request.output.c_str(), result.reference.width, result.reference.height, result.outline_features,
                result.detected_features, r.triangles, r.vertices, static_cast<unsigned long long>(file_size), r.psnr,
                result.approximate ? " (approximate)" : "");
  }
  return Status::Ok();
}

}  // namespace

void RegisterImportSvg(CLI::App& app, Outcome& outcome) {
  auto r = std::make_shared<ImportSvgRequest>();
  r->threads = DefaultThreads();
  CLI::App* c = AddCommand(
      app, "import-svg",
      "turn an SVG drawing into a .sdvi: its exact outlines become sharp features, colours fitted to librsvg's rendering (spec/SVG.md)",
      {"sdvi import-svg logo.svg -o logo.sdvi", "sdvi import-svg icon.svg -o icon.sdvi --width 512 --max-triangles 4000",
       "sdvi import-svg art.svg -o art.sdvi --scale 2 --report report.json",
       "sdvi import-svg examples/curves/cherries.svg -o cherries.sdvi --mode curves",
       "sdvi import-svg icons/ -O out/ -j 2   # icons/NAME.svg -> out/NAME.sdvi"});
  AddOutput(c, r->output, "the .sdvi file to write");
  AddInputs(c, r->input, "the SVG file ('-' reads standard input)", {{"svg"}, "sdvi", "", {"--debug-dir", "--report"}});
  c->add_option("--mode", r->mode,
                "artwork: the SVG's shapes and colours; curves: paths with sdvi:left-color, sdvi:right-color, "
                "sdvi:sharpness (spec/CURVES.md), colours diffused between them")
      ->check(CLI::IsMember({"artwork", "curves"}));
  auto* width = c->add_option("--width", r->width, "output width in pixels (0: the SVG's own size)")
                    ->check(CLI::Range(0, 65536));
  c->add_option("--scale", r->scale, "scale of the SVG's own size (0: 1)")->check(CLI::Range(0.0, 1024.0))->excludes(width);
  c->add_option("--max-triangles", r->max_triangles, "triangle budget (0: automatic)")->check(CLI::Range(0, 1 << 30));
  c->add_option("--target-psnr", r->target_psnr, "stop refining at this PSNR in dB against librsvg (0: no target)")
      ->check(CLI::Range(0.0, 200.0));
  MarkOutput(c, r->report);
  c->add_option("--report", r->report, "write the report as JSON")->type_name("R.json");
  c->add_option("--debug-dir", r->debug_dir, "write reference, features, mesh, reconstruction and error pictures here")
      ->type_name("DIR");
  c->add_option("--threads", r->threads, "worker threads")->check(CLI::Range(1, 256));
  AddQuiet(c, r->quiet);
  AddJson(c, r->json);
  SetAction(c, outcome, [r] {
    if (r->json && IsStdStream(r->output)) return ReportUsage("import-svg", "--json and -o - both use standard output");
    const Status status = ImportSvgCommand(*r);
    return status.ok() ? kExitOk : ReportError("import-svg", status);
  });
}

}  // namespace sdvi::cli
