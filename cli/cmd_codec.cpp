// sdvi compress (raw -> Draco payload) and sdvi decompress (any payload -> raw).
#include <cstdio>
#include <string>

#include "args.h"
#include "commands.h"
#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"

namespace sdvi::cli {
namespace {

StatusOr<std::string> InputAndOutput(const Args& args, const char* command) {
  if (args.positional().size() != 1)
    return Status(StatusCode::kInvalidArgument,
                  std::string("expected one input file: sdvi ") + command + " IN.sdvi -o OUT.sdvi");
  if (!args.get("-o"))
    return Status(StatusCode::kInvalidArgument, "missing -o OUT.sdvi");
  return args.positional()[0];
}

}  // namespace

int RunCompress(const CommandArgs& raw_args) {
  const std::string command = "compress";
  auto parsed = Args::Parse(raw_args, {{"-o", "--position-bits", "--color-bits", "--speed"},
                                       {"--keep-vertex-order", "--quiet"}});
  if (!parsed.ok()) return ReportError(command, parsed.status());
  const Args& args = *parsed;
  auto input = InputAndOutput(args, "compress");
  if (!input.ok()) return ReportError(command, input.status());
  const std::string output = *args.get("-o");
  CompressOptions options;
  auto position_bits = args.GetInt("--position-bits", 0);
  auto color_bits = args.GetInt("--color-bits", 0);
  auto speed = args.GetInt("--speed", 0);
  for (const auto* v : {&position_bits, &color_bits, &speed})
    if (!v->ok()) return ReportError(command, v->status());
  options.position_bits = *position_bits;
  options.color_bits = *color_bits;
  options.speed = *speed;
  options.keep_vertex_order = args.flag("--keep-vertex-order");
  if (options.position_bits < 0 || options.position_bits > 30 || options.color_bits < 0 ||
      options.color_bits > 30 || options.speed < 0 || options.speed > 10)
    return ReportError(command, Status(StatusCode::kInvalidArgument,
                                       "--position-bits and --color-bits take 1..30, --speed 0..10"));

  auto image = ReadImage(*input);
  if (!image.ok()) return ReportError(command, image.status());
  auto bytes = EncodeImage(*image, &options, *input);
  if (!bytes.ok()) return ReportError(command, bytes.status());
  if (Status s = WriteFileAtomic(output, *bytes); !s.ok()) return ReportError(command, s);
  if (!args.flag("--quiet")) {
    const uint64_t paper = PaperSizeBytes(image->vertices.size(), image->triangles.size());
    const double pixels = double(image->width) * double(image->height);
    std::printf("%s: %zu vertices, %zu triangles: %zu bytes (paper raw size %llu, ratio %.3f, "
                "%.3f bits/pixel, %.2f bytes/vertex)\n",
                output.c_str(), image->vertices.size(), image->triangles.size(), bytes->size(),
                static_cast<unsigned long long>(paper), double(bytes->size()) / double(paper),
                pixels > 0 ? 8.0 * double(bytes->size()) / pixels : 0.0,
                double(bytes->size()) / double(image->vertices.size()));
  }
  return 0;
}

int RunDecompress(const CommandArgs& raw_args) {
  const std::string command = "decompress";
  auto parsed = Args::Parse(raw_args, {{"-o"}, {"--quiet"}});
  if (!parsed.ok()) return ReportError(command, parsed.status());
  const Args& args = *parsed;
  auto input = InputAndOutput(args, "decompress");
  if (!input.ok()) return ReportError(command, input.status());
  auto image = ReadImage(*input);
  if (!image.ok()) return ReportError(command, image.status());
  const std::string output = *args.get("-o");
  if (Status s = WriteImage(output, *image, nullptr); !s.ok()) return ReportError(command, s);
  return 0;
}

}  // namespace sdvi::cli
