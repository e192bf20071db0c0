// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the render module: fixed-point scan conversion of triangles with the
// top-left fill rule (see the rule in sdvi/render.h).
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <thread>
#include <tuple>
#include <vector>

#include "sdvi/default_init_allocator.h"
#include "sdvi/parallel.h"
#include "sdvi/render.h"

namespace sdvi::render_internal {

constexpr int64_t kOne = int64_t(1) << kSubpixelBits;  // one output pixel in fixed point
constexpr int64_t kHalf = kOne / 2;                      // pixel centre offset

// A vertex in output pixels, fixed point; valid = finite and within kMaxOutputCoord
// (|x|, |y| <= 2^29 in fixed point: 32 bits hold them, and the invalid mark is outside).
struct FixedPoint {
  static constexpr int32_t kInvalid = INT32_MIN;
  int32_t x = kInvalid, y = kInvalid;
  bool valid() const { return x != kInvalid; }
};
static_assert(kMaxOutputCoord * (1 << kSubpixelBits) < double(INT32_MAX));

// std::llround of v (|v| < 2^31), inlined and without a branch: the whole part, then one away
// from zero when the fraction (exact) is at least a half.
inline int32_t RoundHalfAway(double v) {
  const double whole = std::trunc(v);
  return int32_t(whole + std::copysign(double(std::abs(v - whole) >= 0.5), v));
}

inline FixedPoint ToFixed(const Vertex& v, const Viewport& vp) {
  const double ox = (double(v.x) - vp.origin_x) * vp.scale_x;
  const double oy = (double(v.y) - vp.origin_y) * vp.scale_y;
  FixedPoint p;
  if (!std::isfinite(ox) || !std::isfinite(oy) || std::abs(ox) > kMaxOutputCoord ||
      std::abs(oy) > kMaxOutputCoord)
    return p;
  p.x = RoundHalfAway(ox * double(kOne));
  p.y = RoundHalfAway(oy * double(kOne));
  return p;
}

// A vector of n value-initialised values whose pages are backed by transparent huge pages where
// the OS allows it: first-touch page faults of a 4096x4096 RGBA float raster (256 MiB) cost
// more than the scan conversion itself with 4 KiB pages.
template <typename T>
void AssignZeroedLarge(std::vector<T>& v, size_t n);

// Large scratch arrays of the scan conversion: resize leaves new elements default-initialised
// (unwritten when trivial) and large ones lie on whole huge pages (sdvi/default_init_allocator.h).
template <typename T>
using ScratchArray = std::vector<T, DefaultInitAllocator<T>>;

// Fixed-point output positions of all vertices.
ScratchArray<FixedPoint> ToFixedAll(const std::vector<Vertex>& fine, const Viewport& vp, int threads);

inline int64_t FloorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
inline int64_t CeilDiv(int64_t a, int64_t b) { return -FloorDiv(-a, b); }

// One triangle ready for scan conversion. Slots are re-ordered so that the signed area is
// positive; slot[k] is the original corner (0..2) in slot k. Edge k is opposite slot k,
// from slot k+1 to slot k+2; E_k(p) > 0 inside, and E_k / area is the barycentric weight
// of slot k.
struct TriangleSetup {
  int64_t x[3], y[3];
  int slot[3];
  int64_t area;     // twice the signed area in fixed point units^2, > 0
  int64_t bias[3];  // 0 on top/left edges, -1 otherwise: owned iff E_k + bias_k >= 0
  int i0, i1, j0, j1;  // inclusive pixel box of candidate centres, clipped to the viewport
};

// Along one axis, the pixel centres [first, last] between the least and the greatest of the
// fixed-point coordinates c0, c1, c2, clipped to 0 .. size - 1; false when there is none.
inline bool CandidateCentres(int64_t c0, int64_t c1, int64_t c2, int size, int& first, int& last) {
  const int64_t lo = std::max<int64_t>(0, CeilDiv(std::min({c0, c1, c2}) - kHalf, kOne));
  const int64_t hi = std::min<int64_t>(size - 1, FloorDiv(std::max({c0, c1, c2}) - kHalf, kOne));
  if (lo > hi) return false;
  first = int(lo), last = int(hi);
  return true;
}

// Fills setup; false when the triangle owns no pixel centre (invalid, degenerate, off-screen).
inline bool SetupTriangle(const FixedPoint& a, const FixedPoint& b, const FixedPoint& c, int width,
                          int height, TriangleSetup& s) {
  if (!a.valid() || !b.valid() || !c.valid()) return false;
  const FixedPoint* p[3] = {&a, &b, &c};
  int64_t area = (int64_t(b.x) - a.x) * (int64_t(c.y) - a.y) - (int64_t(b.y) - a.y) * (int64_t(c.x) - a.x);
  if (area == 0) return false;
  s.slot[0] = 0;
  s.slot[1] = area > 0 ? 1 : 2;
  s.slot[2] = area > 0 ? 2 : 1;
  s.area = area > 0 ? area : -area;
  for (int k = 0; k < 3; ++k) {
    s.x[k] = p[s.slot[k]]->x;
    s.y[k] = p[s.slot[k]]->y;
  }
  if (!CandidateCentres(s.x[0], s.x[1], s.x[2], width, s.i0, s.i1) ||
      !CandidateCentres(s.y[0], s.y[1], s.y[2], height, s.j0, s.j1))
    return false;
  for (int k = 0; k < 3; ++k) {
    const int a1 = (k + 1) % 3, a2 = (k + 2) % 3;
    const int64_t dx = s.x[a2] - s.x[a1], dy = s.y[a2] - s.y[a1];
    const bool top = dy == 0 && dx > 0;  // y grows downwards: interior below
    const bool left = dy < 0;            // interior to the right
    s.bias[k] = (top || left) ? 0 : -1;
  }
  return true;
}

// E_k's growth per pixel to the right.
inline int64_t StepX(const TriangleSetup& s, int k) { return -(s.y[(k + 2) % 3] - s.y[(k + 1) % 3]) * kOne; }

// floor(m / p) for m = m0, m0 + step, m0 + 2 step, ... (p > 0), with its remainder carried
// from row to row: exact, and two integer divisions an edge instead of one a row.
struct FloorWalk {
  int64_t q, r, dq, dr, p;  // m = q * p + r, 0 <= r < p; step = dq * p + dr, 0 <= dr < p
  FloorWalk(int64_t m0, int64_t step, int64_t divisor) : p(divisor) {
    Divide(m0, q, r);
    Divide(step, dq, dr);
  }
  // Floor division by p with its remainder, without a branch on the sign.
  void Divide(int64_t m, int64_t& quotient, int64_t& remainder) const {
    quotient = m / p, remainder = m % p;  // truncated
    const int64_t borrow = remainder < 0;
    quotient -= borrow;
    remainder += p & -borrow;
  }
  // Branch-free: the carry is data-dependent, a mispredicted branch a row cost more than the
  // divisions it replaces.
  void Next() {
    r += dr;
    const int64_t carry = r >= p;
    q += dq + carry;
    r -= p & -carry;
  }
};

// The edge functions of a triangle from row j0 on: E_k(i, j) = a[k] * i + b[k] + (j - j0) *
// db[k], exact in int64.
struct EdgeRows {
  int64_t a[3], b[3], db[3];
  int j0;
  int64_t At(int k, int64_t i, int j) const { return a[k] * i + b[k] + int64_t(j - j0) * db[k]; }
};

// Calls rows(edges, left, right, j_begin, j_end) for the runs of rows of s in [row0, row1)
// bounded by one left and one right edge (at most two runs, top to bottom): on row j of a
// run the owned pixel centres are i in [max(left.q, s.i0), min(right.q, s.i1)] (none when
// that is empty), left and right being the values passed, stepped by Next() once a row.
template <typename Rows>
inline void ScanSegments(const TriangleSetup& s, int row0, int row1, Rows&& rows) {
  const int j0 = std::max(s.j0, row0), j1 = std::min(s.j1, row1 - 1);
  if (j0 > j1) return;
  // Pixel i of row j is on the owned side of edge k iff E_k + bias[k] >= 0: for a[k] > 0 (a
  // left edge) iff i >= ceil(-(b + bias) / a) = floor((a - 1 - b - bias) / a), for a[k] < 0
  // (a right edge) iff i <= floor((b + bias) / -a); each bound walks down the rows (FloorWalk).
  EdgeRows e;
  e.j0 = j0;
  for (int k = 0; k < 3; ++k) {
    const int a1 = (k + 1) % 3, a2 = (k + 2) % 3;
    const int64_t dx = s.x[a2] - s.x[a1], dy = s.y[a2] - s.y[a1];
    e.a[k] = -dy * kOne;
    e.db[k] = dx * kOne;
    e.b[k] = dx * (int64_t(j0) * kOne + kHalf - s.y[a1]) - dy * (kHalf - s.x[a1]);
  }
  auto walk_from = [&](int k, int j) {  // edge k's bound from row j on
    const int64_t t = e.b[k] + int64_t(j - j0) * e.db[k] + s.bias[k];
    return e.a[k] > 0 ? FloorWalk(e.a[k] - 1 - t, -e.db[k], e.a[k]) : FloorWalk(t, e.db[k], -e.a[k]);
  };
  // Rows [j_begin, j_end) bounded by the left edge l and the right edge r alone.
  auto run = [&](int l, int r, int j_begin, int j_end) {
    if (j_begin < j_end) rows(e, walk_from(l, j_begin), walk_from(r, j_begin), j_begin, j_end);
  };
  int lefts[3], rights[3], n_left = 0, n_right = 0, flat = -1;
  for (int k = 0; k < 3; ++k) {
    if (e.a[k] > 0) lefts[n_left++] = k;
    else if (e.a[k] < 0) rights[n_right++] = k;
    else flat = k;
  }
  if (flat >= 0) {
    // A horizontal edge is the top or bottom of the box: E_flat > 0 on every row of the box
    // but its own, which the bias decides.
    const int64_t on_row = FloorDiv(s.y[(flat + 1) % 3] - kHalf, kOne);  // the edge's row, if a pixel row
    const bool on_centres = on_row * kOne + kHalf == s.y[(flat + 1) % 3];
    const bool skip = on_centres && s.bias[flat] < 0;
    const int skip_row = skip && on_row >= j0 && on_row <= j1 ? int(on_row) : j1 + 1;
    run(lefts[0], rights[0], j0, skip_row);
    run(lefts[0], rights[0], skip_row + 1, j1 + 1);
    return;
  }
  // One edge alone on its side spans every row (the long edge); the two on the other side
  // meet at the middle vertex m. Rows above m are bounded by the long edge and the upper
  // short edge only (the lower one holds strictly there: the row's segment is inside the
  // triangle and away from that edge), rows below by the long and the lower short edge. On
  // a row through m both short edges cross the row at m and, being on the same side, have
  // the same bias: either gives the row's bound; the lower one is taken.
  const bool long_left = n_left == 1;
  const int long_edge = long_left ? lefts[0] : rights[0];
  const int short0 = long_left ? rights[0] : lefts[0], short1 = long_left ? rights[1] : lefts[1];
  const int m = long_edge;  // the vertex opposite the long edge, where the short edges meet
  // short0's other end: slot (short0 + 1) % 3 or (short0 + 2) % 3, whichever is not m.
  const int other0 = (short0 + 1) % 3 == m ? (short0 + 2) % 3 : (short0 + 1) % 3;
  const int upper = s.y[other0] < s.y[m] ? short0 : short1, lower = upper == short0 ? short1 : short0;
  // The first row whose centre is at or below m.
  const int jm = int(std::clamp<int64_t>(CeilDiv(s.y[m] - kHalf, kOne), j0, int64_t(j1) + 1));
  if (long_left) {
    run(long_edge, upper, j0, jm);
    run(long_edge, lower, jm, j1 + 1);
  } else {
    run(upper, long_edge, j0, jm);
    run(lower, long_edge, jm, j1 + 1);
  }
}

// Calls span(j, i_begin, i_end, e) for every row j in [row0, row1) that has owned pixel
// centres, i in [i_begin, i_end] (inclusive); e[k] is the exact edge function E_k at
// (i_begin, j), and E_k grows by StepX(s, k) per pixel to the right.
template <typename Span>
inline void ScanSpans(const TriangleSetup& s, int row0, int row1, Span&& span) {
  ScanSegments(s, row0, row1, [&](const EdgeRows& e, FloorWalk left, FloorWalk right, int j_begin, int j_end) {
    for (int j = j_begin; j < j_end; ++j, left.Next(), right.Next()) {
      const int64_t lo = std::max<int64_t>(left.q, s.i0), hi = std::min<int64_t>(right.q, s.i1);
      if (lo > hi) continue;
      const int64_t at[3] = {e.At(0, lo, j), e.At(1, lo, j), e.At(2, lo, j)};
      span(j, int(lo), int(hi), at);
    }
  });
}

// Calls visit(i, j, e0, e1, e2) for every owned pixel centre of s in rows [row0, row1),
// with the exact edge functions e_k (barycentric weight of slot k = e_k / s.area).
template <typename Visit>
inline void ScanTriangle(const TriangleSetup& s, int row0, int row1, Visit&& visit) {
  const int64_t step[3] = {StepX(s, 0), StepX(s, 1), StepX(s, 2)};
  ScanSpans(s, row0, row1, [&](int j, int i_begin, int i_end, const int64_t* e0) {
    int64_t e[3] = {e0[0], e0[1], e0[2]};
    for (int i = i_begin; i <= i_end; ++i) {
      visit(i, j, e[0], e[1], e[2]);
      e[0] += step[0], e[1] += step[1], e[2] += step[2];
    }
  });
}

// Number of worker threads for a request (0 = hardware concurrency), at least 1.
inline int WorkerCount(int requested, int rows) {
  int n = requested > 0 ? requested : int(std::thread::hardware_concurrency());
  n = std::max(1, std::min(n, 16));
  return std::max(1, std::min(n, rows / 16 + 1));
}

// Runs body(band, row0, row1) over contiguous row bands, one thread per band.
template <typename Body>
inline void ForEachRowBand(int height, int threads, Body&& body) {
  const int n = WorkerCount(threads, height);
  if (n == 1) {
    body(0, 0, height);
    return;
  }
  RunTasks(n, [&body, height, n](int b) {
    body(b, int(int64_t(height) * b / n), int(int64_t(height) * (b + 1) / n));
  });
}

// Fine triangles sorted into bands of output rows, so that a band's pixels stay in cache
// while its triangles are drawn (the fine triangles of a vectorized mesh come in the
// order of their control triangles, which is not spatial: drawn in that order, nearly
// every span of a 4096-pixel-wide output misses the cache). Band b holds rows
// [b * band_rows, min(height, (b + 1) * band_rows)) and lists, in increasing index, every
// triangle with valid vertices whose rows of candidate centres (CandidateCentres) meet
// those rows; whether it owns a pixel there (SetupTriangle) is left to the drawing.
struct RowBandBins {
  int band_rows = 1;
  std::vector<uint32_t> offsets{0};  // bands + 1 entries; band b = [offsets[b], offsets[b + 1])
  ScratchArray<uint32_t> triangles;
  int bands() const { return int(offsets.size()) - 1; }
};

// The bins of triangles (vertex positions pts) for an output of height rows.
RowBandBins BinTrianglesByRowBand(const std::vector<Triangle>& triangles, const ScratchArray<FixedPoint>& pts,
                                  int height, int band_rows, int threads);

// Rows a band holds so that its pixels (bytes_per_pixel each) take about 512 KiB, half
// of a typical L2 cache, and at least 4 rows (measured on x8 renders: 32 rows of 16 KiB a few
// per cent faster than 16, 8 rows slower).
inline int BandRowsFor(int width, size_t bytes_per_pixel) {
  const size_t row_bytes = std::max<size_t>(1, size_t(width) * bytes_per_pixel);
  return int(std::clamp<size_t>((size_t(1) << 19) / row_bytes, 4, 256));
}

// Runs body(band) for every band in [0, bands) on WorkerCount(threads, rows) threads, each
// taking the next undone band: a band is drawn by one thread, in one order, whatever
// their number.
template <typename Body>
inline void ForEachBand(int bands, int threads, int rows, Body&& body) {
  const int n = std::min(WorkerCount(threads, rows), std::max(1, bands));
  if (n == 1) {
    for (int b = 0; b < bands; ++b) body(b);
    return;
  }
  std::atomic<int> next{0};
  RunTasks(n, [&](int) {
    try {
      for (int b = next.fetch_add(1); b < bands; b = next.fetch_add(1)) body(b);
    } catch (...) {
      next = bands;
      throw;
    }
  });
}

// Runs body(begin, end) over contiguous index chunks of [0, count) in parallel.
template <typename Body>
inline void ForEachChunk(size_t count, int threads, Body&& body) {
  int n = threads > 0 ? threads : int(std::thread::hardware_concurrency());
  n = std::max(1, std::min<int>(n, 16));
  if (count < 65536) n = 1;
  if (n == 1) {
    body(size_t(0), count);
    return;
  }
  RunTasks(n, [&body, count, n](int b) { body(count * size_t(b) / size_t(n), count * size_t(b + 1) / size_t(n)); });
}

}  // namespace sdvi::render_internal
