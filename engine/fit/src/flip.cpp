// SPDX-License-Identifier: GPL-3.0-or-later
// Data-dependent edge flips of a control mesh (vectorize.h, FlipEdgesToData): the
// constrained Delaunay triangulation ignores the colours; a flip of a non-crease edge is
// kept when the piecewise-linear interpolation of the image colours at the vertices fits
// the pixels of the edge's quadrilateral better with the other diagonal.
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

// The 9 taps of a Gaussian of sigma 1 px (offsets -4..4), summing to 1.
std::array<double, 9> GaussianTaps() {
  std::array<double, 9> taps;
  double sum = 0;
  for (int i = 0; i < 9; ++i) sum += taps[size_t(i)] = std::exp(-0.5 * double((i - 4) * (i - 4)));
  for (double& t : taps) t /= sum;
  return taps;
}

// Index i of a row or column of n pixels, reflected at the ends (... 1 0 | 0 1 ... n-1 | n-1 n-2 ...).
int Reflect(int i, int n) {
  while (i < 0 || i >= n) i = i < 0 ? -i - 1 : 2 * n - 1 - i;
  return i;
}

// R, G, B of raster smoothed by a Gaussian of sigma 1 px (9 taps, reflected border) and
// interpolated bilinearly at v's position (pixel centres at half-integers).
Rgb SmoothedColour(const Raster& raster, const Vertex& v) {
  static const std::array<double, 9> taps = GaussianTaps();
  const int width = raster.width, height = raster.height;
  const double fx = std::clamp(double(v.x) - 0.5, 0.0, double(width - 1));
  const double fy = std::clamp(double(v.y) - 0.5, 0.0, double(height - 1));
  const int ix = std::min(int(fx), std::max(0, width - 2)), iy = std::min(int(fy), std::max(0, height - 2));
  const int jx = std::min(ix + 1, width - 1), jy = std::min(iy + 1, height - 1);
  const double u = fx - ix, w = fy - iy;
  const int grey = raster.channels <= 2;
  // Horizontal passes at columns ix, jx over rows iy - 4 .. jy + 4, then vertical ones.
  double rows[10][2][3] = {};
  for (int r = 0; r < 10; ++r) {
    const int y = Reflect(iy - 4 + r, height);
    for (int side = 0; side < 2; ++side) {
      const int x0 = side == 0 ? ix : jx;
      for (int t = 0; t < 9; ++t) {
        const float* px = &raster.data[(size_t(y) * width + size_t(Reflect(x0 - 4 + t, width))) * raster.channels];
        for (int k = 0; k < 3; ++k) rows[r][side][k] += taps[size_t(t)] * px[grey ? 0 : k];
      }
    }
  }
  Rgb out;
  for (int k = 0; k < 3; ++k) {
    double s[2][2] = {};  // [row iy / jy][column ix / jx]
    for (int t = 0; t < 9; ++t) {
      for (int side = 0; side < 2; ++side) {
        s[0][side] += taps[size_t(t)] * rows[t][side][k];
        s[1][side] += taps[size_t(t)] * rows[t + (jy - iy)][side][k];
      }
    }
    out.c[k] = float((1 - u) * (1 - w) * s[0][0] + u * (1 - w) * s[0][1] + (1 - u) * w * s[1][0] + u * w * s[1][1]);
  }
  return out;
}

// The three corners of t in the canonical order (ascending x, then y, as float bits), and
// its cache key: an error is computed in that order, so it is a function of the triangle
// alone, whatever the rotation or orientation its mesh lists it in.
std::array<uint32_t, 3> CanonicalCorners(const Image& mesh, const std::array<uint32_t, 3>& t,
                                         std::array<uint32_t, 6>* key) {
  std::array<std::array<uint32_t, 3>, 3> items;  // x bits, y bits, vertex
  for (int k = 0; k < 3; ++k) {
    std::memcpy(&items[k][0], &mesh.vertices[t[k]].x, 4);
    std::memcpy(&items[k][1], &mesh.vertices[t[k]].y, 4);
    items[k][2] = t[k];
  }
  std::sort(items.begin(), items.end());
  for (int k = 0; k < 3; ++k) {
    (*key)[2 * k] = items[k][0];
    (*key)[2 * k + 1] = items[k][1];
  }
  return {items[0][2], items[1][2], items[2][2]};
}

// How far ahead QuadError::Triangle asks for raster rows, and the most pixels of a row it
// asks for (longer runs are streamed by the hardware once started).
constexpr int64_t kPrefetchRows = 2, kPrefetchPixels = 48;

class QuadError {
 public:
  QuadError(const Image& mesh, const Raster& raster, const Raster* mask, const std::vector<Rgb>& colour)
      : mesh_(mesh), raster_(raster), mask_(mask), colour_(colour),
        whole_(mask == nullptr && !raster.has_alpha()) {}

  // Squared error of the linear interpolation over triangle t (vertex triple, in
  // CanonicalCorners order) at the pixel centres it owns. Ownership is exact: positions in
  // fixed point (kSubpixelBits, as the renderer), a centre strictly inside or on a top or
  // left edge (sdvi/render.h), so the pixels of a quadrilateral belong to exactly one of its
  // two triangles whichever diagonal it has. The interpolation is c2 + w0 (c0 - c2) +
  // w1 (c1 - c2) with w_k = E_k / area from the exact edge functions: constant where the
  // three colours are equal.
  double Triangle(const std::array<uint32_t, 3>& t) const {
    constexpr int64_t kOne = int64_t(1) << kSubpixelBits, kHalf = kOne / 2;
    int64_t x[3], y[3];
    const Rgb* c[3];
    for (int k = 0; k < 3; ++k) {
      const Vertex& v = mesh_.vertices[t[k]];
      if (!(std::abs(v.x) < kMaxOutputCoord && std::abs(v.y) < kMaxOutputCoord)) return 0;
      x[k] = std::llround(double(v.x) * double(kOne));
      y[k] = std::llround(double(v.y) * double(kOne));
      c[k] = &colour_[t[k]];
    }
    int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if (area == 0) return 0;
    if (area < 0) {  // counter-clockwise on screen: edge functions positive inside
      std::swap(x[1], x[2]);
      std::swap(y[1], y[2]);
      std::swap(c[1], c[2]);
      area = -area;
    }
    auto floor_div = [](int64_t n, int64_t d) { return n >= 0 ? n / d : -((-n + d - 1) / d); };
    const int64_t j0 = std::max<int64_t>(0, -floor_div(-(std::min({y[0], y[1], y[2]}) - kHalf), kOne));
    const int64_t j1 = std::min<int64_t>(raster_.height - 1, floor_div(std::max({y[0], y[1], y[2]}) - kHalf, kOne));
    const int64_t i0 = std::max<int64_t>(0, -floor_div(-(std::min({x[0], x[1], x[2]}) - kHalf), kOne));
    const int64_t i1 = std::min<int64_t>(raster_.width - 1, floor_div(std::max({x[0], x[1], x[2]}) - kHalf, kOne));
    // E_k (edge from corner k+1 to k+2) at pixel (i, j) = a[k] i + dx[k] (j kOne + kHalf - y1) + cst[k].
    int64_t a[3], dx[3], y1[3], cst[3], bias[3];
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      dx[k] = x[k2] - x[k1];
      const int64_t dy = y[k2] - y[k1];
      a[k] = -dy * kOne;
      y1[k] = y[k1];
      cst[k] = -dy * (kHalf - x[k1]);
      const bool top = dy == 0 && dx[k] > 0, left = dy < 0;
      bias[k] = top || left ? 0 : -1;
    }
    const double inv_area = 1.0 / double(area);
    double d0[3], d1[3], base[3];
    for (int q = 0; q < 3; ++q) {
      d0[q] = double(c[0]->c[q]) - c[2]->c[q];
      d1[q] = double(c[1]->c[q]) - c[2]->c[q];
      base[q] = c[2]->c[q];
    }
    const int channels = raster_.channels;
    const int o1 = channels <= 2 ? 0 : 1, o2 = channels <= 2 ? 0 : 2;
    double sum = 0;
    for (int64_t j = j0; j <= j1; ++j) {
      const int64_t py = j * kOne + kHalf;
      int64_t lo = i0, hi = i1, e[3];
      for (int k = 0; k < 3; ++k) {
        e[k] = dx[k] * (py - y1[k]) + cst[k];  // E_k at i = 0
        const int64_t owned = e[k] + bias[k];  // owned iff a[k] i + owned >= 0
        if (a[k] > 0) {
          lo = std::max(lo, -floor_div(owned, a[k]));
        } else if (a[k] < 0) {
          hi = std::min(hi, floor_div(owned, -a[k]));
        } else if (owned < 0) {
          lo = hi + 1;
        }
      }
      if (lo > hi) continue;
      // The raster is read row by row, each row's run starting on lines not in cache: ask
      // for the run kPrefetchRows rows down (this run's columns, a few pixels wider) now.
      if (j + kPrefetchRows <= j1) {
        const int64_t c0 = std::max(i0, lo - 4), c1 = std::min(i1, std::min(hi + 4, c0 + kPrefetchPixels));
        const float* row = &raster_.data[size_t(j + kPrefetchRows) * size_t(raster_.width) * size_t(channels)];
        const char* first = reinterpret_cast<const char*>(row + c0 * channels);
        const char* last = reinterpret_cast<const char*>(row + c1 * channels + channels - 1);
        for (const char* q = first; q < last; q += 64) __builtin_prefetch(q);
        __builtin_prefetch(last);
      }
      int64_t e0 = a[0] * lo + e[0], e1 = a[1] * lo + e[1];
      const float* px = &raster_.data[(size_t(j) * size_t(raster_.width) + size_t(lo)) * size_t(channels)];
      for (int64_t i = lo; i <= hi; ++i, e0 += a[0], e1 += a[1], px += channels) {
        if (!whole_ && !InDomain(raster_, mask_, int(i), int(j))) continue;
        const double w0 = double(e0) * inv_area, w1 = double(e1) * inv_area;
        const double r = base[0] + w0 * d0[0] + w1 * d1[0] - px[0];
        const double g = base[1] + w0 * d0[1] + w1 * d1[1] - px[o1];
        const double b = base[2] + w0 * d0[2] + w1 * d1[2] - px[o2];
        sum += r * r + g * g + b * b;
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

// The interior edges' two triangles by edge key ((a << 32) | b, a < b): open addressing,
// linear probing, deletion by backward shift; at most half full (a flip erases one edge and
// adds one, so the count never exceeds the first sweep's). What a lookup answers does not
// depend on the table's layout, so the flips are those of any map (std::unordered_map
// before: a node allocation an edge and most of the first sweep's serial time).
class EdgeTriangleMap {
 public:
  static constexpr uint64_t kEmpty = ~uint64_t(0);  // no edge has a = b = 2^32 - 1
  void Reserve(size_t n) {
    size_t size = 16;
    while (size < 2 * n + 2) size *= 2;
    keys_.assign(size, kEmpty);
    values_.assign(size, {0, 0});
    mask_ = size - 1;
  }
  std::array<uint32_t, 2>* Find(uint64_t key) {
    for (size_t i = Slot(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) return &values_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }
  bool Contains(uint64_t key) { return Find(key) != nullptr; }
  // Inserts key or replaces its triangles.
  void Set(uint64_t key, const std::array<uint32_t, 2>& value) {
    size_t i = Slot(key);
    while (keys_[i] != key && keys_[i] != kEmpty) i = (i + 1) & mask_;
    keys_[i] = key;
    values_[i] = value;
  }
  void Erase(uint64_t key) {
    size_t i = Slot(key);
    while (keys_[i] != key) {
      if (keys_[i] == kEmpty) return;
      i = (i + 1) & mask_;
    }
    // Backward shift: move up every later entry of the run whose probe start is not
    // cyclically in (i, j].
    for (size_t j = (i + 1) & mask_; keys_[j] != kEmpty; j = (j + 1) & mask_) {
      const size_t k = Slot(keys_[j]);
      const bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
      if (stays) continue;
      keys_[i] = keys_[j];
      values_[i] = values_[j];
      i = j;
    }
    keys_[i] = kEmpty;
  }

 private:
  size_t Slot(uint64_t key) const {
    key ^= key >> 31;
    key *= 0x9e3779b97f4a7c15ull;
    return size_t(key ^ (key >> 32)) & mask_;
  }
  std::vector<uint64_t> keys_;
  std::vector<std::array<uint32_t, 2>> values_;
  size_t mask_ = 0;
};

}  // namespace

namespace {

// The slot a key's probe starts at in a table of `mask + 1` slots.
size_t CacheSlot(const std::array<uint32_t, 6>& key, size_t mask) {
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (uint32_t word : key) h = (h ^ word) * 0xff51afd7ed558ccdull;
  return size_t(h ^ (h >> 29)) & mask;
}

}  // namespace

const double* FlipErrorCache::Find(const std::array<uint32_t, 6>& key) const {
  if (slots_.empty()) return nullptr;
  const size_t mask = slots_.size() - 1;
  for (size_t i = CacheSlot(key, mask); slots_[i] != 0; i = (i + 1) & mask) {
    const Entry& e = previous_[slots_[i] - 1];
    if (e.key == key) {
      hits_.fetch_add(1, std::memory_order_relaxed);
      return &e.error;
    }
  }
  return nullptr;
}

void FlipErrorCache::EndCall() {
  size_t size = 16;
  while (size < current_.size() + current_.size() / 2) size *= 2;
  std::vector<uint32_t>().swap(slots_);  // the old table goes before the new one is made
  previous_.clear();
  previous_.shrink_to_fit();
  slots_.assign(size, 0);
  const size_t mask = size - 1;
  // A key recorded twice has the same error both times (a function of the key): kept once,
  // in place in current_, which becomes the entries.
  size_t kept = 0;
  for (size_t k = 0; k < current_.size(); ++k) {
    const Entry entry = current_[k];
    size_t i = CacheSlot(entry.key, mask);
    while (slots_[i] != 0 && current_[slots_[i] - 1].key != entry.key) i = (i + 1) & mask;
    if (slots_[i] != 0) continue;
    current_[kept] = entry;
    slots_[i] = uint32_t(++kept);
  }
  current_.resize(kept);
  current_.shrink_to_fit();
  previous_.swap(current_);
}

int FlipEdgesToData(Image& mesh, const Raster& raster, const Raster* mask, int passes,
                    double min_angle_deg, int threads, FlipErrorCache* cache) {
  const int width = raster.width, height = raster.height;
  if (passes <= 0 || mesh.triangles.empty() || width <= 0 || height <= 0) return 0;
  // Vertex colours: the image smoothed by a Gaussian of sigma 1 px, bilinear.
  std::vector<Rgb> colour(mesh.vertices.size());
  fit_internal::ForEachChunk(mesh.vertices.size(), 4096, threads, [&](size_t, size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) colour[i] = SmoothedColour(raster, mesh.vertices[i]);
  });
  FlipErrorCache local;
  if (cache == nullptr) cache = &local;
  const QuadError error(mesh, raster, mask, colour);
  // The error of triangle t, from the cache when it holds it; key_of is its cache key.
  // The error of triangle t and its cache entry (what cache->Add records).
  auto triangle_entry_of = [&](const std::array<uint32_t, 3>& t, FlipErrorCache::Entry* entry) {
    const std::array<uint32_t, 3> corners = CanonicalCorners(mesh, t, &entry->key);
    const double* e = cache->Find(entry->key);
    entry->error = e != nullptr ? *e : error.Triangle(corners);
    return entry->error;
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
  constexpr size_t kPairChunk = 4096;  // edges a thread tests at a time
  // The interior edges and their two triangles (lower index first), kept up to date by the
  // flips: the first sweep finds them by sorting every triangle's sides, a later one lists
  // only the edges of the triangles the previous sweep changed, in the same (edge) order.
  auto edge_key = [](const Edge& e) { return (uint64_t(e.a) << 32) | e.b; };
  EdgeTriangleMap edge_triangles;
  for (int pass = 0; pass < passes; ++pass) {
    // The edges a sweep may flip, by the geometry at the sweep's start: the sweep's interior
    // edges (with their triangles) are listed in edge order, then tested on the threads in
    // fixed chunks and the candidates gathered in that order.
    struct Pair {
      Edge e;
      uint32_t t0, t1;
    };
    std::vector<Pair> pairs;
    auto consider = [&](const Edge& e, uint32_t t0, uint32_t t1, std::vector<Candidate>& candidates) {
      if (!(changed[t0] || changed[t1])) return;
      if (std::binary_search(creases.begin(), creases.end(), e)) return;
      auto opposite = [&](uint32_t t) {
        for (uint32_t w : mesh.triangles[t].v) {
          if (w != e.a && w != e.b) return w;
        }
        return e.a;
      };
      const uint32_t r = opposite(t0), s = opposite(t1);
      if (r == s) return;
      const Vertex& P = mesh.vertices[e.a];
      const Vertex& Q = mesh.vertices[e.b];
      const Vertex& R = mesh.vertices[r];
      const Vertex& S = mesh.vertices[s];
      // Convex quadrilateral: r-s must cross p-q strictly.
      const double op = Orient(R, S, P), oq = Orient(R, S, Q);
      const double orr = Orient(P, Q, R), os = Orient(P, Q, S);
      if (!((op > 0 && oq < 0) || (op < 0 && oq > 0))) return;
      if (!((orr > 0 && os < 0) || (orr < 0 && os > 0))) return;
      if (MinAngleSine(R, S, P) < min_sine || MinAngleSine(R, S, Q) < min_sine) return;
      candidates.push_back({e, t0, t1, r, s, 0.0, 0.0});
    };
    if (pass == 0) {
      // (edge, triangle) pairs sorted by edge: interior edges appear twice.
      struct Side {
        Edge e;
        uint32_t t;
      };
      // Sorted by (a, b, t): listed in triangle order, then stably counting-sorted by b,
      // then by a (the order std::sort with that comparison gives).
      std::vector<Side> sides(mesh.triangles.size() * 3), sorted(sides.size());
      for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& v = mesh.triangles[t].v;
        for (int k = 0; k < 3; ++k) sides[3 * size_t(t) + size_t(k)] = {Edge::Of(v[k], v[(k + 1) % 3]), t};
      }
      {
        std::vector<uint32_t> start(mesh.vertices.size() + 1);
        auto counting_sort = [&](auto vertex_of) {
          std::fill(start.begin(), start.end(), 0);
          for (const Side& side : sides) ++start[vertex_of(side) + 1];
          for (size_t v = 0; v + 1 < start.size(); ++v) start[v + 1] += start[v];
          for (const Side& side : sides) sorted[start[vertex_of(side)]++] = side;
          sides.swap(sorted);
        };
        counting_sort([](const Side& side) { return side.e.b; });
        counting_sort([](const Side& side) { return side.e.a; });
      }
      std::vector<Side>().swap(sorted);
      for (size_t i = 0; i + 1 < sides.size(); ++i) {
        if (sides[i].e != sides[i + 1].e) continue;
        const Edge e = sides[i].e;
        const uint32_t t0 = sides[i].t, t1 = sides[i + 1].t;
        ++i;
        pairs.push_back({e, t0, t1});
      }
      std::vector<Side>().swap(sides);
      edge_triangles.Reserve(pairs.size());
      for (const Pair& p : pairs) edge_triangles.Set(edge_key(p.e), {p.t0, p.t1});
    } else {
      std::vector<Edge> edges;
      for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        if (!changed[t]) continue;
        const auto& v = mesh.triangles[t].v;
        for (int k = 0; k < 3; ++k) {
          const Edge e = Edge::Of(v[k], v[(k + 1) % 3]);
          if (edge_triangles.Contains(edge_key(e))) edges.push_back(e);
        }
      }
      std::sort(edges.begin(), edges.end());
      edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
      for (const Edge& e : edges) {
        const std::array<uint32_t, 2>& t = *edge_triangles.Find(edge_key(e));
        pairs.push_back({e, t[0], t[1]});
      }
    }
    std::vector<std::vector<Candidate>> chunk_candidates(fit_internal::ChunkCount(pairs.size(), kPairChunk));
    fit_internal::ForEachChunk(pairs.size(), kPairChunk, threads, [&](size_t chunk, size_t k0, size_t k1) {
      for (size_t k = k0; k < k1; ++k) consider(pairs[k].e, pairs[k].t0, pairs[k].t1, chunk_candidates[chunk]);
    });
    std::vector<Pair>().swap(pairs);
    std::vector<Candidate> candidates;
    {
      size_t total = 0;
      for (const std::vector<Candidate>& c : chunk_candidates) total += c.size();
      candidates.reserve(total);
      for (std::vector<Candidate>& c : chunk_candidates) {
        candidates.insert(candidates.end(), c.begin(), c.end());
        std::vector<Candidate>().swap(c);
      }
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
    // Each error's cache entry is recorded where it is computed: the unknown triangles'
    // in their order, then the candidates' two flipped triangles each.
    FlipErrorCache::Entry* entries = cache->Extend(unknown.size() + 2 * candidates.size());
    fit_internal::ForEachChunk(unknown.size(), kChunk, threads, [&](size_t, size_t k0, size_t k1) {
      for (size_t k = k0; k < k1; ++k) {
        triangle_error[unknown[k]] = triangle_entry_of(mesh.triangles[unknown[k]].v, &entries[k]);
      }
    });
    entries += unknown.size();
    fit_internal::ForEachChunk(candidates.size(), kChunk, threads, [&](size_t, size_t k0, size_t k1) {
      for (size_t k = k0; k < k1; ++k) {
        Candidate& c = candidates[k];
        c.after0 = triangle_entry_of({c.r, c.s, c.e.a}, &entries[2 * k]);
        c.after1 = triangle_entry_of({c.r, c.s, c.e.b}, &entries[2 * k + 1]);
      }
    });
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
      // The edge map: (a, b) becomes (r, s); side (a, s) moves from t1 to t0, (b, r) from t0
      // to t1 (the others keep their triangles).
      edge_triangles.Erase(edge_key(c.e));
      edge_triangles.Set(edge_key(Edge::Of(c.r, c.s)), {std::min(t0, t1), std::max(t0, t1)});
      auto move_side = [&](const Edge& e, uint32_t from, uint32_t to) {
        std::array<uint32_t, 2>* found = edge_triangles.Find(edge_key(e));
        if (found == nullptr) return;  // a boundary edge
        std::array<uint32_t, 2>& t = *found;
        if (t[0] == from) t[0] = to;
        else if (t[1] == from) t[1] = to;
        if (t[0] > t[1]) std::swap(t[0], t[1]);
      };
      move_side(Edge::Of(c.e.a, c.s), t1, t0);
      move_side(Edge::Of(c.e.b, c.r), t0, t1);
      ++pass_flips;
    }
    changed.swap(touched);
    flips += pass_flips;
    if (pass_flips == 0) break;
  }
  cache->EndCall();
  return flips;
}

}  // namespace sdvi
