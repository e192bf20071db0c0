// SPDX-License-Identifier: GPL-3.0-or-later
// Metrics (spec/METHOD.md section 9) against an independent, direct computation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "render_meshes.h"
#include "sdvi/render.h"

using namespace sdvi;
using sdvi::test::Lcg;

namespace {

// A smooth test image and a noisy, clipped, 8-bit-quantised copy (like the skimage oracle).
void SyntheticPair(int w, int h, int channels, Raster& clean, Raster& noisy) {
  clean = Raster(w, h, channels);
  noisy = Raster(w, h, channels);
  Lcg rng(5);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) {
        const double v = std::round(127 + 100 * std::sin(x * 0.13 + c) * std::cos(y * 0.07 - c) + (x > w / 2 ? 20 : 0));
        // Box-Muller normal noise, sigma 20.
        const double u1 = std::max(1e-12, rng.Next()), u2 = rng.Next();
        const double n = std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
        clean.at(x, y, c) = float(v);
        noisy.at(x, y, c) = float(std::floor(std::clamp(v + 20 * n, 0.0, 255.0)));
      }
}

// Direct SSIM: 11x11 Gaussian (sigma 1.5) weights summed per pixel, population
// statistics, averaged over the pixels >= 5 from the border, then over channels.
double DirectMssim(const Raster& a, const Raster& b) {
  double g[11], norm = 0;
  for (int k = -5; k <= 5; ++k) g[k + 5] = std::exp(-k * k / 4.5);
  for (int i = 0; i < 11; ++i)
    for (int j = 0; j < 11; ++j) norm += g[i] * g[j];
  const double c1 = 6.5025, c2 = 58.5225;
  double total = 0;
  for (int c = 0; c < a.channels; ++c) {
    double sum = 0;
    int count = 0;
    for (int y = 5; y < a.height - 5; ++y)
      for (int x = 5; x < a.width - 5; ++x) {
        double mx = 0, my = 0, sxx = 0, syy = 0, sxy = 0;
        for (int dy = -5; dy <= 5; ++dy)
          for (int dx = -5; dx <= 5; ++dx) {
            const double wgt = g[dx + 5] * g[dy + 5] / norm;
            const double p = a.at(x + dx, y + dy, c), q = b.at(x + dx, y + dy, c);
            mx += wgt * p, my += wgt * q, sxx += wgt * p * p, syy += wgt * q * q, sxy += wgt * p * q;
          }
        const double vx = sxx - mx * mx, vy = syy - my * my, cv = sxy - mx * my;
        sum += (2 * mx * my + c1) * (2 * cv + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
        ++count;
      }
    total += sum / count;
  }
  return total / a.channels;
}

}  // namespace

TEST_CASE("PSNR, mean error and MSSIM match a direct computation (grey)", "[metrics]") {
  Raster clean, noisy;
  SyntheticPair(53, 41, 1, clean, noisy);
  auto m = CompareImages(noisy, clean);
  REQUIRE(m.ok());
  double sq = 0, ab = 0;
  for (size_t i = 0; i < clean.data.size(); ++i) {
    const double d = double(noisy.data[i]) - clean.data[i];
    sq += d * d, ab += std::abs(d);
  }
  const double mse = sq / clean.data.size();
  CHECK(m->mse == Approx(mse).epsilon(1e-12));
  CHECK(m->psnr == Approx(10 * std::log10(255.0 * 255.0 / mse)).epsilon(1e-12));
  CHECK(m->mean_error == Approx(ab / clean.data.size()).epsilon(1e-12));
  CHECK(m->mssim == Approx(DirectMssim(noisy, clean)).epsilon(1e-9));
  CHECK(m->mssim > 0.05);
  CHECK(m->mssim < 0.9);
  CHECK(m->pixels == 53u * 41u);
}

TEST_CASE("MSSIM is averaged over R, G, B and grey counts as R = G = B", "[metrics]") {
  Raster clean, noisy;
  SyntheticPair(40, 33, 3, clean, noisy);
  auto m = CompareImages(noisy, clean);
  REQUIRE(m.ok());
  CHECK(m->mssim == Approx(DirectMssim(noisy, clean)).epsilon(1e-9));
  // A grey image against its RGB expansion is identical.
  Raster grey, grey_noisy;
  SyntheticPair(30, 30, 1, grey, grey_noisy);
  Raster rgb(30, 30, 3);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 30; ++x)
      for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = grey.at(x, y, 0);
  auto same = CompareImages(rgb, grey);
  REQUIRE(same.ok());
  CHECK(std::isinf(same->psnr));
  CHECK(same->mssim == Approx(1.0));
  CHECK(same->mean_error == 0.0);
  auto g1 = CompareImages(grey_noisy, grey);
  auto g3 = CompareImages(grey_noisy, rgb);
  REQUIRE(g1.ok());
  REQUIRE(g3.ok());
  CHECK(g3->psnr == Approx(g1->psnr));
  CHECK(g3->mssim == Approx(g1->mssim));
}

TEST_CASE("Metrics count only pixels inside both domains (alpha > 0.5)", "[metrics]") {
  Raster clean, noisy;
  SyntheticPair(32, 32, 3, clean, noisy);
  Raster a(32, 32, 4), b(32, 32, 4);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      for (int c = 0; c < 3; ++c) a.at(x, y, c) = noisy.at(x, y, c), b.at(x, y, c) = clean.at(x, y, c);
      a.at(x, y, 3) = 1, b.at(x, y, 3) = 1;
    }
  auto full = CompareImages(a, b);
  auto plain = CompareImages(noisy, clean);
  REQUIRE(full.ok());
  REQUIRE(plain.ok());
  CHECK(full->psnr == Approx(plain->psnr));
  CHECK(full->mssim == Approx(plain->mssim));  // full alpha = the plain window
  // Outside the reference domain, garbage does not count.
  for (int y = 0; y < 32; ++y)
    for (int x = 16; x < 32; ++x) b.at(x, y, 3) = 0.2f, a.at(x, y, 0) = 9999;
  auto half = CompareImages(a, b);
  REQUIRE(half.ok());
  CHECK(half->pixels == 16u * 32u);
  CHECK(half->mean_error < 40);
  CHECK(half->mssim > 0);
  CHECK(half->mssim < 1);
}

TEST_CASE("CompareImages reports bad input with specific codes", "[metrics][errors]") {
  Raster a(8, 8, 3), b(9, 8, 3);
  CHECK(CompareImages(a, b).status().code() == StatusCode::kInvalidArgument);
  CHECK(CompareImages(Raster(), a).status().code() == StatusCode::kEmptyInput);
  Raster t(8, 8, 4);  // alpha 0 everywhere: no domain
  CHECK(CompareImages(a, t).status().code() == StatusCode::kEmptyInput);
  Raster broken(8, 8, 3);
  broken.data.resize(10);
  CHECK(CompareImages(broken, a).status().code() == StatusCode::kInvalidArgument);
  // Small images (under 11 px) still get an MSSIM (no border crop).
  Raster s1(6, 5, 1), s2(6, 5, 1);
  for (size_t i = 0; i < s1.data.size(); ++i) s1.data[i] = float(i * 7 % 255), s2.data[i] = float(i * 5 % 255);
  auto small = CompareImages(s1, s2);
  REQUIRE(small.ok());
  CHECK(std::isfinite(small->mssim));
}

TEST_CASE("MSSIM is the same for any thread count", "[metrics]") {
  // Tall enough for several row bands per thread count (bands of at least 16 rows), with
  // an alpha hole so that masked pixels fall inside bands and on their edges; also an image
  // smaller than the window (no crop), and one taller than a slab of bands for every thread
  // count (ChannelSsim's slabs of 128 rows a thread), whose rows mix the masked rule (rows
  // through the hole) and the unmasked one, and one wider than a strip of columns (512).
  for (const auto& [w, h] : {std::pair{37, 203}, std::pair{9, 7}, std::pair{23, 1400}, std::pair{1100, 29}}) {
    Raster clean, noisy;
    SyntheticPair(w, h, 3, clean, noisy);
    Raster masked(w, h, 4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) masked.at(x, y, c) = noisy.at(x, y, c);
        masked.at(x, y, 3) = (x - w / 2) * (x - w / 2) + (y - h / 3) * (y - h / 3) < w * h / 50 ? 0.f : 1.f;
      }
    for (const Raster* a : {&noisy, &masked}) {
      auto one = CompareImages(*a, clean, 1);
      REQUIRE(one.ok());
      if (a == &noisy && w > 11) CHECK(one->mssim == Approx(DirectMssim(*a, clean)).epsilon(1e-9));
      for (int threads : {2, 3, 5}) {
        auto many = CompareImages(*a, clean, threads);
        REQUIRE(many.ok());
        INFO(w << "x" << h << ", " << threads << " threads");
        CHECK(many->mssim == one->mssim);  // bit for bit
        CHECK(many->psnr == one->psnr);
      }
    }
  }
}

TEST_CASE("An 8-bit reconstruction measures as the float raster its bytes hold", "[metrics][render8]") {
  // A float RGBA render-like raster: colours off the integers and past 0..255, alpha over
  // 0..1 with values at and around the 0.5 domain threshold; its 8-bit copy by the PNG rule
  // (colours round(clamp(v, 0, 255)), alpha round(255 a), halves away from zero) and its
  // RoundTo8Bit copy. The two must give the same metrics bit for bit.
  const int w = 61, h = 47;
  Raster clean, noisy;
  SyntheticPair(w, h, 3, clean, noisy);
  Raster f(w, h, 4);
  Raster8 bytes(w, h, 4);
  Lcg rng(11);
  // 255 a: 0, 124.95, 127.245, 127.5 (-> 128), 128.01, 191.25, 255; the first three are out.
  const float alphas[] = {0.f, 0.49f, 0.499f, 0.5f, 0.502f, 0.75f, 1.f, 1.f, 1.f, 1.f};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) f.at(x, y, c) = float(noisy.at(x, y, c) + (rng.Next() - 0.5) * 30.0 - 10.0);
      f.at(x, y, 3) = alphas[(x * 7 + y * 3) % 10];
      for (int c = 0; c < 4; ++c) {
        const double v = f.at(x, y, c);
        bytes.at(x, y, c) = uint8_t(c == 3 ? std::round(std::clamp(v, 0.0, 1.0) * 255.0) : std::round(std::clamp(v, 0.0, 255.0)));
      }
    }
  Raster rounded = f;
  RoundTo8Bit(rounded);
  Raster reference = clean;  // and one with an alpha of its own
  Raster reference_alpha(w, h, 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) reference_alpha.at(x, y, c) = clean.at(x, y, c);
      reference_alpha.at(x, y, 3) = (x + y) % 9 == 0 ? 0.f : 1.f;
    }
  for (const Raster* ref : {&reference, &reference_alpha}) {
    auto want = CompareImages(rounded, *ref, 2);
    auto got = CompareImages(bytes, *ref, 2);
    auto pixels_only = ComparePixelErrors(bytes, *ref);
    REQUIRE(want.ok());
    REQUIRE(got.ok());
    REQUIRE(pixels_only.ok());
    CHECK(want->pixels < uint64_t(w) * h);
    CHECK(got->pixels == want->pixels);
    CHECK(got->psnr == want->psnr);  // bit for bit
    CHECK(got->mse == want->mse);
    CHECK(got->mean_error == want->mean_error);
    CHECK(got->mssim == want->mssim);
    CHECK(pixels_only->psnr == want->psnr);
    CHECK(pixels_only->mean_error == want->mean_error);
    CHECK(pixels_only->pixels == want->pixels);
    CHECK(std::isnan(pixels_only->mssim));
  }
  // Grey: one byte channel against a grey reference.
  Raster8 grey(w, h, 1);
  Raster grey_float(w, h, 1), grey_ref(w, h, 1);
  for (size_t p = 0; p < size_t(w) * h; ++p) {
    grey.data[p] = bytes.data[p * 4];
    grey_float.data[p] = float(bytes.data[p * 4]);
    grey_ref.data[p] = clean.data[p * 3];
  }
  auto want = CompareImages(grey_float, grey_ref);
  auto got = CompareImages(grey, grey_ref);
  REQUIRE(want.ok());
  REQUIRE(got.ok());
  CHECK(got->psnr == want->psnr);
  CHECK(got->mssim == want->mssim);
  // Bad input: the float overload's codes.
  CHECK(CompareImages(Raster8(8, 8, 3), Raster(9, 8, 3)).status().code() == StatusCode::kInvalidArgument);
  CHECK(ComparePixelErrors(Raster8(), Raster(8, 8, 3)).status().code() == StatusCode::kEmptyInput);
  CHECK(ComparePixelErrors(Raster8(8, 8, 4), Raster(8, 8, 3)).status().code() == StatusCode::kEmptyInput);
  Raster8 broken(8, 8, 3);
  broken.data.resize(10);
  CHECK(ComparePixelErrors(broken, Raster(8, 8, 3)).status().code() == StatusCode::kInvalidArgument);
}

TEST_CASE("A vectorized file's PSNR is that of its 8-bit render", "[metrics][render8]") {
  // What rate control measures (Render8 + ComparePixelErrors) against the rule of
  // spec/RATE.md 1 computed the long way: the float render, rounded as its PNG, compared.
  sdvi::test::GridSpec spec;
  spec.xs = {0, 7, 13.5, 20, 26, 33};
  spec.ys = {0, 6, 12.5, 19, 25};
  spec.colour = [](double x, double y) {
    return std::array<float, 3>{float(40 + 6.1 * x), float(200 - 3.3 * y), float(90 + 2.2 * x * y / 10)};
  };
  const Image image = sdvi::test::GridImage(spec);
  Raster reference(int(image.width), int(image.height), 3);
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x)
      for (int c = 0; c < 3; ++c) reference.at(x, y, c) = float((x * 37 + y * 11 + c * 50) % 256);
  RenderOptions o;
  o.viewport = Viewport::Identity(reference.width, reference.height);
  auto f = Render(image, o);
  auto b = Render8(image, o);
  REQUIRE(f.ok());
  REQUIRE(b.ok());
  RoundTo8Bit(*f);
  auto want = CompareImages(*f, reference);
  auto got = ComparePixelErrors(*b, reference);
  REQUIRE(want.ok());
  REQUIRE(got.ok());
  CHECK(got->psnr == want->psnr);
  CHECK(std::isfinite(got->psnr));
}
