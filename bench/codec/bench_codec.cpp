// SPDX-License-Identifier: GPL-3.0-or-later
// bench_codec: the Draco payload against the paper's raw layout, JPEG and WebP.
//
// For every photo and graphic under --data (default /work/shared/data/{photos,graphics}):
// vectorize at the default budget, then print raw paper size, raw file size, Draco file
// size, ratio, bits per pixel, PSNR of the raw and of the Draco render (and the drop),
// and the bytes JPEG (cjpeg -optimize) and WebP (cwebp -m 6) need to reach the Draco
// file's PSNR, found by bisecting their quality setting in this run. Then a bytes-vs-PSNR
// curve (several vectorizer budgets, JPEG and WebP quality sweeps) for Lena and one
// graphic, drawn as PNG plots under --out.
//
//   bench_codec [--data DIR] [--out DIR] [--only SUBSTRING] [--threads N]
//               [--no-curves] [--curves-only] [--curve-graphic NAME]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/codec.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/vectorize.h"
#include "codec_bench.h"

namespace fs = std::filesystem;
using namespace sdvi::bench;

namespace {



// The colour channels of raster as an 8-bit grey or BGR cv::Mat (alpha dropped).
cv::Mat ToColorMat(const sdvi::Raster& r) {
  const bool grey = r.channels <= 2;
  cv::Mat m(r.height, r.width, grey ? CV_8UC1 : CV_8UC3);
  auto q = [](float v) { return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
  for (int y = 0; y < r.height; ++y) {
    uint8_t* row = m.ptr<uint8_t>(y);
    for (int x = 0; x < r.width; ++x) {
      if (grey) {
        row[x] = q(r.at(x, y, 0));
      } else {
        row[3 * x + 0] = q(r.at(x, y, 2));
        row[3 * x + 1] = q(r.at(x, y, 1));
        row[3 * x + 2] = q(r.at(x, y, 0));
      }
    }
  }
  return m;
}

double Psnr(const sdvi::Raster& reconstruction, const sdvi::Raster& reference) {
  auto m = sdvi::CompareImages(reconstruction, reference);
  return m.ok() ? m->psnr : std::nan("");
}

// One external codec: encode the prepared input at quality q into a file, decode it.
struct ExternalCodec {
  std::string name;
  std::string input;  // prepared input file (PPM/PGM for cjpeg, PNG for cwebp)
  std::string encoded, decoded;
  std::function<std::string(int)> encode_command;
  std::string decode_command;
};

struct Point {
  int quality = 0;
  uint64_t bytes = 0;
  double psnr = 0;
};

std::optional<Point> Measure(const ExternalCodec& codec, int quality, const sdvi::Raster& reference) {
  if (!Run(codec.encode_command(quality)) || !Run(codec.decode_command)) return std::nullopt;
  cv::Mat decoded = cv::imread(codec.decoded, cv::IMREAD_UNCHANGED);
  if (decoded.empty() || decoded.depth() != CV_8U) return std::nullopt;
  return Point{quality, static_cast<uint64_t>(fs::file_size(codec.encoded)),
               Psnr(FromMat(decoded), reference)};
}

// Smallest quality (1..100) whose PSNR reaches target, by bisection (PSNR rises with
// quality); nullopt when even quality 100 falls short.
std::optional<Point> BytesForPsnr(const ExternalCodec& codec, double target, const sdvi::Raster& reference,
                                  Point* best_effort) {
  auto top = Measure(codec, 100, reference);
  if (!top) return std::nullopt;
  *best_effort = *top;
  if (top->psnr < target) return std::nullopt;
  int lo = 1, hi = 100;  // hi reaches the target
  Point at_hi = *top;
  auto low = Measure(codec, lo, reference);
  if (low && low->psnr >= target) return low;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    auto p = Measure(codec, mid, reference);
    if (!p) return std::nullopt;
    if (p->psnr >= target) {
      hi = mid;
      at_hi = *p;
    } else {
      lo = mid;
    }
  }
  return at_hi;
}

struct Codecs {
  ExternalCodec jpeg, webp;
};

Codecs PrepareCodecs(const sdvi::Raster& raster, const fs::path& work) {
  Codecs c;
  const bool grey = raster.channels <= 2;
  c.jpeg.name = "jpeg";
  c.jpeg.input = (work / (grey ? "in.pgm" : "in.ppm")).string();
  cv::imwrite(c.jpeg.input, ToColorMat(raster));
  c.jpeg.encoded = (work / "out.jpg").string();
  c.jpeg.decoded = (work / (grey ? "jpeg_dec.pgm" : "jpeg_dec.ppm")).string();
  c.jpeg.encode_command = [in = c.jpeg.input, out = c.jpeg.encoded](int q) {
    return "cjpeg -quality " + std::to_string(q) + " -optimize -outfile " + ShellQuote(out) + " " +
           ShellQuote(in);
  };
  c.jpeg.decode_command = "djpeg -outfile " + ShellQuote(c.jpeg.decoded) + " " + ShellQuote(c.jpeg.encoded);

  c.webp.name = "webp";
  c.webp.input = (work / "in.png").string();
  (void)sdvi::SaveRasterPng(c.webp.input, raster, 8);
  c.webp.encoded = (work / "out.webp").string();
  c.webp.decoded = (work / "webp_dec.png").string();
  c.webp.encode_command = [in = c.webp.input, out = c.webp.encoded](int q) {
    return "cwebp -quiet -m 6 -q " + std::to_string(q) + " " + ShellQuote(in) + " -o " + ShellQuote(out);
  };
  c.webp.decode_command = "dwebp -quiet " + ShellQuote(c.webp.encoded) + " -o " + ShellQuote(c.webp.decoded);
  return c;
}

// One vectorized image: raw file, conservative Draco (no reference MSE) and rate-adapted
// Draco (reference MSE = the raw render's MSE against the source, as `sdvi vectorize
// --compress` knows it).
struct SdviPoint {
  uint32_t vertices = 0, triangles = 0;
  uint64_t paper = 0, raw_file = 0, draco_file = 0, conservative_file = 0;
  double psnr_raw = 0, psnr_draco = 0, psnr_conservative = 0, vectorize_s = 0, encode_ms = 0,
         decode_ms = 0;
  int position_bits = 0, color_bits = 0;
};

sdvi::StatusOr<sdvi::Raster> RenderAt(const sdvi::Image& image) {
  sdvi::RenderOptions options;
  options.viewport = sdvi::Viewport::Identity(static_cast<int>(image.width), static_cast<int>(image.height));
  return sdvi::Render(image, options);
}

sdvi::StatusOr<SdviPoint> RunSdvi(const sdvi::Raster& raster, double compression_ratio, int threads) {
  SdviPoint out;
  sdvi::VectorizeOptions options;
  if (compression_ratio > 0) options.compression_ratio = compression_ratio;
  options.threads = threads;
  const auto start = Clock::now();
  SDVI_ASSIGN_OR_RETURN(sdvi::VectorizeResult result, sdvi::Vectorize(raster, nullptr, options));
  out.vectorize_s = Seconds(start);
  const sdvi::Image& image = result.image;
  out.vertices = static_cast<uint32_t>(image.vertices.size());
  out.triangles = static_cast<uint32_t>(image.triangles.size());
  out.paper = sdvi::PaperSizeBytes(out.vertices, out.triangles);
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> raw, sdvi::EncodeImage(image, nullptr));
  out.raw_file = raw.size();
  SDVI_ASSIGN_OR_RETURN(sdvi::Image raw_image, sdvi::DecodeImage(raw, "raw"));
  SDVI_ASSIGN_OR_RETURN(sdvi::Raster raw_render, RenderAt(raw_image));
  SDVI_ASSIGN_OR_RETURN(sdvi::ImageMetrics raw_metrics, sdvi::CompareImages(raw_render, raster));
  out.psnr_raw = raw_metrics.psnr;
  // Conservative defaults.
  const sdvi::CompressOptions conservative;
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> cons, sdvi::EncodeImage(image, &conservative));
  out.conservative_file = cons.size();
  SDVI_ASSIGN_OR_RETURN(sdvi::Image cons_image, sdvi::DecodeImage(cons, "conservative"));
  SDVI_ASSIGN_OR_RETURN(sdvi::Raster cons_render, RenderAt(cons_image));
  out.psnr_conservative = Psnr(cons_render, raster);
  // Rate-adapted defaults.
  sdvi::CompressOptions compress;
  compress.reference_mse = raw_metrics.mse;
  out.position_bits = sdvi::DefaultPositionBits(image, compress.reference_mse);
  out.color_bits = sdvi::DefaultColorBits(image, compress.reference_mse);
  auto t0 = Clock::now();
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> draco, sdvi::EncodeImage(image, &compress));
  out.encode_ms = 1000 * Seconds(t0);
  out.draco_file = draco.size();
  t0 = Clock::now();
  SDVI_ASSIGN_OR_RETURN(sdvi::Image draco_image, sdvi::DecodeImage(draco, "draco"));
  out.decode_ms = 1000 * Seconds(t0);
  SDVI_ASSIGN_OR_RETURN(sdvi::Raster draco_render, RenderAt(draco_image));
  out.psnr_draco = Psnr(draco_render, raster);
  return out;
}


// ---- rate-distortion plot --------------------------------------------------------------


}  // namespace

int main(int argc, char** argv) {
  fs::path data = "/work/shared/data", out = "bench_codec_out";
  std::string only, curve_graphic = "tango_face-smile_512";
  bool curves = true, table = true;
  int threads = 2;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_codec: %s needs a value\n", a.c_str());
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--data") data = next();
    else if (a == "--out") out = next();
    else if (a == "--only") only = next();
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--curve-graphic") curve_graphic = next();
    else if (a == "--no-curves") curves = false;
    else if (a == "--curves-only") table = false;
    else {
      std::fprintf(stderr,
                   "usage: bench_codec [--data DIR] [--out DIR] [--only SUBSTRING] [--threads N] "
                   "[--no-curves] [--curves-only] [--curve-graphic NAME]\n");
      return 1;
    }
  }
  if (!Run("command -v cjpeg") || !Run("command -v cwebp") || !Run("command -v djpeg") ||
      !Run("command -v dwebp")) {
    std::fprintf(stderr, "bench_codec: needs cjpeg/djpeg (libjpeg-turbo-progs) and cwebp/dwebp (webp)\n");
    return 2;
  }
  fs::create_directories(out);
  const fs::path work = out / "work";
  fs::create_directories(work);

  if (table) {
    std::printf(
        "Default vectorizer budget. Sizes in bytes. paper = 20V+6T+8; cons = Draco file at the conservative\n"
        "defaults (no reference MSE) and its PSNR drop vs the raw file's render; draco = Draco file with the\n"
        "reference MSE (quantization from a 1%% MSE budget; pb/cb = bits used); ratio = draco / paper;\n"
        "bpp = draco bits per pixel; dr/riv = draco / rival bytes (JPEG for photos, WebP for graphics); jpeg/webp = bytes (quality) needed to reach the draco render's PSNR\n"
        "('>N(100)': even quality 100 (N bytes) falls short); webpLL = lossless WebP bytes.\n\n");
    std::printf("%-8s %-32s %5s %5s %7s %7s %6s %7s %5s %6s %6s %5s %6s %7s %7s %6s %12s %12s %7s %6s %6s\n", "kind",
                "image", "V", "T", "paper", "cons", "dropc", "draco", "pb/cb", "ratio", "bpp", "B/vx", "PSNRrw",
                "PSNRdr", "drop", "dr/riv", "jpeg(q)", "webp(q)", "webpLL", "enc_ms", "dec_ms");
    struct Tally {
      int n = 0, ratio_ok = 0, drop_ok = 0, cons_drop_ok = 0, beats = 0, unreachable = 0;
      double worst_drop = 0, worst_cons_drop = 0, worst_ratio = 0, sum_vs_rival = 0;
      int vs_rival_n = 0;
    };
    std::map<std::string, Tally> tally;
    for (const std::string kind : {"photos", "graphics"}) {
      for (const fs::path& path : ListImages(data / kind)) {
        const std::string name = path.stem().string();
        if (!only.empty() && path.filename().string().find(only) == std::string::npos) continue;
        auto raster = sdvi::LoadRaster(path.string());
        if (!raster.ok()) {
          std::printf("%-8s %-32s load failed: %s\n", kind.c_str(), name.c_str(), raster.status().ToString().c_str());
          continue;
        }
        auto s = RunSdvi(*raster, 0, threads);
        if (!s.ok()) {
          std::printf("%-8s %-32s failed: %s\n", kind.c_str(), name.c_str(), s.status().ToString().c_str());
          std::fflush(stdout);
          continue;
        }
        const Codecs codecs = PrepareCodecs(*raster, work);
        Point jpeg_best, webp_best;
        auto jpeg = BytesForPsnr(codecs.jpeg, s->psnr_draco, *raster, &jpeg_best);
        auto webp = BytesForPsnr(codecs.webp, s->psnr_draco, *raster, &webp_best);
        auto cell = [](const std::optional<Point>& p, const Point& best) {
          char buf[32];
          if (p) std::snprintf(buf, sizeof buf, "%llu(%d)", static_cast<unsigned long long>(p->bytes), p->quality);
          else std::snprintf(buf, sizeof buf, ">%llu(100)", static_cast<unsigned long long>(best.bytes));
          return std::string(buf);
        };
        const double pixels = double(raster->width) * raster->height;
        const double ratio = double(s->draco_file) / double(s->paper);
        const double drop = s->psnr_raw - s->psnr_draco;
        const double cons_drop = s->psnr_raw - s->psnr_conservative;
        const auto& rival = kind == "photos" ? jpeg : webp;
        const Point& rival_best = kind == "photos" ? jpeg_best : webp_best;
        const double vs_rival = rival ? double(s->draco_file) / double(rival->bytes) : 0;
        uint64_t lossless = 0;
        if (Run("cwebp -quiet -lossless -m 6 " + ShellQuote(codecs.webp.input) + " -o " +
                ShellQuote(codecs.webp.encoded)))
          lossless = fs::file_size(codecs.webp.encoded);
        char bits[16];
        std::snprintf(bits, sizeof bits, "%d/%d", s->position_bits, s->color_bits);
        std::printf("%-8s %-32s %5u %5u %7llu %7llu %6.3f %7llu %5s %6.3f %6.3f %5.2f %6.2f %7.2f %7.3f %6.2f %12s %12s %7llu %6.1f %6.1f\n",
                    kind.c_str(), name.c_str(), s->vertices, s->triangles,
                    static_cast<unsigned long long>(s->paper), static_cast<unsigned long long>(s->conservative_file),
                    cons_drop, static_cast<unsigned long long>(s->draco_file), bits, ratio,
                    8.0 * double(s->draco_file) / pixels, double(s->draco_file) / s->vertices, s->psnr_raw,
                    s->psnr_draco, drop, vs_rival, cell(jpeg, jpeg_best).c_str(), cell(webp, webp_best).c_str(),
                    static_cast<unsigned long long>(lossless), s->encode_ms, s->decode_ms);
        std::fflush(stdout);
        Tally& t = tally[kind];
        ++t.n;
        t.ratio_ok += ratio <= 0.25;
        t.drop_ok += drop < 0.1;
        t.cons_drop_ok += cons_drop < 0.1;
        t.worst_drop = std::max(t.worst_drop, drop);
        t.worst_cons_drop = std::max(t.worst_cons_drop, cons_drop);
        t.worst_ratio = std::max(t.worst_ratio, ratio);
        // A win: the rival needs more bytes for the same PSNR, or cannot reach it at all
        // while its quality-100 file is larger.
        const bool unreachable = !rival && rival_best.bytes > 0;
        t.unreachable += unreachable;
        t.beats += (rival && s->draco_file <= rival->bytes) || (unreachable && s->draco_file <= rival_best.bytes);
        if (rival) {
          t.sum_vs_rival += std::log(vs_rival);
          ++t.vs_rival_n;
        }
      }
    }
    std::printf("\nGoals:\n");
    for (const auto& [kind, t] : tally) {
      std::printf("  %-8s Draco <= 0.25x paper size: %d/%d (worst %.3f)\n", kind.c_str(), t.ratio_ok, t.n,
                  t.worst_ratio);
      std::printf("  %-8s PSNR drop < 0.1 dB: with reference MSE %d/%d (worst %.3f dB); conservative %d/%d (worst %.3f dB)\n",
                  kind.c_str(), t.drop_ok, t.n, t.worst_drop, t.cons_drop_ok, t.n, t.worst_cons_drop);
      std::printf("  %-8s sdvi bytes <= %s bytes at equal PSNR: %d/%d (%d where %s cannot reach the PSNR); "
                  "geometric mean sdvi/%s where it can: %.2f\n",
                  kind.c_str(), kind == "photos" ? "JPEG" : "WebP", t.beats, t.n, t.unreachable,
                  kind == "photos" ? "JPEG" : "WebP", kind == "photos" ? "JPEG" : "WebP",
                  t.vs_rival_n ? std::exp(t.sum_vs_rival / t.vs_rival_n) : 0.0);
    }
  }

  if (curves) {
    struct CurveInput {
      fs::path path;
      std::string title;
    };
    std::vector<CurveInput> inputs = {{data / "photos" / "lena_512.png", "lena_512"},
                                      {data / "graphics" / (curve_graphic + ".png"), curve_graphic}};
    for (const CurveInput& in : inputs) {
      auto raster = sdvi::LoadRaster(in.path.string());
      if (!raster.ok()) {
        std::printf("curve %s: %s\n", in.title.c_str(), raster.status().ToString().c_str());
        continue;
      }
      std::printf("\nBytes vs PSNR, %s\n%-6s %10s %8s\n", in.title.c_str(), "codec", "bytes", "PSNR");
      Series sdvi_series{"sdvi (Draco, reference MSE)", cv::Scalar(40, 40, 200), {}};
      Series raw_series{"sdvi (raw)", cv::Scalar(140, 140, 230), {}};
      Series cons_series{"sdvi (Draco, conservative)", cv::Scalar(120, 40, 160), {}};
      for (double ratio : {256.0, 128.0, 64.0, 32.0, 16.0}) {
        auto s = RunSdvi(*raster, ratio, threads);
        if (!s.ok()) {
          std::printf("sdvi   ratio %g failed: %s\n", ratio, s.status().ToString().c_str());
          continue;
        }
        sdvi_series.points.push_back({double(s->draco_file), s->psnr_draco});
        cons_series.points.push_back({double(s->conservative_file), s->psnr_conservative});
        raw_series.points.push_back({double(s->raw_file), s->psnr_raw});
        std::printf("sdvi   %10llu %8.2f   (pixels/vertex %g, %u vertices; conservative Draco %llu, raw file %llu at %.2f dB)\n",
                    static_cast<unsigned long long>(s->draco_file), s->psnr_draco, ratio, s->vertices,
                    static_cast<unsigned long long>(s->conservative_file),
                    static_cast<unsigned long long>(s->raw_file), s->psnr_raw);
        std::fflush(stdout);
      }
      const Codecs codecs = PrepareCodecs(*raster, work);
      Series jpeg_series{"JPEG (cjpeg)", cv::Scalar(200, 120, 30), {}};
      Series webp_series{"WebP (cwebp -m 6)", cv::Scalar(40, 160, 40), {}};
      for (int q : {5, 10, 20, 30, 40, 50, 60, 70, 80, 90, 95}) {
        if (auto p = Measure(codecs.jpeg, q, *raster)) {
          jpeg_series.points.push_back({double(p->bytes), p->psnr});
          std::printf("jpeg   %10llu %8.2f   (q %d)\n", static_cast<unsigned long long>(p->bytes), p->psnr, q);
        }
        if (auto p = Measure(codecs.webp, q, *raster)) {
          webp_series.points.push_back({double(p->bytes), p->psnr});
          std::printf("webp   %10llu %8.2f   (q %d)\n", static_cast<unsigned long long>(p->bytes), p->psnr, q);
        }
      }
      const std::string plot = (out / ("rd_" + in.title + ".png")).string();
      DrawRdPlot(plot, "bytes vs PSNR: " + in.title, "bytes", {sdvi_series, cons_series, raw_series, jpeg_series, webp_series});
      std::printf("plot: %s\n", plot.c_str());
    }
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  return 0;
}
