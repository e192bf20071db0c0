// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi export-svg: writes the limit surface as SVG 1.1, flat-shaded fine triangles any
// browser draws (spec/SVG_EXPORT.md; the PDF is the smaller, smoothly shaded vector file).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/file_util.h"
#include "sdvi/progress.h"
#include "sdvi/svg_export.h"

namespace sdvi::cli {
namespace {

constexpr const char* kExportSvg = "export-svg";

// The options of `sdvi export-svg`.
struct ExportSvgArgs {
  std::string input, output;
  SvgExportOptions options;
  bool quiet = false, json = false;
};

int ExportSvg(const ExportSvgArgs& a) {
  if (a.json && IsStdStream(a.output)) return ReportUsage(kExportSvg, "--json and -o - both use standard output");
  auto image = LoadSdvi(a.input);
  if (!image.ok()) return ReportError(kExportSvg, image.status());
  Progress progress(a.quiet || a.json);  // on a terminal only
  SvgExportOptions options = a.options;
  options.progress = &progress;
  auto exported = WriteSvg(a.output, *image, options);
  if (!exported.ok()) return ReportError(kExportSvg, ExportError(exported.status(), a.input));
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["level"] = exported->levels;
    j["triangles"] = exported->triangles;
    j["flat_psnr_db"] = std::isfinite(exported->flat_psnr) ? nlohmann::ordered_json(exported->flat_psnr)
                                                           : nlohmann::ordered_json(nullptr);
    j["bytes"] = exported->bytes.size();
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::fprintf(SummaryStream(a.output), "%s: level %d, %u triangles, %zu bytes\n", a.output.c_str(),
                 exported->levels, exported->triangles, exported->bytes.size());
  }
  return kExitOk;
}

}  // namespace

void RegisterExportSvg(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<ExportSvgArgs>();
  CLI::App* c = AddCommand(
      app, "export-svg",
      "write the limit surface as SVG 1.1 (flat-shaded fine triangles; export-pdf shades smoothly)",
      {"sdvi export-svg in.sdvi -o out.svg", "sdvi export-svg in.sdvi -o out.svg --levels 4",
       "sdvi export-svg out/ -O svg/ -j 2   # out/NAME.sdvi -> svg/NAME.svg"});
  AddOutput(c, a->output, "OUT.svg");
  AddInputs(c, a->input, "the .sdvi file ('-' reads standard input)", {{"sdvi"}, "svg", "", {}});
  c->add_option("--levels", a->options.levels,
                "subdivision level r (-1: one below export-pdf's, or export-pdf's where flat shading one below "
                "is under 38 dB against smooth shading)")
      ->check(CLI::Range(-1, kMaxSvgLevels));
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return ExportSvg(*a); });
}

}  // namespace sdvi::cli
