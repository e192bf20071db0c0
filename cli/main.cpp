// sdvi: the command-line tool. Parses the subcommand and hands over to it.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "commands.h"

namespace {

struct Command {
  const char* name;
  int (*run)(const sdvi::cli::CommandArgs&);
  const char* usage;
};

const Command kCommands[] = {
    {"vectorize", sdvi::cli::RunVectorize,
     "IN.png|jpg|tif|bmp -o OUT.sdvi [--target-psnr dB] [--max-triangles N] [--iterations K] "
     "[--compression-ratio R] [--mask M] [--report R.json] [--debug-dir D] [--threads N] [--compress] "
     "[--quality Q | --target-bytes N] [--strict] [--quiet]   (spec/RATE.md)"},
    {"import-svg", sdvi::cli::RunImportSvg,
     "IN.svg -o OUT.sdvi [--mode artwork|curves] [--width W | --scale S] [--max-triangles N] "
     "[--target-psnr dB] [--report R.json] [--debug-dir D] [--threads N] [--quiet]   (spec/SVG.md)"},
    {"render", sdvi::cli::RunRender,
     "IN.sdvi -o OUT.png|OUT.exr [--scale S | --width W --height H] [--region x,y,w,h] "
     "[--levels r] [--bits 8|16] [--half] [--reference IMG]"},
    {"compare", sdvi::cli::RunCompare, "A B [--json]   (images or .sdvi files)"},
    {"info", sdvi::cli::RunInfo, "FILE.sdvi [--json]"},
    {"convert", sdvi::cli::RunConvert, "IN.json|IN.sdvi OUT.sdvi|OUT.json"},
    {"subdivide", sdvi::cli::RunSubdivide, "IN.sdvi --levels r [--limit] -o OUT.ply"},
    {"export-gltf", sdvi::cli::RunExportGltf,
     "IN.sdvi -o OUT.glb|OUT.gltf [--levels r] [--draco] [--position-bits N] [--color-bits N] "
     "[--speed S] [--control-mesh] [--copyright TEXT] [--quiet]"},
    {"compress", sdvi::cli::RunCompress,
     "IN.sdvi -o OUT.sdvi [--position-bits N] [--color-bits N] [--speed S] "
     "[--reference IMG | --reference-mse M] [--keep-vertex-order] [--quiet]"},
    {"decompress", sdvi::cli::RunDecompress, "IN.sdvi -o OUT.sdvi"},
    {"sample", sdvi::cli::RunSample, "-o OUT.png [--width W --height H]   (the built-in sample image)"},
};

void PrintUsage(std::FILE* out) {
  std::fprintf(out, "usage: sdvi <command> [options]\n\ncommands:\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-12s %s\n", c.name, c.usage);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    PrintUsage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 1 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("sdvi %s\n", SDVI_VERSION);
    return 0;
  }
  for (const Command& c : kCommands) {
    if (std::strcmp(argv[1], c.name) == 0) {
      std::vector<std::string> args(argv + 2, argv + argc);
      for (const std::string& a : args) {
        if (a == "--help" || a == "-h") {
          std::printf("usage: sdvi %s %s\n", c.name, c.usage);
          return 0;
        }
      }
      return c.run(args);
    }
  }
  std::fprintf(stderr, "sdvi: unknown command '%s'\n\n", argv[1]);
  PrintUsage(stderr);
  return 1;
}
