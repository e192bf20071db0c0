// SPDX-License-Identifier: GPL-3.0-or-later
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
#include "sdvi/edit.h"
#include "sdvi/exr_io.h"
#include "sdvi/progress.h"
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

// The options of `sdvi render`.
struct RenderArgs {
  std::string input, output, region, reference, format, overlay;
  double scale = 1.0;
  int width = 0, height = 0, levels = -1, bits = 8, threads = 0;
  bool half = false, quiet = false, json = false;
  CLI::Option *scale_opt = nullptr, *width_opt = nullptr, *height_opt = nullptr, *bits_opt = nullptr;
};

// The output viewport of `sdvi render` for image and the size options.
StatusOr<Viewport> OutputViewport(const Image& image, const RenderArgs& args) {
  if (image.width == 0 || image.height == 0)
    return Status(StatusCode::kEmptyInput, "the image has no size (width or height 0)");
  const bool has_size = args.width_opt->count() > 0 || args.height_opt->count() > 0;
  Viewport vp;
  if (has_size) {
    int w = args.width, h = args.height;
    // One side given: keep the aspect ratio.
    if (w == 0) w = std::max(1, int(std::lround(double(h) * image.width / image.height)));
    if (h == 0) h = std::max(1, int(std::lround(double(w) * image.height / image.width)));
    vp.width = w, vp.height = h;
    vp.scale_x = double(w) / image.width, vp.scale_y = double(h) / image.height;
  } else {
    const double s = args.scale;
    vp.scale_x = vp.scale_y = s;
    vp.width = int(std::min(1e9, std::max(1.0, std::round(image.width * s))));
    vp.height = int(std::min(1e9, std::max(1.0, std::round(image.height * s))));
  }
  if (!args.region.empty()) {
    SDVI_ASSIGN_OR_RETURN(auto r, ParseRegion(args.region));
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

// Render options for the whole image at the given output size.
StatusOr<RenderOptions> AtSize(const Image& image, int width, int height, int levels) {
  if (image.width == 0 || image.height == 0)
    return Status(StatusCode::kEmptyInput, "the image has no size (width or height 0)");
  RenderOptions o;
  o.viewport.width = width, o.viewport.height = height;
  o.viewport.scale_x = double(width) / image.width, o.viewport.scale_y = double(height) / image.height;
  o.levels = levels;
  return o;
}

// The output format of `sdvi render`: --format, else the output's extension.
std::string RenderFormat(const RenderArgs& a) {
  if (!a.format.empty()) return a.format;
  return FileExtension(a.output);
}

int Render(const RenderArgs& a) {
  const char* cmd = "render";
  const std::string ext = RenderFormat(a);
  if (ext != "png" && ext != "exr")
    return ReportUsage(cmd, a.output + ": output must be .png or .exr (or give --format png|exr), got '" + ext + "'");
  if (ext == "exr" && a.bits_opt->count()) return ReportUsage(cmd, "--bits is for PNG; EXR takes --half");
  if (ext == "png" && (a.half || !a.reference.empty()))
    return ReportUsage(cmd, "--half and --reference are for EXR output");
  if (!a.overlay.empty() && (ext != "png" || a.bits != 8)) return ReportUsage(cmd, "--overlay draws into an 8-bit PNG");
  if (a.json && IsStdStream(a.output)) return ReportUsage(cmd, "--json and -o - both use standard output");
  if (a.width_opt->count() && a.height_opt->count() && a.width == 0 && a.height == 0)
    return ReportUsage(cmd, "--width and --height must not both be 0");
  if (!a.region.empty()) {
    if (auto r = ParseRegion(a.region); !r.ok()) return ReportUsage(cmd, r.status().message());
  }

  auto image = LoadSdvi(a.input);
  if (!image.ok()) return ReportError(cmd, image.status());
  auto vp = OutputViewport(*image, a);
  if (!vp.ok()) return ReportError(cmd, Status(vp.status().code(), a.input + ": " + vp.status().message()));
  RenderOptions options;
  options.viewport = *vp;
  options.levels = a.levels;
  options.threads = a.threads;
  Progress progress(a.quiet || a.json);  // on a terminal only
  options.progress = &progress;
  const auto start = std::chrono::steady_clock::now();
  // An 8-bit PNG is rendered straight into 8-bit samples (no float raster); 16-bit PNG,
  // EXR and the overlay take the float render (spec/METHOD.md section 4, item 5).
  const bool eight_bit = ext == "png" && a.bits == 8 && a.overlay.empty();
  StatusOr<Raster> rendered = Raster();
  StatusOr<Raster8> rendered8 = Raster8();
  if (eight_bit)
    rendered8 = Render8(*image, options);
  else
    rendered = Render(*image, options);
  const Status render_status = eight_bit ? rendered8.status() : rendered.status();
  if (!render_status.ok()) return ReportError(cmd, Status(render_status.code(), a.input + ": " + render_status.message()));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  Status written;
  if (eight_bit) {
    // Alpha only where the surface does not cover the output; grey when R = G = B everywhere.
    written = SaveRasterPng(a.output, WithNeededChannels(*rendered8));
  } else if (ext == "png") {
    if (a.overlay == "features") *rendered = DrawFeatureOverlay(*rendered, *image, *vp);
    written = SaveRasterPng(a.output, WithNeededChannels(*rendered), a.bits);
  } else {
    const Raster raster = WithNeededChannels(*rendered);
    ExrWriteOptions exr;
    exr.half = a.half;
    if (!a.region.empty()) {
      // The region keeps its place in the whole render: data window inside the display window.
      RenderArgs whole = a;
      whole.region.clear();
      auto full = OutputViewport(*image, whole);
      auto r = ParseRegion(a.region);
      if (full.ok() && r.ok()) {
        exr.data_x = (*r)[0], exr.data_y = (*r)[1];
        exr.display_width = full->width, exr.display_height = full->height;
      }
    }
    std::vector<float> error;
    if (!a.reference.empty()) {
      auto ref = LoadRaster(a.reference);
      if (!ref.ok()) return ReportError(cmd, ref.status());
      auto e = ErrorChannel(raster, *ref);
      if (!e.ok()) return ReportError(cmd, Status(e.status().code(), a.reference + ": " + e.status().message()));
      error = std::move(*e);
      exr.error = &error;
    }
    written = SaveExr(a.output, raster, exr);
  }
  if (!written.ok()) return ReportError(cmd, written);
  const int level = std::min(ChooseRenderLevels(*image, options), kMaxLevels);
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["width"] = vp->width;
    j["height"] = vp->height;
    j["level"] = level;
    j["seconds"] = seconds;
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::fprintf(SummaryStream(a.output), "%s: %dx%d, level %d, rendered in %.3f s\n", a.output.c_str(),
                 vp->width, vp->height, level, seconds);
  }
  return kExitOk;
}

// The options of `sdvi compare`.
struct CompareArgs {
  std::string a, b;
  int levels = -1;
  bool json = false;
};

int Compare(const CompareArgs& args) {
  const char* cmd = "compare";
  auto a = LoadCompareInput(args.a);
  if (!a.ok()) return ReportError(cmd, a.status());
  auto b = LoadCompareInput(args.b);
  if (!b.ok()) return ReportError(cmd, b.status());
  // A .sdvi is rendered at the other input's raster size (at its own size if both are .sdvi),
  // and counts as its 8-bit render, as its PNG would (spec/RATE.md 1: one PSNR): A straight
  // into bytes (Render8, compared in place), B as the float render rounded.
  const int width = a->is_sdvi ? (b->is_sdvi ? int(a->image.width) : b->raster.width) : a->raster.width;
  const int height = a->is_sdvi ? (b->is_sdvi ? int(a->image.height) : b->raster.height) : a->raster.height;
  auto named = [](const std::string& path, const Status& s) { return Status(s.code(), path + ": " + s.message()); };
  Raster8 a_render;
  if (a->is_sdvi) {
    auto o = AtSize(a->image, width, height, args.levels);
    auto r = o.ok() ? Render8(a->image, *o) : StatusOr<Raster8>(o.status());
    if (!r.ok()) return ReportError(cmd, named(args.a, r.status()));
    a_render = std::move(*r);
  }
  if (b->is_sdvi) {
    auto o = AtSize(b->image, width, height, args.levels);
    auto r = o.ok() ? Render(b->image, *o) : StatusOr<Raster>(o.status());
    if (!r.ok()) return ReportError(cmd, named(args.b, r.status()));
    b->raster = std::move(*r);
    RoundTo8Bit(b->raster);
  }
  // The metrics are the same for any thread count: all cores.
  auto m = a->is_sdvi ? CompareImages(a_render, b->raster, 0) : CompareImages(a->raster, b->raster, 0);
  if (!m.ok())
    return ReportError(cmd, Status(m.status().code(), args.a + " vs " + args.b + ": " + m.status().message()));
  const int a_channels = a->is_sdvi ? a_render.channels : a->raster.channels;
  const bool grey = a_channels < 3 && b->raster.channels < 3;
  if (args.json) {
    nlohmann::ordered_json j;
    j["psnr"] = std::isfinite(m->psnr) ? nlohmann::json(m->psnr) : nlohmann::json(nullptr);  // null: identical
    j["mssim"] = m->mssim;
    j["mssim_channels"] = grey ? "grey" : "RGB";
    j["mean_error"] = m->mean_error;
    j["mse"] = m->mse;
    j["pixels"] = m->pixels;
    j["width"] = width;
    j["height"] = height;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    if (std::isfinite(m->psnr))
      std::printf("PSNR        %.4f dB (R, G, B, 8-bit units)\n", m->psnr);
    else
      std::printf("PSNR        inf (identical)\n");
    std::printf("MSSIM       %.5f (Gaussian 11x11, sigma 1.5; mean over %s)\n", m->mssim, grey ? "grey" : "R, G, B");
    std::printf("mean error  %.4f (8-bit units)\n", m->mean_error);
    std::printf("pixels      %llu of %dx%d\n", static_cast<unsigned long long>(m->pixels), width,
                height);
  }
  return kExitOk;
}

}  // namespace

void RegisterRender(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* c = AddCommand(
      app, "render", "render the limit surface of a .sdvi at any resolution, to PNG or EXR",
      {"sdvi render in.sdvi -o out.png                  # at the image's own size",
       "sdvi render in.sdvi -o big.png --scale 4        # 4x magnification",
       "sdvi render in.sdvi -o out.png --width 1920     # height keeps the aspect ratio",
       "sdvi render in.sdvi -o crop.exr --scale 8 --region 100,100,512,512 --half",
       "sdvi render in.sdvi -o - --format png > out.png",
       "sdvi render in.sdvi -o ids.png --scale 3 --overlay features   # feature ids for sdvi edit",
       "sdvi render 'out/*.sdvi' -O png/ --scale 4 -j 2   # out/NAME.sdvi -> png/NAME.png"});
  AddOutput(c, a->output, "the output image, .png (8/16-bit sRGB, alpha = domain) or .exr (linear light)");
  AddInputs(c, a->input, "the .sdvi file ('-' reads standard input)", {{"sdvi"}, "png", "--format", {}});
  c->add_option("--format", a->format, "output format when -o does not tell it by extension")
      ->check(CLI::IsMember({"png", "exr"}));
  a->scale_opt = c->add_option("--scale", a->scale, "magnification factor")->check(CLI::Range(1e-6, 65536.0));
  a->width_opt = c->add_option("--width", a->width, "output width in pixels (0: from --height)")
                     ->check(CLI::Range(0, 1 << 20))->excludes(a->scale_opt);
  a->height_opt = c->add_option("--height", a->height, "output height in pixels (0: from --width)")
                      ->check(CLI::Range(0, 1 << 20))->excludes(a->scale_opt);
  c->add_option("--region", a->region, "render only this window x,y,w,h of the full-size output")
      ->type_name("X,Y,W,H");
  c->add_option("--levels", a->levels, "subdivision level r (-1: chosen from the scale)")->check(CLI::Range(-1, 8));
  a->bits_opt = c->add_option("--bits", a->bits, "PNG bits per channel")->check(CLI::IsMember({8, 16}));
  c->add_flag("--half", a->half, "EXR: 16-bit half floats instead of 32-bit floats");
  MarkInput(c, a->reference);
  UsesRasterCodecs(c, &a->reference);  // PNG output needs no codec module; the reference does
  c->add_option("--reference", a->reference, "EXR: add an 'error' channel against this image")->type_name("IMG");
  c->add_option("--threads", a->threads, "worker threads (0: all cores)")->check(CLI::Range(0, 256));
  c->add_option("--overlay", a->overlay,
                "draw over the render: 'features' = feature polylines, deBoor points and ids (P<n> pair, L<n> polyline)")
      ->check(CLI::IsMember({"features"}));
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return Render(*a); });
}

void RegisterCompare(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* c = AddCommand(
      app, "compare",
      "PSNR, MSSIM and mean error between two images, or a .sdvi (rendered at the other's size) and an image",
      {"sdvi compare out.png in.png", "sdvi compare result.sdvi original.png --json"});
  MarkInput(c, a->a);
  UsesRasterCodecs(c);
  c->add_option("A", a->a, "the reconstruction: an image or a .sdvi")->required();
  MarkInput(c, a->b);
  c->add_option("B", a->b, "the reference: an image or a .sdvi")->required();
  c->add_option("--levels", a->levels, "subdivision level for rendering a .sdvi (-1: automatic)")
      ->check(CLI::Range(-1, 8));
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return Compare(*a); });
}

}  // namespace sdvi::cli
