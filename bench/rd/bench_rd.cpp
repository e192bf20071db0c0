// SPDX-License-Identifier: GPL-3.0-or-later
// bench_rd: the whole chain's rate-distortion against JPEG, WebP, AVIF and JPEG XL.
//
// For every image in --data/photos and --data/graphics and every budget (pixels per
// vertex, default 10 25 50 100 200): vectorize, write sdvi's smallest file (what
// `sdvi vectorize --compress` writes), decode it, render it at x1 and measure its PSNR;
// then search each codec's quality setting (bisection, memoised) for the smallest file
// that reaches the same PSNR: cjpeg -optimize -sample 2x2 (4:2:0), cwebp -m 6,
// avifenc (--min = --max quantizer, speed 6), cjxl (-q, effort 7).
//
// Metric (one for every codec): PSNR over all pixels of the premultiplied colour (R, G, B
// times alpha, 8-bit units) and, for images with alpha, the alpha channel (times 255), i.e.
// premultiplied RGBA over all pixels. Grey images count as R = G = B. JPEG has no alpha: an
// image with alpha is coded as its premultiplied colour plus its alpha as a greyscale JPEG at
// the same quality, and the two files' bytes are summed; WebP codes alpha at -alpha_q = q,
// AVIF at the colour's quantizer, JPEG XL at its default.
//
// BD-rate (Bjontegaard delta rate, PSNR-rate): the mean difference of log(bytes) between
// two RD curves over the PSNR interval both cover, each curve interpolated piecewise
// linearly in (PSNR, log bytes) (the piecewise variant of Bjontegaard's cubic fit: no
// overshoot with 5 points). sdvi's curve: its points at the budgets; a codec's curve: every
// point its searches measured (upper convex hull). Positive = sdvi needs more bytes.
//
// Timing: decode + x1 render of the sdvi file at the 50 ppv budget (best of 3, in
// process) against the decoders (djpeg, dwebp, avifdec, djxl; best of 3, process
// start included) on each codec's file at the same PSNR.
//
//   bench_rd [--data DIR] [--out DIR] [--only SUBSTRING] [--class photos|graphics] [--budgets 10,25,50,100,200]
//            [--threads N] [--baseline] [--variants v1,rd,rd0,rd11,rd13,rd14,rd15] [--codecs jpeg,webp,avif,jxl] [--no-plots] [--parts]
//
// sdvi files per budget (one vectorization): v1 = Draco at the steps v1 `vectorize --compress`
// used (1% of the fit's MSE; container params recorded, as v1 wrote them), rd = what `vectorize --compress` writes now (CompressForRate,
// sdvi/rate.h), rd0 = the same RD search without the colour refit (RateOptions::refit_colors
// false: colours fitted on the float positions, then quantised; the A/B of spec/RATE.md 3).
// rd11 = rd as payload 1.1 codes it (crease edges first, no neighbour-mean colours:
// RateOptions::features_first and neighbour_mean false; the A/B of spec/RATE.md 5).
// rd13 = rd without positions in the tag stream (payload 1.3 at most: RateOptions::stream_positions
// false; the A/B of spec/RATE.md 7). rd14 = rd without colours in the tag stream (payload 1.4 at
// most: RateOptions::stream_colors false; the A/B of spec/RATE.md 8). rd15 = rd without a grey
// image's colour in the tag stream (payload 1.5 at most: RateOptions::stream_grey_colors false;
// the A/B of spec/RATE.md 9).
// --variants picks them (default v1,rd); --baseline = --variants v1 (the BEFORE table). With
// several variants each is also compared with the first (BD-rate sdvi against sdvi).
// --codecs limits the codecs searched (the others print '-'; the searches dominate the time).
// --parts: each sdvi file's bytes by part (MeasureParts) under its row.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/rate.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/vectorize.h"
#include "codec_bench.h"

namespace fs = std::filesystem;
using namespace sdvi::bench;
constexpr size_t kMaxVariants = 3;

namespace {


// ---- the metric ------------------------------------------------------------------------

// An image as premultiplied planes over all pixels: R, G, B (times alpha) and, when the
// source has alpha, A (times 255). 8-bit units.
struct Planes {
  int width = 0, height = 0, count = 3;
  std::vector<double> v;  // pixel-major, count values a pixel
};

Planes Premultiplied(const sdvi::Raster& r, bool with_alpha) {
  Planes p;
  p.width = r.width;
  p.height = r.height;
  p.count = with_alpha ? 4 : 3;
  p.v.resize(size_t(r.width) * r.height * p.count);
  for (int y = 0; y < r.height; ++y) {
    for (int x = 0; x < r.width; ++x) {
      const bool grey = r.channels <= 2;
      const double a = r.has_alpha() ? std::clamp(double(r.at(x, y, r.channels - 1)), 0.0, 1.0) : 1.0;
      double* out = &p.v[(size_t(y) * r.width + x) * p.count];
      for (int c = 0; c < 3; ++c) {
        const double value = std::clamp(double(r.at(x, y, grey ? 0 : c)), 0.0, 255.0);
        out[c] = value * a;
      }
      if (with_alpha) out[3] = 255.0 * a;
    }
  }
  return p;
}

double Psnr(const Planes& a, const Planes& b) {
  if (a.v.size() != b.v.size() || a.v.empty()) return std::nan("");
  double sum = 0;
  for (size_t i = 0; i < a.v.size(); ++i) sum += (a.v[i] - b.v[i]) * (a.v[i] - b.v[i]);
  const double mse = sum / double(a.v.size());
  return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0;
}


// The premultiplied colour (grey or BGR) and the alpha (grey) of planes as 8-bit mats.
cv::Mat ColorMat(const Planes& p, bool grey) {
  cv::Mat m(p.height, p.width, grey ? CV_8UC1 : CV_8UC3);
  for (int y = 0; y < p.height; ++y) {
    uint8_t* row = m.ptr<uint8_t>(y);
    for (int x = 0; x < p.width; ++x) {
      const double* v = &p.v[(size_t(y) * p.width + x) * p.count];
      auto q = [](double d) { return static_cast<uint8_t>(std::clamp(std::lround(d), 0L, 255L)); };
      if (grey) {
        row[x] = q(v[0]);
      } else {
        row[3 * x + 0] = q(v[2]);
        row[3 * x + 1] = q(v[1]);
        row[3 * x + 2] = q(v[0]);
      }
    }
  }
  return m;
}

cv::Mat AlphaMat(const Planes& p) {
  cv::Mat m(p.height, p.width, CV_8UC1);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      m.at<uint8_t>(y, x) = static_cast<uint8_t>(std::lround(p.v[(size_t(y) * p.width + x) * p.count + 3]));
  return m;
}

// ---- external codecs -------------------------------------------------------------------

struct Point {
  int quality = 0;
  double bytes = 0, psnr = 0;
};

// One codec on one image: encode at an integer quality k in [lo, hi] (PSNR rises with k),
// decode, measure. Memoised.
class ExternalCodec {
 public:
  std::string name;
  int lo = 0, hi = 100;
  std::function<bool(int, double* bytes)> encode;   // writes the coded file(s)
  std::function<std::optional<sdvi::Raster>()> decode;  // reads them back
  std::string decode_command;                        // for timing
  const Planes* reference = nullptr;
  bool with_alpha = false;

  std::optional<Point> At(int k) {
    if (auto it = memo_.find(k); it != memo_.end()) return it->second;
    std::optional<Point> p;
    double bytes = 0;
    if (encode(k, &bytes)) {
      if (auto r = decode()) p = Point{k, bytes, Psnr(Premultiplied(*r, with_alpha), *reference)};
    }
    memo_[k] = p;
    return p;
  }

  // The smallest quality whose PSNR reaches target; the top quality's point (flagged
  // unreached) when none does.
  std::optional<Point> Search(double target, bool* reached) {
    auto top = At(hi);
    if (!top) return std::nullopt;
    *reached = top->psnr >= target;
    if (!*reached) return top;
    auto bottom = At(lo);
    if (bottom && bottom->psnr >= target) return bottom;
    int a = lo, b = hi;
    Point at_b = *top;
    while (b - a > 1) {
      const int mid = (a + b) / 2;
      auto p = At(mid);  // a setting the encoder refuses counts as too low
      if (p && p->psnr >= target) {
        b = mid;
        at_b = *p;
      } else {
        a = mid;
      }
    }
    // Re-encode at b so the file on disk is the chosen one (for timing).
    double bytes = 0;
    encode(b, &bytes);
    return at_b;
  }

  std::vector<Point> Measured() const {
    std::vector<Point> out;
    for (const auto& [k, p] : memo_)
      if (p) out.push_back(*p);
    return out;
  }

 private:
  std::map<int, std::optional<Point>> memo_;
};

double FileBytes(const std::string& path) {
  std::error_code ec;
  const auto n = fs::file_size(path, ec);
  return ec ? 0 : double(n);
}

std::optional<sdvi::Raster> ReadDecoded(const std::string& path) {
  cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) return std::nullopt;
  return FromMat(m);
}

std::vector<ExternalCodec> PrepareCodecs(const Planes& reference, bool grey, bool with_alpha,
                                         const fs::path& work) {
  // Inputs: premultiplied colour as PPM/PGM (+ alpha PGM) for cjpeg; straight RGBA PNG of the
  // same premultiplied values for the others (alpha-weighted colour is what the metric sees).
  const std::string ppm = (work / (grey ? "in.pgm" : "in.ppm")).string();
  cv::imwrite(ppm, ColorMat(reference, grey));
  const std::string alpha_pgm = (work / "alpha.pgm").string();
  const std::string png = (work / "in.png").string();
  if (with_alpha) {
    cv::imwrite(alpha_pgm, AlphaMat(reference));
    // Straight colour = premultiplied / alpha where alpha > 0.
    cv::Mat bgra(reference.height, reference.width, CV_8UC4);
    for (int y = 0; y < reference.height; ++y) {
      for (int x = 0; x < reference.width; ++x) {
        const double* v = &reference.v[(size_t(y) * reference.width + x) * reference.count];
        const double a = v[3] / 255.0;
        auto q = [&](double d) {
          return static_cast<uint8_t>(std::clamp(std::lround(a > 0 ? d / a : 0.0), 0L, 255L));
        };
        bgra.at<cv::Vec4b>(y, x) = {q(v[2]), q(v[1]), q(v[0]), static_cast<uint8_t>(std::lround(v[3]))};
      }
    }
    cv::imwrite(png, bgra);
  } else {
    cv::imwrite(png, ColorMat(reference, grey));
  }
  std::vector<ExternalCodec> codecs(4);
  for (auto& c : codecs) {
    c.reference = &reference;
    c.with_alpha = with_alpha;
  }
  const std::string q_png = ShellQuote(png);

  ExternalCodec& jpeg = codecs[0];
  jpeg.name = "jpeg";
  jpeg.lo = 1;
  jpeg.hi = 100;
  const std::string jpg = (work / "out.jpg").string(), ajpg = (work / "alpha.jpg").string();
  const std::string jdec = (work / (grey ? "jdec.pgm" : "jdec.ppm")).string(), adec = (work / "adec.pgm").string();
  jpeg.encode = [=](int q, double* bytes) {
    const std::string base = "cjpeg -quality " + std::to_string(q) + " -optimize -sample 2x2 -outfile ";
    if (!Run(base + ShellQuote(jpg) + " " + ShellQuote(ppm))) return false;
    *bytes = FileBytes(jpg);
    if (with_alpha) {
      if (!Run(base + ShellQuote(ajpg) + " " + ShellQuote(alpha_pgm))) return false;
      *bytes += FileBytes(ajpg);
    }
    return true;
  };
  jpeg.decode_command = "djpeg -outfile " + ShellQuote(jdec) + " " + ShellQuote(jpg) +
                        (with_alpha ? " && djpeg -outfile " + ShellQuote(adec) + " " + ShellQuote(ajpg) : "");
  jpeg.decode = [=, cmd = jpeg.decode_command]() -> std::optional<sdvi::Raster> {
    if (!Run(cmd)) return std::nullopt;
    auto colour = ReadDecoded(jdec);
    if (!colour || !with_alpha) return colour;
    // Premultiplied colour + alpha -> straight RGBA raster for the metric.
    auto alpha = ReadDecoded(adec);
    if (!alpha) return std::nullopt;
    sdvi::Raster r(colour->width, colour->height, 4);
    for (int y = 0; y < r.height; ++y) {
      for (int x = 0; x < r.width; ++x) {
        const float a = alpha->at(x, y, 0) / 255.f;
        for (int c = 0; c < 3; ++c) {
          const float v = colour->at(x, y, colour->channels <= 2 ? 0 : c);
          r.at(x, y, c) = a > 0 ? std::min(255.f, v / a) : 0.f;
        }
        r.at(x, y, 3) = a;
      }
    }
    return r;
  };

  ExternalCodec& webp = codecs[1];
  webp.name = "webp";
  webp.lo = 0;
  webp.hi = 100;
  const std::string wfile = (work / "out.webp").string(), wdec = (work / "wdec.png").string();
  webp.encode = [=](int q, double* bytes) {
    if (!Run("cwebp -quiet -m 6 -q " + std::to_string(q) + " -alpha_q " + std::to_string(q) + " " + q_png +
             " -o " + ShellQuote(wfile)))
      return false;
    *bytes = FileBytes(wfile);
    return true;
  };
  webp.decode_command = "dwebp -quiet " + ShellQuote(wfile) + " -o " + ShellQuote(wdec);
  webp.decode = [=, cmd = webp.decode_command]() -> std::optional<sdvi::Raster> {
    if (!Run(cmd)) return std::nullopt;
    return ReadDecoded(wdec);
  };

  ExternalCodec& avif = codecs[2];
  avif.name = "avif";
  avif.lo = 0;  // quantizer 63 - k
  avif.hi = 63;
  const std::string afile = (work / "out.avif").string(), adec2 = (work / "avdec.png").string();
  avif.encode = [=](int k, double* bytes) {
    const std::string q = std::to_string(63 - k);
    if (!Run("avifenc -s 6 -j 1 --min " + q + " --max " + q + " --minalpha " + q + " --maxalpha " + q + " " +
             q_png + " " + ShellQuote(afile)))
      return false;
    *bytes = FileBytes(afile);
    return true;
  };
  avif.decode_command = "avifdec -j 1 --depth 8 " + ShellQuote(afile) + " " + ShellQuote(adec2);
  avif.decode = [=, cmd = avif.decode_command]() -> std::optional<sdvi::Raster> {
    if (!Run(cmd)) return std::nullopt;
    return ReadDecoded(adec2);
  };

  ExternalCodec& jxl = codecs[3];
  jxl.name = "jxl";
  jxl.lo = 1;
  jxl.hi = 99;  // 100 is lossless
  const std::string xfile = (work / "out.jxl").string(), xdec = (work / "xdec.png").string();
  jxl.encode = [=](int q, double* bytes) {
    if (!Run("cjxl --quiet -e 7 -q " + std::to_string(q) + " " + q_png + " " + ShellQuote(xfile))) return false;
    *bytes = FileBytes(xfile);
    return true;
  };
  jxl.decode_command = "djxl --quiet --bits_per_sample=8 " + ShellQuote(xfile) + " " + ShellQuote(xdec);
  jxl.decode = [=, cmd = jxl.decode_command]() -> std::optional<sdvi::Raster> {
    if (!Run(cmd)) return std::nullopt;
    return ReadDecoded(xdec);
  };
  return codecs;
}

// ---- sdvi ------------------------------------------------------------------------------

struct SdviPoint {
  double ppv = 0;
  uint32_t vertices = 0;
  double bytes = 0, psnr = 0, fit_psnr = 0, vectorize_s = 0;
  std::vector<uint8_t> file;
};

sdvi::StatusOr<sdvi::Raster> RenderX1(const sdvi::Image& image, int threads) {
  sdvi::RenderOptions options;
  options.viewport = sdvi::Viewport::Identity(int(image.width), int(image.height));
  options.threads = threads;
  return sdvi::Render(image, options);
}

// One vectorization at a budget and the files made from it, one per variant: v1 (the file v1
// `vectorize --compress` wrote: Draco at the conservative steps from a 1% MSE budget), rd
// (CompressForRate: what `vectorize --compress` writes now), rd0 (rd without the refit).
sdvi::StatusOr<std::vector<SdviPoint>> RunSdvi(const sdvi::Raster& raster, const Planes& reference, double ppv,
                                               int threads, const std::vector<std::string>& variants) {
  sdvi::VectorizeOptions options;
  options.compression_ratio = ppv;
  options.threads = threads;
  options.fit.threads = threads;
  const auto start = Clock::now();
  SDVI_ASSIGN_OR_RETURN(sdvi::VectorizeResult result, sdvi::Vectorize(raster, nullptr, options));
  const double vectorize_s = Seconds(start);
  std::vector<SdviPoint> out;
  for (const std::string& variant : variants) {
    SdviPoint p;
    p.ppv = ppv;
    p.vertices = uint32_t(result.image.vertices.size());
    p.fit_psnr = result.report.fit_psnr;
    const auto t0 = Clock::now();
    if (variant == "v1") {
      sdvi::CompressOptions compress;
      compress.reference_mse = 255.0 * 255.0 / std::pow(10.0, result.report.fit_psnr / 10.0);
      compress.container_params = true;  // as v1 wrote them
      SDVI_ASSIGN_OR_RETURN(p.file, sdvi::EncodeImage(result.image, &compress));
    } else {
      sdvi::RateOptions rate;
      rate.threads = threads;
      rate.refit_colors = variant != "rd0";
      rate.features_first = rate.neighbour_mean = variant != "rd11";
      rate.stream_positions = variant != "rd11" && variant != "rd13";
      rate.stream_colors = rate.stream_positions && variant != "rd14";
      rate.stream_grey_colors = variant != "rd15";
      SDVI_ASSIGN_OR_RETURN(sdvi::RateResult r, sdvi::CompressForRate(result, raster, nullptr, options.fit, rate));
      p.file = std::move(r.file);
    }
    p.vectorize_s = vectorize_s + Seconds(t0);
    p.bytes = double(p.file.size());
    SDVI_ASSIGN_OR_RETURN(sdvi::Image decoded, sdvi::DecodeImage(p.file, "bench"));
    SDVI_ASSIGN_OR_RETURN(sdvi::Raster render, RenderX1(decoded, threads));
    p.psnr = Psnr(Premultiplied(render, reference.count == 4), reference);
    out.push_back(std::move(p));
  }
  return out;
}

// ---- BD-rate ---------------------------------------------------------------------------

// The lower-rate envelope of points as (psnr, log bytes), psnr strictly increasing and
// rate increasing (points that a cheaper point dominates are dropped).
std::vector<std::pair<double, double>> Envelope(std::vector<Point> points) {
  std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.bytes < b.bytes; });
  std::vector<std::pair<double, double>> out;
  for (const Point& p : points) {
    if (!(p.bytes > 0) || !std::isfinite(p.psnr)) continue;
    if (!out.empty() && p.psnr <= out.back().first) continue;
    out.push_back({p.psnr, std::log(p.bytes)});
  }
  return out;
}

double Interpolate(const std::vector<std::pair<double, double>>& c, double psnr) {
  for (size_t i = 1; i < c.size(); ++i) {
    if (psnr <= c[i].first) {
      const double t = (psnr - c[i - 1].first) / (c[i].first - c[i - 1].first);
      return c[i - 1].second + t * (c[i].second - c[i - 1].second);
    }
  }
  return c.back().second;
}

// BD-rate of a against b in percent (NaN when the PSNR ranges do not overlap).
double BdRate(const std::vector<Point>& a, const std::vector<Point>& b) {
  const auto ca = Envelope(a), cb = Envelope(b);
  if (ca.size() < 2 || cb.size() < 2) return std::nan("");
  const double lo = std::max(ca.front().first, cb.front().first);
  const double hi = std::min(ca.back().first, cb.back().first);
  if (!(hi > lo)) return std::nan("");
  const int steps = 200;
  double sum = 0;
  for (int i = 0; i <= steps; ++i) {
    const double p = lo + (hi - lo) * i / steps;
    const double w = (i == 0 || i == steps) ? 0.5 : 1.0;
    sum += w * (Interpolate(ca, p) - Interpolate(cb, p));
  }
  return 100.0 * (std::exp(sum / steps) - 1.0);
}

// ---- plot ------------------------------------------------------------------------------



double BestOf3(const std::function<bool()>& f) {
  double best = 1e300;
  for (int i = 0; i < 3; ++i) {
    const auto t0 = Clock::now();
    if (!f()) return std::nan("");
    best = std::min(best, Seconds(t0));
  }
  return 1000 * best;
}

}  // namespace

int main(int argc, char** argv) {
  fs::path data = "/work/shared/data", out = "out/rd";
  std::string only, only_class;
  std::vector<double> budgets = {10, 25, 50, 100, 200};
  int threads = 2;
  bool plots = true, parts = false;
  std::vector<std::string> variants = {"v1", "rd"};
  const char* names[4] = {"jpeg", "webp", "avif", "jxl"};
  bool searched[4] = {true, true, true, true};
  auto split = [](const std::string& list) {
    std::vector<std::string> items;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');) items.push_back(item);
    return items;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_rd: %s needs a value\n", a.c_str());
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--data") data = next();
    else if (a == "--out") out = next();
    else if (a == "--only") only = next();
    else if (a == "--class") only_class = next();
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--baseline") variants = {"v1"};
    else if (a == "--variants") {
      variants = split(next());
      if (variants.empty() || variants.size() > kMaxVariants) variants = {"?"};
      for (const std::string& v : variants) {
        if (v != "v1" && v != "rd" && v != "rd0" && v != "rd11" && v != "rd13" && v != "rd14" &&
            v != "rd15") {
          std::fprintf(stderr, "bench_rd: --variants takes 1-%zu of v1, rd, rd0, rd11, rd13, rd14, rd15\n", kMaxVariants);
          return 1;
        }
      }
    } else if (a == "--codecs") {
      std::fill(searched, searched + 4, false);
      for (const std::string& c : split(next())) {
        const auto* it = std::find_if(names, names + 4, [&](const char* n) { return c == n; });
        if (it == names + 4) {
          std::fprintf(stderr, "bench_rd: --codecs takes jpeg, webp, avif, jxl\n");
          return 1;
        }
        searched[it - names] = true;
      }
    }
    else if (a == "--no-plots") plots = false;
    else if (a == "--parts") parts = true;
    else if (a == "--budgets") {
      budgets.clear();
      for (const std::string& item : split(next())) budgets.push_back(std::atof(item.c_str()));
    } else {
      std::fprintf(stderr,
                   "usage: bench_rd [--data DIR] [--out DIR] [--only SUBSTRING] [--class photos|graphics] [--budgets 10,25,50,100,200] "
                   "[--threads N] [--baseline] [--variants v1,rd,rd0,rd11,rd13,rd14,rd15] [--codecs jpeg,webp,avif,jxl] [--no-plots] [--parts]\n");
      return 1;
    }
  }
  for (const char* tool : {"cjpeg", "djpeg", "cwebp", "dwebp", "avifenc", "avifdec", "cjxl", "djxl"}) {
    if (!Run(std::string("command -v ") + tool)) {
      std::fprintf(stderr,
                   "bench_rd: needs %s (libjpeg-turbo-progs, webp, libavif-bin, libjxl-tools)\n", tool);
      return 2;
    }
  }
  fs::create_directories(out);
  const fs::path work = out / ("work_" + (only_class.empty() ? std::string("all") : only_class));
  fs::create_directories(work);
  const size_t nv = variants.size();
  std::printf("sdvi files: v1 = Draco at the v1 `vectorize --compress` steps (1%% of the fit's MSE); rd = "
              "`vectorize --compress` now (CompressForRate: RD-chosen steps, colours refitted); rd0 = rd without "
              "the refit; rd11 = rd in payload 1.1 (crease edges before the feature layer, no neighbour-mean colours); rd13 = rd without positions in the tag stream (payload 1.3); rd14 = rd without colours in the tag stream (payload 1.4); rd15 = rd without a grey image's colour in the tag stream (payload 1.5). Here: %s.\n", [&] {
                std::string list;
                for (const std::string& v : variants) list += (list.empty() ? "" : ", ") + v;
                return list;
              }().c_str());
  std::printf("Metric: PSNR of premultiplied RGBA over all pixels (RGB for opaque images), sdvi rendered at x1.\n");
  std::printf("Each codec searched to the sdvi file's PSNR: bytes(quality setting), '>' = not reached at its top.\n\n");
  std::printf("%-8s %-30s %4s %-3s %6s %7s %6s %6s %7s | %15s %15s %15s %15s\n", "class", "image", "ppv", "sdv", "V",
              "bytes", "bpp", "PSNR", "fitPSNR", "jpeg", "webp", "avif", "jxl");

  struct ClassTally {
    std::vector<double> bd[kMaxVariants][4];
    std::vector<double> bd_first[kMaxVariants];  // each variant against the first
    std::vector<double> sdvi_ms, codec_ms[4];
  };
  std::map<std::string, ClassTally> tally;
  struct ImageRow {
    std::string kind, name;
    double bd[kMaxVariants][4];
    double bd_first[kMaxVariants];
  };
  std::vector<ImageRow> rows;

  for (const std::string kind : {"photos", "graphics"}) {
    if (!only_class.empty() && kind != only_class) continue;
    for (const fs::path& path : ListImages(data / kind)) {
      const std::string name = path.stem().string();
      if (!only.empty() && path.filename().string().find(only) == std::string::npos) continue;
      auto raster = sdvi::LoadRaster(path.string());
      if (!raster.ok()) {
        std::printf("%-8s %-30s load failed: %s\n", kind.c_str(), name.c_str(), raster.status().ToString().c_str());
        continue;
      }
      const bool with_alpha = raster->has_alpha();
      const bool grey = raster->channels <= 2;
      const Planes reference = Premultiplied(*raster, with_alpha);
      const double pixels = double(raster->width) * raster->height;
      std::vector<ExternalCodec> codecs = PrepareCodecs(reference, grey, with_alpha, work);
      std::vector<Point> sdvi_points[kMaxVariants];
      std::vector<std::pair<double, double>> sdvi_plot[kMaxVariants];
      double sdvi_ms = std::nan(""), codec_ms[4] = {std::nan(""), std::nan(""), std::nan(""), std::nan("")};
      for (double ppv : budgets) {
        auto points = RunSdvi(*raster, reference, ppv, threads, variants);
        if (!points.ok()) {
          std::printf("%-8s %-30s %4g failed: %s\n", kind.c_str(), name.c_str(), ppv,
                      points.status().ToString().c_str());
          std::fflush(stdout);
          continue;
        }
        for (size_t v = 0; v < nv; ++v) {
          const SdviPoint& s = (*points)[v];
          sdvi_points[v].push_back({0, s.bytes, s.psnr});
          sdvi_plot[v].push_back({8 * s.bytes / pixels, s.psnr});
          std::string cells[4];
          const bool timing = ppv == 50 && v + 1 == nv;
          if (timing) {
            const std::vector<uint8_t> file = s.file;
            sdvi_ms = BestOf3([&] {
              auto img = sdvi::DecodeImage(file, "bench");
              return img.ok() && RenderX1(*img, threads).ok();
            });
          }
          for (int c = 0; c < 4; ++c) {
            if (!searched[c]) {
              cells[c] = "-";
              continue;
            }
            bool reached = false;
            auto p = codecs[c].Search(s.psnr, &reached);
            char buf[48];
            if (!p) std::snprintf(buf, sizeof buf, "failed");
            else std::snprintf(buf, sizeof buf, "%s%.0f(%d)", reached ? "" : ">", p->bytes, p->quality);
            cells[c] = buf;
            if (timing && p) codec_ms[c] = BestOf3([&] { return Run(codecs[c].decode_command); });
          }
          std::printf("%-8s %-30s %4g %-3s %6u %7.0f %6.3f %6.2f %7.2f | %15s %15s %15s %15s\n", kind.c_str(),
                      name.c_str(), ppv, variants[v].c_str(), s.vertices, s.bytes, 8 * s.bytes / pixels, s.psnr,
                      s.fit_psnr, cells[0].c_str(), cells[1].c_str(), cells[2].c_str(), cells[3].c_str());
          if (parts) {
            auto p = sdvi::MeasureParts(s.file, name);
            if (p.ok())
              std::printf("  bytes by part: connectivity %llu, positions %llu, colours %llu, tags %llu, "
                          "feature layer %llu, container %llu\n",
                          (unsigned long long)p->connectivity, (unsigned long long)p->positions,
                          (unsigned long long)p->colors, (unsigned long long)p->tags,
                          (unsigned long long)p->feature_layer, (unsigned long long)p->container);
          }
          std::fflush(stdout);
        }
      }
      ImageRow row{kind, name, {}, {}};
      ClassTally& t = tally[kind];
      std::vector<Series> series;
      const cv::Scalar sdvi_colours[kMaxVariants] = {cv::Scalar(150, 150, 230), cv::Scalar(30, 30, 200),
                                                     cv::Scalar(90, 200, 230)};
      for (size_t v = 0; v < nv; ++v) series.push_back({"sdvi " + variants[v], sdvi_colours[v], sdvi_plot[v]});
      const cv::Scalar colours[4] = {cv::Scalar(200, 120, 30), cv::Scalar(40, 160, 40), cv::Scalar(160, 40, 160),
                                     cv::Scalar(30, 160, 200)};
      for (size_t v = 0; v < kMaxVariants; ++v) {
        row.bd_first[v] = v < nv ? BdRate(sdvi_points[v], sdvi_points[0]) : std::nan("");
        if (v > 0 && std::isfinite(row.bd_first[v])) t.bd_first[v].push_back(row.bd_first[v]);
      }
      for (int c = 0; c < 4; ++c) {
        if (!searched[c]) {
          for (size_t v = 0; v < kMaxVariants; ++v) row.bd[v][c] = std::nan("");
          continue;
        }
        const std::vector<Point> measured = codecs[c].Measured();
        for (size_t v = 0; v < kMaxVariants; ++v) {
          row.bd[v][c] = v < nv ? BdRate(sdvi_points[v], measured) : std::nan("");
          if (std::isfinite(row.bd[v][c])) t.bd[v][c].push_back(row.bd[v][c]);
        }
        if (std::isfinite(codec_ms[c])) t.codec_ms[c].push_back(codec_ms[c]);
        Series s{names[c], colours[c], {}};
        for (const auto& [psnr, logb] : Envelope(measured)) s.points.push_back({8 * std::exp(logb) / pixels, psnr});
        series.push_back(s);
      }
      if (std::isfinite(sdvi_ms)) t.sdvi_ms.push_back(sdvi_ms);
      rows.push_back(row);
      for (size_t v = 0; v < nv; ++v)  // at once, so that a partial run still says something
        std::printf("%-8s %-30s BD-rate sdvi %s vs jpeg %+.1f%%, webp %+.1f%%, avif %+.1f%%, jxl %+.1f%%\n",
                    kind.c_str(), name.c_str(), variants[v].c_str(), row.bd[v][0], row.bd[v][1], row.bd[v][2],
                    row.bd[v][3]);
      for (size_t v = 1; v < nv; ++v)
        std::printf("%-8s %-30s BD-rate sdvi %s vs sdvi %s %+.1f%%\n", kind.c_str(), name.c_str(),
                    variants[v].c_str(), variants[0].c_str(), row.bd_first[v]);
      std::fflush(stdout);
      if (plots && !sdvi_plot[0].empty()) {
        const std::string plot = (out / ("rd_" + kind + "_" + name + ".png")).string();
        DrawRdPlot(plot, "bpp vs PSNR (premultiplied RGBA): " + name, "bits per pixel", series);
      }
    }
  }

  auto fmt = [](double v) {
    char buf[16];
    if (std::isfinite(v)) std::snprintf(buf, sizeof buf, "%+.1f%%", v);
    else std::snprintf(buf, sizeof buf, "n/a");
    return std::string(buf);
  };
  auto mean = [](const std::vector<double>& v) {
    double sum = 0;
    for (double x : v) sum += x;
    return v.empty() ? std::nan("") : sum / double(v.size());
  };
  for (size_t v = 0; v < nv; ++v) {
    std::printf("\nBD-rate of sdvi %s against each codec (PSNR-rate; positive = sdvi needs more bytes)\n",
                variants[v].c_str());
    std::printf("%-8s %-30s %9s %9s %9s %9s\n", "class", "image", "jpeg", "webp", "avif", "jxl");
    for (const ImageRow& r : rows)
      std::printf("%-8s %-30s %9s %9s %9s %9s\n", r.kind.c_str(), r.name.c_str(), fmt(r.bd[v][0]).c_str(),
                  fmt(r.bd[v][1]).c_str(), fmt(r.bd[v][2]).c_str(), fmt(r.bd[v][3]).c_str());
    for (const auto& [kind, t] : tally)
      std::printf("%-8s %-30s %9s %9s %9s %9s   (arithmetic mean over %zu images)\n", kind.c_str(), "MEAN",
                  fmt(mean(t.bd[v][0])).c_str(), fmt(mean(t.bd[v][1])).c_str(), fmt(mean(t.bd[v][2])).c_str(),
                  fmt(mean(t.bd[v][3])).c_str(), t.bd[v][0].size());
  }
  for (size_t v = 1; v < nv; ++v) {
    std::printf("\nBD-rate of sdvi %s against sdvi %s (positive = %s needs more bytes)\n", variants[v].c_str(),
                variants[0].c_str(), variants[v].c_str());
    for (const ImageRow& r : rows)
      std::printf("%-8s %-30s %9s\n", r.kind.c_str(), r.name.c_str(), fmt(r.bd_first[v]).c_str());
    for (const auto& [kind, t] : tally)
      std::printf("%-8s %-30s %9s   (arithmetic mean over %zu images)\n", kind.c_str(), "MEAN",
                  fmt(mean(t.bd_first[v])).c_str(), t.bd_first[v].size());
  }
  std::printf("\nDecode + x1 render, ms (mean over the class at 50 ppv; sdvi in process with %d threads, "
              "codecs as processes, best of 3)\n",
              threads);
  std::printf("%-8s %9s %9s %9s %9s %9s\n", "class", "sdvi", "djpeg", "dwebp", "avifdec", "djxl");
  for (const auto& [kind, t] : tally)
    std::printf("%-8s %9.1f %9.1f %9.1f %9.1f %9.1f\n", kind.c_str(), mean(t.sdvi_ms), mean(t.codec_ms[0]),
                mean(t.codec_ms[1]), mean(t.codec_ms[2]), mean(t.codec_ms[3]));
  if (plots) std::printf("\nplots: %s/rd_*.png\n", out.string().c_str());
  std::error_code ec;
  fs::remove_all(work, ec);
  return 0;
}
