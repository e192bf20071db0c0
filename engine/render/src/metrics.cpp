// SPDX-License-Identifier: GPL-3.0-or-later
// Image metrics of spec/METHOD.md section 9: PSNR, MSSIM (Wang et al. 2004), mean absolute error.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "scan_convert.h"
#include "sdvi/render.h"

namespace sdvi {
namespace {

constexpr int kRadius = 5;         // 11x11 window
constexpr double kSigma = 1.5;
constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
constexpr double kC2 = (0.03 * 255) * (0.03 * 255);

std::array<double, 2 * kRadius + 1> GaussianWindow() {
  std::array<double, 2 * kRadius + 1> g{};
  double sum = 0;
  for (int k = -kRadius; k <= kRadius; ++k) sum += g[k + kRadius] = std::exp(-k * k / (2 * kSigma * kSigma));
  for (double& v : g) v /= sum;
  return g;
}

// One colour channel of a raster (float) or an 8-bit raster (uint8_t) read in place: value
// p = data[p * stride], exact in double either way.
template <typename T>
struct ChannelView {
  const T* data;
  size_t stride;
  double operator[](size_t p) const { return double(data[p * stride]); }
};

// The view of colour channel c (0..2) of r; grey rasters count as R = G = B.
template <typename R>
auto ViewOf(const R& r, int c) {
  using T = typename decltype(r.data)::value_type;
  return ChannelView<T>{r.data.data() + (r.channels >= 3 ? c : 0), size_t(r.channels)};
}

// Whether pixel p lies in r's domain for the metrics: alpha > 0.5 (an 8-bit alpha a stands for
// a / 255, so a > 127); every pixel when r has no alpha.
bool InDomain(const Raster& r, size_t p) {
  return !r.has_alpha() || r.data[p * r.channels + r.channels - 1] > 0.5f;
}
bool InDomain(const Raster8& r, size_t p) {
  return !r.has_alpha() || r.data[p * r.channels + r.channels - 1] > 127;
}

// Rows of output a thread takes per slab of ChannelSsim (each also filters kRadius rows on
// either side of its rows horizontally).
constexpr int kSsimBandRows = 128;
// Columns of a strip: a band is filtered strip by strip (see ChannelSsim).
constexpr int kSsimStripColumns = 512;

// The three loops that take most of the MSSIM's time, each compiled twice (AVX2 and the
// baseline, chosen when the program loads): the loops run over independent pixels, so the
// wider registers compute each pixel's products and sums exactly as the baseline does (no
// fused multiply-add: the AVX2 clone has none to contract into).
//
// Tap k of a run of n pixels whose every tap is compared: ax[i], bx[i] the tap's two values
// for pixel i; m1..m5 the pixels' moments sum g x (a, b, a a, b b, a b).
__attribute__((target_clones("avx2", "default"))) void AddTap(double gw, const double* __restrict ax,
                                                               const double* __restrict bx, int n,
                                                               double* __restrict m1, double* __restrict m2,
                                                               double* __restrict m3, double* __restrict m4,
                                                               double* __restrict m5) {
  for (int i = 0; i < n; ++i) {
    const double a = ax[i], b = bx[i];
    m1[i] += gw * a;
    m2[i] += gw * b;
    m3[i] += gw * a * a;
    m4[i] += gw * b * b;
    m5[i] += gw * a * b;
  }
}

// acc[q] += gw row[q], q < count (one row of the vertical filter).
__attribute__((target_clones("avx2", "default"))) void AddScaled(double gw, const double* __restrict row,
                                                                  size_t count, double* __restrict acc) {
  for (size_t q = 0; q < count; ++q) acc[q] += gw * row[q];
}

// SSIM of pixels [i0, i1) of a strip from their filtered moments: acc[m sw + i] the moment m
// (weight, x, y, x^2, y^2, x y) of pixel i; out[i] its term.
__attribute__((target_clones("avx2", "default"))) void SsimTerms(const double* __restrict acc, size_t sw,
                                                                  size_t i0, size_t i1,
                                                                  double* __restrict out) {
  for (size_t i = i0; i < i1; ++i) {
    const double wsum = acc[i];
    const double mx = acc[sw + i] / wsum, my = acc[2 * sw + i] / wsum;
    const double vx = acc[3 * sw + i] / wsum - mx * mx;
    const double vy = acc[4 * sw + i] / wsum - my * my;
    const double cxy = acc[5 * sw + i] / wsum - mx * my;
    out[i] = ((2 * mx * my + kC1) * (2 * cxy + kC2)) / ((mx * mx + my * my + kC1) * (vx + vy + kC2));
  }
}

// Mean SSIM of one channel over the compared pixels (mask), at pixels >= kRadius from the
// border when the image allows it. Rows are filtered horizontally into a ring of
// 2*kRadius+1 rows of the six moments, then combined vertically, in strips of columns (the
// ring of a strip stays in cache; a whole 8000-px row's ring did not). The image is taken in
// slabs of rows: each thread filters a band of kSsimBandRows output rows of the slab (and
// the rows its window needs) and stores each pixel's SSIM; the slab's sum is then taken
// serially in row-major order, slab after slab, so the sum is that of one serial pass over
// the whole image in row-major order for any thread count, and only a slab's SSIM values
// are held. A pixel whose window lies inside the image and the mask (every pixel of its row
// compared) is filtered without the per-tap tests: the same sums in the same order.
struct SsimSum {
  double sum = 0;
  uint64_t count = 0;
};
template <typename X, typename Y>
SsimSum ChannelSsim(X x, Y y, const std::vector<uint8_t>& mask,
                    const std::vector<uint8_t>& full_row, int w, int h, int threads) {
  const auto g = GaussianWindow();
  constexpr int kWin = 2 * kRadius + 1;
  constexpr int kMoments = 6;  // m, m x, m y, m x^2, m y^2, m x y
  const bool crop = w >= kWin && h >= kWin;
  const int x0 = crop ? kRadius : 0, x1 = crop ? w - kRadius : w;
  auto counted_row = [&](int yo) { return !crop || (yo >= kRadius && yo < h - kRadius); };
  double full_weight = 0;  // s[0] of a window with every tap counted, summed as below
  for (int k = -kRadius; k <= kRadius; ++k) full_weight += g[k + kRadius];
  const int workers = render_internal::WorkerCount(threads, h);
  const int slab_rows = workers * kSsimBandRows;
  std::vector<double> terms(size_t(std::min(h, slab_rows)) * w);
  // Output rows [r0, r1) of the slab starting at row slab0 into terms, in strips of
  // kSsimStripColumns columns (a strip's ring of moments stays in cache from row to row).
  auto band = [&](int slab0, int r0, int r1) {
    const int strip = std::min(w, kSsimStripColumns);
    std::vector<double> ring(size_t(kWin) * kMoments * strip, 0.0);
    std::vector<double> acc(size_t(kMoments) * strip);
    std::vector<double> row_x(size_t(strip) + 2 * kRadius), row_y(size_t(strip) + 2 * kRadius);
    for (int c0 = 0; c0 < w; c0 += strip) {
      const int c1 = std::min(w, c0 + strip), sw = c1 - c0;
      for (int yi = std::max(0, r0 - kRadius); yi < r1 + kRadius; ++yi) {
        if (yi < h) {
          double* row = &ring[size_t(yi % kWin) * kMoments * sw];
          // The general rule at pixel xo: the taps inside the image and the mask, in order.
          auto general = [&](int xo) {
            double s[kMoments] = {0, 0, 0, 0, 0, 0};
            for (int k = -kRadius; k <= kRadius; ++k) {
              const int xs = xo + k;
              if (xs < 0 || xs >= w) continue;
              const size_t p = size_t(yi) * w + xs;
              if (!mask[p]) continue;
              const double gw = g[k + kRadius], a = x[p], b = y[p];
              s[0] += gw;
              s[1] += gw * a;
              s[2] += gw * b;
              s[3] += gw * a * a;
              s[4] += gw * b * b;
              s[5] += gw * a * b;
            }
            for (int m = 0; m < kMoments; ++m) row[size_t(m) * sw + (xo - c0)] = s[m];
          };
          // Pixels [f0, f1) have every tap inside the image and the mask (their row is).
          const bool full = full_row[size_t(yi)] != 0;
          const int f0 = full ? std::max(c0, kRadius) : c1, f1 = full ? std::min(c1, w - kRadius) : c1;
          if (f0 >= f1) {
            for (int xo = c0; xo < c1; ++xo) general(xo);
          } else {
            // Each moment summed tap by tap over the run of pixels (the same sums in the same
            // order as the general rule, the loop over pixels innermost).
            for (int xo = c0; xo < f0; ++xo) general(xo);
            for (int xo = f1; xo < c1; ++xo) general(xo);
            const size_t base = size_t(yi) * w;
            for (int xs = f0 - kRadius; xs < f1 + kRadius; ++xs) {
              row_x[size_t(xs - (f0 - kRadius))] = x[base + size_t(xs)];
              row_y[size_t(xs - (f0 - kRadius))] = y[base + size_t(xs)];
            }
            const int n = f1 - f0;
            double* m0 = row + (f0 - c0);
            double* m1 = m0 + sw;
            double* m2 = m0 + size_t(2) * sw;
            double* m3 = m0 + size_t(3) * sw;
            double* m4 = m0 + size_t(4) * sw;
            double* m5 = m0 + size_t(5) * sw;
            for (int i = 0; i < n; ++i) {
              m0[i] = full_weight;
              m1[i] = m2[i] = m3[i] = m4[i] = m5[i] = 0.0;
            }
            for (int k = 0; k < kWin; ++k) {
              AddTap(g[k], row_x.data() + k, row_y.data() + k, n, m1, m2, m3, m4, m5);
            }
          }
        }
        const int yo = yi - kRadius;
        if (yo < r0 || !counted_row(yo)) continue;
        std::fill(acc.begin(), acc.begin() + size_t(kMoments) * sw, 0.0);
        for (int k = -kRadius; k <= kRadius; ++k) {
          const int ys = yo + k;
          if (ys < 0 || ys >= h) continue;
          AddScaled(g[k + kRadius], &ring[size_t(ys % kWin) * kMoments * sw], size_t(kMoments) * sw, acc.data());
        }
        double* out = &terms[size_t(yo - slab0) * w];
        // Every pixel of the strip's counted columns (a pixel outside the mask gets a term
        // that the sum below skips).
        const int lo = std::max(x0, c0), hi = std::min(x1, c1);
        if (lo < hi) SsimTerms(acc.data(), size_t(sw), size_t(lo - c0), size_t(hi - c0), out + c0);
      }
    }
  };
  SsimSum out;
  for (int slab0 = 0; slab0 < h; slab0 += slab_rows) {
    const int slab1 = std::min(h, slab0 + slab_rows);
    const int bands = (slab1 - slab0 + kSsimBandRows - 1) / kSsimBandRows;
    auto run = [&](int b) { band(slab0, slab0 + b * kSsimBandRows, std::min(slab1, slab0 + (b + 1) * kSsimBandRows)); };
    if (bands == 1) {
      run(0);
    } else {
      RunTasks(bands, run);
    }
    for (int yo = slab0; yo < slab1; ++yo) {
      if (!counted_row(yo)) continue;
      const double* row = &terms[size_t(yo - slab0) * w];
      for (int xo = x0; xo < x1; ++xo) {
        if (!mask[size_t(yo) * w + xo]) continue;
        out.sum += row[xo];
        ++out.count;
      }
    }
  }
  return out;
}

// CompareImages for a reconstruction a held as floats (Raster) or bytes (Raster8); the MSSIM
// only when with_mssim (else NaN).
template <typename A>
StatusOr<ImageMetrics> Compare(const A& a, const Raster& b, int threads, bool with_mssim) {
  if (a.empty() || b.empty())
    return Status(StatusCode::kEmptyInput, "compare: an image is empty (" + std::to_string(a.width) + "x" +
                                               std::to_string(a.height) + " vs " + std::to_string(b.width) +
                                               "x" + std::to_string(b.height) + ")");
  if (a.width != b.width || a.height != b.height)
    return Status(StatusCode::kInvalidArgument,
                  "compare: sizes differ: reconstruction " + std::to_string(a.width) + "x" +
                      std::to_string(a.height) + ", reference " + std::to_string(b.width) + "x" +
                      std::to_string(b.height));
  auto bad_shape = [](int channels, size_t samples, size_t pixels) {
    return channels < 1 || channels > 4 || samples != pixels * size_t(channels);
  };
  const size_t npix = size_t(a.width) * a.height;
  for (auto [channels, samples] : {std::pair{a.channels, a.data.size()}, std::pair{b.channels, b.data.size()}}) {
    if (bad_shape(channels, samples, npix))
      return Status(StatusCode::kInvalidArgument,
                    "compare: raster has " + std::to_string(channels) + " channels and " +
                        std::to_string(samples) + " samples; expected 1-4 channels, width*height*channels");
  }
  const int w = a.width, h = a.height;
  std::vector<uint8_t> mask(npix, 1);
  uint64_t count = 0;
  for (size_t p = 0; p < npix; ++p) {
    mask[p] = InDomain(a, p) && InDomain(b, p);
    count += mask[p];
  }
  if (count == 0) return Status(StatusCode::kEmptyInput, "compare: no pixel lies in both images' domains (alpha > 0.5)");

  // Rows whose every pixel is compared: ChannelSsim filters them without per-tap tests.
  std::vector<uint8_t> full_row(with_mssim ? size_t(h) : 0, 1);
  for (int y = 0; y < int(full_row.size()); ++y) {
    for (int x = 0; x < w && full_row[size_t(y)]; ++x) full_row[size_t(y)] = mask[size_t(y) * w + x];
  }

  const bool grey = a.channels < 3 && b.channels < 3;
  const int nchan = grey ? 1 : 3;
  double sq = 0, abs_sum = 0, ssim_sum = 0;
  uint64_t ssim_count = 0;
  // One channel of each image, read in place (exact; every sum is in double).
  for (int c = 0; c < nchan; ++c) {
    const auto xa = ViewOf(a, c);
    const auto xb = ViewOf(b, c);
    for (size_t p = 0; p < npix; ++p) {
      if (!mask[p]) continue;
      const double d = xa[p] - xb[p];
      sq += d * d;
      abs_sum += std::abs(d);
    }
    if (!with_mssim) continue;
    const SsimSum s = ChannelSsim(xa, xb, mask, full_row, w, h, threads);
    ssim_sum += s.count ? s.sum / double(s.count) : 0.0;
    ssim_count += s.count;
  }
  ImageMetrics m;
  m.pixels = count;
  m.mse = sq / (double(count) * nchan);
  m.mean_error = abs_sum / (double(count) * nchan);
  m.psnr = m.mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / m.mse) : std::numeric_limits<double>::infinity();
  m.mssim = ssim_count ? ssim_sum / nchan : std::numeric_limits<double>::quiet_NaN();
  return m;
}

}  // namespace

StatusOr<ImageMetrics> CompareImages(const Raster& reconstruction, const Raster& reference, int threads) {
  return Compare(reconstruction, reference, threads, /*with_mssim=*/true);
}

StatusOr<ImageMetrics> CompareImages(const Raster8& reconstruction, const Raster& reference, int threads) {
  return Compare(reconstruction, reference, threads, /*with_mssim=*/true);
}

StatusOr<ImageMetrics> ComparePixelErrors(const Raster8& reconstruction, const Raster& reference) {
  return Compare(reconstruction, reference, /*threads=*/1, /*with_mssim=*/false);
}

void RoundTo8Bit(Raster& raster) {
  const int alpha = raster.has_alpha() ? raster.channels - 1 : -1;
  for (size_t i = 0; i < raster.data.size(); ++i) {
    float& v = raster.data[i];
    if (int(i % size_t(raster.channels)) == alpha) v = std::round(std::clamp(v, 0.f, 1.f) * 255.f) / 255.f;
    else v = std::round(std::clamp(v, 0.f, 255.f));
  }
}

}  // namespace sdvi
