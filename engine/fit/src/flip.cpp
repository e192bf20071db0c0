// SPDX-License-Identifier: GPL-3.0-or-later
// Data-dependent edge flips of a control mesh (vectorize.h, FlipEdgesToData): the
// constrained Delaunay triangulation ignores the colours; a flip of a non-crease edge is
// kept when the piecewise-linear interpolation of the image colours at the vertices fits
// the pixels of the edge's quadrilateral better with the other diagonal.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "parallel.h"
#include "sdvi/color_fit.h"
#include "sdvi/vectorize.h"

namespace sdvi {
namespace {

struct Rgb {
  float c[3] = {0, 0, 0};
};

double Orient(const Vertex& a, const Vertex& b, const Vertex& c) {
  return (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
}

// sin of the smallest angle of triangle abc (0 when degenerate).
double MinAngleSine(const Vertex& a, const Vertex& b, const Vertex& c) {
  const double area2 = std::abs(Orient(a, b, c));
  auto len = [](const Vertex& p, const Vertex& q) { return std::hypot(double(p.x) - q.x, double(p.y) - q.y); };
  const double ab = len(a, b), bc = len(b, c), ca = len(c, a);
  const double m = std::max({ab * bc, bc * ca, ca * ab});
  return m > 0 ? area2 / m : 0;
}

class QuadError {
 public:
  QuadError(const Image& mesh, const Raster& raster, const Raster* mask, const std::vector<Rgb>& colour)
      : mesh_(mesh), raster_(raster), mask_(mask), colour_(colour),
        whole_(mask == nullptr && !raster.has_alpha()) {}

  // Squared error of the linear interpolation over triangle t (vertex triple) at the
  // pixel centres inside it.
  double Triangle(const std::array<uint32_t, 3>& t) const {
    const Vertex& a = mesh_.vertices[t[0]];
    const Vertex& b = mesh_.vertices[t[1]];
    const Vertex& c = mesh_.vertices[t[2]];
    const double det = Orient(a, b, c);
    if (std::abs(det) < 1e-12) return 0;
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}) - 0.5f)));
    const int x1 = std::min(raster_.width - 1, int(std::ceil(std::max({a.x, b.x, c.x}) - 0.5f)));
    const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}) - 0.5f)));
    const int y1 = std::min(raster_.height - 1, int(std::ceil(std::max({a.y, b.y, c.y}) - 0.5f)));
    const Rgb& ca = colour_[t[0]];
    const Rgb& cb = colour_[t[1]];
    const Rgb& cc = colour_[t[2]];
    double sum = 0;
    const Vertex* corners[3] = {&a, &b, &c};
    for (int y = y0; y <= y1; ++y) {
      // Only pixels near the row's span of the triangle (one pixel of margin each side)
      // can be inside; the exact test below decides, so the span only saves work.
      const double py = y + 0.5;
      double span_lo = INFINITY, span_hi = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const Vertex& u = *corners[k];
        const Vertex& v = *corners[(k + 1) % 3];
        const double uy = u.y, vy = v.y;
        if (py < std::min(uy, vy) - 1 || py > std::max(uy, vy) + 1) continue;
        double x_at;
        if (std::abs(vy - uy) < 1e-9) {
          span_lo = std::min({span_lo, double(u.x), double(v.x)});
          span_hi = std::max({span_hi, double(u.x), double(v.x)});
          continue;
        }
        const double t = std::clamp((py - uy) / (vy - uy), 0.0, 1.0);
        x_at = u.x + t * (double(v.x) - u.x);
        span_lo = std::min(span_lo, x_at);
        span_hi = std::max(span_hi, x_at);
      }
      if (!(span_lo <= span_hi)) continue;
      const int xa = std::max(x0, int(std::floor(span_lo - 1.5)));
      const int xb = std::min(x1, int(std::ceil(span_hi + 0.5)));
      for (int x = xa; x <= xb; ++x) {
        Vertex p;
        p.x = float(x + 0.5);
        p.y = float(y + 0.5);
        // Barycentrics; a pixel on a shared edge counts in both triangulations alike.
        const double la = Orient(p, b, c) / det, lb = Orient(a, p, c) / det;
        const double lc = 1 - la - lb;
        if (la < 0 || lb < 0 || lc < 0) continue;
        if (!whole_ && !InDomain(raster_, mask_, x, y)) continue;
        for (int k = 0; k < 3; ++k) {
          const double ref = raster_.channels <= 2 ? raster_.at(x, y, 0) : raster_.at(x, y, k);
          const double d = la * ca.c[k] + lb * cb.c[k] + lc * cc.c[k] - ref;
          sum += d * d;
        }
      }
    }
    return sum;
  }

 private:
  const Image& mesh_;
  const Raster& raster_;
  const Raster* mask_;
  const std::vector<Rgb>& colour_;
  bool whole_;  // every pixel is in the domain
};

}  // namespace

const double* FlipErrorCache::Find(const std::array<uint32_t, 6>& key) const {
  const auto it = std::lower_bound(previous_.begin(), previous_.end(), key,
                                   [](const Entry& e, const std::array<uint32_t, 6>& k) { return e.key < k; });
  return it != previous_.end() && it->key == key ? &it->error : nullptr;
}

void FlipErrorCache::EndCall() {
  std::sort(current_.begin(), current_.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
  current_.erase(std::unique(current_.begin(), current_.end(),
                             [](const Entry& a, const Entry& b) { return a.key == b.key; }),
                 current_.end());
  previous_.swap(current_);
  current_.clear();
  current_.shrink_to_fit();
}

int FlipEdgesToData(Image& mesh, const Raster& raster, const Raster* mask, int passes,
                    double min_angle_deg, int threads, FlipErrorCache* cache) {
  const int width = raster.width, height = raster.height;
  if (passes <= 0 || mesh.triangles.empty() || width <= 0 || height <= 0) return 0;
  // Vertex colours: the image smoothed by a Gaussian of sigma 1 px, bilinear.
  cv::Mat3f smooth(height, width);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int k = 0; k < 3; ++k) smooth(y, x)[k] = raster.channels <= 2 ? raster.at(x, y, 0) : raster.at(x, y, k);
    }
  }
  cv::GaussianBlur(smooth, smooth, cv::Size(0, 0), 1.0, 1.0, cv::BORDER_REFLECT);
  std::vector<Rgb> colour(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const double fx = std::clamp(double(mesh.vertices[i].x) - 0.5, 0.0, double(width - 1));
    const double fy = std::clamp(double(mesh.vertices[i].y) - 0.5, 0.0, double(height - 1));
    const int ix = std::min(int(fx), width - 2 < 0 ? 0 : width - 2);
    const int iy = std::min(int(fy), height - 2 < 0 ? 0 : height - 2);
    const int jx = std::min(ix + 1, width - 1), jy = std::min(iy + 1, height - 1);
    const double u = fx - ix, v = fy - iy;
    for (int k = 0; k < 3; ++k) {
      colour[i].c[k] = float((1 - u) * (1 - v) * smooth(iy, ix)[k] + u * (1 - v) * smooth(iy, jx)[k] +
                             (1 - u) * v * smooth(jy, ix)[k] + u * v * smooth(jy, jx)[k]);
    }
  }
  const QuadError error(mesh, raster, mask, colour);
  auto key_of = [&](const std::array<uint32_t, 3>& t) {
    std::array<uint32_t, 6> key;
    for (int k = 0; k < 3; ++k) {
      std::memcpy(&key[2 * k], &mesh.vertices[t[k]].x, 4);
      std::memcpy(&key[2 * k + 1], &mesh.vertices[t[k]].y, 4);
    }
    return key;
  };
  // The error of triangle t, from the cache when it holds it.
  auto triangle_error_of = [&](const std::array<uint32_t, 3>& t) {
    if (cache != nullptr) {
      if (const double* e = cache->Find(key_of(t))) return *e;
    }
    return error.Triangle(t);
  };
  const double min_sine = std::sin(min_angle_deg * 3.14159265358979323846 / 180.0);
  std::vector<Edge> creases = mesh.crease_edges;
  std::sort(creases.begin(), creases.end());
  int flips = 0;
  // Per-triangle error of the current triangulation (-1: not known yet); a sweep after the
  // first visits only the edges of triangles the previous sweep changed.
  std::vector<double> triangle_error(mesh.triangles.size(), -1.0);
  std::vector<uint8_t> changed(mesh.triangles.size(), 1);
  // A sweep decides edge by edge in edge order, and a flip of one edge only changes its two
  // triangles, which no later edge of the sweep may use (`touched`). So every quantity a
  // decision reads (the two triangles, their errors, the errors after the flip) is that of
  // the sweep's start: they are computed first, on threads in fixed chunks, and the
  // decisions then taken in edge order exactly as one serial sweep takes them.
  struct Candidate {
    Edge e;
    uint32_t t0, t1, r, s;
    double after0, after1;
  };
  constexpr size_t kChunk = 256;
  for (int pass = 0; pass < passes; ++pass) {
    // (edge, triangle) pairs sorted by edge: interior edges appear twice.
    struct Side {
      Edge e;
      uint32_t t;
    };
    std::vector<Side> sides;
    sides.reserve(mesh.triangles.size() * 3);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& v = mesh.triangles[t].v;
      for (int k = 0; k < 3; ++k) sides.push_back({Edge::Of(v[k], v[(k + 1) % 3]), t});
    }
    std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
      return a.e != b.e ? a.e < b.e : a.t < b.t;
    });
    // The edges a sweep may flip, by the geometry at the sweep's start.
    std::vector<Candidate> candidates;
    for (size_t i = 0; i + 1 < sides.size(); ++i) {
      if (sides[i].e != sides[i + 1].e) continue;
      const Edge e = sides[i].e;
      const uint32_t t0 = sides[i].t, t1 = sides[i + 1].t;
      ++i;
      if (!(changed[t0] || changed[t1])) continue;
      if (std::binary_search(creases.begin(), creases.end(), e)) continue;
      auto opposite = [&](uint32_t t) {
        for (uint32_t w : mesh.triangles[t].v) {
          if (w != e.a && w != e.b) return w;
        }
        return e.a;
      };
      const uint32_t r = opposite(t0), s = opposite(t1);
      if (r == s) continue;
      const Vertex& P = mesh.vertices[e.a];
      const Vertex& Q = mesh.vertices[e.b];
      const Vertex& R = mesh.vertices[r];
      const Vertex& S = mesh.vertices[s];
      // Convex quadrilateral: r-s must cross p-q strictly.
      const double op = Orient(R, S, P), oq = Orient(R, S, Q);
      const double orr = Orient(P, Q, R), os = Orient(P, Q, S);
      if (!((op > 0 && oq < 0) || (op < 0 && oq > 0))) continue;
      if (!((orr > 0 && os < 0) || (orr < 0 && os > 0))) continue;
      if (MinAngleSine(R, S, P) < min_sine || MinAngleSine(R, S, Q) < min_sine) continue;
      candidates.push_back({e, t0, t1, r, s, 0.0, 0.0});
    }
    // Errors of the candidates' triangles not known yet, then of the flipped pairs.
    std::vector<uint32_t> unknown;
    for (const Candidate& c : candidates) {
      for (uint32_t t : {c.t0, c.t1}) {
        if (triangle_error[t] < 0) {
          triangle_error[t] = 0;  // listed once
          unknown.push_back(t);
        }
      }
    }
    fit_internal::ForEachChunk(unknown.size(), kChunk, threads, [&](size_t, size_t k0, size_t k1) {
      for (size_t k = k0; k < k1; ++k) triangle_error[unknown[k]] = triangle_error_of(mesh.triangles[unknown[k]].v);
    });
    fit_internal::ForEachChunk(candidates.size(), kChunk, threads, [&](size_t, size_t k0, size_t k1) {
      for (size_t k = k0; k < k1; ++k) {
        Candidate& c = candidates[k];
        c.after0 = triangle_error_of({c.r, c.s, c.e.a});
        c.after1 = triangle_error_of({c.r, c.s, c.e.b});
      }
    });
    if (cache != nullptr) {
      for (uint32_t t : unknown) cache->Add(key_of(mesh.triangles[t].v), triangle_error[t]);
      for (const Candidate& c : candidates) {
        cache->Add(key_of({c.r, c.s, c.e.a}), c.after0);
        cache->Add(key_of({c.r, c.s, c.e.b}), c.after1);
      }
    }
    std::vector<uint8_t> touched(mesh.triangles.size(), 0);
    int pass_flips = 0;
    for (const Candidate& c : candidates) {
      const uint32_t t0 = c.t0, t1 = c.t1;
      if (touched[t0] || touched[t1]) continue;
      const double before = triangle_error[t0] + triangle_error[t1];
      if (!(c.after0 + c.after1 < 0.98 * before)) continue;
      // Keep the orientation of t0.
      const auto& v0 = mesh.triangles[t0].v;
      const double sign = Orient(mesh.vertices[v0[0]], mesh.vertices[v0[1]], mesh.vertices[v0[2]]);
      auto oriented = [&](uint32_t a, uint32_t b, uint32_t d) {
        const double o = Orient(mesh.vertices[a], mesh.vertices[b], mesh.vertices[d]);
        return (o > 0) == (sign > 0) ? std::array<uint32_t, 3>{a, b, d} : std::array<uint32_t, 3>{a, d, b};
      };
      mesh.triangles[t0].v = oriented(c.r, c.s, c.e.a);
      mesh.triangles[t1].v = oriented(c.r, c.s, c.e.b);
      triangle_error[t0] = c.after0;
      triangle_error[t1] = c.after1;
      touched[t0] = touched[t1] = 1;
      ++pass_flips;
    }
    changed.swap(touched);
    flips += pass_flips;
    if (pass_flips == 0) break;
  }
  if (cache != nullptr) cache->EndCall();
  return flips;
}

}  // namespace sdvi
