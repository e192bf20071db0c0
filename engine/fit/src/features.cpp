// SPDX-License-Identifier: GPL-3.0-or-later
// Curvilinear feature detection (paper section IV step 1) and B-spline fitting (step 2).
// The rules are documented on FeatureOptions in sdvi/features.h.
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <unordered_map>

#include "contours.h"
#include "opencv_kernels.h"
#include "parallel.h"
#include "sdvi/bspline.h"
#include "sdvi/default_init_allocator.h"
#include "sdvi/features.h"

namespace sdvi {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kContrastReach = 5.0;  // px each side of the edge for the contrast C

// 8-neighbourhood in cyclic order: E, NE, N, NW, W, SW, S, SE.
constexpr int kDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kDy[8] = {0, -1, -1, -1, 0, 1, 1, 1};

// The gradient field: magnitude and unit normal (across the edge) per pixel.
struct GradientField {
  int width = 0, height = 0;
  cv::Mat mag, nx, ny;               // CV_32F
  std::vector<cv::Mat> smoothed;     // smoothed colour channels, CV_32F
  // SuppressAndLink's sub-pixel peak offsets, at its candidates only (the pixels an edge
  // can take), by ascending pixel index y * width + x: no per-pixel plane.
  std::vector<uint32_t> offset_pixels;
  std::vector<float> offsets;
  // The matrices' storage, plane after plane, on huge pages from the first byte (a fresh
  // 4 KiB page costs a fault, slow on virtual machines: sdvi/default_init_allocator.h).
  std::vector<float, DefaultInitAllocator<float>> planes;

  // The peak offset SuppressAndLink found at pixel (x, y); 0 where it found none.
  float OffsetAt(int x, int y) const {
    const uint32_t p = uint32_t(y) * uint32_t(width) + uint32_t(x);
    const auto it = std::lower_bound(offset_pixels.begin(), offset_pixels.end(), p);
    return it != offset_pixels.end() && *it == p ? offsets[size_t(it - offset_pixels.begin())] : 0.0f;
  }
};

float Bilinear(const cv::Mat& m, double x, double y) {
  // (x, y) in pixel-index coordinates (pixel centres at integers); clamped to the image.
  x = std::clamp(x, 0.0, double(m.cols - 1));
  y = std::clamp(y, 0.0, double(m.rows - 1));
  int x0 = std::min(int(x), m.cols - 2 < 0 ? 0 : m.cols - 2);
  int y0 = std::min(int(y), m.rows - 2 < 0 ? 0 : m.rows - 2);
  int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
  float fx = float(x - x0), fy = float(y - y0);
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y1);
  return (r0[x0] * (1 - fx) + r0[x1] * fx) * (1 - fy) + (r1[x0] * (1 - fx) + r1[x1] * fx) * fy;
}

// Rows per band of the per-pixel passes (parallel.h: the bands do not depend on the
// thread count, and every pixel's value is computed as on the whole image).
constexpr size_t kBandRows = 64;

// The smoothed channels, their Sobel derivatives and the structure tensor's principal
// eigenvector, in passes over bands of rows on the threads: the channels apart, each
// smoothed, then the derivatives, the tensor and its eigenvector. The filters run on views
// of bands of the whole matrices: OpenCV reads the rows around a view as the neighbouring
// image rows and applies the border only at the image's top and bottom, so every value has
// the bits of the filters run on the whole image. The derivatives are a band's scratch
// (two band-sized matrices), not whole planes.
GradientField ComputeGradient(const Raster& image, double sigma, int threads) {
  fit_internal::UseOpenCvBaselineKernels();
  GradientField g;
  const int w = image.width, h = image.height;
  g.width = w;
  g.height = h;
  const int nc = image.channels >= 3 ? 3 : 1;
  const size_t plane = size_t(w) * size_t(h);
  g.planes.resize(plane * size_t(3 + nc));  // unwritten: each band writes its own rows
  auto plane_mat = [&](int k) { return cv::Mat(h, w, CV_32F, g.planes.data() + plane * size_t(k)); };
  g.mag = plane_mat(0);
  g.nx = plane_mat(1);
  g.ny = plane_mat(2);
  for (int c = 0; c < nc; ++c) g.smoothed.push_back(plane_mat(3 + c));
  // The channels apart, into mag, nx, ny (free until the tensor), or, unsmoothed, as they are.
  const cv::Mat channel[3] = {g.mag, g.nx, g.ny};
  fit_internal::ForEachChunk(size_t(h), kBandRows, threads, [&](size_t, size_t y0, size_t y1) {
    for (int c = 0; c < nc; ++c) {
      cv::Mat out = sigma > 0 ? channel[c] : g.smoothed[c];
      for (int y = int(y0); y < int(y1); ++y) {
        float* row = out.ptr<float>(y);
        const float* px = &image.data[size_t(y) * size_t(w) * size_t(image.channels) + size_t(c)];
        for (int x = 0; x < w; ++x) row[x] = px[size_t(x) * size_t(image.channels)];
      }
    }
  });
  if (sigma > 0) {
    fit_internal::ForEachChunk(size_t(h), kBandRows, threads, [&](size_t, size_t y0, size_t y1) {
      for (int c = 0; c < nc; ++c) {
        cv::Mat out = g.smoothed[c].rowRange(int(y0), int(y1));
        cv::GaussianBlur(channel[c].rowRange(int(y0), int(y1)), out, cv::Size(0, 0), sigma, sigma,
                         cv::BORDER_REPLICATE);
      }
    });
  }
  // The tensor [jxx jxy; jxy jyy] in mag, nx, ny, the derivatives in a band's scratch.
  fit_internal::ForEachChunk(size_t(h), kBandRows, threads, [&](size_t, size_t b0, size_t b1) {
    const int y0 = int(b0), y1 = int(b1);
    for (const cv::Mat& m : channel) m.rowRange(y0, y1).setTo(0.0f);
    cv::Mat gx(y1 - y0, w, CV_32F), gy(y1 - y0, w, CV_32F);
    for (int c = 0; c < nc; ++c) {
      const cv::Mat band = g.smoothed[c].rowRange(y0, y1);
      cv::Sobel(band, gx, CV_32F, 1, 0, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
      cv::Sobel(band, gy, CV_32F, 0, 1, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
      // Summed over the channels in channel order, float products and sums.
      for (int y = y0; y < y1; ++y) {
        const float* dx = gx.ptr<float>(y - y0);
        const float* dy = gy.ptr<float>(y - y0);
        float* a = g.mag.ptr<float>(y);
        float* b = g.nx.ptr<float>(y);
        float* d = g.ny.ptr<float>(y);
        for (int x = 0; x < w; ++x) {
          const float xx = dx[x] * dx[x], xy = dx[x] * dy[x], yy = dy[x] * dy[x];
          a[x] += xx;
          b[x] += xy;
          d[x] += yy;
        }
      }
    }
    // Principal eigenvector in place: jxx -> mag, jxy -> nx, jyy -> ny.
    for (int y = y0; y < y1; ++y) {
      float* a = g.mag.ptr<float>(y);
      float* b = g.nx.ptr<float>(y);
      float* d = g.ny.ptr<float>(y);
      for (int x = 0; x < w; ++x) {
        double half = 0.5 * (a[x] - d[x]);
        double root = std::sqrt(half * half + double(b[x]) * b[x]);
        double l1 = 0.5 * (a[x] + d[x]) + root;
        double vx, vy;
        if (half >= 0) {
          vx = half + root;
          vy = b[x];
        } else {
          vx = b[x];
          vy = -half + root;
        }
        double len = std::hypot(vx, vy);
        if (len > 1e-12) {
          vx /= len;
          vy /= len;
        } else {
          vx = 1;
          vy = 0;
        }
        a[x] = float(std::sqrt(std::max(0.0, l1) / nc));
        b[x] = float(vx);
        d[x] = float(vy);
      }
    }
  });
  return g;
}

// Hysteresis threshold: explicit, or max(floor, quantile of the magnitude in the domain).
double HighThreshold(const GradientField& g, const cv::Mat& domain, const FeatureOptions& o, int threads) {
  if (o.high_threshold > 0) return o.high_threshold;
  // Histogram of magnitudes, 0.25 units per bin (counts per band, then added).
  constexpr int kBins = 1024;
  constexpr double kBinWidth = 0.25;
  std::vector<std::vector<uint64_t>> band_hist(fit_internal::ChunkCount(size_t(g.height), kBandRows));
  fit_internal::ForEachChunk(size_t(g.height), kBandRows, threads, [&](size_t band, size_t y0, size_t y1) {
    std::vector<uint64_t>& hist = band_hist[band];
    hist.assign(kBins, 0);
    for (size_t y = y0; y < y1; ++y) {
      const float* m = g.mag.ptr<float>(int(y));
      const uint8_t* d = domain.empty() ? nullptr : domain.ptr<uint8_t>(int(y));
      for (int x = 0; x < g.width; ++x) {
        if (d && !d[x]) continue;
        hist[std::min(kBins - 1, int(m[x] / kBinWidth))]++;
      }
    }
  });
  std::vector<uint64_t> hist(kBins, 0);
  uint64_t total = 0;
  for (const std::vector<uint64_t>& b : band_hist)
    for (int i = 0; i < kBins; ++i) {
      hist[i] += b[i];
      total += b[i];
    }
  double q = 0;
  uint64_t target = uint64_t(std::clamp(o.high_quantile, 0.0, 1.0) * double(total));
  uint64_t acc = 0;
  for (int i = 0; i < kBins; ++i) {
    acc += hist[i];
    if (acc >= target) {
      q = (i + 1) * kBinWidth;
      break;
    }
  }
  return std::max(o.min_high_threshold, q);
}

// Non-maximum suppression across the edge + hysteresis. Returns the edge map (1 = edge) and
// fills g's offsets, the sub-pixel offset of each candidate's peak along its normal.
cv::Mat SuppressAndLink(GradientField& g, const cv::Mat& domain, double high, double low, int threads) {
  const int w = g.width, h = g.height;
  cv::Mat cand(h, w, CV_8U);  // 1 = candidate, 2 = strong; each band zeroes its rows first
  // Each band's candidates and their offsets, concatenated in band order (ascending pixel).
  struct BandOffsets {
    std::vector<uint32_t> pixels;
    std::vector<float> offsets;
  };
  std::vector<BandOffsets> band_offsets(fit_internal::ChunkCount(size_t(h), kBandRows));
  fit_internal::ForEachChunk(size_t(h), kBandRows, threads, [&](size_t band, size_t y0, size_t y1) {
    BandOffsets& found = band_offsets[band];
    for (int y = int(y0); y < int(y1); ++y) {
      const float* m = g.mag.ptr<float>(y);
      const float* nx = g.nx.ptr<float>(y);
      const float* ny = g.ny.ptr<float>(y);
      const uint8_t* d = domain.empty() ? nullptr : domain.ptr<uint8_t>(y);
      uint8_t* c = cand.ptr<uint8_t>(y);
      std::fill(c, c + w, uint8_t(0));
      for (int x = 0; x < w; ++x) {
        if (m[x] < low || (d && !d[x])) continue;
        float a = Bilinear(g.mag, x - nx[x], y - ny[x]);
        float b = Bilinear(g.mag, x + nx[x], y + ny[x]);
        // Ties: keep the pixel on the "minus" side only, so plateaus give one line.
        if (!(m[x] > a && m[x] >= b)) continue;
        double denom = a - 2.0 * m[x] + b;
        double delta = denom < 0 ? 0.5 * (a - b) / denom : 0.0;
        found.pixels.push_back(uint32_t(y) * uint32_t(w) + uint32_t(x));
        found.offsets.push_back(float(std::clamp(delta, -0.5, 0.5)));
        c[x] = m[x] >= high ? 2 : 1;
      }
    }
  });
  {
    size_t total = 0;
    for (const BandOffsets& b : band_offsets) total += b.pixels.size();
    g.offset_pixels.reserve(total);
    g.offsets.reserve(total);
    for (BandOffsets& b : band_offsets) {
      g.offset_pixels.insert(g.offset_pixels.end(), b.pixels.begin(), b.pixels.end());
      g.offsets.insert(g.offsets.end(), b.offsets.begin(), b.offsets.end());
      b = BandOffsets();
    }
  }
  // Hysteresis: keep candidates 8-connected to a strong pixel. The pixels reached are
  // marked in cand itself (no second map), which then becomes the edge map.
  constexpr uint8_t kReached = 0x80;
  std::vector<int> stack;
  for (int y = 0; y < h; ++y) {
    uint8_t* c = cand.ptr<uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      if (c[x] != 2) continue;  // not strong, or reached already
      c[x] |= kReached;
      stack.push_back(y * w + x);
      while (!stack.empty()) {
        int p = stack.back();
        stack.pop_back();
        int px = p % w, py = p / w;
        for (int k = 0; k < 8; ++k) {
          int qx = px + kDx[k], qy = py + kDy[k];
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          uint8_t& q = cand.at<uint8_t>(qy, qx);
          if (!q || (q & kReached)) continue;
          q |= kReached;
          stack.push_back(qy * w + qx);
        }
      }
    }
  }
  fit_internal::ForEachChunk(size_t(h), kBandRows, threads, [&](size_t, size_t y0, size_t y1) {
    for (int y = int(y0); y < int(y1); ++y) {
      uint8_t* c = cand.ptr<uint8_t>(y);
      for (int x = 0; x < w; ++x) c[x] = (c[x] & kReached) ? 1 : 0;
    }
  });
  return cand;
}

uint8_t NeighbourBits(const cv::Mat& edge, int x, int y) {
  uint8_t bits = 0;
  for (int k = 0; k < 8; ++k) {
    int qx = x + kDx[k], qy = y + kDy[k];
    if (qx >= 0 && qy >= 0 && qx < edge.cols && qy < edge.rows && edge.at<uint8_t>(qy, qx))
      bits |= uint8_t(1u << k);
  }
  return bits;
}

// removable[bits]: a pixel whose set neighbours (>= 2) form one 8-connected group can be
// removed without changing connectivity (it is a staircase corner or a thick-line pixel).
std::array<bool, 256> RemovableTable() {
  std::array<bool, 256> table{};
  for (int bits = 0; bits < 256; ++bits) {
    int parent[8];
    std::iota(parent, parent + 8, 0);
    auto find = [&](int i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    int count = 0;
    for (int k = 0; k < 8; ++k) {
      if (!(bits >> k & 1)) continue;
      ++count;
      int next = (k + 1) % 8;
      if (bits >> next & 1) parent[find(k)] = find(next);
      // Two 4-neighbours two steps apart (E and N, ...) touch diagonally.
      int next2 = (k + 2) % 8;
      if (k % 2 == 0 && (bits >> next2 & 1)) parent[find(k)] = find(next2);
    }
    int groups = 0;
    for (int k = 0; k < 8; ++k)
      if ((bits >> k & 1) && find(k) == k) ++groups;
    table[bits] = count >= 2 && groups == 1;
  }
  return table;
}

void Thin(cv::Mat& edge) {
  static const std::array<bool, 256> removable = RemovableTable();
  for (int pass = 0; pass < 2; ++pass) {
    bool changed = false;
    for (int y = 0; y < edge.rows; ++y)
      for (int x = 0; x < edge.cols; ++x) {
        if (!edge.at<uint8_t>(y, x)) continue;
        if (removable[NeighbourBits(edge, x, y)]) {
          edge.at<uint8_t>(y, x) = 0;
          changed = true;
        }
      }
    if (!changed) break;
  }
}

struct Chain {
  std::vector<int> pixels;  // y * width + x, in order
  bool closed = false;
};

// Links the thinned edge map into chains that run between nodes (pixels with 1 or >= 3
// neighbours) and closed loops; scan order makes the result deterministic.
std::vector<Chain> LinkChains(const cv::Mat& edge) {
  const int w = edge.cols, h = edge.rows;
  cv::Mat degree(h, w, CV_8U), visited(h, w, CV_8U);
  for (int y = 0; y < h; ++y) {
    const uint8_t* e = edge.ptr<uint8_t>(y);
    uint8_t* d = degree.ptr<uint8_t>(y);
    for (int x = 0; x < w; ++x) d[x] = e[x] ? uint8_t(__builtin_popcount(NeighbourBits(edge, x, y))) : 0;
  }
  visited.setTo(0);
  auto is_node = [&](int x, int y) {
    uint8_t d = degree.at<uint8_t>(y, x);
    return d != 2;
  };
  std::vector<Chain> chains;
  auto trace = [&](int sx, int sy, int fx, int fy, bool from_node) {
    Chain c;
    c.pixels.push_back(sy * w + sx);
    int px = sx, py = sy, cx = fx, cy = fy;
    visited.at<uint8_t>(cy, cx) = 1;
    c.pixels.push_back(cy * w + cx);
    while (true) {
      if (is_node(cx, cy)) break;
      int nxp = -1, nyp = -1;
      for (int k = 0; k < 8; ++k) {
        int qx = cx + kDx[k], qy = cy + kDy[k];
        if (qx < 0 || qy < 0 || qx >= w || qy >= h || !edge.at<uint8_t>(qy, qx)) continue;
        if (qx == px && qy == py) continue;
        nxp = qx;
        nyp = qy;
        break;
      }
      if (nxp < 0) break;
      if (!from_node && nxp == sx && nyp == sy) {
        c.closed = true;
        break;
      }
      if (visited.at<uint8_t>(nyp, nxp) && !is_node(nxp, nyp)) break;
      px = cx;
      py = cy;
      cx = nxp;
      cy = nyp;
      if (!is_node(cx, cy)) visited.at<uint8_t>(cy, cx) = 1;
      c.pixels.push_back(cy * w + cx);
    }
    chains.push_back(std::move(c));
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!edge.at<uint8_t>(y, x) || !is_node(x, y)) continue;
      for (int k = 0; k < 8; ++k) {
        int qx = x + kDx[k], qy = y + kDy[k];
        if (qx < 0 || qy < 0 || qx >= w || qy >= h || !edge.at<uint8_t>(qy, qx)) continue;
        if (is_node(qx, qy) || visited.at<uint8_t>(qy, qx)) continue;
        trace(x, y, qx, qy, true);
      }
    }
  // Loops without nodes.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!edge.at<uint8_t>(y, x) || visited.at<uint8_t>(y, x) || is_node(x, y)) continue;
      visited.at<uint8_t>(y, x) = 1;
      int fx = -1, fy = -1;
      for (int k = 0; k < 8; ++k) {
        int qx = x + kDx[k], qy = y + kDy[k];
        if (qx < 0 || qy < 0 || qx >= w || qy >= h || !edge.at<uint8_t>(qy, qx)) continue;
        fx = qx;
        fy = qy;
        break;
      }
      if (fx < 0) continue;
      trace(x, y, fx, fy, false);
    }
  return chains;
}

// Good continuation through junctions: at each junction (a cluster of 8-adjacent pixels
// with >= 3 neighbours) the two chain ends that continue each other best (directions
// over the last kJoinReach pixels at least kJoinAngleDeg apart) are joined, repeatedly,
// so that a curve crossed or touched by another stays one chain.
std::vector<Chain> JoinAtJunctions(std::vector<Chain> chains, const cv::Mat& edge) {
  constexpr int kJoinReach = 6;
  constexpr double kJoinCos = -0.8;  // ~143 degrees between the two inward directions
  const int w = edge.cols, h = edge.rows;
  auto junction = [&](int p) {
    int x = p % w, y = p / w;
    return __builtin_popcount(NeighbourBits(edge, x, y)) >= 3;
  };
  // Junction clusters.
  std::unordered_map<int, int> cluster;
  int clusters = 0;
  for (const Chain& c : chains) {
    if (c.closed) continue;
    for (int end : {c.pixels.front(), c.pixels.back()}) {
      if (cluster.count(end) || !junction(end)) continue;
      std::vector<int> stack{end};
      cluster[end] = clusters;
      while (!stack.empty()) {
        int p = stack.back();
        stack.pop_back();
        int px = p % w, py = p / w;
        for (int k = 0; k < 8; ++k) {
          int qx = px + kDx[k], qy = py + kDy[k];
          if (qx < 0 || qy < 0 || qx >= w || qy >= h || !edge.at<uint8_t>(qy, qx)) continue;
          int q = qy * w + qx;
          if (cluster.count(q) || !junction(q)) continue;
          cluster[q] = clusters;
          stack.push_back(q);
        }
      }
      ++clusters;
    }
  }
  // Chain ends per cluster: end id = 2 * chain + (0 front, 1 back).
  std::vector<std::vector<int>> ends(clusters);
  auto inward = [&](const Chain& c, bool back) {
    const int n = int(c.pixels.size());
    int a = back ? c.pixels[n - 1] : c.pixels[0];
    int b = back ? c.pixels[std::max(0, n - 1 - kJoinReach)] : c.pixels[std::min(n - 1, kJoinReach)];
    double dx = b % w - a % w, dy = b / w - a / w, l = std::hypot(dx, dy);
    return l > 0 ? Point2{dx / l, dy / l} : Point2{0, 0};
  };
  for (size_t i = 0; i < chains.size(); ++i) {
    const Chain& c = chains[i];
    if (c.closed || c.pixels.size() < 3) continue;
    auto f = cluster.find(c.pixels.front());
    if (f != cluster.end()) ends[f->second].push_back(int(2 * i));
    auto b = cluster.find(c.pixels.back());
    if (b != cluster.end()) ends[b->second].push_back(int(2 * i + 1));
  }
  std::vector<int> partner(2 * chains.size(), -1);
  for (const std::vector<int>& e : ends) {
    struct Candidate {
      double cos;
      int a, b;
    };
    std::vector<Candidate> cand;
    for (size_t i = 0; i < e.size(); ++i)
      for (size_t j = i + 1; j < e.size(); ++j) {
        if (e[i] / 2 == e[j] / 2) continue;  // a chain's two ends: would close a loop
        Point2 da = inward(chains[e[i] / 2], e[i] % 2), db = inward(chains[e[j] / 2], e[j] % 2);
        double c = da.x * db.x + da.y * db.y;
        if (c <= kJoinCos) cand.push_back({c, e[i], e[j]});
      }
    std::stable_sort(cand.begin(), cand.end(), [](const Candidate& x, const Candidate& y) { return x.cos < y.cos; });
    for (const Candidate& c : cand)
      if (partner[c.a] < 0 && partner[c.b] < 0) {
        partner[c.a] = c.b;
        partner[c.b] = c.a;
      }
  }
  // Walk the joined paths; joins that would close a cycle are cut at the first chain.
  std::vector<Chain> out;
  std::vector<bool> used(chains.size(), false);
  auto walk = [&](size_t start, int entry_end) {
    Chain merged;
    size_t chain = start;
    int entry = entry_end;  // the end we enter the chain by (0 front, 1 back)
    while (true) {
      used[chain] = true;
      const auto& px = chains[chain].pixels;
      std::vector<int> seq(px.begin(), px.end());
      if (entry == 1) std::reverse(seq.begin(), seq.end());
      size_t skip = (!merged.pixels.empty() && merged.pixels.back() == seq.front()) ? 1 : 0;
      merged.pixels.insert(merged.pixels.end(), seq.begin() + skip, seq.end());
      int exit_end = int(2 * chain) + (entry == 0 ? 1 : 0);
      int next = partner[exit_end];
      if (next >= 0 && size_t(next / 2) == start && next % 2 == entry_end && chain != start) {
        merged.closed = true;  // the joins went all the way round
        if (merged.pixels.size() > 1 && merged.pixels.back() == merged.pixels.front()) merged.pixels.pop_back();
        break;
      }
      if (next < 0 || used[next / 2]) break;
      chain = size_t(next / 2);
      entry = next % 2;
    }
    out.push_back(std::move(merged));
  };
  for (size_t i = 0; i < chains.size(); ++i) {
    if (used[i]) continue;
    if (chains[i].closed) {
      used[i] = true;
      out.push_back(chains[i]);
      continue;
    }
    // Start at a path end: an end without partner.
    if (partner[2 * i] < 0) walk(i, 0);
    else if (partner[2 * i + 1] < 0) walk(i, 1);
  }
  for (size_t i = 0; i < chains.size(); ++i)
    if (!used[i]) walk(i, 0);  // cycles of joined chains: cut open at i
  return out;
}

double ChainLength(const std::vector<Point2>& p, bool closed) {
  double len = 0;
  for (size_t i = 1; i < p.size(); ++i) len += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
  if (closed && p.size() > 2) len += std::hypot(p[0].x - p.back().x, p[0].y - p.back().y);
  return len;
}

// sigma_0: the edge width (px) a perfect step gets from our smoothing, the pixel grid and
// the Sobel difference (measured on synthetic steps: sqrt(sigma^2 + 0.45)).
double BaseWidth(double sigma) { return std::sqrt(sigma * sigma + 0.45); }

// Blur width sigma_b of the image at one edge pixel (see FeatureOptions); *contrast gets
// the colour distance C across the edge.
double PixelBlur(const GradientField& g, int x, int y, double sigma, double* contrast) {
  float m = g.mag.at<float>(y, x);
  double nx = g.nx.at<float>(y, x), ny = g.ny.at<float>(y, x);
  double c2 = 0;
  for (const cv::Mat& s : g.smoothed) {
    double a = Bilinear(s, x + kContrastReach * nx, y + kContrastReach * ny);
    double b = Bilinear(s, x - kContrastReach * nx, y - kContrastReach * ny);
    c2 += (a - b) * (a - b);
  }
  *contrast = std::sqrt(c2 / double(g.smoothed.size()));
  if (m <= 1e-3f) return 0;
  double width = *contrast / (std::sqrt(2 * kPi) * m);
  double base = BaseWidth(sigma);
  return std::sqrt(std::max(0.0, width * width - base * base));
}

// What the chains' measurement reads of the gradient at the edge pixels, taken before the
// gradient's planes are released (chaining and joining need only the edge map): per edge
// pixel (ascending index y * width + x), its peak offset, normal, blur and contrast.
struct EdgeMeasures {
  struct At {
    float offset, nx, ny;
    double blur, contrast;
  };
  int width = 0;
  std::vector<uint32_t> pixels;
  std::vector<At> values;

  // The measures of edge pixel (x, y); the caller's pixel must be one of the edge map's
  // (the chains are made of edge pixels only).
  const At& Find(int x, int y) const {
    const uint32_t p = uint32_t(y) * uint32_t(width) + uint32_t(x);
    const auto it = std::lower_bound(pixels.begin(), pixels.end(), p);
    assert(it != pixels.end() && *it == p);
    return values[size_t(it - pixels.begin())];
  }
};

// The measures of every pixel of edge (bands of rows on the threads, gathered in order).
EdgeMeasures MeasureEdgePixels(const GradientField& g, const cv::Mat& edge, double sigma, int threads) {
  struct Band {
    std::vector<uint32_t> pixels;
    std::vector<EdgeMeasures::At> values;
  };
  std::vector<Band> bands(fit_internal::ChunkCount(size_t(g.height), kBandRows));
  fit_internal::ForEachChunk(size_t(g.height), kBandRows, threads, [&](size_t band, size_t y0, size_t y1) {
    Band& b = bands[band];
    for (int y = int(y0); y < int(y1); ++y) {
      const uint8_t* e = edge.ptr<uint8_t>(y);
      for (int x = 0; x < g.width; ++x) {
        if (!e[x]) continue;
        EdgeMeasures::At at;
        at.offset = g.OffsetAt(x, y);
        at.nx = g.nx.at<float>(y, x);
        at.ny = g.ny.at<float>(y, x);
        at.blur = PixelBlur(g, x, y, sigma, &at.contrast);
        b.pixels.push_back(uint32_t(y) * uint32_t(g.width) + uint32_t(x));
        b.values.push_back(at);
      }
    }
  });
  EdgeMeasures m;
  m.width = g.width;
  for (Band& b : bands) {
    m.pixels.insert(m.pixels.end(), b.pixels.begin(), b.pixels.end());
    m.values.insert(m.values.end(), b.values.begin(), b.values.end());
    b = Band();
  }
  return m;
}

// Otsu's threshold of values in [0, 1] weighted by weights; returns the two class means
// and the threshold.
void OtsuTwoClasses(const std::vector<double>& v, const std::vector<double>& wt, double* thr,
                    double* mean_lo, double* mean_hi) {
  constexpr int kBins = 64;
  std::vector<double> hist(kBins, 0), sum(kBins, 0);
  double total = 0, total_sum = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    int b = std::clamp(int(v[i] * kBins), 0, kBins - 1);
    hist[b] += wt[i];
    sum[b] += wt[i] * v[i];
    total += wt[i];
    total_sum += wt[i] * v[i];
  }
  double best = -1, w0 = 0, s0 = 0;
  *thr = 1.0;
  for (int b = 0; b + 1 < kBins; ++b) {
    w0 += hist[b];
    s0 += sum[b];
    double w1 = total - w0;
    if (w0 <= 0 || w1 <= 0) continue;
    double m0 = s0 / w0, m1 = (total_sum - s0) / w1;
    double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      *thr = double(b + 1) / kBins;
    }
  }
  double lo_w = 0, lo_s = 0, hi_w = 0, hi_s = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] < *thr) {
      lo_w += wt[i];
      lo_s += wt[i] * v[i];
    } else {
      hi_w += wt[i];
      hi_s += wt[i] * v[i];
    }
  }
  *mean_lo = lo_w > 0 ? lo_s / lo_w : 0;
  *mean_hi = hi_w > 0 ? hi_s / hi_w : 1;
}

// False when no pixel's gradient magnitude can reach the hysteresis' low threshold, so the
// edge map is empty whatever the per-pixel passes compute (an image of one colour, or
// nearly): the Gaussian keeps each channel within its range R, the Sobel derivative
// (scaled by 1/8) is then at most R / 2 in x and in y, and the magnitude, the root of the
// structure tensor's larger eigenvalue (at most its trace) over the channels, at most
// R / sqrt(2). The test asks R < low, a margin far beyond the filters' rounding.
bool CanHaveEdges(const Raster& image, const FeatureOptions& o) {
  const double high = o.high_threshold > 0 ? o.high_threshold : o.min_high_threshold;
  const double low = o.low_ratio * high;  // the low threshold is at least this
  const int nc = image.channels >= 3 ? 3 : 1;
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  const size_t pixels = size_t(image.width) * image.height;
  for (size_t p = 0; p < pixels; ++p) {
    const float* px = &image.data[p * size_t(image.channels)];
    for (int c = 0; c < nc; ++c) {
      lo[c] = std::min(lo[c], px[c]);
      hi[c] = std::max(hi[c], px[c]);
    }
  }
  for (int c = 0; c < nc; ++c) {
    if (!(double(hi[c]) - double(lo[c]) < low)) return true;
  }
  return false;
}

Status ValidateOptions(const FeatureOptions& o) {
  auto bad = [](const char* name, double v) {
    return Status(StatusCode::kInvalidArgument,
                  std::string("feature option ") + name + " = " + std::to_string(v) + " is out of range");
  };
  if (!(o.smoothing_sigma >= 0 && o.smoothing_sigma <= 20)) return bad("smoothing_sigma", o.smoothing_sigma);
  if (!(o.high_threshold >= 0)) return bad("high_threshold", o.high_threshold);
  if (!(o.low_ratio > 0 && o.low_ratio <= 1)) return bad("low_ratio", o.low_ratio);
  if (!(o.high_quantile >= 0 && o.high_quantile <= 1)) return bad("high_quantile", o.high_quantile);
  if (!(o.min_chain_length >= 0)) return bad("min_chain_length", o.min_chain_length);
  if (!(o.corner_angle_deg > 0 && o.corner_angle_deg <= 180)) return bad("corner_angle_deg", o.corner_angle_deg);
  if (!(o.corner_window >= 1 && o.corner_window <= 64)) return bad("corner_window", o.corner_window);
  if (!(o.blur_scale > 0)) return bad("blur_scale", o.blur_scale);
  if (!(o.fit_tolerance > 0)) return bad("fit_tolerance", o.fit_tolerance);
  if (!(o.max_spacing >= 2)) return bad("max_spacing", o.max_spacing);
  if (!(o.min_domain_area >= 0)) return bad("min_domain_area", o.min_domain_area);
  return Status::Ok();
}

}  // namespace

std::vector<uint32_t> FindChainCorners(const std::vector<Point2>& p, bool closed,
                                       double angle_deg, int window) {
  const int m = int(p.size());
  std::vector<uint32_t> corners;
  if (m < 2 * window + 1) return corners;
  const double thr = angle_deg * kPi / 180;
  std::vector<double> turn(m, 0.0);
  for (int i = 0; i < m; ++i) {
    int a = i - window, b = i + window;
    if (!closed && (a < 0 || b >= m)) continue;
    const Point2& pa = p[(a + m) % m];
    const Point2& pb = p[b % m];
    double v1x = p[i].x - pa.x, v1y = p[i].y - pa.y, v2x = pb.x - p[i].x, v2y = pb.y - p[i].y;
    double l1 = std::hypot(v1x, v1y), l2 = std::hypot(v2x, v2y);
    if (l1 < 1e-9 || l2 < 1e-9) continue;
    double c = std::clamp((v1x * v2x + v1y * v2y) / (l1 * l2), -1.0, 1.0);
    turn[i] = std::acos(c);
  }
  for (int i = 0; i < m; ++i) {
    if (turn[i] <= thr) continue;
    bool is_max = true;
    for (int k = -window; k <= window && is_max; ++k) {
      if (k == 0) continue;
      int j = i + k;
      if (!closed && (j < 0 || j >= m)) continue;
      j = (j + m) % m;
      // Strict maximum on the left, >= on the right: plateaus give one corner.
      if (turn[j] > turn[i] || (k < 0 && turn[j] == turn[i])) is_max = false;
    }
    if (!is_max) continue;
    if (!closed && (i < window || i >= m - window)) continue;
    corners.push_back(uint32_t(i));
  }
  return corners;
}

StatusOr<std::vector<FeatureCurve>> DetectFeatures(const Raster& image, const Raster* mask,
                                                   const FeatureOptions& options) {
  SDVI_RETURN_IF_ERROR(ValidateOptions(options));
  if (image.empty() || image.channels < 1 || image.channels > 4 ||
      image.data.size() != size_t(image.width) * image.height * image.channels)
    return Status(StatusCode::kEmptyInput, "DetectFeatures: image is empty or its size (" +
                                               std::to_string(image.width) + "x" + std::to_string(image.height) +
                                               "x" + std::to_string(image.channels) + ") disagrees with its data");
  for (float v : image.data)
    if (!std::isfinite(v)) return Status(StatusCode::kNonFinite, "DetectFeatures: image has a NaN or infinite sample");
  const int w = image.width, h = image.height;

  // Domain: mask channel 0 > 0.5, else alpha > 0.5, else everything.
  cv::Mat domain;
  bool object_mode = false;
  if (mask) {
    if (mask->width != w || mask->height != h || mask->channels < 1 ||
        mask->data.size() != size_t(w) * h * mask->channels)
      return Status(StatusCode::kInvalidArgument,
                    "DetectFeatures: mask is " + std::to_string(mask->width) + "x" + std::to_string(mask->height) +
                        ", expected the image size " + std::to_string(w) + "x" + std::to_string(h));
    domain = cv::Mat::zeros(h, w, CV_8U);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) domain.at<uint8_t>(y, x) = mask->at(x, y, 0) > 0.5f ? 1 : 0;
    object_mode = true;
  } else if (image.has_alpha()) {
    domain = cv::Mat::zeros(h, w, CV_8U);
    const int ac = image.channels - 1;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) domain.at<uint8_t>(y, x) = image.at(x, y, ac) > 0.5f ? 1 : 0;
    object_mode = cv::countNonZero(domain) < w * h;
  }

  std::vector<FeatureCurve> curves;
  cv::Mat edge_domain;  // where interior edges may be detected
  if (object_mode) {
    SDVI_ASSIGN_OR_RETURN(curves, DomainBoundaryCurves(domain, options));
    // Stay a few pixels inside the domain: its rim is a boundary curve already.
    int r = int(std::ceil(2 * options.smoothing_sigma)) + 2;
    cv::erode(domain, edge_domain, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  }
  if (!options.detect_edges || !CanHaveEdges(image, options)) return curves;

  const int threads = std::max(1, options.threads);
  GradientField g = ComputeGradient(image, options.smoothing_sigma, threads);
  if (object_mode) {
    // Colours outside the domain are arbitrary: do not let them into the gradient.
    g.mag.setTo(0.0f, edge_domain == 0);
  }
  const double high = HighThreshold(g, edge_domain, options, threads);
  const double low = options.low_ratio * high;
  cv::Mat edge = SuppressAndLink(g, edge_domain, high, low, threads);
  Thin(edge);
  // The chains read the gradient at edge pixels only: those values are kept, the planes
  // released before chaining (less peak memory).
  const EdgeMeasures measures = MeasureEdgePixels(g, edge, options.smoothing_sigma, threads);
  g = GradientField();
  std::vector<Chain> chains = JoinAtJunctions(LinkChains(edge), edge);

  // Samples, blur and length per chain, chains in chunks on the threads; the kept ones in
  // chain order.
  struct Kept {
    std::vector<Point2> samples;
    bool closed;
    double blur;
    double contrast;
    double length;
    bool keep = false;
  };
  constexpr size_t kChainChunk = 32;
  std::vector<Kept> measured(chains.size());
  fit_internal::ForEachChunk(chains.size(), kChainChunk, threads, [&](size_t, size_t i0, size_t i1) {
    std::vector<double> blurs, contrasts;
    for (size_t i = i0; i < i1; ++i) {
      const Chain& c = chains[i];
      Kept& k = measured[i];
      k.closed = c.closed;
      blurs.clear();
      contrasts.clear();
      k.samples.reserve(c.pixels.size());
      for (int p : c.pixels) {
        int x = p % w, y = p / w;
        const EdgeMeasures::At& at = measures.Find(x, y);
        double d = at.offset;
        k.samples.push_back({x + 0.5 + d * at.nx, y + 0.5 + d * at.ny});
        blurs.push_back(at.blur);
        contrasts.push_back(at.contrast);
      }
      k.length = ChainLength(k.samples, k.closed);
      if (k.length < options.min_chain_length || k.samples.size() < 3) {
        std::vector<Point2>().swap(k.samples);
        continue;
      }
      std::nth_element(blurs.begin(), blurs.begin() + blurs.size() / 2, blurs.end());
      k.blur = std::min(1.0, blurs[blurs.size() / 2] / options.blur_scale);
      std::nth_element(contrasts.begin(), contrasts.begin() + contrasts.size() / 2, contrasts.end());
      k.contrast = contrasts[contrasts.size() / 2];
      k.keep = true;
    }
  });
  std::vector<Chain>().swap(chains);
  std::vector<Kept> kept;
  for (Kept& k : measured)
    if (k.keep) kept.push_back(std::move(k));
  std::vector<Kept>().swap(measured);
  std::vector<double> sharpness(kept.size());
  if (options.quantize_sharpness && !kept.empty()) {
    std::vector<double> v, wt;
    for (const Kept& k : kept) {
      v.push_back(k.blur);
      wt.push_back(k.length);
    }
    double thr, lo, hi;
    OtsuTwoClasses(v, wt, &thr, &lo, &hi);
    for (size_t i = 0; i < kept.size(); ++i) sharpness[i] = 1.0 - (kept[i].blur < thr ? lo : hi);
  } else {
    for (size_t i = 0; i < kept.size(); ++i) sharpness[i] = 1.0 - kept[i].blur;
  }

  BSplineFitOptions fit;
  fit.tolerance = options.fit_tolerance;
  fit.max_spacing = options.max_spacing;
  const int window = std::max(1, int(std::lround(options.corner_window)));
  // The fits in chunks of chains on the threads, appended in chain order.
  std::vector<FeatureCurve> fitted(kept.size());
  fit_internal::ForEachChunk(kept.size(), kChainChunk, threads, [&](size_t, size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) {
      std::vector<uint32_t> corners =
          FindChainCorners(kept[i].samples, kept[i].closed, options.corner_angle_deg, window);
      FeatureCurve& curve = fitted[i];
      curve = FitChain(kept[i].samples, kept[i].closed, corners, fit);
      curve.sharpness = float(std::clamp(sharpness[i], 0.0, 1.0));
      curve.contrast = float(kept[i].contrast);
      curve.boundary = false;
    }
  });
  // Copies made here: the fits' own memory, from the threads' malloc arenas, is all freed.
  for (const FeatureCurve& curve : fitted)
    if (curve.points.size() >= 2) curves.push_back(curve);
  return curves;
}

double PolygonLength(const FeatureCurve& c) {
  double len = 0;
  const size_t n = c.points.size();
  for (size_t k = 0; k + 1 < n + (c.closed && n > 2 ? 1 : 0); ++k) {
    const Point2& a = c.points[k];
    const Point2& b = c.points[(k + 1) % n];
    len += std::hypot(b.x - a.x, b.y - a.y);
  }
  return len;
}

}  // namespace sdvi
