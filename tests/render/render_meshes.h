// SPDX-License-Identifier: GPL-3.0-or-later
// Synthetic meshes for the render tests (generated in code, deterministic) and their
// temporary file names.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/raster.h"

namespace sdvi::test {

// A path in the system's temporary directory for a render test's file called name.
inline std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("sdvi_render_test_" + name)).string();
}

// Deterministic pseudo-random numbers in [0, 1).
class Lcg {
 public:
  explicit Lcg(uint64_t seed) : s_(seed * 6364136223846793005ull + 1442695040888963407ull) {}
  double Next() {
    s_ = s_ * 6364136223846793005ull + 1442695040888963407ull;
    return double(s_ >> 11) * (1.0 / 9007199254740992.0);
  }

 private:
  uint64_t s_;
};

// A grid mesh tiling [0, W] x [0, H] with columns xs and rows ys (both including the
// ends); interior vertices moved by jitter(x, y) (returns the displacement), each cell
// split along a pseudo-random diagonal. Colour from colour(x, y) -> (r, g, b).
struct GridSpec {
  std::vector<double> xs, ys;
  std::function<std::array<float, 3>(double, double)> colour;
  std::function<std::array<double, 2>(double, double)> jitter;
  uint64_t seed = 1;
};

inline Image GridImage(const GridSpec& spec) {
  Image img;
  const int nx = int(spec.xs.size()), ny = int(spec.ys.size());
  img.width = uint32_t(std::lround(spec.xs.back()));
  img.height = uint32_t(std::lround(spec.ys.back()));
  for (int r = 0; r < ny; ++r) {
    for (int c = 0; c < nx; ++c) {
      double x = spec.xs[c], y = spec.ys[r];
      if (spec.jitter && c > 0 && c < nx - 1 && r > 0 && r < ny - 1) {
        const auto d = spec.jitter(x, y);
        x += d[0], y += d[1];
      }
      const auto col = spec.colour ? spec.colour(x, y) : std::array<float, 3>{128, 128, 128};
      img.vertices.push_back({float(x), float(y), col[0], col[1], col[2]});
    }
  }
  Lcg rng(spec.seed);
  auto id = [&](int c, int r) { return uint32_t(r * nx + c); };
  for (int r = 0; r + 1 < ny; ++r) {
    for (int c = 0; c + 1 < nx; ++c) {
      const uint32_t a = id(c, r), b = id(c + 1, r), d = id(c, r + 1), e = id(c + 1, r + 1);
      if (rng.Next() < 0.5) {
        img.triangles.push_back({{a, b, e}});
        img.triangles.push_back({{a, e, d}});
      } else {
        img.triangles.push_back({{a, b, d}});
        img.triangles.push_back({{b, e, d}});
      }
    }
  }
  img.corners = {id(0, 0), id(nx - 1, 0), id(0, ny - 1), id(nx - 1, ny - 1)};
  std::sort(img.corners.begin(), img.corners.end());
  return img;
}

inline std::vector<double> Steps(double from, double to, int n) {
  std::vector<double> v;
  for (int i = 0; i <= n; ++i) v.push_back(from + (to - from) * i / n);
  return v;
}

// Marks the vertical grid column c (all rows) as a crease polyline.
inline void AddColumnCrease(Image& img, int nx, int ny, int c) {
  for (int r = 0; r + 1 < ny; ++r) img.crease_edges.push_back(Edge::Of(uint32_t(r * nx + c), uint32_t((r + 1) * nx + c)));
  std::sort(img.crease_edges.begin(), img.crease_edges.end());
  img.crease_edges.erase(std::unique(img.crease_edges.begin(), img.crease_edges.end()), img.crease_edges.end());
}

// Mean of each factor x factor block (colour weighted by alpha when present).
inline Raster BoxDownsample(const Raster& in, int factor) {
  Raster out(in.width / factor, in.height / factor, in.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < in.channels; ++c) {
        double s = 0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) s += in.at(x * factor + dx, y * factor + dy, c);
        out.at(x, y, c) = float(s / (factor * factor));
      }
  return out;
}

}  // namespace sdvi::test
