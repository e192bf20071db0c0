// SPDX-License-Identifier: GPL-3.0-or-later
// bench_subdiv: the subdivision engine against OpenSubdiv 3.5's Loop scheme with
// infinitely sharp creases, on the same meshes (bench_meshes.h: jittered grids with
// open, closed and junction feature polylines).
//
//   bench_subdiv [--sizes 1000,10000,100000] [--levels 1,2,3,4] [--reps 3]
//                [--max-fine-vertices 3e6] [--max-osd-limit-points 1e6] [--no-osd]
// Configurations over --max-fine-vertices are skipped (memory: OpenSubdiv needs ~3 GiB at
// 100k control vertices, level 1); OpenSubdiv's limit stencils are skipped (0 in the
// table) above --max-osd-limit-points.
//
// Each (size, level, engine) runs in its own child process, so that its peak resident
// memory (getrusage of the child) is its own. Times are the best of --reps runs, wall
// clock, with the CPU time (all threads) of that run beside it. Operations, each timed on
// both engines:
//   refine    topology of level r (sdvi: TaggedMesh::Refine x r; OSD: RefineUniform)
//   stencils  stencil table of the level-r vertices from the control mesh
//             (sdvi: BuildLimitSurface with to_limit = false; OSD: RefineUniform +
//             StencilTableFactory, last level only)
//   limit     limit stencils of the level-r vertices (sdvi: BuildLimitSurface; OSD:
//             RefineAdaptive(r) + LimitStencilTableFactory at the same number of points,
//             a barycentric lattice of 2^r per control triangle edge, no derivatives)
//   eval      applying the level-r stencil table to 5-float vertices (x, y, R, G, B)
// Throughput is in fine vertices (points) per second; ratio = sdvi / OSD throughput (wall
// clock); cpu_ratio = OSD CPU time / sdvi CPU time (the same points on both sides except
// for limit, where OSD evaluates its lattice: compare the throughputs there).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "bench_meshes.h"
#include "sdvi/subdiv.h"
#include "sdvi/tagged_mesh.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

enum Op { kRefine = 0, kStencils, kLimit, kEval, kNumOps };
const char* const kOpNames[kNumOps] = {"refine", "stencils", "limit", "eval"};

// What one child reports.
struct Result {
  int ok = 0;
  double seconds[kNumOps] = {};
  double cpu_seconds[kNumOps] = {};
  double points[kNumOps] = {};  // fine vertices (or limit points) each op produced
  long peak_kib = 0;
  char error[160] = {};
};

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// Best wall-clock time of reps runs; *cpu receives the process CPU time (all threads) of
// that run. On a shared machine the CPU time is the steadier figure.
double BestOf(int reps, const std::function<void()>& run, double* cpu) {
  double best = 1e30;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    const double c0 = CpuSeconds();
    run();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    if (wall < best) {
      best = wall;
      *cpu = CpuSeconds() - c0;
    }
  }
  return best;
}

// ---- sdvi ----
Result RunSdvi(const sdvi::Image& image, int levels, int reps) {
  Result r;
  r.seconds[kRefine] = BestOf(reps, [&] {
    auto mesh = sdvi::TaggedMesh::FromImage(image);
    sdvi::TaggedMesh m = std::move(mesh).value();
    for (int k = 0; k < levels; ++k) m = m.Refine();
    r.points[kRefine] = m.num_vertices();
  }, &r.cpu_seconds[kRefine]);
  sdvi::LimitSurfaceOptions options;
  options.levels = levels;
  options.max_fine_triangles = uint64_t{1} << 40;
  options.to_limit = false;
  sdvi::LimitSurface fine;
  r.seconds[kStencils] = BestOf(reps, [&] {
    fine = sdvi::BuildLimitSurface(image, options).value();
    r.points[kStencils] = fine.stencils.rows();
  }, &r.cpu_seconds[kStencils]);
  options.to_limit = true;
  r.seconds[kLimit] = BestOf(reps, [&] {
    auto limit = sdvi::BuildLimitSurface(image, options);
    r.points[kLimit] = limit->stencils.rows();
  }, &r.cpu_seconds[kLimit]);
  std::vector<sdvi::Vertex> out(fine.stencils.rows());
  r.seconds[kEval] = BestOf(reps, [&] {
    fine.stencils.Apply(reinterpret_cast<const float*>(image.vertices.data()), 5, reinterpret_cast<float*>(out.data()),
                        5, 5);
  }, &r.cpu_seconds[kEval]);
  r.points[kEval] = fine.stencils.rows();
  r.ok = 1;
  return r;
}

// ---- OpenSubdiv ----
struct OsdVertex {
  float v[5];
  void Clear(void* = nullptr) { std::fill(v, v + 5, 0.0f); }
  void AddWithWeight(const OsdVertex& src, float w) {
    for (int c = 0; c < 5; ++c) v[c] += w * src.v[c];
  }
};

struct OsdTopology {
  std::vector<int> verts_per_face, indices, crease_pairs, corners;
  std::vector<float> crease_weights, corner_weights;
  Far::TopologyDescriptor descriptor;
};

OsdTopology MakeOsdTopology(const sdvi::Image& image) {
  OsdTopology t;
  t.verts_per_face.assign(image.triangles.size(), 3);
  for (const auto& tri : image.triangles)
    for (uint32_t v : tri.v) t.indices.push_back(static_cast<int>(v));
  for (const auto& e : image.crease_edges) {
    t.crease_pairs.push_back(static_cast<int>(e.a));
    t.crease_pairs.push_back(static_cast<int>(e.b));
    t.crease_weights.push_back(Sdc::Crease::SHARPNESS_INFINITE);
  }
  // The same corners as sdvi (OSD would treat a crease end as a dart, not a corner).
  auto mesh = sdvi::TaggedMesh::FromImage(image);
  for (uint32_t v = 0; v < mesh->num_vertices(); ++v)
    if (mesh->is_corner(v)) {
      t.corners.push_back(static_cast<int>(v));
      t.corner_weights.push_back(Sdc::Crease::SHARPNESS_INFINITE);
    }
  Far::TopologyDescriptor& d = t.descriptor;
  d.numVertices = static_cast<int>(image.vertices.size());
  d.numFaces = static_cast<int>(image.triangles.size());
  d.numVertsPerFace = t.verts_per_face.data();
  d.vertIndicesPerFace = t.indices.data();
  d.numCreases = static_cast<int>(t.crease_weights.size());
  d.creaseVertexIndexPairs = t.crease_pairs.data();
  d.creaseWeights = t.crease_weights.data();
  d.numCorners = static_cast<int>(t.corners.size());
  d.cornerVertexIndices = t.corners.data();
  d.cornerWeights = t.corner_weights.data();
  return t;
}

Far::TopologyRefiner* CreateRefiner(const OsdTopology& t) {
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  return Factory::Create(t.descriptor, Factory::Options(Sdc::SCHEME_LOOP, sdc));
}

Result RunOsd(const sdvi::Image& image, int levels, int reps, double max_limit_points) {
  Result r;
  const OsdTopology topology = MakeOsdTopology(image);
  r.seconds[kRefine] = BestOf(reps, [&] {
    Far::TopologyRefiner* refiner = CreateRefiner(topology);
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    r.points[kRefine] = refiner->GetLevel(levels).GetNumVertices();
    delete refiner;
  }, &r.cpu_seconds[kRefine]);
  const Far::StencilTable* table = nullptr;
  r.seconds[kStencils] = BestOf(reps, [&] {
    delete table;
    Far::TopologyRefiner* refiner = CreateRefiner(topology);
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    Far::StencilTableFactory::Options options;
    options.generateIntermediateLevels = false;
    options.generateOffsets = true;
    table = Far::StencilTableFactory::Create(*refiner, options);
    r.points[kStencils] = table->GetNumStencils();
    delete refiner;
  }, &r.cpu_seconds[kStencils]);
  // Limit points: the barycentric lattice i/2^r, j/2^r (i + j <= 2^r) of every triangle.
  const int n = 1 << levels;
  std::vector<float> s, t;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i) {
      s.push_back(static_cast<float>(i) / n);
      t.push_back(static_cast<float>(j) / n);
    }
  // OSD's limit stencils are slow on large meshes (157 s for 1.2M points here, 100k control vertices): skip
  // above max_limit_points (reported as 0).
  const bool limit_skipped = static_cast<double>(s.size()) * image.triangles.size() > max_limit_points;
  if (!limit_skipped) r.seconds[kLimit] = BestOf(reps, [&] {
    Far::TopologyRefiner* refiner = CreateRefiner(topology);
    refiner->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(levels));
    Far::LimitStencilTableFactory::LocationArrayVec locations(image.triangles.size());
    for (size_t f = 0; f < locations.size(); ++f) {
      locations[f].ptexIdx = static_cast<int>(f);
      locations[f].numLocations = static_cast<int>(s.size());
      locations[f].s = s.data();
      locations[f].t = t.data();
    }
    Far::LimitStencilTableFactory::Options options;
    options.generate1stDerivatives = false;
    const Far::LimitStencilTable* limit =
        Far::LimitStencilTableFactory::Create(*refiner, locations, nullptr, nullptr, options);
    r.points[kLimit] = limit->GetNumStencils();
    delete limit;
    delete refiner;
  }, &r.cpu_seconds[kLimit]);
  std::vector<OsdVertex> in(image.vertices.size()), out(table->GetNumStencils());
  for (size_t i = 0; i < in.size(); ++i) std::memcpy(in[i].v, &image.vertices[i], sizeof(in[i].v));
  r.seconds[kEval] = BestOf(reps, [&] { table->UpdateValues(in.data(), out.data()); }, &r.cpu_seconds[kEval]);
  r.points[kEval] = table->GetNumStencils();
  delete table;
  r.ok = 1;
  return r;
}

// Runs one configuration in a child process; its peak memory comes from wait4.
Result RunChild(bool osd, int size, int levels, int reps, double max_limit_points) {
  int fds[2];
  Result result;
  if (pipe(fds) != 0) return result;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    Result r;
    try {
      const sdvi::Image image = sdvi::bench::FeatureGridImage(size);
      r = osd ? RunOsd(image, levels, reps, max_limit_points) : RunSdvi(image, levels, reps);
    } catch (const std::exception& e) {
      std::snprintf(r.error, sizeof(r.error), "%s", e.what());
    }
    if (write(fds[1], &r, sizeof(r)) != static_cast<ssize_t>(sizeof(r))) _exit(2);
    _exit(0);
  }
  close(fds[1]);
  ssize_t got = 0;
  while (got < static_cast<ssize_t>(sizeof(result))) {
    const ssize_t n = read(fds[0], reinterpret_cast<char*>(&result) + got, sizeof(result) - got);
    if (n <= 0) break;
    got += n;
  }
  close(fds[0]);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  if (got != static_cast<ssize_t>(sizeof(result))) {
    result = Result{};
    std::snprintf(result.error, sizeof(result.error), "child failed (status %d)", status);
  }
  result.peak_kib = usage.ru_maxrss;
  return result;
}

std::vector<int> ParseList(const char* text) {
  std::vector<int> out;
  for (const char* p = text; *p;) {
    out.push_back(std::atoi(p));
    while (*p && *p != ',') ++p;
    if (*p == ',') ++p;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes{1000, 10000, 100000}, levels{1, 2, 3, 4};
  int reps = 3;
  double max_fine = 3e6, max_osd_limit = 1e6;
  bool with_osd = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--sizes" && has_value) sizes = ParseList(argv[++i]);
    else if (a == "--levels" && has_value) levels = ParseList(argv[++i]);
    else if (a == "--reps" && has_value) reps = std::max(1, std::atoi(argv[++i]));
    else if (a == "--max-fine-vertices" && has_value) max_fine = std::atof(argv[++i]);
    else if (a == "--max-osd-limit-points" && has_value) max_osd_limit = std::atof(argv[++i]);
    else if (a == "--no-osd") with_osd = false;
    else {
      std::fprintf(stderr,
                   "usage: bench_subdiv [--sizes 1000,10000,100000] [--levels 1,2,3,4] [--reps 3] "
                   "[--max-fine-vertices 3e6] [--max-osd-limit-points 1e6] [--no-osd]\n");
      return 1;
    }
  }
  std::printf("%8s %6s %5s %10s %-9s %10s %10s %10s %10s %10s %10s %7s %9s %9s %9s\n", "control", "tris", "level",
              "fine_verts", "op", "sdvi_ms", "osd_ms", "sdvi_cpu", "osd_cpu", "sdvi_Mv/s", "osd_Mv/s", "ratio",
              "cpu_ratio", "sdvi_MiB", "osd_MiB");
  for (int size : sizes) {
    const sdvi::Image image = sdvi::bench::FeatureGridImage(size);
    for (int level : levels) {
      const double fine_estimate = static_cast<double>(image.triangles.size()) * (1 << (2 * level)) / 2;
      if (fine_estimate > max_fine) {
        std::printf("%8zu %6zu %5d %10.0f skipped (over --max-fine-vertices)\n", image.vertices.size(),
                    image.triangles.size(), level, fine_estimate);
        continue;
      }
      const int r = fine_estimate > 2e6 ? 1 : reps;
      const Result ours = RunChild(false, size, level, r, max_osd_limit);
      const Result theirs = with_osd ? RunChild(true, size, level, r, max_osd_limit) : Result{};
      if (!ours.ok) std::printf("sdvi failed: %s\n", ours.error);
      if (with_osd && !theirs.ok) std::printf("osd failed: %s\n", theirs.error);
      for (int op = 0; op < kNumOps; ++op) {
        const double ours_rate = ours.ok ? ours.points[op] / ours.seconds[op] / 1e6 : 0;
        const double theirs_rate = theirs.ok && theirs.seconds[op] > 0 ? theirs.points[op] / theirs.seconds[op] / 1e6 : 0;
        const double cpu_ratio = ours.cpu_seconds[op] > 0 && theirs.ok ? theirs.cpu_seconds[op] / ours.cpu_seconds[op] : 0.0;
        std::printf("%8zu %6zu %5d %10.0f %-9s %10.2f %10.2f %10.2f %10.2f %10.2f %10.2f %7.2f %9.2f %9.1f %9.1f\n",
                    image.vertices.size(), image.triangles.size(), level, ours.points[kStencils], kOpNames[op],
                    1e3 * ours.seconds[op], 1e3 * theirs.seconds[op], 1e3 * ours.cpu_seconds[op],
                    1e3 * theirs.cpu_seconds[op], ours_rate, theirs_rate,
                    theirs_rate > 0 ? ours_rate / theirs_rate : 0.0, cpu_ratio, ours.peak_kib / 1024.0,
                    theirs.peak_kib / 1024.0);
      }
      std::fflush(stdout);
    }
  }
  return 0;
}
