// sdvi render (a .sdvi at any size, to PNG or EXR) and sdvi compare (PSNR, MSSIM, mean
// error between images, or between a .sdvi rendered at a raster's size and that raster).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/exr_io.h"
#include "sdvi/file_util.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"

namespace sdvi::cli {
namespace {

// "x,y,w,h" in output pixels of the full-size render.
StatusOr<std::array<int, 4>> ParseRegion(const std::string& text) {
  std::array<int, 4> v{};
  std::stringstream in(text);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n == 4) { n = -1; break; }
    char* end = nullptr;
    const long x = std::strtol(part.c_str(), &end, 10);
    if (part.empty() || *end != '\0' || x < -(1L << 30) || x > (1L << 30)) { n = -1; break; }
    v[n++] = int(x);
  }
  if (n != 4 || v[2] <= 0 || v[3] <= 0)
    return Status(StatusCode::kInvalidArgument,
                  "option --region: expected x,y,w,h (integers, w and h > 0), got '" + text + "'");
  return v;
}

// The output viewport of `sdvi render` for image and the size options.
StatusOr<Viewport> OutputViewport(const Image& image, const Args& args) {
  if (image.width == 0 || image.height == 0)
    return Status(StatusCode::kEmptyInput, "the image has no size (width or height 0)");
  const bool has_scale = args.get("--scale").has_value();
  const bool has_size = args.get("--width").has_value() || args.get("--height").has_value();
  if (has_scale && has_size)
    return Status(StatusCode::kInvalidArgument, "give either --scale or --width/--height, not both");
  Viewport vp;
  if (has_size) {
    SDVI_ASSIGN_OR_RETURN(int w, args.GetInt("--width", 0));
    SDVI_ASSIGN_OR_RETURN(int h, args.GetInt("--height", 0));
    if (w < 0 || h < 0 || (w == 0 && h == 0))
      return Status(StatusCode::kInvalidArgument, "--width and --height must be positive");
    // One side given: keep the aspect ratio.
    if (w == 0) w = std::max(1, int(std::lround(double(h) * image.width / image.height)));
    if (h == 0) h = std::max(1, int(std::lround(double(w) * image.height / image.width)));
    vp.width = w, vp.height = h;
    vp.scale_x = double(w) / image.width, vp.scale_y = double(h) / image.height;
  } else {
    SDVI_ASSIGN_OR_RETURN(double s, args.GetDouble("--scale", 1.0));
    if (!(s > 0) || s > 65536)
      return Status(StatusCode::kInvalidArgument, "--scale must be > 0 (got " + std::to_string(s) + ")");
    vp.scale_x = vp.scale_y = s;
    vp.width = int(std::min(1e9, std::max(1.0, std::round(image.width * s))));
    vp.height = int(std::min(1e9, std::max(1.0, std::round(image.height * s))));
  }
  if (auto region = args.get("--region")) {
    SDVI_ASSIGN_OR_RETURN(auto r, ParseRegion(*region));
    vp.origin_x = r[0] / vp.scale_x, vp.origin_y = r[1] / vp.scale_y;
    vp.width = r[2], vp.height = r[3];
  }
  return vp;
}

// An input of `sdvi compare`: a .sdvi file (by its identifier) or a raster image.
struct CompareInput {
  bool is_sdvi = false;
  Image image;
  Raster raster;
};
StatusOr<CompareInput> LoadCompareInput(const std::string& path) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path));
  CompareInput in;
  in.is_sdvi = (bytes.size() >= 8 && std::equal(bytes.begin() + 4, bytes.begin() + 8, "SDVI")) ||
               FileExtension(path) == "sdvi";
  if (in.is_sdvi) {
    SDVI_ASSIGN_OR_RETURN(in.image, LoadSdvi(path));
  } else {
    SDVI_ASSIGN_OR_RETURN(in.raster, LoadRaster(path));
  }
  return in;
}

// Renders image at the given output size (the whole image).
StatusOr<Raster> RenderAtSize(const Image& image, int width, int height, int levels) {
  if (image.width == 0 || image.height == 0)
    return Status(StatusCode::kEmptyInput, "the image has no size (width or height 0)");
  RenderOptions o;
  o.viewport.width = width, o.viewport.height = height;
  o.viewport.scale_x = double(width) / image.width, o.viewport.scale_y = double(height) / image.height;
  o.levels = levels;
  return Render(image, o);
}

}  // namespace

int RunRender(const CommandArgs& args) {
  const char* cmd = "render";
  auto parsed = Args::Parse(args, ArgSpec{{"-o", "--scale", "--width", "--height", "--region", "--levels",
                                           "--bits", "--reference", "--threads"},
                                          {"--half", "--quiet"}});
  if (!parsed.ok()) return ReportError(cmd, parsed.status());
  const Args& a = *parsed;
  if (a.positional().size() != 1 || !a.get("-o"))
    return ReportError(cmd, Status(StatusCode::kInvalidArgument, "expected IN.sdvi -o OUT.png|OUT.exr"));
  const std::string in = a.positional()[0], out = *a.get("-o");
  const std::string ext = FileExtension(out);
  if (ext != "png" && ext != "exr")
    return ReportError(cmd, Status(StatusCode::kInvalidArgument,
                                   out + ": output must be .png or .exr (got '" + ext + "')"));
  auto bits = a.GetInt("--bits", 8);
  if (!bits.ok()) return ReportError(cmd, bits.status());
  if (*bits != 8 && *bits != 16) return ReportError(cmd, Status(StatusCode::kInvalidArgument, "--bits must be 8 or 16"));
  if (ext == "exr" && a.get("--bits"))
    return ReportError(cmd, Status(StatusCode::kInvalidArgument, "--bits is for PNG; EXR takes --half"));
  if (ext == "png" && (a.flag("--half") || a.get("--reference")))
    return ReportError(cmd, Status(StatusCode::kInvalidArgument, "--half and --reference are for EXR output"));
  auto levels = a.GetInt("--levels", -1);
  if (!levels.ok()) return ReportError(cmd, levels.status());
  auto threads = a.GetInt("--threads", 0);
  if (!threads.ok()) return ReportError(cmd, threads.status());

  auto image = LoadSdvi(in);
  if (!image.ok()) return ReportError(cmd, image.status());
  auto vp = OutputViewport(*image, a);
  if (!vp.ok()) return ReportError(cmd, vp.status());
  RenderOptions options;
  options.viewport = *vp;
  options.levels = *levels;
  options.threads = std::max(0, *threads);
  const auto start = std::chrono::steady_clock::now();
  auto raster = Render(*image, options);
  if (!raster.ok()) return ReportError(cmd, raster.status());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  Status written;
  if (ext == "png") {
    written = SaveRasterPng(out, *raster, *bits);
  } else {
    ExrWriteOptions exr;
    exr.half = a.flag("--half");
    std::vector<float> error;
    if (auto ref_path = a.get("--reference")) {
      auto ref = LoadRaster(*ref_path);
      if (!ref.ok()) return ReportError(cmd, ref.status());
      auto e = ErrorChannel(*raster, *ref);
      if (!e.ok()) return ReportError(cmd, e.status());
      error = std::move(*e);
      exr.error = &error;
    }
    written = SaveExr(out, *raster, exr);
  }
  if (!written.ok()) return ReportError(cmd, written);
  if (!a.flag("--quiet"))
    std::printf("%s: %dx%d, level %d, rendered in %.3f s\n", out.c_str(), vp->width, vp->height,
                std::min(ChooseRenderLevels(*image, options), kMaxLevels), seconds);
  return 0;
}

int RunCompare(const CommandArgs& args) {
  const char* cmd = "compare";
  auto parsed = Args::Parse(args, ArgSpec{{"--levels"}, {"--json"}});
  if (!parsed.ok()) return ReportError(cmd, parsed.status());
  if (parsed->positional().size() != 2)
    return ReportError(cmd, Status(StatusCode::kInvalidArgument,
                                   "expected A B (images, or a .sdvi and an image; A is the reconstruction)"));
  auto levels = parsed->GetInt("--levels", -1);
  if (!levels.ok()) return ReportError(cmd, levels.status());
  auto a = LoadCompareInput(parsed->positional()[0]);
  if (!a.ok()) return ReportError(cmd, a.status());
  auto b = LoadCompareInput(parsed->positional()[1]);
  if (!b.ok()) return ReportError(cmd, b.status());
  // A .sdvi is rendered at the other input's raster size (at its own size if both are .sdvi).
  if (a->is_sdvi && !b->is_sdvi) {
    auto r = RenderAtSize(a->image, b->raster.width, b->raster.height, *levels);
    if (!r.ok()) return ReportError(cmd, r.status());
    a->raster = std::move(*r);
  } else if (a->is_sdvi) {
    auto r = RenderAtSize(a->image, int(a->image.width), int(a->image.height), *levels);
    if (!r.ok()) return ReportError(cmd, r.status());
    a->raster = std::move(*r);
  }
  if (b->is_sdvi) {
    auto r = RenderAtSize(b->image, a->raster.width, a->raster.height, *levels);
    if (!r.ok()) return ReportError(cmd, r.status());
    b->raster = std::move(*r);
  }
  // A .sdvi counts as its 8-bit render, as its PNG would (spec/RATE.md 1: one PSNR).
  if (a->is_sdvi) RoundTo8Bit(a->raster);
  if (b->is_sdvi) RoundTo8Bit(b->raster);
  auto m = CompareImages(a->raster, b->raster);
  if (!m.ok()) return ReportError(cmd, m.status());
  const bool grey = a->raster.channels < 3 && b->raster.channels < 3;
  if (parsed->flag("--json")) {
    nlohmann::ordered_json j;
    j["psnr"] = std::isfinite(m->psnr) ? nlohmann::json(m->psnr) : nlohmann::json(nullptr);  // null: identical
    j["mssim"] = m->mssim;
    j["mssim_channels"] = grey ? "grey" : "RGB";
    j["mean_error"] = m->mean_error;
    j["mse"] = m->mse;
    j["pixels"] = m->pixels;
    j["width"] = a->raster.width;
    j["height"] = a->raster.height;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    if (std::isfinite(m->psnr))
      std::printf("PSNR        %.4f dB (R, G, B, 8-bit units)\n", m->psnr);
    else
      std::printf("PSNR        inf (identical)\n");
    std::printf("MSSIM       %.5f (Gaussian 11x11, sigma 1.5; mean over %s)\n", m->mssim, grey ? "grey" : "R, G, B");
    std::printf("mean error  %.4f (8-bit units)\n", m->mean_error);
    std::printf("pixels      %llu of %dx%d\n", static_cast<unsigned long long>(m->pixels), a->raster.width,
                a->raster.height);
  }
  return 0;
}

}  // namespace sdvi::cli
