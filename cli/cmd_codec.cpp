// sdvi compress (raw -> Draco payload) and sdvi decompress (any payload -> raw).
#include <cstdio>
#include <string>

#include "args.h"
#include "commands.h"
#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"

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

// MSE (8-bit units) of image's render at its own size against the reference raster.
StatusOr<double> ReferenceMse(const Image& image, const std::string& reference_path) {
  SDVI_ASSIGN_OR_RETURN(Raster reference, LoadRaster(reference_path));
  if (uint32_t(reference.width) != image.width || uint32_t(reference.height) != image.height)
    return Status(StatusCode::kInvalidArgument,
                  reference_path + ": the reference is " + std::to_string(reference.width) + "x" +
                      std::to_string(reference.height) + ", the image " + std::to_string(image.width) +
                      "x" + std::to_string(image.height));
  RenderOptions options;
  options.viewport = Viewport::Identity(static_cast<int>(image.width), static_cast<int>(image.height));
  SDVI_ASSIGN_OR_RETURN(Raster render, Render(image, options));
  SDVI_ASSIGN_OR_RETURN(ImageMetrics metrics, CompareImages(render, reference));
  return metrics.mse;
}

}  // namespace

int RunCompress(const CommandArgs& raw_args) {
  const std::string command = "compress";
  auto parsed = Args::Parse(raw_args, {{"-o", "--position-bits", "--color-bits", "--speed", "--reference", "--reference-mse"},
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
  auto reference_mse = args.GetDouble("--reference-mse", 0);
  for (const auto* v : {&position_bits, &color_bits, &speed})
    if (!v->ok()) return ReportError(command, v->status());
  if (!reference_mse.ok()) return ReportError(command, reference_mse.status());
  if (*reference_mse < 0)
    return ReportError(command, Status(StatusCode::kInvalidArgument, "--reference-mse must be >= 0"));
  if (args.get("--reference") && args.get("--reference-mse"))
    return ReportError(command, Status(StatusCode::kInvalidArgument,
                                       "give --reference IMG or --reference-mse M, not both"));
  options.reference_mse = *reference_mse;
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
  if (auto reference = args.get("--reference")) {
    auto mse = ReferenceMse(*image, *reference);
    if (!mse.ok()) return ReportError(command, mse.status());
    options.reference_mse = *mse;
  }
  auto bytes = EncodeImage(*image, &options, *input);
  if (!bytes.ok()) return ReportError(command, bytes.status());
  if (Status s = WriteFileAtomic(output, *bytes); !s.ok()) return ReportError(command, s);
  if (!args.flag("--quiet")) {
    const uint64_t paper = PaperSizeBytes(image->vertices.size(), image->triangles.size());
    const double pixels = double(image->width) * double(image->height);
    std::printf("%s: %zu vertices, %zu triangles: %zu bytes (paper raw size %llu, ratio %.3f, "
                "%.3f bits/pixel, %.2f bytes/vertex; position bits %d, colour bits %d)\n",
                output.c_str(), image->vertices.size(), image->triangles.size(), bytes->size(),
                static_cast<unsigned long long>(paper), double(bytes->size()) / double(paper),
                pixels > 0 ? 8.0 * double(bytes->size()) / pixels : 0.0,
                double(bytes->size()) / double(image->vertices.size()),
                options.position_bits ? options.position_bits : DefaultPositionBits(*image, options.reference_mse),
                options.color_bits ? options.color_bits : DefaultColorBits(*image, options.reference_mse));
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
