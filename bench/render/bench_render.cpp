// SPDX-License-Identifier: GPL-3.0-or-later
// bench_render: x8 magnification of a ~10k-triangle mesh over a 512x512 image to 4096x4096,
// against OpenCV's bicubic resize of the 512x512 raster in the same run (time, peak memory,
// ratio), a x8 crop of both side by side as a PNG, and the metrics oracle check.
// What each timed row includes: bicubic = cv::resize of the 8-bit RGB raster already in
// memory into a new 8-bit RGB image (allocation included); sdvi = Render / Render8 of the
// Image already in memory (subdivision, limit, scan conversion, allocation of the float or
// 8-bit RGBA output). File reading and writing are excluded on both sides; the PNG section
// times the encoding of each output in memory (ours: EncodePng, OpenCV: cv::imencode).
//
//   bench_render [--image PNG] [--sdvi FILE] [--out DIR] [--grid N] [--scale S] [--repeat K]
//                [--reference IMG] [--oracle DIR] [--pairs N [--threads T]]
//   (--pairs N: only bicubic and Render8 at the automatic level, N times in turn, the
//   median ratio pair by pair: for a shared machine; --threads: Render8's, 0 = all)
//   (--oracle DIR holds camera.png and camera_noisy_seed5_sigma20.png; --reference is the
//   truth at the output size, e.g. the photo --image was downscaled from: PSNR of bicubic
//   and of the render against it)
// Without --sdvi the mesh is a jittered grid over --image with colours sampled from it
// (timing only); with --sdvi (e.g. `sdvi vectorize lena_512.png -o lena.sdvi
// --max-triangles 10000`) it is a vectorized image and --image its source raster.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/raster_io.h"
#if defined(SDVI_BENCH_HAS_CODEC)
#include "sdvi/codec.h"
#endif
#include "sdvi/render.h"
#include "sdvi/subdiv.h"

using namespace sdvi;

namespace {

// Peak resident memory since the last ResetPeakMemory (Linux VmHWM), MiB.
void ResetPeakMemory() {
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
}
double PeakMemoryMiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return -1;
}
double CurrentMemoryMiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return -1;
}

// Process CPU time (all threads, user + system), seconds.
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Bilinear sample of an RGB(A)/grey raster at source point (x, y).
std::array<float, 3> Sample(const Raster& r, double x, double y) {
  x = std::clamp(x - 0.5, 0.0, r.width - 1.0), y = std::clamp(y - 0.5, 0.0, r.height - 1.0);
  const int x0 = std::min(int(x), r.width - 2), y0 = std::min(int(y), r.height - 2);
  const double fx = x - x0, fy = y - y0;
  std::array<float, 3> out{};
  for (int c = 0; c < 3; ++c) {
    const int ch = r.channels >= 3 ? c : 0;
    out[c] = float((1 - fy) * ((1 - fx) * r.at(x0, y0, ch) + fx * r.at(x0 + 1, y0, ch)) +
                   fy * ((1 - fx) * r.at(x0, y0 + 1, ch) + fx * r.at(x0 + 1, y0 + 1, ch)));
  }
  return out;
}

// A jittered n x n grid of vertices over the raster (2 (n-1)^2 triangles), colours sampled
// from it, with two crease polylines (a grid row and a grid column) as features.
Image GridMesh(const Raster& src, int n) {
  Image img;
  img.width = uint32_t(src.width), img.height = uint32_t(src.height);
  uint64_t s = 12345;
  auto rnd = [&s] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return double(s >> 11) / 9007199254740992.0 - 0.5;
  };
  const double dx = double(src.width) / (n - 1), dy = double(src.height) / (n - 1);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      double x = c * dx, y = r * dy;
      if (c > 0 && c < n - 1 && r > 0 && r < n - 1) x += 0.5 * dx * rnd(), y += 0.5 * dy * rnd();
      const auto col = Sample(src, x, y);
      img.vertices.push_back({float(x), float(y), col[0], col[1], col[2]});
    }
  auto id = [n](int c, int r) { return uint32_t(r * n + c); };
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const uint32_t a = id(c, r), b = id(c + 1, r), d = id(c, r + 1), e = id(c + 1, r + 1);
      if ((r + c) % 2) {
        img.triangles.push_back({{a, b, e}});
        img.triangles.push_back({{a, e, d}});
      } else {
        img.triangles.push_back({{a, b, d}});
        img.triangles.push_back({{b, e, d}});
      }
    }
  for (int k = 0; k + 1 < n; ++k) {
    img.crease_edges.push_back(Edge::Of(id(k, n / 2), id(k + 1, n / 2)));
    img.crease_edges.push_back(Edge::Of(id(n / 3, k), id(n / 3, k + 1)));
  }
  std::sort(img.crease_edges.begin(), img.crease_edges.end());
  img.crease_edges.erase(std::unique(img.crease_edges.begin(), img.crease_edges.end()), img.crease_edges.end());
  img.corners = {id(0, 0), id(n - 1, 0), id(0, n - 1), id(n - 1, n - 1)};
  std::sort(img.corners.begin(), img.corners.end());
  return img;
}

cv::Mat ToMat8(const Raster& r) {
  cv::Mat m(r.height, r.width, CV_8UC3);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x)
      for (int c = 0; c < 3; ++c)
        m.ptr<uint8_t>(y)[x * 3 + c] =
            uint8_t(std::lround(std::clamp(r.at(x, y, r.channels >= 3 ? c : 0), 0.0f, 255.0f)));
  return m;
}
Raster FromMat8(const cv::Mat& m) {
  Raster r(m.cols, m.rows, 3);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int c = 0; c < 3; ++c) r.at(x, y, c) = m.ptr<uint8_t>(y)[x * 3 + c];
  return r;
}

// A Raster of 8-bit samples (alpha back to 0..1).
Raster ToRaster(const Raster8& r) {
  Raster f(r.width, r.height, r.channels);
  for (size_t i = 0; i < r.data.size(); ++i)
    f.data[i] = r.has_alpha() && int(i % size_t(r.channels)) == r.channels - 1 ? r.data[i] / 255.0f : float(r.data[i]);
  return f;
}

int OracleCheck(const std::string& dir) {
  auto clean = LoadRaster(dir + "/camera.png");
  auto noisy = LoadRaster(dir + "/camera_noisy_seed5_sigma20.png");
  if (!clean.ok() || !noisy.ok()) {
    std::fprintf(stderr, "oracle: %s\n", (!clean.ok() ? clean.status() : noisy.status()).ToString().c_str());
    return 2;
  }
  auto m = CompareImages(*noisy, *clean);
  if (!m.ok()) return std::fprintf(stderr, "oracle: %s\n", m.status().ToString().c_str()), 2;
  const bool psnr_ok = std::abs(m->psnr - 22.4094) < 5e-5, mssim_ok = std::abs(m->mssim - 0.35796) < 5e-5;
  std::printf("metrics oracle (skimage test values)\n");
  std::printf("  PSNR   %.6f  expected 22.4094 (4 decimals)   %s\n", m->psnr, psnr_ok ? "ok" : "MISMATCH");
  std::printf("  MSSIM  %.6f  expected 0.35796 (Gaussian)     %s\n", m->mssim, mssim_ok ? "ok" : "MISMATCH");
  return psnr_ok && mssim_ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string image_path = "/work/shared/data/photos/lena_512.png", out_dir = "out/bench/render", oracle, sdvi_path,
              reference_path;
  int grid = 71, repeat = 3, pairs = 0, threads = 0;
  double scale = 8;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--image") image_path = v;
    else if (k == "--out") out_dir = v;
    else if (k == "--grid") grid = std::max(3, std::atoi(v.c_str()));
    else if (k == "--scale") scale = std::atof(v.c_str());
    else if (k == "--repeat") repeat = std::max(1, std::atoi(v.c_str()));
    else if (k == "--oracle") oracle = v;
    else if (k == "--sdvi") sdvi_path = v;
    else if (k == "--reference") reference_path = v;
    else if (k == "--pairs") pairs = std::max(1, std::atoi(v.c_str()));
    else if (k == "--threads") threads = std::max(0, std::atoi(v.c_str()));
    else return std::fprintf(stderr, "unknown option %s\n", k.c_str()), 1;
  }
  if (!oracle.empty()) return OracleCheck(oracle);

  auto src = LoadRaster(image_path);
  if (!src.ok()) return std::fprintf(stderr, "%s\n", src.status().ToString().c_str()), 2;
  Image mesh;
  if (sdvi_path.empty()) {
    mesh = GridMesh(*src, grid);
  } else {
#if defined(SDVI_BENCH_HAS_CODEC)
    auto loaded = ReadImage(sdvi_path);
    if (!loaded.ok()) return std::fprintf(stderr, "%s\n", loaded.status().ToString().c_str()), 2;
    mesh = std::move(*loaded);
#else
    return std::fprintf(stderr, "--sdvi: this build has no .sdvi reader (sdvi_codec)\n"), 2;
#endif
  }
  const cv::Mat src8 = ToMat8(*src);
  const int W = int(std::lround(src->width * scale)), H = int(std::lround(src->height * scale));
  std::printf("bench_render: %s%s %s %dx%d, mesh %zu vertices / %zu triangles, x%g -> %dx%d, %u hardware threads\n",
              sdvi_path.empty() ? "grid mesh over" : sdvi_path.c_str(), sdvi_path.empty() ? "" : " vectorized from",
              image_path.c_str(), src->width, src->height, mesh.vertices.size(), mesh.triangles.size(), scale, W, H,
              std::thread::hardware_concurrency());

  // --pairs N: only bicubic and Render8 at the automatic level, run in turn N times; the
  // ratio of each pair, so that a shared machine's drifting speed touches both sides of a
  // ratio alike. Prints the median and the range of the ratios and of each side's times.
  if (pairs > 0) {
    RenderOptions o;
    o.viewport = Viewport{W, H, scale, scale, 0, 0};
    o.threads = threads;
    std::vector<double> t_bic, t_ours, c_ours, ratio, c_ratio;
    for (int k = 0; k < pairs; ++k) {
      cv::Mat b;
      auto t0 = std::chrono::steady_clock::now();
      double c0 = CpuSeconds();
      cv::resize(src8, b, cv::Size(W, H), 0, 0, cv::INTER_CUBIC);
      const double tb = Seconds(t0), cb = CpuSeconds() - c0;
      b.release();
      t0 = std::chrono::steady_clock::now();
      c0 = CpuSeconds();
      auto r = Render8(mesh, o);
      const double to = Seconds(t0), co = CpuSeconds() - c0;
      if (!r.ok()) return std::fprintf(stderr, "%s\n", r.status().ToString().c_str()), 1;
      t_bic.push_back(tb), t_ours.push_back(to), c_ours.push_back(co), ratio.push_back(to / tb), c_ratio.push_back(co / cb);
    }
    auto row = [](const char* name, std::vector<double> v) {
      std::sort(v.begin(), v.end());
      std::printf("%-40s %9.3f %9.3f %9.3f\n", name, v[v.size() / 2], v.front(), v.back());
    };
    std::printf("\n%d pairs, in turn: bicubic then Render8 at the automatic level (%d), %d threads (0: all)\n%-40s %9s %9s %9s\n",
                pairs, ChooseRenderLevels(mesh, o), threads, "", "median", "min", "max");
    row("OpenCV bicubic wall s", t_bic);
    row("sdvi Render8 wall s", t_ours);
    row("sdvi Render8 cpu s", c_ours);
    row("Render8 / bicubic, wall, pair by pair", ratio);
    row("Render8 / bicubic, cpu, pair by pair", c_ratio);
    return 0;
  }

  // Bicubic reference: cv::resize of the 8-bit raster (best of `repeat`).
  cv::Mat bicubic;
  double t_bicubic = 1e30, c_bicubic = 1e30;
  ResetPeakMemory();
  const double base_bicubic = CurrentMemoryMiB();
  for (int k = 0; k < repeat; ++k) {
    bicubic.release();
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = CpuSeconds();
    cv::resize(src8, bicubic, cv::Size(W, H), 0, 0, cv::INTER_CUBIC);
    t_bicubic = std::min(t_bicubic, Seconds(t0));
    c_bicubic = std::min(c_bicubic, CpuSeconds() - c0);
  }
  const double mem_bicubic = PeakMemoryMiB() - base_bicubic;

  std::printf("\n%-36s %8s %8s %9s %9s %9s %14s\n", "method (best of repeat)", "wall s", "cpu s", "peak MiB",
              "wall/bic", "cpu/bic", "PSNR vs lvl 5");
  std::printf("%-36s %8.3f %8.3f %9.1f %9s %9s %14s\n", "OpenCV bicubic (8-bit RGB out)", t_bicubic, c_bicubic,
              mem_bicubic, "1.00", "1.00", "-");
  Raster ours, finest;  // finest: the level-5 render, closest to the limit surface
  for (int levels : {5, 4, 3, 2, -1}) {
    RenderOptions o;
    o.viewport = Viewport{W, H, scale, scale, 0, 0};
    o.levels = levels;
    double best = 1e30, best_cpu = 1e30;
    ResetPeakMemory();
    const double base = CurrentMemoryMiB();
    StatusOr<Raster> r = Status(StatusCode::kInternal, "not run");
    for (int k = 0; k < repeat; ++k) {
      r = Raster();  // release the previous output first
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = CpuSeconds();
      r = Render(mesh, o);
      best = std::min(best, Seconds(t0));
      best_cpu = std::min(best_cpu, CpuSeconds() - c0);
      if (!r.ok()) break;
    }
    const double mem = PeakMemoryMiB() - base;
    char name[64];
    std::snprintf(name, sizeof name, "sdvi Render (float RGBA out) %s%d", levels < 0 ? "auto=" : "level ",
                  levels < 0 ? std::min(ChooseRenderLevels(mesh, o), kMaxLevels) : levels);
    if (!r.ok()) {
      std::printf("%-36s %s\n", name, r.status().ToString().c_str());
      continue;
    }
    std::string vs_finest = "reference";
    if (!finest.empty()) {
      auto m = CompareImages(*r, finest);
      vs_finest = !m.ok() ? m.status().ToString() : std::isinf(m->psnr) ? "identical" : std::to_string(m->psnr);
    }
    std::printf("%-36s %8.3f %8.3f %9.1f %9.2f %9.2f %14s\n", name, best, best_cpu, mem, best / t_bicubic,
                best_cpu / c_bicubic, vs_finest.c_str());
    if (levels == -1) ours = std::move(*r);
    else if (finest.empty()) finest = std::move(*r);
  }
  // The 8-bit path (Render8, what `sdvi render` uses for 8-bit PNG), with its byte check
  // against the float render quantised as the PNG writer does.
  Raster8 ours8;
  double t_ours8 = 0;
  Raster finest8 = finest;  // the level-5 render as its 8-bit PNG holds it
  RoundTo8Bit(finest8);
  for (int levels : {3, 4, -1}) {
    RenderOptions o;
    o.viewport = Viewport{W, H, scale, scale, 0, 0};
    o.levels = levels;
    double best = 1e30, best_cpu = 1e30;
    ResetPeakMemory();
    const double base = CurrentMemoryMiB();
    StatusOr<Raster8> r = Status(StatusCode::kInternal, "not run");
    for (int k = 0; k < repeat; ++k) {
      r = Raster8();
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = CpuSeconds();
      r = Render8(mesh, o);
      best = std::min(best, Seconds(t0));
      best_cpu = std::min(best_cpu, CpuSeconds() - c0);
      if (!r.ok()) break;
    }
    const double mem = PeakMemoryMiB() - base;
    char name[64];
    std::snprintf(name, sizeof name, "sdvi Render8 (8-bit RGBA out) %s%d", levels < 0 ? "auto=" : "level ",
                  levels < 0 ? std::min(ChooseRenderLevels(mesh, o), kMaxLevels) : levels);
    if (!r.ok()) {
      std::printf("%-36s %s\n", name, r.status().ToString().c_str());
      continue;
    }
    std::string vs_finest = "-";
    if (!finest8.empty()) {
      auto m = CompareImages(ToRaster(*r), finest8);
      vs_finest = !m.ok() ? m.status().ToString() : std::isinf(m->psnr) ? "identical" : std::to_string(m->psnr);
    }
    std::printf("%-36s %8.3f %8.3f %9.1f %9.2f %9.2f %14s\n", name, best, best_cpu, mem, best / t_bicubic,
                best_cpu / c_bicubic, vs_finest.c_str());
    if (levels == -1) {
      ours8 = std::move(*r);
      t_ours8 = best;
    }
  }
  std::printf("(Render8 rows: PSNR against the level-5 render rounded to 8 bits, as its PNG holds it)\n");
  finest8 = Raster();
  finest = Raster();

  // Where the time goes: refinement (RefineImage) and scan conversion (RenderFineMesh).
  std::printf("\n%-10s %12s %12s %12s %12s %12s\n", "level", "fine tris", "refine s", "refine cpu", "scan s", "scan cpu");
  for (int levels : {2, 3, 4}) {
    LimitSurfaceOptions lso;
    lso.levels = levels;
    auto t0 = std::chrono::steady_clock::now();
    double c0 = CpuSeconds();
    auto fine = RefineImage(mesh, lso);
    const double t_refine = Seconds(t0), c_refine = CpuSeconds() - c0;
    if (!fine.ok()) continue;
    t0 = std::chrono::steady_clock::now();
    c0 = CpuSeconds();
    const std::vector<Edge> boundary = MeshBoundaryEdges(fine->triangles, &fine->vertex_tags);
    Raster r = RenderFineMesh(fine->triangles, fine->vertices, Viewport{W, H, scale, scale, 0, 0}, &boundary);
    const double t_scan = Seconds(t0), c_scan = CpuSeconds() - c0;
    std::printf("%-10d %12zu %12.3f %12.3f %12.3f %12.3f\n", levels, fine->triangles.size(), t_refine, c_refine,
                t_scan, c_scan);
  }

  // The PNG of each output, encoded in memory (writing the file excluded on both sides):
  // ours through EncodePng (libpng, rows filtered Up, zlib runs), OpenCV's through
  // cv::imencode with its defaults.
  if (!ours8.empty()) {
    double t_ours_png = 1e30, t_cv_png = 1e30;
    size_t ours_bytes = 0, cv_bytes = 0;
    const Raster8 needed = WithNeededChannels(ours8);
    for (int k = 0; k < repeat; ++k) {
      auto t0 = std::chrono::steady_clock::now();
      auto png = EncodePng(needed);
      t_ours_png = std::min(t_ours_png, Seconds(t0));
      ours_bytes = png.ok() ? png->size() : 0;
      std::vector<uint8_t> cv_png;
      t0 = std::chrono::steady_clock::now();
      cv::imencode(".png", bicubic, cv_png);
      t_cv_png = std::min(t_cv_png, Seconds(t0));
      cv_bytes = cv_png.size();
    }
    std::printf("\nPNG in memory (best of %d; file write excluded on both sides)\n", repeat);
    std::printf("%-44s %8s %12s\n", "", "wall s", "bytes");
    std::printf("%-44s %8.3f %12zu\n", "sdvi EncodePng (libpng, Up, zlib RLE)", t_ours_png, ours_bytes);
    std::printf("%-44s %8.3f %12zu\n", "OpenCV cv::imencode .png (its defaults)", t_cv_png, cv_bytes);
    std::printf("render + PNG: sdvi %.3f s, bicubic %.3f s, ratio %.2f\n", t_ours8 + t_ours_png,
                t_bicubic + t_cv_png, (t_ours8 + t_ours_png) / (t_bicubic + t_cv_png));
  }

  // Quality against the truth at the output size (e.g. the photo --image was downscaled
  // from): bicubic and the default-level renders, 8-bit and float.
  if (!reference_path.empty()) {
    auto truth = LoadRaster(reference_path);
    if (!truth.ok()) return std::fprintf(stderr, "%s\n", truth.status().ToString().c_str()), 2;
    auto line = [&](const char* name, const Raster& r) {
      auto m = CompareImages(r, *truth);
      if (!m.ok()) return (void)std::printf("%-40s %s\n", name, m.status().ToString().c_str());
      std::printf("%-40s %10.3f %10.4f\n", name, m->psnr, m->mssim);
    };
    std::printf("\nagainst %s\n%-40s %10s %10s\n", reference_path.c_str(), "method", "PSNR dB", "MSSIM");
    line("OpenCV bicubic", FromMat8(bicubic));
    if (!ours8.empty()) line("sdvi Render8, default level", ToRaster(ours8));
    if (!ours.empty()) line("sdvi Render (float), default level", ours);
  }

  // Region rendering: a 512x512 crop of the x8 output, at the automatic level (which may
  // be finer than the full render's: the fine-triangle budget applies to the region).
  {
    RenderOptions o;
    o.viewport = Viewport{512, 512, scale, scale, 1800 / scale, 1800 / scale};
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = CpuSeconds();
    auto r = Render(mesh, o);
    std::printf("\n512x512 region of the x%g output, level %d: wall %.3f s, cpu %.3f s, %zu of %zu control triangles\n",
                scale, ChooseRenderLevels(mesh, o), Seconds(t0), CpuSeconds() - c0,
                ControlTrianglesInViewport(mesh, o.viewport, 2).size(), mesh.triangles.size());
  }

  // A x8 crop of ours next to bicubic.
  std::filesystem::create_directories(out_dir);
  if (!ours.empty()) {
    const int cx = std::min(W - 512, int(1800)), cy = std::min(H - 512, int(1800));
    const int cw = std::min(512, W), ch = std::min(512, H);
    const cv::Mat ours8 = ToMat8(ours);
    cv::Mat side(ch, 2 * cw + 8, CV_8UC3, cv::Scalar(255, 255, 255));
    ours8(cv::Rect(std::max(0, cx), std::max(0, cy), cw, ch)).copyTo(side(cv::Rect(0, 0, cw, ch)));
    bicubic(cv::Rect(std::max(0, cx), std::max(0, cy), cw, ch)).copyTo(side(cv::Rect(cw + 8, 0, cw, ch)));
    const std::string path = out_dir + "/x8_crop_sdvi_left_bicubic_right.png";
    const Status s = SaveRasterPng(path, FromMat8(side));
    std::printf("\ncrop (ours left, bicubic right): %s %s\n", path.c_str(), s.ok() ? "" : s.ToString().c_str());
    // Agreement with bicubic over the whole output, for scale.
    auto m = CompareImages(ours, FromMat8(bicubic));
    if (m.ok()) std::printf("ours vs bicubic at x%g: PSNR %.2f dB, MSSIM %.4f\n", scale, m->psnr, m->mssim);
  }
  return 0;
}
