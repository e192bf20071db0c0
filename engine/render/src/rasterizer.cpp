// SPDX-License-Identifier: GPL-3.0-or-later
// Scan conversion of fine triangles: the pixel -> fine triangle map (MapPixels) and the
// direct colour render with domain-edge coverage (RenderFineMesh). Rules in sdvi/render.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <thread>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "scan_convert.h"
#include "sdvi/large_buffers.h"
#include "sdvi/render.h"

namespace sdvi {
namespace render_internal {

template <typename T>
void AssignZeroedLarge(std::vector<T>& v, size_t n) {
  v.clear();
  v.shrink_to_fit();
  internal::ReserveLarge(v, n);
  v.resize(n);  // value-initialised: zero
}
template void AssignZeroedLarge<float>(std::vector<float>&, size_t);
template void AssignZeroedLarge<uint8_t>(std::vector<uint8_t>&, size_t);

ScratchArray<FixedPoint> ToFixedAll(const std::vector<Vertex>& fine, const Viewport& vp, int threads) {
  ScratchArray<FixedPoint> out;
  internal::ReserveLarge(out, fine.size());
  out.resize(fine.size());
  ForEachChunk(fine.size(), threads, [&](size_t s0, size_t s1) {
    for (size_t i = s0; i < s1; ++i) out[i] = ToFixed(fine[i], vp);
  });
  return out;
}

RowBandBins BinTrianglesByRowBand(const std::vector<Triangle>& triangles, const ScratchArray<FixedPoint>& pts,
                                  int width, int height, int band_rows, int threads) {
  RowBandBins bins;
  bins.band_rows = std::max(1, band_rows);
  const int bands = height > 0 ? (height + bins.band_rows - 1) / bins.band_rows : 0;
  const size_t count = triangles.size();
  // Chunks of triangles counted and filled in parallel; band b lists chunk 0's triangles,
  // then chunk 1's, ..., so every list is in increasing index whatever the chunk count.
  int chunks = threads > 0 ? threads : int(std::thread::hardware_concurrency());
  chunks = count < 65536 ? 1 : std::clamp(chunks, 1, 16);
  constexpr uint32_t kNoBand = std::numeric_limits<uint32_t>::max();
  ScratchArray<uint32_t> range;  // first band << 16 | last band (bands <= 2^16)
  internal::ReserveLarge(range, count);
  range.assign(count, kNoBand);
  std::vector<std::vector<uint32_t>> start(size_t(chunks), std::vector<uint32_t>(size_t(bands) + 1, 0));
  const uint32_t nv = uint32_t(pts.size());
  auto in_parallel = [&](auto&& body) { RunTasks(chunks, body); };
  in_parallel([&](int c) {
    std::vector<uint32_t>& n = start[size_t(c)];
    TriangleSetup s;
    for (size_t t = count * size_t(c) / size_t(chunks), end = count * size_t(c + 1) / size_t(chunks); t < end; ++t) {
      const auto& v = triangles[t].v;
      if (v[0] >= nv || v[1] >= nv || v[2] >= nv) continue;
      if (!SetupTriangle(pts[v[0]], pts[v[1]], pts[v[2]], width, height, s)) continue;
      const uint32_t b0 = uint32_t(s.j0 / bins.band_rows), b1 = uint32_t(s.j1 / bins.band_rows);
      range[t] = b0 << 16 | b1;
      for (uint32_t b = b0; b <= b1; ++b) ++n[b];
    }
  });
  // start[c][b]: where chunk c's triangles of band b begin.
  bins.offsets.assign(size_t(bands) + 1, 0);
  uint32_t total = 0;
  for (int b = 0; b < bands; ++b) {
    bins.offsets[size_t(b)] = total;
    for (int c = 0; c < chunks; ++c) {
      const uint32_t n = start[size_t(c)][size_t(b)];
      start[size_t(c)][size_t(b)] = total;
      total += n;
    }
  }
  bins.offsets[size_t(bands)] = total;
  internal::ReserveLarge(bins.triangles, total);
  bins.triangles.resize(total);
  in_parallel([&](int c) {
    std::vector<uint32_t>& next = start[size_t(c)];
    for (size_t t = count * size_t(c) / size_t(chunks), end = count * size_t(c + 1) / size_t(chunks); t < end; ++t) {
      if (range[t] == kNoBand) continue;
      for (uint32_t b = range[t] >> 16; b <= (range[t] & 0xffffu); ++b) bins.triangles[next[b]++] = uint32_t(t);
    }
  });
  return bins;
}

namespace {

bool ValidViewport(const Viewport& vp) {
  return vp.width > 0 && vp.height > 0 && std::isfinite(vp.scale_x) && std::isfinite(vp.scale_y) &&
         vp.scale_x > 0 && vp.scale_y > 0 && std::isfinite(vp.origin_x) && std::isfinite(vp.origin_y);
}

}  // namespace
}  // namespace render_internal

using namespace render_internal;

CoverageMap MapPixels(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                      const Viewport& viewport) {
  CoverageMap map;
  MapPixelsInto(triangles, fine, viewport, map);
  return map;
}

void MapPixelsInto(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                   const Viewport& viewport, CoverageMap& map) {
  std::vector<PixelSample> dense = std::move(map.samples);  // its storage is reused
  dense.clear();
  map = CoverageMap();
  if (!ValidViewport(viewport)) return;
  map.width = viewport.width;
  map.height = viewport.height;
  const size_t npix = size_t(viewport.width) * size_t(viewport.height);
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  internal::ReserveLarge(dense, npix);
  dense.assign(npix, PixelSample{0, kNone, 0, 0, 0});
  const ScratchArray<FixedPoint> pts = ToFixedAll(fine, viewport, 0);
  const int width = viewport.width;
  // Row bands of cache-sized pixels, each listing its triangles in increasing index (as
  // DrawFineMesh): the lowest index still wins, and a band's pixels stay in cache while
  // its triangles are scanned.
  const RowBandBins bins =
      BinTrianglesByRowBand(triangles, pts, width, viewport.height, BandRowsFor(width, sizeof(PixelSample)), 0);
  ForEachBand(bins.bands(), 0, viewport.height, [&](int band) {
    const int row0 = band * bins.band_rows, row1 = std::min(viewport.height, row0 + bins.band_rows);
    TriangleSetup s;
    for (uint32_t k = bins.offsets[size_t(band)]; k < bins.offsets[size_t(band) + 1]; ++k) {
      const uint32_t t = bins.triangles[k];
      const auto& v = triangles[t].v;
      if (!SetupTriangle(pts[v[0]], pts[v[1]], pts[v[2]], width, viewport.height, s)) continue;  // binned: true
      const double inv_area = 1.0 / double(s.area);
      ScanTriangle(s, row0, row1, [&](int i, int j, int64_t e0, int64_t e1, int64_t e2) {
        PixelSample& ps = dense[size_t(j) * width + i];
        if (ps.triangle != kNone) return;  // lowest fine triangle index wins
        float w[3];
        w[s.slot[0]] = float(double(e0) * inv_area);
        w[s.slot[1]] = float(double(e1) * inv_area);
        w[s.slot[2]] = float(double(e2) * inv_area);
        ps.triangle = t;
        ps.w0 = w[0], ps.w1 = w[1], ps.w2 = w[2];
      });
    }
  });
  // Compacted in place (a covered pixel moves to a lower or equal index): no second
  // per-pixel array.
  size_t count = 0;
  for (size_t p = 0; p < npix; ++p) {
    if (dense[p].triangle == kNone) continue;
    PixelSample s = dense[p];
    s.pixel = uint32_t(p);
    dense[count++] = s;
  }
  dense.resize(count);
  if (count < npix / 2) dense.shrink_to_fit();
  map.samples = std::move(dense);
}

namespace {

inline float Clamp255(double v) { return float(v < 0 ? 0 : v > 255 ? 255 : v); }

// The PNG writer's rule on a value already in 0..255 (a float, so exact in double): round,
// halves away from zero.
inline uint8_t Round8(float v) { return uint8_t(int(double(v) + 0.5)); }

// Pixel stores of the two outputs: float RGBA (alpha 0..1) and 8-bit RGBA (alpha 0..255,
// quantised as Render8 says). Owned(p) is true once a triangle has drawn the pixel; before
// the domain-edge pass only drawn pixels have a non-zero alpha.
struct FloatPixels {
  using Sample = float;
  static bool Owned(const float* p) { return p[3] != 0; }
  static void Draw(float* p, double r, double g, double b) {
    p[0] = Clamp255(r), p[1] = Clamp255(g), p[2] = Clamp255(b);
    p[3] = 1.0f;
  }
  static void SetColour(float* p, float r, float g, float b) {
    p[0] = Clamp255(r), p[1] = Clamp255(g), p[2] = Clamp255(b);
  }
  static void SetAlpha(float* p, float a) { p[3] = a; }
  // n pixels from px, colour (r, g, b) at the first and step[] more at each next one; pixels
  // already drawn are kept (the lowest fine triangle index wins).
  static void DrawSpan(float* px, int n, double r, double g, double b, const double step[3]) {
    for (int k = 0; k < n; ++k, px += 4, r += step[0], g += step[1], b += step[2])
      if (!Owned(px)) Draw(px, r, g, b);
  }
};
struct BytePixels {
  using Sample = uint8_t;
  static bool Owned(const uint8_t* p) { return p[3] != 0; }
  static void Draw(uint8_t* p, double r, double g, double b) {
    p[0] = Round8(Clamp255(r)), p[1] = Round8(Clamp255(g)), p[2] = Round8(Clamp255(b));
    p[3] = 255;
  }
  static void SetColour(uint8_t* p, float r, float g, float b) {
    p[0] = Round8(Clamp255(r)), p[1] = Round8(Clamp255(g)), p[2] = Round8(Clamp255(b));
  }
  static void SetAlpha(uint8_t* p, float a) {
    p[3] = uint8_t(std::round(std::clamp(double(a) * 255.0, 0.0, 255.0)));
  }
  // As FloatPixels::DrawSpan, each pixel's bytes as Draw writes them.
  static void DrawSpan(uint8_t* px, int n, double r, double g, double b, const double step[3]) {
#if defined(__SSE2__)
    // Draw's steps on (r, g) and (b, 0) in two-lane registers, one 32-bit store a pixel: the
    // same double sums (one IEEE addition a lane a pixel, as the scalar loop), the clamp as
    // max(v, 0) then min(., 255) (equal to Clamp255 for every double: -0 gives 0, and a NaN
    // gives 0 where Clamp255's NaN rounds to byte 0 too), the conversion to float and the
    // rounding int(double(f) + 0.5) lane by lane.
    const __m128d zero = _mm_setzero_pd(), top = _mm_set1_pd(255.0), half = _mm_set1_pd(0.5);
    const __m128d step_rg = _mm_set_pd(step[1], step[0]), step_b = _mm_set_pd(0.0, step[2]);
    __m128d rg = _mm_set_pd(g, r), bz = _mm_set_pd(0.0, b);
    for (int k = 0; k < n; ++k, px += 4, rg = _mm_add_pd(rg, step_rg), bz = _mm_add_pd(bz, step_b)) {
      if (Owned(px)) continue;
      const __m128 f_rg = _mm_cvtpd_ps(_mm_min_pd(_mm_max_pd(rg, zero), top));
      const __m128 f_bz = _mm_cvtpd_ps(_mm_min_pd(_mm_max_pd(bz, zero), top));
      const __m128i i_rg = _mm_cvttpd_epi32(_mm_add_pd(_mm_cvtps_pd(f_rg), half));
      const __m128i i_bz = _mm_cvttpd_epi32(_mm_add_pd(_mm_cvtps_pd(f_bz), half));
      const __m128i rgbz = _mm_unpacklo_epi64(i_rg, i_bz);  // r, g, b, 0 as int32 in 0..255
      const __m128i bytes = _mm_packus_epi16(_mm_packs_epi32(rgbz, rgbz), _mm_setzero_si128());
      const uint32_t word = uint32_t(_mm_cvtsi128_si32(bytes)) | 0xff000000u;  // alpha 255
      std::memcpy(px, &word, 4);  // little-endian: r, g, b, alpha
    }
#else
    for (int k = 0; k < n; ++k, px += 4, r += step[0], g += step[1], b += step[2])
      if (!Owned(px)) Draw(px, r, g, b);
#endif
  }
};

// Domain-edge coverage: see RenderFineMesh in sdvi/render.h.
template <typename Pixels>
void AntialiasBoundary(const std::vector<Edge>& boundary, const std::vector<Vertex>& fine,
                       const Viewport& vp, typename Pixels::Sample* data) {
  struct Candidate {
    uint32_t pixel;
    float distance;
    float r, g, b;
  };
  std::vector<Candidate> cand;
  const uint32_t nv = uint32_t(fine.size());
  for (const Edge& e : boundary) {
    if (e.a >= nv || e.b >= nv) continue;
    const Vertex &va = fine[e.a], &vb = fine[e.b];
    const double ax = (va.x - vp.origin_x) * vp.scale_x, ay = (va.y - vp.origin_y) * vp.scale_y;
    const double bx = (vb.x - vp.origin_x) * vp.scale_x, by = (vb.y - vp.origin_y) * vp.scale_y;
    if (!std::isfinite(ax + ay + bx + by)) continue;
    const double reach = 0.5;  // coverage changes only within half a pixel of the edge
    const double i0d = std::floor(std::min(ax, bx) - reach - 0.5), i1d = std::ceil(std::max(ax, bx) + reach - 0.5);
    const double j0d = std::floor(std::min(ay, by) - reach - 0.5), j1d = std::ceil(std::max(ay, by) + reach - 0.5);
    if (i1d < 0 || j1d < 0 || i0d >= vp.width || j0d >= vp.height) continue;
    const int i0 = int(std::max(0.0, i0d)), i1 = int(std::min(double(vp.width - 1), i1d));
    const int j0 = int(std::max(0.0, j0d)), j1 = int(std::min(double(vp.height - 1), j1d));
    const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const double px = i + 0.5 - ax, py = j + 0.5 - ay;
        double t = len2 > 0 ? (px * dx + py * dy) / len2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        const double qx = px - t * dx, qy = py - t * dy;
        const double d = std::sqrt(qx * qx + qy * qy);
        if (d >= reach) continue;
        cand.push_back({uint32_t(size_t(j) * vp.width + i), float(d),
                        float(va.r + t * (vb.r - va.r)), float(va.g + t * (vb.g - va.g)),
                        float(va.b + t * (vb.b - va.b))});
      }
    }
  }
  std::stable_sort(cand.begin(), cand.end(), [](const Candidate& x, const Candidate& y) {
    return x.pixel != y.pixel ? x.pixel < y.pixel : x.distance < y.distance;
  });
  for (size_t k = 0; k < cand.size(); ++k) {
    if (k > 0 && cand[k].pixel == cand[k - 1].pixel) continue;  // nearest edge only
    const Candidate& c = cand[k];
    auto* px = data + size_t(c.pixel) * 4;
    if (Pixels::Owned(px)) {
      Pixels::SetAlpha(px, std::min(1.0f, 0.5f + c.distance));
    } else {
      Pixels::SetColour(px, c.r, c.g, c.b);
      Pixels::SetAlpha(px, std::max(0.0f, 0.5f - c.distance));
    }
  }
}

// Draws the fine triangles into data (RGBA, viewport size) in row bands, then the
// domain-edge coverage: the body of RenderFineMesh and RenderFineMesh8. data is zeroed
// already, or (zero_bands) unwritten: then each band zeroes its own rows before drawing
// them, so that the output's first touch (page faults included) is spread over the threads
// and each band's pixels are in cache when drawn.
template <typename Pixels>
void DrawFineMesh(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine, const Viewport& viewport,
                  const std::vector<Edge>* boundary, int threads, bool zero_bands, typename Pixels::Sample* data) {
  const ScratchArray<FixedPoint> pts = ToFixedAll(fine, viewport, threads);
  const int width = viewport.width;
  const RowBandBins bins = BinTrianglesByRowBand(triangles, pts, width, viewport.height,
                                                 BandRowsFor(width, 4 * sizeof(typename Pixels::Sample)), threads);
  ForEachBand(bins.bands(), threads, viewport.height, [&](int band) {
    const int row0 = band * bins.band_rows, row1 = std::min(viewport.height, row0 + bins.band_rows);
    // The band's pixels brought into cache in address order first (zeroed, or prefetched):
    // the triangles then touch them in no order, and a miss each 16 pixels was most of the
    // drawing time.
    auto* band_begin = reinterpret_cast<char*>(data + size_t(row0) * width * 4);
    auto* band_end = reinterpret_cast<char*>(data + size_t(row1) * width * 4);
    if (zero_bands)
      std::memset(band_begin, 0, size_t(band_end - band_begin));
    else
      for (const char* p = band_begin; p < band_end; p += 64) __builtin_prefetch(p, 1);
    TriangleSetup s;
    for (uint32_t k = bins.offsets[size_t(band)]; k < bins.offsets[size_t(band) + 1]; ++k) {
      const uint32_t t = bins.triangles[k];
      const auto& v = triangles[t].v;
      if (!SetupTriangle(pts[v[0]], pts[v[1]], pts[v[2]], width, viewport.height, s)) continue;  // binned: true
      const double inv_area = 1.0 / double(s.area);
      const Vertex* cv[3] = {&fine[v[s.slot[0]]], &fine[v[s.slot[1]]], &fine[v[s.slot[2]]]};
      // Colour is affine in the pixel index along a row: exact weights at the span start,
      // then a constant step per pixel.
      double step[3];
      for (int ch = 0; ch < 3; ++ch) {
        const float Vertex::*m = ch == 0 ? &Vertex::r : ch == 1 ? &Vertex::g : &Vertex::b;
        step[ch] = (double(StepX(s, 0)) * (cv[0]->*m) + double(StepX(s, 1)) * (cv[1]->*m) +
                    double(StepX(s, 2)) * (cv[2]->*m)) * inv_area;
      }
      ScanSpans(s, row0, row1, [&](int j, int i_begin, int i_end, const int64_t* e) {
        const double w0 = double(e[0]) * inv_area, w1 = double(e[1]) * inv_area, w2 = double(e[2]) * inv_area;
        double r = w0 * cv[0]->r + w1 * cv[1]->r + w2 * cv[2]->r;
        double g = w0 * cv[0]->g + w1 * cv[1]->g + w2 * cv[2]->g;
        double b = w0 * cv[0]->b + w1 * cv[1]->b + w2 * cv[2]->b;
        Pixels::DrawSpan(data + (size_t(j) * width + i_begin) * 4, i_end - i_begin + 1, r, g, b, step);
      });
    }
  });
  if (boundary) AntialiasBoundary<Pixels>(*boundary, fine, viewport, data);
}

}  // namespace

Raster RenderFineMesh(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                      const Viewport& viewport, const std::vector<Edge>* boundary, int threads) {
  if (!ValidViewport(viewport)) return Raster();
  Raster out;
  out.width = viewport.width, out.height = viewport.height, out.channels = 4;
  AssignZeroedLarge(out.data, size_t(viewport.width) * viewport.height * 4);
  DrawFineMesh<FloatPixels>(triangles, fine, viewport, boundary, threads, false, out.data.data());
  return out;
}

Raster8 RenderFineMesh8(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                        const Viewport& viewport, const std::vector<Edge>* boundary, int threads) {
  if (!ValidViewport(viewport)) return Raster8();
  Raster8 out;
  out.width = viewport.width, out.height = viewport.height, out.channels = 4;
  // Left unwritten here (DefaultInitAllocator): the bands zero their own rows.
  internal::ReserveLarge(out.data, size_t(viewport.width) * viewport.height * 4);
  out.data.resize(size_t(viewport.width) * viewport.height * 4);
  DrawFineMesh<BytePixels>(triangles, fine, viewport, boundary, threads, true, out.data.data());
  return out;
}

std::vector<Edge> MeshBoundaryEdges(const std::vector<Triangle>& triangles,
                                    const std::vector<VertexTag>* tags) {
  std::vector<uint64_t> keys;
  keys.reserve(tags ? triangles.size() / 4 : triangles.size() * 3);
  auto smooth = [&](uint32_t v) {
    return tags && (v >= tags->size() || (*tags)[v] == VertexTag::kSmooth);
  };
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t.v[k], b = t.v[(k + 1) % 3];
      if (a == b || smooth(a) || smooth(b)) continue;
      const Edge e = Edge::Of(a, b);
      keys.push_back((uint64_t(e.a) << 32) | e.b);
    }
  }
  std::sort(keys.begin(), keys.end());
  std::vector<Edge> out;
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i == 1) out.push_back(Edge{uint32_t(keys[i] >> 32), uint32_t(keys[i] & 0xffffffffu)});
    i = j;
  }
  return out;
}

}  // namespace sdvi
