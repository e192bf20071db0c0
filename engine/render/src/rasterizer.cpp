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
                                  int height, int band_rows, int threads) {
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
    for (size_t t = count * size_t(c) / size_t(chunks), end = count * size_t(c + 1) / size_t(chunks); t < end; ++t) {
      const auto& v = triangles[t].v;
      if (v[0] >= nv || v[1] >= nv || v[2] >= nv) continue;
      const FixedPoint &p0 = pts[v[0]], &p1 = pts[v[1]], &p2 = pts[v[2]];
      int j0, j1;
      if (!p0.valid() || !p1.valid() || !p2.valid() || !CandidateCentres(p0.y, p1.y, p2.y, height, j0, j1)) continue;
      const uint32_t b0 = uint32_t(j0 / bins.band_rows), b1 = uint32_t(j1 / bins.band_rows);
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

// The pixel maps' traversal (MapPixelsInto, MapPixelOwnersInto): row bands of cache-sized
// pixels (pixel_bytes each), each listing its triangles in increasing index, so that the
// lowest index wins a pixel its first writer claims and a band's pixels stay in cache while
// its triangles are scanned; scan(s, t, row0, row1) for each triangle the set-up accepts.
template <typename Scan>
void ForEachBandTriangle(const std::vector<Triangle>& triangles, const ScratchArray<FixedPoint>& pts,
                         const Viewport& viewport, size_t pixel_bytes, Scan&& scan) {
  const int width = viewport.width;
  const RowBandBins bins = BinTrianglesByRowBand(triangles, pts, viewport.height, BandRowsFor(width, pixel_bytes), 0);
  ForEachBand(bins.bands(), 0, viewport.height, [&](int band) {
    const int row0 = band * bins.band_rows, row1 = std::min(viewport.height, row0 + bins.band_rows);
    TriangleSetup s;
    for (uint32_t k = bins.offsets[size_t(band)]; k < bins.offsets[size_t(band) + 1]; ++k) {
      const uint32_t t = bins.triangles[k];
      const auto& v = triangles[t].v;
      // Binned by its rows alone: the set-up rejects a degenerate triangle, or one between columns.
      if (!SetupTriangle(pts[v[0]], pts[v[1]], pts[v[2]], width, viewport.height, s)) continue;
      scan(s, t, row0, row1);
    }
  });
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
  ForEachBandTriangle(triangles, pts, viewport, sizeof(PixelSample),
                      [&](const TriangleSetup& s, uint32_t t, int row0, int row1) {
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

void MapPixelOwnersInto(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                        const Viewport& viewport, PixelOwners& map) {
  std::vector<uint32_t> owner = std::move(map.owner);  // its storage is reused
  owner.clear();
  map = PixelOwners();
  if (!ValidViewport(viewport)) return;
  map.width = viewport.width;
  map.height = viewport.height;
  const size_t npix = size_t(viewport.width) * size_t(viewport.height);
  internal::ReserveLarge(owner, npix);
  owner.assign(npix, PixelOwners::kNoOwner);
  const ScratchArray<FixedPoint> pts = ToFixedAll(fine, viewport, 0);
  const int width = viewport.width;
  ForEachBandTriangle(triangles, pts, viewport, sizeof(uint32_t),
                      [&](const TriangleSetup& s, uint32_t t, int row0, int row1) {
    ScanSpans(s, row0, row1, [&](int j, int i_begin, int i_end, const int64_t*) {
      uint32_t* row = owner.data() + size_t(j) * width;
      for (int i = i_begin; i <= i_end; ++i) {
        if (row[i] == PixelOwners::kNoOwner) row[i] = t;
      }
    });
  });
  map.owner = std::move(owner);
  map.corners.resize(2 * pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    map.corners[2 * i] = pts[i].x;
    map.corners[2 * i + 1] = pts[i].y;
  }
}

namespace {

// The setup of fine triangle t of map (true: t owns a pixel of map, so it has one).
bool OwnerSetup(const PixelOwners& map, const std::vector<Triangle>& triangles, uint32_t t, TriangleSetup& s) {
  const auto& v = triangles[t].v;
  auto corner = [&](uint32_t i) {
    FixedPoint p;
    p.x = map.corners[2 * size_t(i)];
    p.y = map.corners[2 * size_t(i) + 1];
    return p;
  };
  return SetupTriangle(corner(v[0]), corner(v[1]), corner(v[2]), map.width, map.height, s);
}

// The exact edge functions of a triangle's setup at pixel centres: E_k(i, j) = step[k] * i +
// row[k] * j + at0[k], as ScanSpans walks them (spec/METHOD.md 4: barycentric weight of
// slot k = E_k / area).
struct EdgeFunctions {
  int64_t step[3], row[3], at0[3];
  double inv_area;
  int slot[3];
  EdgeFunctions() = default;
  explicit EdgeFunctions(const TriangleSetup& s) { Set(s.x, s.y, s.slot, s.area); }
  // From SetupTriangle's corners x, y (in slot order), slots and area (> 0).
  void Set(const int64_t* x, const int64_t* y, const int* slots, int64_t area) {
    inv_area = 1.0 / double(area);
    for (int k = 0; k < 3; ++k) {
      const int a1 = (k + 1) % 3, a2 = (k + 2) % 3;
      const int64_t dx = x[a2] - x[a1], dy = y[a2] - y[a1];
      step[k] = -dy * kOne;
      row[k] = dx * kOne;
      at0[k] = dx * (kHalf - y[a1]) - dy * (kHalf - x[a1]);
      slot[k] = slots[k];
    }
  }
  // SetupTriangle's slots and area for fine triangle t of map, without its pixel box (the
  // owners give the pixels); false where the triangle has no area.
  bool SetOwner(const PixelOwners& map, const std::vector<Triangle>& triangles, uint32_t t) {
    const auto& v = triangles[t].v;
    const int32_t* c[3] = {&map.corners[2 * size_t(v[0])], &map.corners[2 * size_t(v[1])],
                           &map.corners[2 * size_t(v[2])]};
    const int64_t area = (int64_t(c[1][0]) - c[0][0]) * (int64_t(c[2][1]) - c[0][1]) -
                         (int64_t(c[1][1]) - c[0][1]) * (int64_t(c[2][0]) - c[0][0]);
    if (area == 0) return false;
    const int slots[3] = {0, area > 0 ? 1 : 2, area > 0 ? 2 : 1};
    int64_t x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = c[slots[k]][0], y[k] = c[slots[k]][1];
    Set(x, y, slots, area > 0 ? area : -area);
    return true;
  }
  void At(int i, int j, int64_t e[3]) const {
    for (int k = 0; k < 3; ++k) e[k] = step[k] * i + row[k] * j + at0[k];
  }
  // MapPixelsInto's sample from the edge functions e at pixel (i, j) = pixel.
  PixelSample Sample(const int64_t e[3], uint32_t t, size_t pixel) const {
    float w[3];
    for (int k = 0; k < 3; ++k) w[slot[k]] = float(double(e[k]) * inv_area);
    return PixelSample{uint32_t(pixel), t, w[0], w[1], w[2]};
  }
};

}  // namespace

void AppendOwnedSamples(const PixelOwners& map, const std::vector<Triangle>& triangles, uint32_t t,
                        std::vector<PixelSample>& out) {
  TriangleSetup s;
  if (!OwnerSetup(map, triangles, t, s)) return;
  const EdgeFunctions f(s);
  const size_t width = size_t(map.width);
  // The pixels of the triangle's box whose owner is t, in pixel order: the owners decide,
  // no edge test is needed.
  for (int j = s.j0; j <= s.j1; ++j) {
    const uint32_t* row = map.owner.data() + size_t(j) * width;
    int64_t e[3];
    f.At(s.i0, j, e);
    for (int i = s.i0; i <= s.i1; ++i, e[0] += f.step[0], e[1] += f.step[1], e[2] += f.step[2]) {
      if (row[i] == t) out.push_back(f.Sample(e, t, size_t(j) * width + size_t(i)));
    }
  }
}

void AppendSamplesInRange(const PixelOwners& map, const std::vector<Triangle>& triangles, size_t p0, size_t p1,
                          std::vector<PixelSample>& out) {
  if (p0 >= p1) return;
  const size_t width = size_t(map.width);
  EdgeFunctions f;
  uint32_t current = PixelOwners::kNoOwner;
  constexpr size_t kFar = 24, kNear = 8;  // pixels ahead whose triangle, then corners, are asked for
  // Row by row; along a row of one owner the edge functions step exactly.
  for (size_t j = p0 / width, row_start = j * width; row_start < p1; ++j, row_start += width) {
    const size_t i_begin = std::max(p0, row_start) - row_start, i_end = std::min(p1, row_start + width) - row_start;
    const uint32_t* row = map.owner.data() + row_start;
    bool stepping = false;  // e holds the edge functions of pixel i - 1 of current
    int64_t e[3] = {0, 0, 0};
    for (size_t i = i_begin; i < i_end; ++i) {
      if (i + kFar < i_end && row[i + kFar] != PixelOwners::kNoOwner) __builtin_prefetch(&triangles[row[i + kFar]]);
      if (i + kNear < i_end && row[i + kNear] != PixelOwners::kNoOwner) {
        for (uint32_t v : triangles[row[i + kNear]].v) __builtin_prefetch(&map.corners[2 * size_t(v)]);
      }
      const uint32_t t = row[i];
      if (t == PixelOwners::kNoOwner) {
        stepping = false;
        continue;
      }
      if (t != current) {
        if (!f.SetOwner(map, triangles, t)) {  // an owner has an area
          stepping = false;
          current = PixelOwners::kNoOwner;
          continue;
        }
        current = t;
        f.At(int(i), int(j), e);
      } else if (stepping) {
        for (int k = 0; k < 3; ++k) e[k] += f.step[k];
      } else {
        f.At(int(i), int(j), e);
      }
      stepping = true;
      out.push_back(f.Sample(e, t, row_start + i));
    }
  }
}

namespace {

inline float Clamp255(double v) { return float(v < 0 ? 0 : v > 255 ? 255 : v); }

// The PNG writer's rule on a value already in 0..255 (a float, so exact in double): round,
// halves away from zero.
inline uint8_t Round8(float v) { return uint8_t(int(double(v) + 0.5)); }

// Colour along a span (spec/METHOD.md section 4, item 3): fixed point with kColourBits
// fraction bits, a value every pixel, the next one the previous plus a constant step.
constexpr int kColourBits = 16;
constexpr int32_t kColourOne = int32_t(1) << kColourBits;
constexpr int32_t kColourTop = 255 * kColourOne;  // 255, the largest colour drawn

// Pixel stores of the two outputs: float RGBA (alpha 0..1) and 8-bit RGBA (alpha 0..255,
// quantised as Render8 says). Owned(p) is true once a triangle has drawn the pixel; before
// the domain-edge pass only drawn pixels have a non-zero alpha. DrawSpan overwrites: the
// triangles are drawn in decreasing index, so the lowest one owning a pixel writes it last.
// A span's colours are the fixed-point values v, v + step, v + 2 step, ... (r, g, b in
// lanes 0..2, lane 3 unused), each clamped to 0..255: the float output stores that value
// exactly (v / kColourOne, below 2^24), the 8-bit one rounds it, halves up, which is the
// PNG writer's rule on the float value: the same bytes as the float render quantised.
struct FloatPixels {
  using Sample = float;
  static bool Owned(const float* p) { return p[3] != 0; }
  static void SetColour(float* p, float r, float g, float b) {
    p[0] = Clamp255(r), p[1] = Clamp255(g), p[2] = Clamp255(b);
  }
  static void SetAlpha(float* p, float a) { p[3] = a; }
  static void DrawSpan(float* px, int n, int /*room*/, const int32_t v[4], const int32_t step[4]) {
    int32_t c[3] = {v[0], v[1], v[2]};
    for (int k = 0; k < n; ++k, px += 4) {
      for (int ch = 0; ch < 3; ++ch) {
        px[ch] = float(std::clamp(c[ch], 0, kColourTop)) * (1.0f / float(kColourOne));
        c[ch] += step[ch];
      }
      px[3] = 1.0f;
    }
  }
};
struct BytePixels {
  using Sample = uint8_t;
  static bool Owned(const uint8_t* p) { return p[3] != 0; }
  static void SetColour(uint8_t* p, float r, float g, float b) {
    p[0] = Round8(Clamp255(r)), p[1] = Round8(Clamp255(g)), p[2] = Round8(Clamp255(b));
  }
  static void SetAlpha(uint8_t* p, float a) {
    p[3] = uint8_t(std::round(std::clamp(double(a) * 255.0, 0.0, 255.0)));
  }
  // As FloatPixels::DrawSpan, rounded: byte (c + kColourOne / 2) >> kColourBits, saturated
  // to 0..255 (equal to rounding the clamped value, halves up); alpha 255. room: pixels from
  // px to the end of its row (>= n).
  static void DrawSpan(uint8_t* px, int n, [[maybe_unused]] int room, const int32_t v[4], const int32_t step[4]) {
#if defined(__SSE2__)
    // Four pixels a 16-byte store, lane 3 of each holding 255 << kColourBits so that the
    // packs give alpha 255. A span's last block keeps the bytes past its end (a masked
    // rewrite of what it read: the row is this thread's), so that the loop runs once for
    // spans of up to four pixels, most of them: a loop ending after 1..4 pixels at random
    // mispredicted about once a span.
    alignas(16) static constexpr int32_t kTake[4][4] = {{0, 0, 0, 0}, {-1, 0, 0, 0}, {-1, -1, 0, 0}, {-1, -1, -1, 0}};
    // Lane 3 of v and of step is 0: alpha from the constant added.
    const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(step));
    __m128i c = _mm_add_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(v)),
                              _mm_set_epi32((255 << kColourBits) + kColourOne / 2, kColourOne / 2, kColourOne / 2,
                                            kColourOne / 2));
    if (n <= 8 && room >= 8) {
      // Most spans: eight pixels computed, two masked 16-byte rewrites, no branch on n.
      alignas(16) static constexpr int32_t kFirst[9][8] = {
          {0, 0, 0, 0, 0, 0, 0, 0},         {-1, 0, 0, 0, 0, 0, 0, 0},        {-1, -1, 0, 0, 0, 0, 0, 0},
          {-1, -1, -1, 0, 0, 0, 0, 0},      {-1, -1, -1, -1, 0, 0, 0, 0},     {-1, -1, -1, -1, -1, 0, 0, 0},
          {-1, -1, -1, -1, -1, -1, 0, 0},   {-1, -1, -1, -1, -1, -1, -1, 0},  {-1, -1, -1, -1, -1, -1, -1, -1}};
      const __m128i c1 = _mm_add_epi32(c, d), c2 = _mm_add_epi32(c1, d), c3 = _mm_add_epi32(c2, d);
      const __m128i c4 = _mm_add_epi32(c3, d), c5 = _mm_add_epi32(c4, d), c6 = _mm_add_epi32(c5, d);
      const __m128i c7 = _mm_add_epi32(c6, d);
      const __m128i b0 = _mm_packus_epi16(
          _mm_packs_epi32(_mm_srai_epi32(c, kColourBits), _mm_srai_epi32(c1, kColourBits)),
          _mm_packs_epi32(_mm_srai_epi32(c2, kColourBits), _mm_srai_epi32(c3, kColourBits)));
      const __m128i b1 = _mm_packus_epi16(
          _mm_packs_epi32(_mm_srai_epi32(c4, kColourBits), _mm_srai_epi32(c5, kColourBits)),
          _mm_packs_epi32(_mm_srai_epi32(c6, kColourBits), _mm_srai_epi32(c7, kColourBits)));
      const __m128i m0 = _mm_load_si128(reinterpret_cast<const __m128i*>(kFirst[n]));
      const __m128i m1 = _mm_load_si128(reinterpret_cast<const __m128i*>(kFirst[n] + 4));
      auto* p0 = reinterpret_cast<__m128i*>(px);
      auto* p1 = reinterpret_cast<__m128i*>(px + 16);
      const __m128i old0 = _mm_loadu_si128(p0), old1 = _mm_loadu_si128(p1);
      _mm_storeu_si128(p0, _mm_or_si128(_mm_and_si128(m0, b0), _mm_andnot_si128(m0, old0)));
      _mm_storeu_si128(p1, _mm_or_si128(_mm_and_si128(m1, b1), _mm_andnot_si128(m1, old1)));
      return;
    }
    for (int k = 0; k < n; k += 4, px += 16, room -= 4) {
      const __m128i c1 = _mm_add_epi32(c, d), c2 = _mm_add_epi32(c1, d), c3 = _mm_add_epi32(c2, d);
      const __m128i lo = _mm_packs_epi32(_mm_srai_epi32(c, kColourBits), _mm_srai_epi32(c1, kColourBits));
      const __m128i hi = _mm_packs_epi32(_mm_srai_epi32(c2, kColourBits), _mm_srai_epi32(c3, kColourBits));
      const __m128i bytes = _mm_packus_epi16(lo, hi);  // 4 pixels r, g, b, alpha
      c = _mm_add_epi32(c3, d);
      if (n - k >= 4) {
        _mm_storeu_si128(reinterpret_cast<__m128i*>(px), bytes);
      } else if (room >= 4) {
        const __m128i take = _mm_load_si128(reinterpret_cast<const __m128i*>(kTake[n - k]));
        const __m128i old = _mm_loadu_si128(reinterpret_cast<const __m128i*>(px));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(px), _mm_or_si128(_mm_and_si128(take, bytes), _mm_andnot_si128(take, old)));
      } else {
        alignas(16) uint8_t b[16];
        _mm_store_si128(reinterpret_cast<__m128i*>(b), bytes);
        std::memcpy(px, b, size_t(n - k) * 4);
      }
    }
#else
    int32_t c[3] = {v[0], v[1], v[2]};
    for (int k = 0; k < n; ++k, px += 4) {
      for (int ch = 0; ch < 3; ++ch) {
        px[ch] = uint8_t((std::clamp(c[ch], 0, kColourTop) + kColourOne / 2) >> kColourBits);
        c[ch] += step[ch];
      }
      px[3] = 255;
    }
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

// The colour of a fine triangle as a plane over the output pixels: value(i, j) = base + i sx +
// j sy at the centre of pixel (i, j), the barycentric interpolation of its vertices' colours
// from their fixed-point positions, in double precision, scaled by kColourOne.
struct ColourPlane {
  // (r, g, b, 0) in two pairs of doubles.
  alignas(16) double base[4], sx[4], sy[4];
  alignas(16) int32_t step[4] = {0, 0, 0, 0};  // sx in fixed point
  int chunk = kChunk;                          // pixels drawn from one value of the plane
  // A span's values are recomputed from the plane every kChunk pixels: the rounding of the
  // step (at most 1/2 of 2^-16 a pixel) stays below 2^-12 of a colour unit.
  static constexpr int kChunk = 16;
  // |values| <= 2^29 and |steps| <= 2^25 (colours beyond +-8192 and slopes beyond 512 a pixel
  // are clamped, a NaN taken as the upper limit): no int32 overflows within a chunk. A
  // steeper plane is evaluated at every pixel.
  static constexpr double kValueLimit = double(1 << 29), kStepLimit = double(1 << 25);

  ColourPlane(const TriangleSetup& s, const Vertex* const cv[3]) {
    // E_k(i, j) = a_k i + db_k j + e0_k (exact integers), weight of slot k = E_k / area.
    double a[3], db[3], e0[3];
    for (int k = 0; k < 3; ++k) {
      const int a1 = (k + 1) % 3, a2 = (k + 2) % 3;
      const int64_t dx = s.x[a2] - s.x[a1], dy = s.y[a2] - s.y[a1];
      a[k] = double(-dy * kOne), db[k] = double(dx * kOne);
      e0[k] = double(dx * (kHalf - s.y[a1]) - dy * (kHalf - s.x[a1]));
    }
    const double scale = double(kColourOne) / double(s.area);
#if defined(__SSE2__)
    // The scalar sums below, two channels a register (r, g) and (b, 0): the same products and
    // sums in the same order, so the same doubles.
    const __m128d scale2 = _mm_set1_pd(scale), zero = _mm_setzero_pd();
    __m128d c_rg[3], c_b[3];
    for (int k = 0; k < 3; ++k) {
      const __m128 rg = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&cv[k]->r)));
      c_rg[k] = _mm_mul_pd(_mm_cvtps_pd(rg), scale2);
      c_b[k] = _mm_move_sd(zero, _mm_mul_pd(_mm_set1_pd(double(cv[k]->b)), scale2));
    }
    auto sum = [&](const double w[3], const __m128d c[3]) {
      return _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_set1_pd(w[0]), c[0]), _mm_mul_pd(_mm_set1_pd(w[1]), c[1])),
                        _mm_mul_pd(_mm_set1_pd(w[2]), c[2]));
    };
    _mm_store_pd(base, sum(e0, c_rg)), _mm_store_pd(base + 2, _mm_move_sd(zero, sum(e0, c_b)));
    _mm_store_pd(sx, sum(a, c_rg)), _mm_store_pd(sx + 2, _mm_move_sd(zero, sum(a, c_b)));
    _mm_store_pd(sy, sum(db, c_rg)), _mm_store_pd(sy + 2, _mm_move_sd(zero, sum(db, c_b)));
#else
    for (int ch = 0; ch < 3; ++ch) {
      const float Vertex::*m = ch == 0 ? &Vertex::r : ch == 1 ? &Vertex::g : &Vertex::b;
      const double c0 = (cv[0]->*m) * scale, c1 = (cv[1]->*m) * scale, c2 = (cv[2]->*m) * scale;
      base[ch] = e0[0] * c0 + e0[1] * c1 + e0[2] * c2;
      sx[ch] = a[0] * c0 + a[1] * c1 + a[2] * c2;
      sy[ch] = db[0] * c0 + db[1] * c1 + db[2] * c2;
    }
    base[3] = sx[3] = sy[3] = 0;
#endif
    const bool steep = !(std::abs(sx[0]) <= kStepLimit) | !(std::abs(sx[1]) <= kStepLimit) |
                       !(std::abs(sx[2]) <= kStepLimit);
    Round(sx, kStepLimit, step);
    if (steep) chunk = 1;
  }
  // out[c] = v[c] rounded to the nearest integer (halves to even), clamped to +-limit, c < 4.
  static void Round(const double v[4], double limit, int32_t out[4]) {
#if defined(__SSE2__)
    // The conversion rounds to nearest, halves to even; min then max take a NaN to +limit.
    const __m128d hi = _mm_set1_pd(limit), lo = _mm_set1_pd(-limit);
    const __m128i rg = _mm_cvtpd_epi32(_mm_max_pd(_mm_min_pd(_mm_load_pd(v), hi), lo));
    const __m128i b0 = _mm_cvtpd_epi32(_mm_max_pd(_mm_min_pd(_mm_load_pd(v + 2), hi), lo));
    _mm_store_si128(reinterpret_cast<__m128i*>(out), _mm_unpacklo_epi64(rg, b0));
#else
    for (int c = 0; c < 4; ++c)
      out[c] = int32_t(std::nearbyint(v[c] != v[c] || v[c] > limit ? limit : v[c] < -limit ? -limit : v[c]));
#endif
  }
  // Calls draw(i, n, value, step) for pixels i .. i + n - 1 of row j, chunk by chunk over
  // [i_begin, i_end].
  template <typename Draw>
  void Spans(int j, int i_begin, int i_end, Draw&& draw) const {
    alignas(16) int32_t value[4];
#if defined(__SSE2__)
    // Round inlined, the values kept in registers.
    const __m128d hi = _mm_set1_pd(kValueLimit), lo = _mm_set1_pd(-kValueLimit), jj = _mm_set1_pd(double(j));
    const __m128d sx_rg = _mm_load_pd(sx), sx_b = _mm_load_pd(sx + 2);
    const __m128d row_rg = _mm_add_pd(_mm_load_pd(base), _mm_mul_pd(jj, _mm_load_pd(sy)));
    const __m128d row_b = _mm_add_pd(_mm_load_pd(base + 2), _mm_mul_pd(jj, _mm_load_pd(sy + 2)));
    for (int i = i_begin;; i += chunk) {
      const __m128d ii = _mm_set1_pd(double(i));
      const __m128d at_rg = _mm_add_pd(row_rg, _mm_mul_pd(ii, sx_rg)), at_b = _mm_add_pd(row_b, _mm_mul_pd(ii, sx_b));
      const __m128i rg = _mm_cvtpd_epi32(_mm_max_pd(_mm_min_pd(at_rg, hi), lo));
      const __m128i b0 = _mm_cvtpd_epi32(_mm_max_pd(_mm_min_pd(at_b, hi), lo));
      _mm_store_si128(reinterpret_cast<__m128i*>(value), _mm_unpacklo_epi64(rg, b0));
#else
    for (int i = i_begin;; i += chunk) {
      alignas(16) double at[4];
      for (int c = 0; c < 4; ++c) at[c] = base[c] + double(j) * sy[c] + double(i) * sx[c];
      Round(at, kValueLimit, value);
#endif
      if (i_end - i < chunk) return draw(i, i_end - i + 1, value, step);
      draw(i, chunk, value, step);
    }
  }
};

// Triangles ahead of the one drawn whose data is prefetched.
constexpr uint32_t kPrefetchAhead = 8;

template <typename Pixels>
void DrawFineMesh(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine, const Viewport& viewport,
                  const std::vector<Edge>* boundary, int threads, bool zero_bands, typename Pixels::Sample* data) {
  const ScratchArray<FixedPoint> pts = ToFixedAll(fine, viewport, threads);
  const int width = viewport.width;
  const RowBandBins bins = BinTrianglesByRowBand(triangles, pts, viewport.height,
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
    // Decreasing index, each span overwriting what it covers: the lowest fine triangle owning
    // a pixel is the last to write it (folded triangles), with no per-pixel test.
    const uint32_t first = bins.offsets[size_t(band)];
    for (uint32_t k = bins.offsets[size_t(band) + 1]; k-- > first;) {
      // The vertex data of the triangles drawn next requested ahead: each triangle's are
      // dependent loads (list, triangle, vertices) that miss the cache in no order, and a
      // triangle's work is too long for the processor to reach the next one's loads itself.
      if (k >= first + 2 * kPrefetchAhead) __builtin_prefetch(&triangles[bins.triangles[k - 2 * kPrefetchAhead]]);
      if (k >= first + kPrefetchAhead) {
        const auto& w = triangles[bins.triangles[k - kPrefetchAhead]].v;
        for (int m = 0; m < 3; ++m) __builtin_prefetch(&pts[w[m]]), __builtin_prefetch(&fine[w[m]]);
      }
      const uint32_t t = bins.triangles[k];
      const auto& v = triangles[t].v;
      // Binned by its rows alone: the set-up rejects a degenerate triangle, or one between columns.
      if (!SetupTriangle(pts[v[0]], pts[v[1]], pts[v[2]], width, viewport.height, s)) continue;
      const Vertex* cv[3] = {&fine[v[s.slot[0]]], &fine[v[s.slot[1]]], &fine[v[s.slot[2]]]};
      const ColourPlane plane(s, cv);
      ScanSegments(s, row0, row1, [&](const EdgeRows&, FloorWalk left, FloorWalk right, int j_begin, int j_end) {
        // Copies in locals: a pixel store may alias whatever is reached through a reference,
        // which the compiler would then load again after every store.
        const ColourPlane p = plane;
        const int i_min = s.i0, i_max = s.i1, w = width;
        typename Pixels::Sample* const out = data;
        for (int j = j_begin; j < j_end; ++j, left.Next(), right.Next()) {
          const int64_t lo = std::max<int64_t>(left.q, i_min), hi = std::min<int64_t>(right.q, i_max);
          if (lo > hi) continue;
          typename Pixels::Sample* const row = out + size_t(j) * size_t(w) * 4;
          p.Spans(j, int(lo), int(hi), [&](int i, int n, const int32_t* c, const int32_t* step) {
            Pixels::DrawSpan(row + size_t(i) * 4, n, w - i, c, step);
          });
        }
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

void PrepareRaster8(const Viewport& viewport, Raster8& out) {
  out = Raster8();
  if (!ValidViewport(viewport)) return;
  out.width = viewport.width, out.height = viewport.height, out.channels = 4;
  // Left unwritten (DefaultInitAllocator): the bands zero their own rows when drawing.
  const size_t bytes = size_t(viewport.width) * viewport.height * 4;
  internal::ReserveLarge(out.data, bytes);
  out.data.resize(bytes);
  // One byte a 4 KiB page: the kernel maps (and zeroes) every page now, not under the drawing.
  uint8_t* data = out.data.data();
  for (size_t p = 0; p < bytes; p += 4096) data[p] = 0;
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

void RenderFineMesh8Into(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                         const Viewport& viewport, const std::vector<Edge>* boundary, int threads, Raster8& out) {
  if (!ValidViewport(viewport) || out.width != viewport.width || out.height != viewport.height ||
      out.channels != 4 || out.data.size() != size_t(viewport.width) * viewport.height * 4) {
    out = RenderFineMesh8(triangles, fine, viewport, boundary, threads);
    return;
  }
  DrawFineMesh<BytePixels>(triangles, fine, viewport, boundary, threads, true, out.data.data());
}

std::vector<Edge> MeshBoundaryEdges(const std::vector<Triangle>& triangles,
                                    const std::vector<VertexTag>* tags) {
  std::vector<uint64_t> keys;
  keys.reserve(tags ? triangles.size() / 4 : triangles.size() * 3);
  auto smooth = [&](uint32_t v) {
    return tags && (v >= tags->size() || (*tags)[v] == VertexTag::kSmooth);
  };
  for (const Triangle& t : triangles) {
    // An edge needs two ends that are not smooth: most fine triangles have none or one.
    const bool s0 = smooth(t.v[0]), s1 = smooth(t.v[1]), s2 = smooth(t.v[2]);
    if (int(s0) + int(s1) + int(s2) >= 2) continue;
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
