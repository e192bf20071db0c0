// sdvi export-gltf IN.sdvi -o OUT.glb|OUT.gltf [--levels r] [--draco] [--position-bits N]
//   [--color-bits N] [--speed S] [--control-mesh] [--copyright TEXT] [--quiet]
// Writes the limit surface as a glTF 2.0 file for viewers (spec/GLTF.md).
#include <cstdio>
#include <string>

#include "args.h"
#include "commands.h"

#if __has_include("sdvi/gltf.h")
#include "io.h"
#include "sdvi/gltf.h"
#define SDVI_HAVE_GLTF 1
#endif

namespace sdvi::cli {

#ifdef SDVI_HAVE_GLTF
namespace {

constexpr const char* kCommand = "export-gltf";

StatusOr<GltfExportOptions> OptionsFrom(const Args& args) {
  GltfExportOptions options;
  SDVI_ASSIGN_OR_RETURN(options.levels, args.GetInt("--levels", options.levels));
  SDVI_ASSIGN_OR_RETURN(options.position_bits,
                        args.GetInt("--position-bits", options.position_bits));
  SDVI_ASSIGN_OR_RETURN(options.color_bits, args.GetInt("--color-bits", options.color_bits));
  SDVI_ASSIGN_OR_RETURN(options.draco_speed, args.GetInt("--speed", options.draco_speed));
  options.draco = args.flag("--draco");
  options.control_mesh = args.flag("--control-mesh");
  options.copyright = args.get("--copyright").value_or("");
  const bool draco_only = args.get("--position-bits") || args.get("--color-bits") ||
                          args.get("--speed");
  if (draco_only && !options.draco) {
    return Status(StatusCode::kInvalidArgument,
                  "--position-bits, --color-bits and --speed need --draco");
  }
  return options;
}

}  // namespace

int RunExportGltf(const CommandArgs& raw) {
  ArgSpec spec;
  spec.valued = {"-o", "--levels", "--position-bits", "--color-bits", "--speed", "--copyright"};
  spec.flags = {"--draco", "--control-mesh", "--quiet"};
  auto args = Args::Parse(raw, spec);
  if (!args.ok()) return ReportError(kCommand, args.status());
  if (args->positional().size() != 1 || !args->get("-o")) {
    return ReportError(kCommand, Status(StatusCode::kInvalidArgument,
                                        "expected IN.sdvi -o OUT.glb|OUT.gltf"));
  }
  auto options = OptionsFrom(*args);
  if (!options.ok()) return ReportError(kCommand, options.status());
  const std::string in = args->positional()[0];
  const std::string out = *args->get("-o");
  // Check the output name before reading the input: a usage error should be cheap.
  if (auto container = GltfContainerForPath(out); !container.ok()) {
    return ReportError(kCommand, container.status());
  }

  auto image = LoadSdvi(in);
  if (!image.ok()) return ReportError(kCommand, image.status());
  auto exported = WriteGltf(out, *image, *options);
  if (!exported.ok()) {
    // Write errors name the output already; the others concern the input image.
    const Status& status = exported.status();
    if (status.code() == StatusCode::kIoError) return ReportError(kCommand, status);
    return ReportError(kCommand, Status(status.code(), in + ": " + status.message()));
  }
  if (!args->flag("--quiet")) {
    std::printf("%s: level %d, %u vertices, %u triangles, %zu bytes", out.c_str(),
                exported->levels, exported->vertices, exported->triangles,
                exported->bytes.size());
    if (options->draco) {
      std::printf(" (Draco surface %llu bytes)", (unsigned long long)exported->draco_bytes);
    }
    std::printf("\n");
  }
  return 0;
}

#else  // sdvi_gltf is not built (the subdivision engine is missing)

int RunExportGltf(const CommandArgs&) {
  std::fprintf(stderr, "sdvi export-gltf: this build has no glTF exporter (sdvi_gltf)\n");
  return 2;
}

#endif

}  // namespace sdvi::cli
