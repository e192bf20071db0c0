// SPDX-License-Identifier: GPL-3.0-or-later
// The built-in sample image of `sdvi sample` (vectorize.h): a smooth background gradient, a
// soft (blurred) wavy edge, a sharp-edged shaded disc and a sharp triangle with corners.
// Drawn analytically (signed distances, no randomness): equal sizes give equal pixels.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "sdvi/vectorize.h"

namespace sdvi {
namespace {

double Smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Blends colour c over dst with weight a in [0, 1].
void Over(double dst[3], const double c[3], double a) {
  for (int k = 0; k < 3; ++k) dst[k] = dst[k] * (1 - a) + c[k] * a;
}

}  // namespace

Raster MakeSampleImage(int width, int height) {
  Raster image(std::max(width, 0), std::max(height, 0), 3);
  if (image.empty()) return image;
  const double w = width, h = height, s = std::min(w, h);
  const double pi = std::numbers::pi;
  // The triangle (corners kept sharp), clockwise on screen (x right, y down).
  const double tri[3][2] = {{0.62 * w, 0.12 * h}, {0.92 * w, 0.30 * h}, {0.66 * w, 0.52 * h}};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double u = px / w, v = py / h;
      // Smooth background: two crossing linear ramps and a gentle bump.
      const double bump = std::exp(-((u - 0.2) * (u - 0.2) + (v - 0.8) * (v - 0.8)) * 6);
      double rgb[3] = {40 + 150 * u + 30 * bump, 70 + 110 * v, 190 - 90 * u + 40 * bump};
      // Soft edge: below a sine wave, blurred over ~2.4% of the size.
      const double wave = h * (0.70 + 0.05 * std::sin(2 * pi * 1.5 * u));
      const double soft = Smoothstep(-0.012 * s, 0.012 * s, py - wave);
      const double warm[3] = {225 - 40 * u, 175 - 30 * v, 95};
      Over(rgb, warm, soft);
      // Sharp disc with a radial shade, antialiased over one pixel.
      const double cx = 0.33 * w, cy = 0.36 * h, r = 0.22 * s;
      const double d = std::hypot(px - cx, py - cy);
      const double t = std::clamp(d / r, 0.0, 1.0);
      const double disc[3] = {250 - 60 * t, 120 - 80 * t, 90 - 50 * t};
      Over(rgb, disc, std::clamp(r - d + 0.5, 0.0, 1.0));
      // Sharp triangle: signed distance = max over edges of the outward distance.
      double outside = -1e30;
      for (int k = 0; k < 3; ++k) {
        const double* a = tri[k];
        const double* b = tri[(k + 1) % 3];
        const double ex = b[0] - a[0], ey = b[1] - a[1], len = std::hypot(ex, ey);
        // Outward normal for this winding (the third corner lies on the other side).
        const double nx = ey / len, ny = -ex / len;
        outside = std::max(outside, (px - a[0]) * nx + (py - a[1]) * ny);
      }
      const double green[3] = {30 + 40 * v, 110 + 60 * u, 60};
      Over(rgb, green, std::clamp(0.5 - outside, 0.0, 1.0));
      for (int k = 0; k < 3; ++k) image.at(x, y, k) = float(std::clamp(rgb[k], 0.0, 255.0));
    }
  }
  return image;
}

}  // namespace sdvi
