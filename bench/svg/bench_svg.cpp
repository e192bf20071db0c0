// SPDX-License-Identifier: GPL-3.0-or-later
// bench_svg: tables for the SVG importer (spec/SVG.md).
//   bench_svg w3c   [DIR (default ../shared/data/svg-w3c)]
//     every *.svg with a *-ref.png: import-svg (artwork; --ratio pixels per vertex, default
//     16) at the PNG's size, render, PSNR against the PNG over all pixels after compositing
//     both over white (the gate: the reference PNGs have a transparent background and are
//     meant to be seen over white), and over the pixels both cover as `sdvi compare` counts
//     them (that one compares raw colours, so it is low where the reference is partly
//     transparent and the import was composited over white).
//     FONTCONFIG_FILE must be an absolute path (fontconfig resolves a relative one against
//     /etc/fonts): FONTCONFIG_FILE=$PWD/bench/svg/w3c_fonts.conf.
//   bench_svg icons [DIR (default ../shared/data/svg)] [--width W (512)] [--max-triangles N (3000)]
//     artwork vs Vectorize of librsvg's raster at the artwork's triangle count: PSNR of each
//     render against librsvg's raster, the gain; Draco-compressed bytes (as `sdvi compress`)
//     next to the SVG's gzip -9 size.
//   --dump DIR (w3c): writes each test's render (NAME-sdvi.png) and librsvg's rendering it was
//     fitted to (NAME-librsvg.png) into DIR (created), for looking at the errors.
//   --outline-only (both tables): outline features only, no detected edges where no outline
//     explains one (SvgArtworkOptions::detect_uncovered_edges = false), the ablation.
//   --no-thin-fills (both tables): fills' parts thinner than 3 px are not thin structures
//   --polygon-offset D (both tables): SvgArtworkOptions::polygon_offset (default 0.5 px; 0:
//     no bound on the control polygon's distance from its spline, the ablation)
//     (SvgArtworkOptions::thin_fills = false), the ablation.
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/svg.h"
#include "sdvi/vectorize.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double Seconds(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

sdvi::StatusOr<sdvi::Raster> RenderAt(const sdvi::Image& image, int width, int height) {
  sdvi::RenderOptions options;
  options.viewport = sdvi::Viewport::Identity(width, height);
  return sdvi::Render(image, options);
}

// Pixels within 2 px of a structure of reference (alpha > 0.5) thinner than 3 px: what a
// 3 x 3 opening removes (hairlines, glyph stems), grown by 2 px.
std::vector<uint8_t> ThinMask(const sdvi::Raster& reference) {
  const int w = reference.width, h = reference.height;
  auto grow = [w, h](const std::vector<uint8_t>& m, int r, bool all) {
    std::vector<uint8_t> out(m.size());
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        bool v = all;
        for (int dy = -r; dy <= r; ++dy) {
          for (int dx = -r; dx <= r; ++dx) {
            const int xx = x + dx, yy = y + dy;
            const bool in = xx >= 0 && yy >= 0 && xx < w && yy < h && m[size_t(yy) * w + xx];
            v = all ? v && in : v || in;
          }
        }
        out[size_t(y) * w + x] = v;
      }
    }
    return out;
  };
  std::vector<uint8_t> drawn(size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) drawn[size_t(y) * w + x] = !reference.has_alpha() || reference.at(x, y, reference.channels - 1) > 0.5f;
  }
  const std::vector<uint8_t> opened = grow(grow(drawn, 1, true), 1, false);
  std::vector<uint8_t> thin(drawn.size());
  for (size_t i = 0; i < thin.size(); ++i) thin[i] = drawn[i] && !opened[i];
  return grow(thin, 2, false);
}

// PSNR over all pixels (or those where skip is 0) after compositing a and b (RGBA or RGB)
// over white.
double PsnrOverWhite(const sdvi::Raster& a, const sdvi::Raster& b, const std::vector<uint8_t>* skip = nullptr) {
  double sum = 0;
  size_t n = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      if (skip != nullptr && (*skip)[size_t(y) * a.width + x]) continue;
      ++n;
      const float aa = a.has_alpha() ? a.at(x, y, a.channels - 1) : 1.f;
      const float ab = b.has_alpha() ? b.at(x, y, b.channels - 1) : 1.f;
      for (int c = 0; c < 3; ++c) {
        const float ca = a.channels >= 3 ? a.at(x, y, c) : a.at(x, y, 0);
        const float cb = b.channels >= 3 ? b.at(x, y, c) : b.at(x, y, 0);
        const double va = std::clamp(ca, 0.f, 255.f) * aa + 255.0 * (1 - aa);
        const double vb = std::clamp(cb, 0.f, 255.f) * ab + 255.0 * (1 - ab);
        sum += (va - vb) * (va - vb);
      }
    }
  }
  const double mse = n > 0 ? sum / (3.0 * double(n)) : 0;
  return mse <= 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

size_t GzipSize(const std::string& bytes) {
  z_stream z{};
  deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY);  // gzip -9 framing
  std::vector<unsigned char> out(deflateBound(&z, uLong(bytes.size())) + 32);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = uInt(bytes.size());
  z.next_out = out.data();
  z.avail_out = uInt(out.size());
  deflate(&z, Z_FINISH);
  const size_t size = z.total_out;
  deflateEnd(&z);
  return size;
}

std::vector<fs::path> SvgFiles(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".svg") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool g_outline_only = false;
bool g_no_thin_fills = false;
double g_polygon_offset = sdvi::SvgArtworkOptions{}.polygon_offset;
std::string g_dump_dir;

int W3cTable(const fs::path& dir, double ratio, double feature_fraction) {
  std::printf("SVG 1.1 tests (%s): sdvi import-svg (artwork, %.0f pixels per vertex) at the reference PNG's "
              "size, sdvi render, against the PNG%s\n"
              "features: from outlines + detected where no outline explains an edge; librsvg: PSNR over white of\n"
              "librsvg's own rendering (what the import is fitted to) against the PNG, the ceiling; thin: share of\n"
              "the pixels within 2 px of structures thinner than 3 px (hairlines, glyph stems); not thin: PSNR\n"
              "over white of the other pixels\n\n",
              dir.c_str(), ratio,
              g_outline_only ? " (outline features only)" : (g_no_thin_fills ? " (no thin fills)" : ""));
  std::printf("%-24s %9s %9s %10s %6s %12s %12s %9s %6s %9s %7s\n", "test", "size", "triangles", "features",
              "approx", "PSNR common", "PSNR white", "librsvg", "thin", "not thin", "time s");
  int failures = 0, below_gate = 0;
  double sum_common = 0, sum_white = 0, sum_rest = 0;
  int count = 0;
  for (const fs::path& svg : SvgFiles(dir)) {
    const fs::path png = svg.parent_path() / (svg.stem().string() + "-ref.png");
    if (!fs::exists(png)) continue;
    const Clock::time_point start = Clock::now();
    auto reference = sdvi::LoadRaster(png.string());
    auto document = sdvi::LoadSvgFile(svg.string(), {});
    if (!reference.ok() || !document.ok()) {
      std::printf("%-24s error: %s\n", svg.stem().c_str(),
                  (!reference.ok() ? reference.status() : document.status()).ToString().c_str());
      ++failures;
      continue;
    }
    sdvi::SvgArtworkOptions options;
    options.width = reference->width;
    options.vectorize.compression_ratio = ratio;
    options.vectorize.max_feature_fraction = feature_fraction;
    options.detect_uncovered_edges = !g_outline_only;
    options.thin_fills = !g_no_thin_fills;
    options.polygon_offset = g_polygon_offset;
    auto result = sdvi::ImportSvgArtwork(*document, options);
    if (!result.ok()) {
      std::printf("%-24s error: %s\n", svg.stem().c_str(), result.status().ToString().c_str());
      ++failures;
      continue;
    }
    auto rendered = RenderAt(result->vectorized.image, reference->width, reference->height);
    if (!rendered.ok()) {
      std::printf("%-24s error: %s\n", svg.stem().c_str(), rendered.status().ToString().c_str());
      ++failures;
      continue;
    }
    if (!g_dump_dir.empty()) {
      const std::string stem = (fs::path(g_dump_dir) / svg.stem()).string();
      (void)sdvi::SaveRasterPng(stem + "-sdvi.png", *rendered);
      (void)sdvi::SaveRasterPng(stem + "-librsvg.png", result->reference);
    }
    auto common = sdvi::CompareImages(*rendered, *reference);
    const double white = PsnrOverWhite(*rendered, *reference);
    const double ceiling = PsnrOverWhite(result->reference, *reference);
    const std::vector<uint8_t> thin = ThinMask(*reference);
    const double thin_share = double(std::count(thin.begin(), thin.end(), 1)) / double(thin.size());
    const double rest = PsnrOverWhite(*rendered, *reference, &thin);
    const double psnr = common.ok() ? common->psnr : 0;
    const std::string features =
        std::to_string(result->outline_features) + "+" + std::to_string(result->detected_features);
    std::printf("%-24s %4dx%-4d %9u %10s %6s %12.2f %12.2f %9.2f %5.0f%% %9.2f %7.1f\n", svg.stem().c_str(),
                reference->width, reference->height, result->vectorized.report.triangles, features.c_str(),
                result->approximate ? "yes" : "no", psnr, white, ceiling, 100 * thin_share, rest, Seconds(start));
    sum_rest += rest;
    sum_common += psnr;
    sum_white += white;
    below_gate += white < 30 ? 1 : 0;
    ++count;
  }
  if (count > 0) {
    std::printf("\n%d tests, mean PSNR %.2f dB (common pixels), %.2f dB (over white), %.2f dB (over white, not thin); "
                "%d below 30 dB over white; %d errors\n",
                count, sum_common / count, sum_white / count, sum_rest / count, below_gate, failures);
  }
  return failures == 0 ? 0 : 1;
}

int IconTable(const fs::path& dir, int width, int max_triangles) {
  std::printf("Icons and emoji (%s) at width %d: artwork mode%s vs vectorize of librsvg's raster at the "
              "artwork's triangle count (--max-triangles %d); PSNR against librsvg's raster over the "
              "pixels both cover\n\n", dir.c_str(), width, g_no_thin_fills ? " (no thin fills)" : "", max_triangles);
  std::printf("%-22s %9s %9s %9s %9s %9s %7s %10s %10s %9s\n", "file", "size", "tri art", "tri vec", "PSNR art",
              "PSNR vec", "gain", "art Draco", "vec Draco", "SVG gzip");
  double sum_gain = 0;
  int count = 0, failures = 0;
  for (const fs::path& svg : SvgFiles(dir)) {
    auto document = sdvi::LoadSvgFile(svg.string(), {});
    if (!document.ok()) {
      std::printf("%-22s error: %s\n", svg.stem().c_str(), document.status().ToString().c_str());
      ++failures;
      continue;
    }
    sdvi::SvgArtworkOptions options;
    options.width = width;
    options.vectorize.max_triangles = max_triangles;
    options.detect_uncovered_edges = !g_outline_only;
    options.thin_fills = !g_no_thin_fills;
    options.polygon_offset = g_polygon_offset;
    auto art = sdvi::ImportSvgArtwork(*document, options);
    if (!art.ok()) {
      std::printf("%-22s error: %s\n", svg.stem().c_str(), art.status().ToString().c_str());
      ++failures;
      continue;
    }
    const sdvi::Raster& reference = art->reference;
    sdvi::VectorizeOptions vectorize;
    vectorize.max_triangles = int(art->vectorized.report.triangles);
    auto vec = sdvi::Vectorize(reference, nullptr, vectorize);
    if (!vec.ok()) {
      std::printf("%-22s vectorize error: %s\n", svg.stem().c_str(), vec.status().ToString().c_str());
      ++failures;
      continue;
    }
    auto art_render = RenderAt(art->vectorized.image, reference.width, reference.height);
    auto vec_render = RenderAt(vec->image, reference.width, reference.height);
    if (!art_render.ok() || !vec_render.ok()) {
      ++failures;
      continue;
    }
    auto art_metrics = sdvi::CompareImages(*art_render, reference);
    auto vec_metrics = sdvi::CompareImages(*vec_render, reference);
    const double pa = art_metrics.ok() ? art_metrics->psnr : 0, pv = vec_metrics.ok() ? vec_metrics->psnr : 0;
    auto draco_bytes = [](const sdvi::Image& image, double psnr) -> long {
      sdvi::CompressOptions compress;
      compress.reference_mse = 255.0 * 255.0 / std::pow(10.0, psnr / 10.0);
      auto bytes = sdvi::EncodeImage(image, &compress);
      return bytes.ok() ? long(bytes->size()) : -1;
    };
    std::ifstream in(svg, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::printf("%-22s %4dx%-4d %9u %9u %9.2f %9.2f %+7.2f %10ld %10ld %9zu\n", svg.stem().c_str(), reference.width,
                reference.height, art->vectorized.report.triangles, vec->report.triangles, pa, pv, pa - pv,
                draco_bytes(art->vectorized.image, pa), draco_bytes(vec->image, pv), GzipSize(text));
    sum_gain += pa - pv;
    ++count;
  }
  if (count > 0) std::printf("\n%d files, mean gain %+.2f dB; %d errors\n", count, sum_gain / count, failures);
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  std::string dir;
  int width = 512, max_triangles = 3000;
  double ratio = 16, feature_fraction = 0.8;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--width") && i + 1 < argc) {
      width = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--ratio") && i + 1 < argc) {
      ratio = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--feature-fraction") && i + 1 < argc) {
      feature_fraction = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--dump") && i + 1 < argc) {
      g_dump_dir = argv[++i];
      std::error_code error;
      fs::create_directories(g_dump_dir, error);
      if (error) {
        std::fprintf(stderr, "bench_svg: cannot create %s: %s\n", g_dump_dir.c_str(), error.message().c_str());
        return 1;
      }
    } else if (!std::strcmp(argv[i], "--outline-only")) {
      g_outline_only = true;
    } else if (!std::strcmp(argv[i], "--polygon-offset") && i + 1 < argc) {
      g_polygon_offset = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--no-thin-fills")) {
      g_no_thin_fills = true;
    } else if (!std::strcmp(argv[i], "--max-triangles") && i + 1 < argc) {
      max_triangles = std::atoi(argv[++i]);
    } else {
      dir = argv[i];
    }
  }
  if (mode == "w3c") return W3cTable(dir.empty() ? "../shared/data/svg-w3c" : dir, ratio, feature_fraction);
  if (mode == "icons") return IconTable(dir.empty() ? "../shared/data/svg" : dir, width, max_triangles);
  std::fprintf(stderr, "usage: bench_svg w3c [DIR] [--ratio R] | icons [DIR] [--width W] [--max-triangles N]; "
                       "[--outline-only] [--no-thin-fills] [--polygon-offset D] [--dump DIR]\n");
  return 2;
}
