// SPDX-License-Identifier: GPL-3.0-or-later
// Interior sample placement (vectorize.h building blocks): initial grid, error map,
// greedy far-apart selection.
#include "sdvi/vectorize.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstring>
#include <cmath>

#include "opencv_kernels.h"
#include "parallel.h"
#include "prefetch.h"
#include "sdvi/color_fit.h"

namespace sdvi {
namespace {

// A uniform grid of cells of side `cell` holding points, for "is any point closer than
// radius" queries with radius <= cell.
class PointGrid {
 public:
  PointGrid(int width, int height, double cell)
      : cell_(std::max(cell, 1e-3)),
        cols_(std::max(1, int(std::ceil(width / cell_)) + 1)),
        rows_(std::max(1, int(std::ceil(height / cell_)) + 1)),
        cells_(size_t(cols_) * rows_) {}

  void Add(double x, double y) { cells_[Index(x, y)].push_back({x, y}); }

  bool AnyCloserThan(double x, double y, double radius) const {
    const int cx = CellX(x), cy = CellY(y);
    const double r2 = radius * radius;
    for (int j = std::max(0, cy - 1); j <= std::min(rows_ - 1, cy + 1); ++j) {
      for (int i = std::max(0, cx - 1); i <= std::min(cols_ - 1, cx + 1); ++i) {
        for (const Point2& p : cells_[size_t(j) * cols_ + i]) {
          const double dx = p.x - x, dy = p.y - y;
          if (dx * dx + dy * dy < r2) return true;
        }
      }
    }
    return false;
  }

 private:
  int CellX(double x) const { return std::clamp(int(std::floor(x / cell_)), 0, cols_ - 1); }
  int CellY(double y) const { return std::clamp(int(std::floor(y / cell_)), 0, rows_ - 1); }
  size_t Index(double x, double y) const { return size_t(CellY(y)) * cols_ + CellX(x); }

  double cell_;
  int cols_, rows_;
  std::vector<std::vector<Point2>> cells_;
};

// OpenCV fixed-point (shift 4) pixel coordinate of source point (x, y): OpenCV puts pixel
// (i, j)'s centre at (i, j), sdvi at (i + 0.5, j + 0.5).
cv::Point FixedPoint(double x, double y) {
  return {int(std::lround((x - 0.5) * 16)), int(std::lround((y - 0.5) * 16))};
}

}  // namespace

std::vector<uint8_t> BlockedPixels(const Raster& target, const Raster* mask, const Image* mesh,
                                   const std::vector<FeatureCurve>& curves, double clearance) {
  const int width = target.width, height = target.height;
  cv::Mat1b blocked(height, width, uchar(0));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!InDomain(target, mask, x, y)) blocked(y, x) = 1;
    }
  }
  // A thin structure's curve is its centreline: its polylines reach width / 2 further.
  auto segment = [&](double x0, double y0, double x1, double y1, double width = 0) {
    const int thickness = std::max(1, int(std::lround(2 * clearance + width)));
    cv::line(blocked, FixedPoint(x0, y0), FixedPoint(x1, y1), cv::Scalar(1), thickness,
             cv::LINE_8, 4);
  };
  if (mesh != nullptr) {
    for (const Edge& e : mesh->crease_edges) {
      if (e.a >= mesh->vertices.size() || e.b >= mesh->vertices.size()) continue;
      const Vertex& a = mesh->vertices[e.a];
      const Vertex& b = mesh->vertices[e.b];
      segment(a.x, a.y, b.x, b.y);
    }
  } else {
    for (const FeatureCurve& c : curves) {
      const size_t n = c.points.size();
      for (size_t k = 0; k + 1 < n + (c.closed ? 1 : 0); ++k) {
        const Point2& a = c.points[k];
        const Point2& b = c.points[(k + 1) % n];
        segment(a.x, a.y, b.x, b.y, c.width > 0 ? c.width : 0);
      }
    }
  }
  // The image rectangle's border is a crease too.
  const int band = std::min({int(std::ceil(clearance)), width, height});
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (x < band || y < band || x >= width - band || y >= height - band) blocked(y, x) = 1;
    }
  }
  return std::vector<uint8_t>(blocked.begin(), blocked.end());
}

std::vector<Point2> GridSamples(int width, int height, double spacing,
                                const std::vector<uint8_t>& blocked) {
  std::vector<Point2> samples;
  if (!(spacing > 0)) return samples;
  const double row_step = spacing * std::sqrt(3.0) / 2;
  int row = 0;
  for (double y = row_step / 2; y < height; y += row_step, ++row) {
    for (double x = (row % 2 ? spacing : spacing / 2); x < width; x += spacing) {
      const int px = int(x), py = int(y);
      if (px < 0 || py < 0 || px >= width || py >= height) continue;
      if (blocked[size_t(py) * width + px]) continue;
      samples.push_back({px + 0.5, py + 0.5});
    }
  }
  return samples;
}

ContentBlocks FindContentBlocks(const Raster& raster, const Raster* mask, int block, double tolerance) {
  ContentBlocks content;
  if (block <= 0 || raster.empty()) return content;
  content.block = block;
  content.columns = (raster.width + block - 1) / block;
  content.rows = (raster.height + block - 1) / block;
  const int channels = raster.channels <= 2 ? 1 : 3;
  std::vector<uint8_t> busy(size_t(content.columns) * content.rows, 0);
  for (int r = 0; r < content.rows; ++r) {
    for (int c = 0; c < content.columns; ++c) {
      float low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
      bool in_domain = false;
      const int x1 = std::min(raster.width, (c + 1) * block), y1 = std::min(raster.height, (r + 1) * block);
      for (int y = r * block; y < y1; ++y) {
        for (int x = c * block; x < x1; ++x) {
          if (!InDomain(raster, mask, x, y)) continue;
          in_domain = true;
          for (int k = 0; k < channels; ++k) {
            low[k] = std::min(low[k], raster.at(x, y, k));
            high[k] = std::max(high[k], raster.at(x, y, k));
          }
        }
      }
      for (int k = 0; k < channels; ++k) {
        if (high[k] - low[k] > tolerance) busy[size_t(r) * content.columns + c] = 1;
      }
      content.domain_blocks += in_domain ? 1 : 0;
    }
  }
  const size_t stride = size_t(content.columns) + 1;
  content.busy_sum.assign(stride * (size_t(content.rows) + 1), 0);
  for (int r = 0; r < content.rows; ++r) {
    for (int c = 0; c < content.columns; ++c) {
      content.busy_sum[size_t(r + 1) * stride + c + 1] = busy[size_t(r) * content.columns + c] +
                                                         content.busy_sum[size_t(r) * stride + c + 1] +
                                                         content.busy_sum[size_t(r + 1) * stride + c] -
                                                         content.busy_sum[size_t(r) * stride + c];
    }
  }
  return content;
}

namespace {

// The Gaussian average and the -1 outside the domain of ErrorMap, on `error` in place.
void BlurAndMarkDomain(std::vector<float>& error, const Raster& target, const Raster* mask, double sigma) {
  const int width = target.width, height = target.height;
  if (sigma > 0) {
    fit_internal::UseOpenCvBaselineKernels();
    cv::Mat1f view(height, width, error.data());  // no copy: blurred in place
    cv::GaussianBlur(view, view, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
  }
  if (mask == nullptr && !target.has_alpha()) return;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!InDomain(target, mask, x, y)) error[size_t(y) * width + x] = -1.f;
    }
  }
}

}  // namespace

std::vector<float> ErrorMap(const Raster& reconstruction, const Raster& target, const Raster* mask,
                            double sigma) {
  const int width = target.width, height = target.height;
  std::vector<float> error(size_t(width) * height, 0.f);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!InDomain(target, mask, x, y)) continue;
      float sum = 0;
      for (int c = 0; c < 3; ++c) {
        const float ref = target.channels <= 2 ? target.at(x, y, 0) : target.at(x, y, c);
        const float d = reconstruction.at(x, y, c) - ref;
        sum += d * d;
      }
      error[size_t(y) * width + x] = sum;
    }
  }
  BlurAndMarkDomain(error, target, mask, sigma);
  return error;
}

std::vector<float> ErrorMap(const ColorFit& fit, const Raster& target, const Raster* mask, double sigma,
                            int threads) {
  const int width = target.width, height = target.height;
  const size_t pixels = size_t(width) * height;
  std::vector<float> error(pixels, 0.f);
  if (fit.coverage.width != width || fit.coverage.height != height || fit.coverage.owner.size() != pixels) {
    return error;
  }
  const bool grey = target.channels <= 2;
  const bool whole = mask == nullptr && !target.has_alpha();
  // Uncovered domain pixels: the reconstruction is 0 there.
  fit_internal::ForEachChunk(size_t(height), 64, threads, [&](size_t, size_t y0, size_t y1) {
    for (size_t y = y0; y < y1; ++y) {
      for (int x = 0; x < width; ++x) {
        if (!whole && !InDomain(target, mask, x, int(y))) continue;
        float sum = 0;
        for (int c = 0; c < 3; ++c) {
          const float d = 0.f - target.at(x, int(y), grey ? 0 : c);
          sum += d * d;
        }
        error[y * width + x] = sum;
      }
    }
  });
  // Covered pixels: the reconstruction as ReconstructRaster computes it, bands of rows'
  // samples (AppendSamplesInRange) on the threads.
  const std::vector<Triangle>& triangles = fit.surface.triangles;
  constexpr size_t kBandRows = 64;
  std::vector<std::vector<PixelSample>> band_samples(size_t(std::max(1, threads)));
  fit_internal::ForEachChunkOnWorkers(size_t(height), kBandRows, threads, [&](size_t worker, size_t, size_t y0, size_t y1) {
    std::vector<PixelSample>& samples = band_samples[worker];
    samples.clear();
    AppendSamplesInRange(fit.coverage, triangles, y0 * size_t(width), y1 * size_t(width), samples);
    const size_t q1 = samples.size();
    for (size_t q = 0; q < q1; ++q) {
      fit_internal::PrefetchSampleData(samples, q, q1, triangles, fit.fine);
      const PixelSample& sm = samples[q];
      const int x = int(sm.pixel % width), y = int(sm.pixel / width);
      if (!whole && !InDomain(target, mask, x, y)) continue;
      const Triangle& tri = triangles[sm.triangle];
      const Vertex& p0 = fit.fine[tri.v[0]];
      const Vertex& p1 = fit.fine[tri.v[1]];
      const Vertex& p2 = fit.fine[tri.v[2]];
      const float rec[3] = {std::clamp(sm.w0 * p0.r + sm.w1 * p1.r + sm.w2 * p2.r, 0.f, 255.f),
                            std::clamp(sm.w0 * p0.g + sm.w1 * p1.g + sm.w2 * p2.g, 0.f, 255.f),
                            std::clamp(sm.w0 * p0.b + sm.w1 * p1.b + sm.w2 * p2.b, 0.f, 255.f)};
      float sum = 0;
      for (int c = 0; c < 3; ++c) {
        const float d = rec[c] - target.at(x, y, grey ? 0 : c);
        sum += d * d;
      }
      error[sm.pixel] = sum;
    }
  });
  BlurAndMarkDomain(error, target, mask, sigma);
  return error;
}

double SpacingRule::At(double error) const {
  double r = base;
  if (exponent != 0 && error > 0 && reference_error > 0) {
    r = base * std::pow(reference_error / error, exponent);
  }
  return std::clamp(r, min, std::max(min, max));
}

std::vector<Point2> SelectRefinementSamples(const std::vector<float>& error, int width, int height,
                                            double threshold, const SpacingRule& spacing,
                                            const std::vector<Vertex>& existing,
                                            const std::vector<uint8_t>& blocked,
                                            size_t max_count) {
  std::vector<Point2> chosen;
  if (max_count == 0) return chosen;
  // Candidates by decreasing error, ties by pixel index: sorted as one 64-bit key each, the
  // error as an unsigned value that grows with it (a float's bits, the sign's flipped, a
  // negative's all flipped; -0 taken as +0; no NaN passes the threshold), inverted, above
  // the index. The sort then reads no error, and its order is the comparison's
  // (error[a] > error[b], then a < b).
  std::vector<uint64_t> candidates;
  for (size_t p = 0; p < error.size(); ++p) {
    if (error[p] > threshold && !blocked[p]) {
      const float e = error[p] + 0.0f;  // -0 -> +0
      uint32_t bits;
      std::memcpy(&bits, &e, sizeof bits);
      const uint32_t rank = (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
      candidates.push_back((uint64_t(~rank) << 32) | uint64_t(p));
    }
  }
  std::sort(candidates.begin(), candidates.end());
  PointGrid grid(width, height, std::max({spacing.base, spacing.min, spacing.max}));
  for (const Vertex& v : existing) grid.Add(v.x, v.y);
  for (const uint64_t key : candidates) {
    const uint32_t p = uint32_t(key);
    const double x = p % width + 0.5, y = double(p / width) + 0.5;
    if (grid.AnyCloserThan(x, y, spacing.At(error[p]))) continue;
    grid.Add(x, y);
    chosen.push_back({x, y});
    if (chosen.size() >= max_count) break;
  }
  return chosen;
}

}  // namespace sdvi
