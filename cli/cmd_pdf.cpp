// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi export-pdf: writes the limit surface as a one-page PDF, a Gouraud-shaded triangle
// mesh any viewer opens and prints at any size (spec/PDF.md).
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/file_util.h"
#include "sdvi/pdf.h"
#include "sdvi/progress.h"

namespace sdvi::cli {
namespace {

constexpr const char* kExportPdf = "export-pdf";

// The options of `sdvi export-pdf`.
struct ExportPdfArgs {
  std::string input, output;
  PdfExportOptions options;
  bool quiet = false, json = false;
};

int ExportPdf(const ExportPdfArgs& a) {
  if (a.json && IsStdStream(a.output)) return ReportUsage(kExportPdf, "--json and -o - both use standard output");
  auto image = LoadSdvi(a.input);
  if (!image.ok()) return ReportError(kExportPdf, image.status());
  Progress progress(a.quiet || a.json);  // on a terminal only
  PdfExportOptions options = a.options;
  options.progress = &progress;
  auto exported = WritePdf(a.output, *image, options);
  if (!exported.ok()) return ReportError(kExportPdf, ExportError(exported.status(), a.input));
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["level"] = exported->levels;
    j["vertices"] = exported->vertices;
    j["triangles"] = exported->triangles;
    j["records"] = exported->records;
    j["bits_per_coordinate"] = exported->bits_per_coordinate;
    j["bits_per_component"] = exported->bits_per_component;
    j["steep_triangles"] = exported->steep_triangles;
    j["page_width_pt"] = exported->page_width_pt;
    j["page_height_pt"] = exported->page_height_pt;
    j["shading_bytes"] = exported->shading_bytes;
    j["bytes"] = exported->bytes.size();
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::fprintf(SummaryStream(a.output),
                 "%s: level %d, %u triangles, %.1f x %.1f pt, %zu bytes\n", a.output.c_str(),
                 exported->levels, exported->triangles, exported->page_width_pt,
                 exported->page_height_pt, exported->bytes.size());
  }
  return kExitOk;
}

}  // namespace

void RegisterExportPdf(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<ExportPdfArgs>();
  PdfExportOptions& o = a->options;
  CLI::App* c = AddCommand(
      app, "export-pdf",
      "write the limit surface as a one-page PDF (a Gouraud-shaded triangle mesh, any size)",
      {"sdvi export-pdf in.sdvi -o out.pdf", "sdvi export-pdf in.sdvi -o out.pdf --dpi 300 --background white",
       "sdvi export-pdf in.sdvi -o out.pdf --width-mm 180 --levels 3",
       "sdvi export-pdf out/ -O pdf/ -j 2   # out/NAME.sdvi -> pdf/NAME.pdf"});
  AddOutput(c, a->output, "OUT.pdf");
  AddInputs(c, a->input, "the .sdvi file ('-' reads standard input)", {{"sdvi"}, "pdf", "", {}});
  c->add_option("--levels", o.levels, "subdivision level r (-1: fine triangles of about 2 source pixels)")
      ->check(CLI::Range(-1, kMaxPdfLevels));
  CLI::Option* dpi = c->add_option("--dpi", o.dpi, "source pixels per inch: the page is width x 72 / dpi points")
                         ->check(CLI::PositiveNumber);
  c->add_option("--width-mm", o.width_mm, "page width in millimetres instead (the height keeps the aspect ratio)")
      ->check(CLI::PositiveNumber)
      ->excludes(dpi);
  c->add_option("--background", o.background, "what the page shows outside the image's domain")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, PdfBackground>{{"none", PdfBackground::kNone}, {"white", PdfBackground::kWhite}},
          CLI::ignore_case))
      ->default_str("none");
  c->add_option("--color-space", o.color_space,
                "the shading's colour space: device-rgb, or srgb-icc (an embedded sRGB profile, about 3 KB)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, PdfColorSpace>{{"device-rgb", PdfColorSpace::kDeviceRgb},
                                               {"srgb-icc", PdfColorSpace::kSrgbIcc}},
          CLI::ignore_case))
      ->default_str("device-rgb");
  c->add_option("--coordinate-bits", o.coordinate_bits,
                 "BitsPerCoordinate of the shading (0: the smallest of 8..32 with steps <= 1/64 source pixel)")
      ->check(CLI::IsMember({0, 8, 12, 16, 24, 32}));
  c->add_option("--color-bits", o.color_bits, "BitsPerComponent of the shading's colours")
      ->check(CLI::IsMember({8, 12, 16}));
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return ExportPdf(*a); });
}

}  // namespace sdvi::cli
