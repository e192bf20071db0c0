// SPDX-License-Identifier: GPL-3.0-or-later
// bench_limit_file: BuildLimitSurface + EvaluateSurface on the control mesh of a .sdvi, as
// the colour fit calls them (level 2, limit, all threads unless told), with a digest of
// everything built, so that two builds of the engine can be checked for the same tables.
//
//   bench_limit_file FILE.sdvi [--reps N] [--threads T] [--levels r] [--crop F]
//                    [--spatial-order]
//   --crop F           only the triangles whose centroid lies in the left F of the width
//                      (a smaller mesh with the same numbering, e.g. for cachegrind)
//   --spatial-order    vertices renumbered by 16-pixel rows (serpentine), triangles by
//                      their smallest vertex: what a coherent numbering would cost (the
//                      tables differ, so does the digest)
// Prints, for each rep: the counts, wall and CPU seconds of the build, seconds of the
// evaluation, and the digest.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "sdvi/format.h"
#include "sdvi/subdiv.h"

namespace {

uint64_t Fnv(uint64_t h, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

constexpr uint32_t kDropped = 0xffffffffu;

// The image with only the given vertices (rank[v] = new index, kDropped: dropped) and
// triangles; crease edges of kept triangles and corners of kept vertices.
void Renumber(sdvi::Image& image, const std::vector<uint32_t>& rank, std::vector<sdvi::Triangle> triangles) {
  std::vector<sdvi::Vertex> vertices(image.vertices.size());
  size_t count = 0;
  for (uint32_t v = 0; v < rank.size(); ++v)
    if (rank[v] != kDropped) vertices[rank[v]] = image.vertices[v], ++count;
  vertices.resize(count);
  std::vector<sdvi::Edge> edges;
  for (auto& t : triangles) {
    for (auto& v : t.v) v = rank[v];
    for (int k = 0; k < 3; ++k) edges.push_back(sdvi::Edge::Of(t.v[k], t.v[(k + 1) % 3]));
  }
  std::sort(edges.begin(), edges.end());
  std::vector<sdvi::Edge> creases;
  for (const auto& e : image.crease_edges) {
    if (rank[e.a] == kDropped || rank[e.b] == kDropped) continue;
    const sdvi::Edge m = sdvi::Edge::Of(rank[e.a], rank[e.b]);
    if (std::binary_search(edges.begin(), edges.end(), m)) creases.push_back(m);
  }
  std::sort(creases.begin(), creases.end());
  std::vector<uint32_t> corners;
  for (uint32_t c : image.corners)
    if (rank[c] != kDropped) corners.push_back(rank[c]);
  std::sort(corners.begin(), corners.end());
  image.vertices = std::move(vertices);
  image.triangles = std::move(triangles);
  image.crease_edges = std::move(creases);
  image.corners = std::move(corners);
  image.polylines.clear();
  image.pairs.clear();
}

void Crop(sdvi::Image& image, double fraction) {
  const double limit = fraction * image.width;
  std::vector<sdvi::Triangle> kept;
  std::vector<uint32_t> rank(image.vertices.size(), kDropped);
  for (const auto& t : image.triangles) {
    double cx = 0;
    for (uint32_t v : t.v) cx += image.vertices[v].x / 3;
    if (cx >= limit) continue;
    kept.push_back(t);
    for (uint32_t v : t.v) rank[v] = 0;
  }
  uint32_t next = 0;
  for (uint32_t& r : rank)
    if (r == 0) r = next++;
  Renumber(image, rank, std::move(kept));
}

void SpatialOrder(sdvi::Image& image) {
  const size_t n = image.vertices.size();
  std::vector<uint32_t> order(n), rank(n);
  for (uint32_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const int ya = int(image.vertices[a].y / 16), yb = int(image.vertices[b].y / 16);
    if (ya != yb) return ya < yb;
    return (ya & 1) ? image.vertices[a].x > image.vertices[b].x : image.vertices[a].x < image.vertices[b].x;
  });
  for (uint32_t i = 0; i < n; ++i) rank[order[i]] = i;
  std::vector<sdvi::Triangle> triangles = image.triangles;
  std::sort(triangles.begin(), triangles.end(), [&](const sdvi::Triangle& a, const sdvi::Triangle& b) {
    return std::min({rank[a.v[0]], rank[a.v[1]], rank[a.v[2]]}) < std::min({rank[b.v[0]], rank[b.v[1]], rank[b.v[2]]});
  });
  Renumber(image, rank, std::move(triangles));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: bench_limit_file FILE.sdvi [--reps N] [--threads T] [--levels r] [--crop F] "
                 "[--spatial-order]\n");
    return 2;
  }
  int reps = 3;
  double crop = 0;
  bool spatial = false;
  sdvi::LimitSurfaceOptions options;
  for (int i = 2; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--spatial-order")) {
      spatial = true;
    } else if (has_value && !std::strcmp(argv[i], "--reps")) {
      reps = std::atoi(argv[++i]);
    } else if (has_value && !std::strcmp(argv[i], "--threads")) {
      options.threads = std::atoi(argv[++i]);
    } else if (has_value && !std::strcmp(argv[i], "--levels")) {
      options.levels = std::atoi(argv[++i]);
    } else if (has_value && !std::strcmp(argv[i], "--crop")) {
      crop = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "bench_limit_file: unknown or incomplete option %s\n", argv[i]);
      return 2;
    }
  }
  auto file = sdvi::ReadSdviFile(argv[1]);
  if (!file.ok()) {
    std::fprintf(stderr, "%s\n", file.status().ToString().c_str());
    return 1;
  }
  sdvi::Image& image = file->image;
  if (crop > 0) Crop(image, crop);
  if (spatial) SpatialOrder(image);
  for (int rep = 0; rep < reps; ++rep) {
    const double c0 = CpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    auto surface = sdvi::BuildLimitSurface(image, options);
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = CpuSeconds();
    if (!surface.ok()) {
      std::fprintf(stderr, "%s\n", surface.status().ToString().c_str());
      return 1;
    }
    const std::vector<sdvi::Vertex> fine = sdvi::EvaluateSurface(*surface, image.vertices);
    const auto t2 = std::chrono::steady_clock::now();
    const sdvi::StencilTable& t = surface->stencils;
    uint64_t h = 1469598103934665603ull;
    h = Fnv(h, t.offsets.data(), t.offsets.size() * 4);
    h = Fnv(h, t.indices.data(), t.indices.size() * 4);
    h = Fnv(h, t.weights.data(), t.weights.size() * 4);
    h = Fnv(h, surface->triangles.data(), surface->triangles.size() * sizeof(sdvi::Triangle));
    h = Fnv(h, surface->parent_triangle.data(), surface->parent_triangle.size() * 4);
    h = Fnv(h, surface->vertex_tags.data(), surface->vertex_tags.size());
    h = Fnv(h, surface->crease_edges.data(), surface->crease_edges.size() * sizeof(sdvi::Edge));
    h = Fnv(h, fine.data(), fine.size() * sizeof(sdvi::Vertex));
    std::printf("control %zu tris %zu fine_vertices %zu fine_tris %zu weights %zu build %.3f s cpu %.3f s "
                "eval %.3f s digest %016llx\n",
                image.vertices.size(), image.triangles.size(), t.rows(), surface->triangles.size(), t.weights.size(),
                std::chrono::duration<double>(t1 - t0).count(), c1 - c0,
                std::chrono::duration<double>(t2 - t1).count(), static_cast<unsigned long long>(h));
  }
  return 0;
}
