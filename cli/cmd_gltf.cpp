// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi export-gltf: writes the limit surface as a glTF 2.0 file for viewers (spec/GLTF.md).
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/file_util.h"
#include "sdvi/gltf.h"
#include "sdvi/progress.h"

namespace sdvi::cli {
namespace {

constexpr const char* kExportGltf = "export-gltf";

// The options of `sdvi export-gltf`.
struct ExportGltfArgs {
  std::string input, output;
  GltfExportOptions options;
  CLI::Option* draco = nullptr;
  bool quiet = false, json = false;
};

int ExportGltf(const ExportGltfArgs& a) {
  if (a.json && IsStdStream(a.output)) return ReportUsage(kExportGltf, "--json and -o - both use standard output");
  // Check the output name before reading the input: a usage error should be cheap.
  if (auto container = GltfContainerForPath(a.output); !container.ok())
    return ReportUsage(kExportGltf, container.status().message());

  if (a.options.embed && GltfContainerForPath(a.output).value() != GltfContainer::kText)
    return ReportUsage(kExportGltf, "--embed is for .gltf output (a .glb carries its buffer inside)");

  auto image = LoadSdvi(a.input);
  if (!image.ok()) return ReportError(kExportGltf, image.status());
  Progress progress(a.quiet || a.json);  // on a terminal only
  GltfExportOptions options = a.options;
  options.progress = &progress;
  auto exported = WriteGltf(a.output, *image, options);
  if (!exported.ok()) return ReportError(kExportGltf, ExportError(exported.status(), a.input));
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["level"] = exported->levels;
    j["vertices"] = exported->vertices;
    j["triangles"] = exported->triangles;
    j["bytes"] = exported->bytes.size();
    j["draco_bytes"] = exported->draco_bytes;
    j["bin"] = exported->bin.empty() ? nlohmann::json(nullptr) : nlohmann::json(GltfBinPath(a.output));
    j["bin_bytes"] = exported->bin.size();
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::FILE* out = SummaryStream(a.output);
    std::fprintf(out, "%s: level %d, %u vertices, %u triangles, %zu bytes", a.output.c_str(),
                 exported->levels, exported->vertices, exported->triangles, exported->bytes.size());
    if (a.options.draco)
      std::fprintf(out, " (Draco surface %llu bytes)", (unsigned long long)exported->draco_bytes);
    if (!exported->bin.empty())
      std::fprintf(out, " + %s (%zu bytes)", GltfBinPath(a.output).c_str(), exported->bin.size());
    std::fprintf(out, "\n");
  }
  return kExitOk;
}

}  // namespace

void RegisterExportGltf(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<ExportGltfArgs>();
  GltfExportOptions& o = a->options;
  CLI::App* c = AddCommand(
      app, "export-gltf", "write the limit surface as glTF 2.0 for viewers (unlit, linear vertex colours)",
      {"sdvi export-gltf in.sdvi -o out.glb", "sdvi export-gltf in.sdvi -o out.glb --draco --levels 3",
       "sdvi export-gltf in.sdvi -o out.gltf --control-mesh   (writes out.gltf and out.bin)",
       "sdvi export-gltf in.sdvi -o out.gltf --embed           (one file, base64 buffer)",
       "sdvi export-gltf out/ -O glb/ -j 2 --draco             (out/NAME.sdvi -> glb/NAME.glb)"});
  AddOutput(c, a->output, "OUT.glb (binary) or OUT.gltf (JSON)");
  AddInputs(c, a->input, "the .sdvi file ('-' reads standard input)", {{"sdvi"}, "glb", "", {}});
  c->add_option("--levels", o.levels, "subdivision level r (-1: about one fine triangle per pixel)")
      ->check(CLI::Range(-1, kMaxGltfLevels));
  a->draco = c->add_flag("--draco", o.draco, "compress the surface with KHR_draco_mesh_compression");
  c->add_option("--position-bits", o.position_bits, "Draco: quantisation bits of POSITION")
      ->check(CLI::Range(1, 30))->needs(a->draco);
  c->add_option("--color-bits", o.color_bits, "Draco: quantisation bits of COLOR_0")
      ->check(CLI::Range(1, 30))->needs(a->draco);
  c->add_option("--speed", o.draco_speed, "Draco: speed 0 (smallest) .. 10 (fastest)")
      ->check(CLI::Range(0, 10))->needs(a->draco);
  c->add_flag("--embed", o.embed, ".gltf: the buffer as base64 inside the JSON instead of OUT.bin beside it");
  c->add_flag("--control-mesh", o.control_mesh, "add the control mesh (triangles and crease lines) as a second node");
  c->add_option("--copyright", o.copyright, "asset.copyright (empty: the file's 'copyright' metadata)")
      ->type_name("TEXT");
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return ExportGltf(*a); });
}

}  // namespace sdvi::cli
