// SPDX-License-Identifier: GPL-3.0-or-later
// BuildLimitSurface (stencils), RefineImage (direct), EvaluateSurface, StencilTable::Apply.
#include "sdvi/subdiv.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <string>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

#include "row_blocks.h"
#include "sdvi/default_init_allocator.h"
#include "sdvi/large_buffers.h"
#include "sdvi/tagged_mesh.h"

namespace sdvi {
namespace {

using subdiv_internal::ForRowBlocks;
using subdiv_internal::HardwareThreads;
using subdiv_internal::ThreadsFor;

// Rings of control triangles kept around a region so that the region's fine vertices
// see exactly the neighbourhood they would see in the whole mesh (a level-r limit point
// depends on control vertices at most two rings away; one more for safety).
constexpr int kRegionMarginRings = 3;

// Above this many fine triangles a stencil table could overflow its uint32 offsets
// (about 20 weights a fine triangle), whatever max_fine_triangles says.
constexpr uint64_t kHardMaxFineTriangles = uint64_t{1} << 27;

// The control mesh a build refines, and which of its triangles the output keeps.
struct RefinementPlan {
  TaggedMesh base;
  std::vector<uint32_t> vertex_map;    // base vertex -> control vertex (empty: identity)
  std::vector<uint32_t> triangle_map;  // base triangle -> control triangle (empty: identity)
  std::vector<uint8_t> keep;           // base triangle in the output (empty: all)
};

StatusOr<RefinementPlan> MakePlan(const Image& image, const LimitSurfaceOptions& options) {
  if (options.levels < 0 || options.levels > kMaxLevels)
    return Status(StatusCode::kInvalidArgument, "subdivision level " + std::to_string(options.levels) +
                                                    " is outside 0.." + std::to_string(kMaxLevels));
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const Vertex& v = image.vertices[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.r) || !std::isfinite(v.g) ||
        !std::isfinite(v.b))
      return Status(StatusCode::kNonFinite, "control vertex " + std::to_string(i) +
                                                " has a non-finite coordinate or colour");
  }
  SDVI_ASSIGN_OR_RETURN(TaggedMesh mesh, TaggedMesh::FromImage(image));
  RefinementPlan plan;
  const size_t nt = mesh.num_triangles();
  size_t region_size = nt;
  if (!options.control_triangles.empty()) {
    std::vector<uint8_t> in_region(nt, 0);
    for (uint32_t t : options.control_triangles) {
      if (t >= nt)
        return Status(StatusCode::kIndexOutOfRange, "region control triangle " + std::to_string(t) +
                                                        " is not a triangle (the mesh has " +
                                                        std::to_string(nt) + ")");
      in_region[t] = 1;
    }
    region_size = static_cast<size_t>(std::count(in_region.begin(), in_region.end(), 1));
    // Grow the region by whole rings: triangles sharing a vertex with the current set.
    std::vector<uint8_t> in_margin = in_region;
    for (int ring = 0; ring < kRegionMarginRings; ++ring) {
      std::vector<uint8_t> touched(mesh.num_vertices(), 0);
      for (size_t t = 0; t < nt; ++t)
        if (in_margin[t])
          for (uint32_t v : mesh.triangles()[t].v) touched[v] = 1;
      for (size_t t = 0; t < nt; ++t) {
        const auto& v = mesh.triangles()[t].v;
        if (touched[v[0]] || touched[v[1]] || touched[v[2]]) in_margin[t] = 1;
      }
    }
    for (uint32_t t = 0; t < nt; ++t)
      if (in_margin[t]) {
        plan.triangle_map.push_back(t);
        plan.keep.push_back(in_region[t]);
      }
    plan.base = mesh.Submesh(plan.triangle_map, &plan.vertex_map);
  } else {
    plan.base = std::move(mesh);
  }
  const uint64_t fine = static_cast<uint64_t>(plan.base.num_triangles()) << (2 * options.levels);
  if (fine > std::min(options.max_fine_triangles, kHardMaxFineTriangles))
    return Status(StatusCode::kLimitExceeded,
                  std::to_string(region_size) + " control triangles at level " +
                      std::to_string(options.levels) + " need " + std::to_string(fine) +
                      " fine triangles (with margin); the limit is " +
                      std::to_string(std::min(options.max_fine_triangles, kHardMaxFineTriangles)));
  return plan;
}

// The output part of the finest level: kept triangles (renumbered), their parents, and the
// kept fine vertices (sorted finest-level indices). The finest level is mesh itself, or
// with refine_once the level after mesh, derived without building its topology.
struct FineSelection {
  std::vector<Triangle> triangles;
  std::vector<uint32_t> parent_triangle;
  std::vector<uint32_t> vertices;  // output vertex i = finest-level vertex vertices[i]
  std::vector<VertexTag> vertex_tags;
  std::vector<Edge> crease_edges;
};

FineSelection SelectOutput(const RefinementPlan& plan, const TaggedMesh& mesh, bool refine_once, int levels,
                           int threads) {
  FineSelection out;
  std::vector<Triangle> triangles = refine_once ? mesh.RefinedTriangles(threads) : mesh.triangles();
  std::vector<VertexTag> tags = refine_once ? mesh.RefinedVertexTags() : mesh.vertex_tags();
  const size_t nt = triangles.size();
  const int shift = 2 * levels;
  auto parent = [&](size_t f) {
    const size_t base = f >> shift;
    return plan.triangle_map.empty() ? static_cast<uint32_t>(base) : plan.triangle_map[base];
  };
  internal::ReserveLarge(out.parent_triangle, nt);
  out.parent_triangle.resize(nt);
  for (size_t f = 0; f < nt; ++f) out.parent_triangle[f] = parent(f);
  if (plan.keep.empty()) {
    out.triangles = std::move(triangles);
    internal::ReserveLarge(out.vertices, tags.size());
    out.vertices.resize(tags.size());
    for (uint32_t v = 0; v < tags.size(); ++v) out.vertices[v] = v;
    out.vertex_tags = std::move(tags);
    out.crease_edges = refine_once ? mesh.RefinedCreaseEdges() : mesh.CreaseEdges();
    return out;
  }
  // A region: keep the triangles descending from it, the vertices they use, and the crease
  // edges of kept triangles. A crease edge of mesh (or its halves) belongs to a kept
  // triangle iff one of its triangles in mesh is kept.
  const int mesh_shift = refine_once ? shift - 2 : shift;
  auto kept_in_mesh = [&](uint32_t t) { return t != kNoIndex && plan.keep[t >> mesh_shift]; };
  std::vector<uint32_t> renumber(tags.size(), kNoIndex);
  for (size_t f = 0; f < nt; ++f)
    if (plan.keep[f >> shift])
      for (uint32_t v : triangles[f].v) renumber[v] = 0;
  for (uint32_t v = 0; v < tags.size(); ++v)
    if (renumber[v] == 0) {
      renumber[v] = static_cast<uint32_t>(out.vertices.size());
      out.vertices.push_back(v);
      out.vertex_tags.push_back(tags[v]);
    }
  std::vector<uint32_t> parents;
  for (size_t f = 0; f < nt; ++f) {
    if (!plan.keep[f >> shift]) continue;
    const auto& v = triangles[f].v;
    out.triangles.push_back(Triangle{{renumber[v[0]], renumber[v[1]], renumber[v[2]]}});
    parents.push_back(out.parent_triangle[f]);
  }
  out.parent_triangle = std::move(parents);
  for (size_t e = 0; e < mesh.num_edges(); ++e) {
    const auto& et = mesh.edge_triangles(e);
    if (!mesh.is_crease(e) || !(kept_in_mesh(et[0]) || kept_in_mesh(et[1]))) continue;
    const Edge& edge = mesh.edges()[e];
    if (refine_once) {
      const uint32_t m = renumber[mesh.num_vertices() + e];
      out.crease_edges.push_back(Edge::Of(renumber[edge.a], m));
      out.crease_edges.push_back(Edge::Of(renumber[edge.b], m));
    } else {
      out.crease_edges.push_back(Edge::Of(renumber[edge.a], renumber[edge.b]));
    }
  }
  std::sort(out.crease_edges.begin(), out.crease_edges.end());
  return out;
}

// Scratch of one composing thread: a dense accumulator over the columns, and a row buffer
// for mask rows computed on the fly.
struct ComposeScratch {
  explicit ComposeScratch(uint32_t num_columns) : accumulator(num_columns, 0.0), stamp(num_columns, kNoIndex) {}
  std::vector<double> accumulator;
  std::vector<uint32_t> stamp;
  std::vector<uint32_t> touched;
  std::vector<uint32_t> row_indices;
  std::vector<double> row_weights;
};

// An array filled by push_back in chunks of kChunk items, moved onto the end of a vector
// chunk by chunk (each freed once copied): appending a block of rows to the output never
// holds a second copy of the whole block.
template <typename T>
struct ChunkedArray {
  using value_type = T;
  static constexpr size_t kChunk = size_t{1} << 18;
  std::vector<std::vector<T>> chunks;
  void push_back(T value) {
    if (chunks.empty() || chunks.back().size() == kChunk) {
      chunks.emplace_back();
      chunks.back().reserve(kChunk);
    }
    chunks.back().push_back(value);
  }
  void MoveAppendTo(std::vector<T>& out) {
    for (std::vector<T>& chunk : chunks) {
      out.insert(out.end(), chunk.begin(), chunk.end());
      std::vector<T>().swap(chunk);
    }
    chunks.clear();
  }
};

template <typename T>
void ReserveEntries(std::vector<T>& v, size_t n) {
  internal::ReserveLarge(v, n);
}
template <typename T>
void ReserveEntries(ChunkedArray<T>&, size_t) {}

// The rows of one block: the first block's entries go straight into the output arrays
// (Array = std::vector), the others' into chunks appended to them after (ChunkedArray).
template <typename Weight, template <typename> typename Array>
struct RowBlock {
  size_t estimate = 0;  // entries to reserve
  std::vector<uint32_t> sizes;
  Array<uint32_t> indices;
  Array<Weight> weights;
};

template <typename T>
using PlainArray = std::vector<T>;

// Output rows [begin, end) of (mask x previous), or of the mask alone when previous is
// null (identity): mask_row(r, scratch) fills scratch.row_indices/row_weights with row r of
// the mask (indices may repeat). Each output row is sorted by index; indices are mapped
// through index_map when it is non-empty.
template <typename Block, typename MaskRow>
void ComposeBlock(size_t begin, size_t end, const MaskRow& mask_row, const SparseRows* previous,
                  const std::vector<uint32_t>& index_map, ComposeScratch& s, Block& out) {
  using Weight = typename decltype(out.weights)::value_type;
  out.sizes.reserve(end - begin);
  ReserveEntries(out.indices, out.estimate);
  ReserveEntries(out.weights, out.estimate);
  // The mask row of r + 1 is computed while row r is composed, and the previous level's
  // rows it names (anywhere in the table) are asked for first: the composition waits on
  // them otherwise. What is computed does not change.
  std::vector<uint32_t> mask_indices;
  std::vector<double> mask_weights;
  auto load_mask = [&](size_t r) {
    s.row_indices.clear();
    s.row_weights.clear();
    mask_row(r, s);
    if (!previous) return;
    for (const uint32_t p : s.row_indices) {
      const uint32_t k = previous->offsets[p];
      __builtin_prefetch(&previous->indices[k]);
      __builtin_prefetch(&previous->weights[k]);
    }
  };
  if (begin < end) load_mask(begin);
  for (size_t r = begin; r < end; ++r) {
    const uint32_t row_stamp = static_cast<uint32_t>(r);
    s.touched.clear();
    std::swap(s.row_indices, mask_indices);
    std::swap(s.row_weights, mask_weights);
    if (r + 1 < end) load_mask(r + 1);
    auto accumulate = [&](uint32_t c, double w) {
      if (s.stamp[c] != row_stamp) {
        s.stamp[c] = row_stamp;
        s.accumulator[c] = 0;
        s.touched.push_back(c);
      }
      s.accumulator[c] += w;
    };
    for (size_t k = 0; k < mask_indices.size(); ++k) {
      const uint32_t p = mask_indices[k];
      const double w = mask_weights[k];
      if (!previous) {
        accumulate(p, w);
        continue;
      }
      for (uint32_t j = previous->offsets[p]; j < previous->offsets[p + 1]; ++j)
        accumulate(previous->indices[j], w * previous->weights[j]);
    }
    std::sort(s.touched.begin(), s.touched.end());
    uint32_t size = 0;
    for (uint32_t c : s.touched) {
      if (s.accumulator[c] == 0) continue;
      out.indices.push_back(index_map.empty() ? c : index_map[c]);
      out.weights.push_back(static_cast<Weight>(s.accumulator[c]));
      ++size;
    }
    out.sizes.push_back(size);
  }
}

// All rows of (mask x previous) into CSR arrays; deterministic whatever the number of
// threads. With several threads the rows go in chunks taken in turn from a shared counter
// (a thread that starts late or is held up by the machine's other work leaves its share to
// the others), each into its own arrays; a chunk is moved onto the output as soon as every
// chunk before it is there, so the chunks held at once are few.
template <typename Weight, typename MaskRow>
void Compose(int requested_threads, size_t num_rows, const MaskRow& mask_row, const SparseRows* previous,
             uint32_t num_columns, const std::vector<uint32_t>& index_map, std::vector<uint32_t>& offsets,
             std::vector<uint32_t>& indices, std::vector<Weight>& weights) {
  const unsigned threads = ThreadsFor(num_rows, requested_threads);
  // The output reserves room for every row's entries, so that the chunks are appended to
  // it without a new allocation (untouched reserved pages cost nothing).
  const size_t per_row = previous ? 14 : 7;
  internal::ReserveLarge(offsets, num_rows + 1);
  offsets.resize(num_rows + 1);
  offsets[0] = 0;
  if (threads == 1) {
    RowBlock<Weight, PlainArray> block;
    block.estimate = per_row * num_rows;
    ComposeScratch scratch(num_columns);
    ComposeBlock(0, num_rows, mask_row, previous, index_map, scratch, block);
    indices = std::move(block.indices);
    weights = std::move(block.weights);
    for (size_t r = 0; r < num_rows; ++r) offsets[r + 1] = offsets[r] + block.sizes[r];
    return;
  }
  indices.clear();
  weights.clear();
  internal::ReserveLarge(indices, per_row * num_rows);
  internal::ReserveLarge(weights, per_row * num_rows);
  const size_t chunk = std::clamp<size_t>(num_rows / (16 * threads), 4096, 65536);
  const size_t num_chunks = (num_rows + chunk - 1) / chunk;
  std::vector<RowBlock<Weight, ChunkedArray>> blocks(num_chunks);
  std::vector<uint8_t> done(num_chunks, 0);
  std::mutex commit_mutex;
  size_t committed = 0;  // chunks moved onto the output
  std::atomic<size_t> next{0};
  RunTasks(int(threads), [&](int) {
    ComposeScratch scratch(num_columns);
    for (size_t c; (c = next.fetch_add(1, std::memory_order_relaxed)) < num_chunks;) {
      const size_t begin = c * chunk, end = std::min(num_rows, begin + chunk);
      ComposeBlock(begin, end, mask_row, previous, index_map, scratch, blocks[c]);
      std::lock_guard<std::mutex> lock(commit_mutex);
      done[c] = 1;
      for (; committed < num_chunks && done[committed]; ++committed) {
        RowBlock<Weight, ChunkedArray>& block = blocks[committed];
        block.indices.MoveAppendTo(indices);
        block.weights.MoveAppendTo(weights);
        size_t r = committed * chunk;
        for (uint32_t size : block.sizes) {
          offsets[r + 1] = offsets[r] + size;
          ++r;
        }
        std::vector<uint32_t>().swap(block.sizes);
      }
    }
  });
}


}  // namespace

namespace {

// Apply's kernels (spec/SUBDIVISION.md section 4). Every kernel computes each output
// component as the same sequence of double operations: sum = 0.0, then sum += w * x for
// the row's weights in table order (w and x the float weight and input converted to
// double), then the float of sum. They differ in how many of those operations one
// instruction carries, so they give the same floats. The AVX-512 kernel computes each
// step as one fused multiply-add, which is the same operation: the product of two floats
// has at most 48 significant bits and an exponent well inside double's range, so w * x is
// exact in double and fma(w, x, sum) rounds w * x + sum once, as the separate add does.
// This file is compiled with -ffp-contract=off (engine/subdiv/CMakeLists.txt), so that no
// other fusion is left to the compiler.

// Rows [begin, end) of table applied to kDims coordinates starting at in / out: the
// portable kernel, reading the floats directly.
template <int kDims>
void ApplyRows(const StencilTable& table, size_t begin, size_t end, const float* in, size_t in_stride, float* out,
               size_t out_stride) {
  const uint32_t* offsets = table.offsets.data();
  const uint32_t* indices = table.indices.data();
  const float* weights = table.weights.data();
  for (size_t i = begin; i < end; ++i) {
    double sum[kDims] = {};
    for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const float* src = in + indices[k] * in_stride;
      const double w = weights[k];
      for (int c = 0; c < kDims; ++c) sum[c] += w * src[c];
    }
    float* dst = out + i * out_stride;
    for (int c = 0; c < kDims; ++c) dst[c] = static_cast<float>(sum[c]);
  }
}

using ApplyFunction = void (*)(const StencilTable&, size_t, size_t, const float*, size_t, float*, size_t);
constexpr ApplyFunction kApplyByDims[8] = {ApplyRows<1>, ApplyRows<2>, ApplyRows<3>, ApplyRows<4>,
                                           ApplyRows<5>, ApplyRows<6>, ApplyRows<7>, ApplyRows<8>};

// The x86-64 kernels first convert the input to doubles (exactly), pad values a vertex in
// a 64-byte aligned copy (zeros past dims), so that the loop over weights has no
// conversion of x left and a vertex's values are one aligned vector (or two). They are
// compiled for AVX2 or AVX-512 by target attributes and chosen at run time
// (__builtin_cpu_supports); the portable kernel stays for other processors and compilers.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SDVI_STENCIL_X86 1

// Vertices [0, count) of in (stride in_stride, kDims values) as doubles, kPad a vertex.
template <int kDims, int kPad>
__attribute__((target("avx2"))) void ToDoubles(const float* in, size_t in_stride, size_t count, double* out) {
  for (size_t v = 0; v < count; ++v) {
    float values[kPad] = {};
    std::memcpy(values, in + v * in_stride, kDims * sizeof(float));
    double* dst = out + v * kPad;
    for (int c = 0; c < kPad; ++c) dst[c] = values[c];
  }
}

// AVX2: the portable loop over the doubles, two weights an iteration (in order); the
// compiler vectorizes each weight's kDims products and sums across components.
template <int kDims, int kPad>
__attribute__((target("avx2"))) void ApplyRowsAvx2(const StencilTable& table, size_t begin, size_t end,
                                                   const double* in, float* out, size_t out_stride) {
  const uint32_t* offsets = table.offsets.data();
  const uint32_t* indices = table.indices.data();
  const float* weights = table.weights.data();
  in = static_cast<const double*>(__builtin_assume_aligned(in, 32));
  for (size_t i = begin; i < end; ++i) {
    double sum[kDims] = {};
    uint32_t k = offsets[i];
    const uint32_t row_end = offsets[i + 1];
    for (; k + 1 < row_end; k += 2) {
      const double* a = in + size_t{indices[k]} * kPad;
      const double* b = in + size_t{indices[k + 1]} * kPad;
      const double wa = weights[k];
      const double wb = weights[k + 1];
      for (int c = 0; c < kDims; ++c) sum[c] += wa * a[c];
      for (int c = 0; c < kDims; ++c) sum[c] += wb * b[c];
    }
    if (k < row_end) {
      const double* a = in + size_t{indices[k]} * kPad;
      const double wa = weights[k];
      for (int c = 0; c < kDims; ++c) sum[c] += wa * a[c];
    }
    float* dst = out + i * out_stride;
    for (int c = 0; c < kDims; ++c) dst[c] = static_cast<float>(sum[c]);
  }
}

// Vertices [0, count) of in as 8 doubles each (AVX-512, 5 to 8 components): one masked
// load of kDims floats (nothing past them is read, zeros in the other lanes) and one
// conversion a vertex.
template <int kDims>
__attribute__((target("avx512f,avx512vl"))) void ToDoublesAvx512(const float* in, size_t in_stride, size_t count,
                                                                  double* out) {
  constexpr __mmask8 kLanes = static_cast<__mmask8>((1u << kDims) - 1);
  for (size_t v = 0; v < count; ++v)
    _mm512_store_pd(out + v * 8, _mm512_maskz_cvtps_pd(kLanes, _mm256_maskz_loadu_ps(kLanes, in + v * in_stride)));
}

// AVX-512 (5 to 8 components, kPad 8): one 8-double vector a weight (the lanes past kDims
// sum zeros and are not stored), one fused multiply-add a weight (exact, see above), two
// weights an iteration.
template <int kDims>
__attribute__((target("avx512f,avx512vl,fma"))) void ApplyRowsAvx512(const StencilTable& table, size_t begin,
                                                                     size_t end, const double* in, float* out,
                                                                     size_t out_stride) {
  static_assert(kDims > 4 && kDims <= 8);
  const uint32_t* offsets = table.offsets.data();
  const uint32_t* indices = table.indices.data();
  const float* weights = table.weights.data();
  const __mmask8 store = static_cast<__mmask8>((1u << kDims) - 1);
  for (size_t i = begin; i < end; ++i) {
    __m512d sum = _mm512_setzero_pd();
    uint32_t k = offsets[i];
    const uint32_t row_end = offsets[i + 1];
    for (; k + 1 < row_end; k += 2) {
      const __m512d a = _mm512_load_pd(in + size_t{indices[k]} * 8);
      const __m512d b = _mm512_load_pd(in + size_t{indices[k + 1]} * 8);
      sum = _mm512_fmadd_pd(_mm512_set1_pd(double{weights[k]}), a, sum);
      sum = _mm512_fmadd_pd(_mm512_set1_pd(double{weights[k + 1]}), b, sum);
    }
    if (k < row_end)
      sum = _mm512_fmadd_pd(_mm512_set1_pd(double{weights[k]}), _mm512_load_pd(in + size_t{indices[k]} * 8), sum);
    _mm256_mask_storeu_ps(out + i * out_stride, store, _mm512_maskz_cvtpd_ps(store, sum));
  }
}

bool CpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

bool CpuHasAvx512() {
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                          __builtin_cpu_supports("fma");
  return has;
}

using ConvertFunction = void (*)(const float*, size_t, size_t, double*);
using SimdFunction = void (*)(const StencilTable&, size_t, size_t, const double*, float*, size_t);
struct SimdKernel {
  ConvertFunction convert;
  SimdFunction rows;
  int pad;  // doubles a vertex
};

template <int kDims>
constexpr SimdKernel kAvx2Kernel = {ToDoubles<kDims, kDims <= 4 ? 4 : 8>, ApplyRowsAvx2<kDims, kDims <= 4 ? 4 : 8>,
                                    kDims <= 4 ? 4 : 8};
constexpr SimdKernel kAvx2ByDims[8] = {kAvx2Kernel<1>, kAvx2Kernel<2>, kAvx2Kernel<3>, kAvx2Kernel<4>,
                                       kAvx2Kernel<5>, kAvx2Kernel<6>, kAvx2Kernel<7>, kAvx2Kernel<8>};
constexpr SimdKernel kAvx512ByDims[4] = {{ToDoublesAvx512<5>, ApplyRowsAvx512<5>, 8},
                                         {ToDoublesAvx512<6>, ApplyRowsAvx512<6>, 8},
                                         {ToDoublesAvx512<7>, ApplyRowsAvx512<7>, 8},
                                         {ToDoublesAvx512<8>, ApplyRowsAvx512<8>, 8}};

// Storage for count doubles of converted input, 64-byte aligned, or nullptr when it cannot
// be allocated. Each thread keeps one buffer of up to kKeptScratchBytes between calls (a
// table evaluated again and again, as in a fit or a benchmark, no longer allocates and
// faults in fresh pages each call); a larger one is allocated for the call, in *owned.
constexpr size_t kKeptScratchBytes = size_t{16} << 20;

double* ScratchDoubles(size_t count, std::unique_ptr<double[]>& owned) {
  const size_t size = count + 8;  // room to align to 64 bytes
  auto aligned = [](double* p) {
    return reinterpret_cast<double*>((reinterpret_cast<uintptr_t>(p) + 63) & ~uintptr_t{63});
  };
  if (size * sizeof(double) > kKeptScratchBytes) {
    owned.reset(new (std::nothrow) double[size]);
    return owned ? aligned(owned.get()) : nullptr;
  }
  thread_local std::unique_ptr<double[]> kept;
  thread_local size_t kept_size = 0;
  if (kept_size < size) {
    kept.reset(new (std::nothrow) double[size]);
    kept_size = kept ? size : 0;
    if (!kept) return nullptr;
  }
  return aligned(kept.get());
}

// The SIMD kernel for nd components (nullptr: the portable one).
const SimdKernel* PickSimdKernel(StencilTable::Kernel kernel, int nd) {
  using Kernel = StencilTable::Kernel;
  const bool avx512 = CpuHasAvx512() && nd > 4 && (kernel == Kernel::kAuto || kernel == Kernel::kAvx512);
  if (avx512) return &kAvx512ByDims[nd - 5];
  const bool avx2 = CpuHasAvx2() && kernel != Kernel::kPortable;
  return avx2 ? &kAvx2ByDims[nd - 1] : nullptr;
}
#endif

// Apply starts a thread for each this many weights (at most the hardware's threads).
constexpr size_t kWeightsPerThread = size_t{1} << 18;

// kAuto converts the input only when the table has this many weights a control vertex
// or more (a region's table refers to all control vertices for few rows).
constexpr size_t kMinWeightsPerControl = 4;

}  // namespace

bool StencilTable::KernelSupported(Kernel kernel) {
  switch (kernel) {
    case Kernel::kAuto:
    case Kernel::kPortable:
      return true;
#ifdef SDVI_STENCIL_X86
    case Kernel::kAvx2:
      return CpuHasAvx2();
    case Kernel::kAvx512:
      return CpuHasAvx512();
#else
    case Kernel::kAvx2:
    case Kernel::kAvx512:
      return false;
#endif
  }
  return false;
}

void StencilTable::Apply(const float* in, size_t in_stride, float* out, size_t out_stride, int dims) const {
  Apply(in, in_stride, out, out_stride, dims, Kernel::kAuto);
}

void StencilTable::Apply(const float* in, size_t in_stride, float* out, size_t out_stride, int dims,
                         Kernel kernel) const {
  const size_t n = rows();
  // Large tables go over threads, one per kWeightsPerThread weights at most, in chunks of
  // rows taken in turn from a shared counter (each row is written by one thread): on a busy
  // machine a thread that starts late leaves its share to the others.
  const unsigned threads = static_cast<unsigned>(std::clamp<size_t>(indices.size() / kWeightsPerThread, 1, HardwareThreads()));
  auto split = [n, threads](const auto& run) {
    if (threads == 1) {
      run(size_t{0}, n);
      return;
    }
    const size_t chunk = std::max<size_t>(1024, n / (8 * threads));
    std::atomic<size_t> next{0};
    RunTasks(int(threads), [&run, &next, n, chunk](int) {
      for (size_t begin; (begin = next.fetch_add(chunk, std::memory_order_relaxed)) < n;)
        run(begin, std::min(n, begin + chunk));
    });
  };
#ifdef SDVI_STENCIL_X86
  const bool simd = num_control > 0 && n > 0 &&
                    (kernel != Kernel::kAuto || indices.size() >= kMinWeightsPerControl * num_control);
#endif
  for (int d0 = 0; d0 < dims; d0 += 8) {
    const int nd = std::min(8, dims - d0);
#ifdef SDVI_STENCIL_X86
    if (const SimdKernel* k = simd ? PickSimdKernel(kernel, nd) : nullptr) {
      std::unique_ptr<double[]> owned;
      if (double* doubles = ScratchDoubles(size_t{num_control} * size_t(k->pad), owned)) {  // else portable below
        k->convert(in + d0, in_stride, num_control, doubles);
        split([&](size_t begin, size_t end) { k->rows(*this, begin, end, doubles, out + d0, out_stride); });
        continue;
      }
    }
#endif
    split([&](size_t begin, size_t end) {
      kApplyByDims[nd - 1](*this, begin, end, in + d0, in_stride, out + d0, out_stride);
    });
  }
}

StatusOr<LimitSurface> BuildLimitSurface(const Image& image, const LimitSurfaceOptions& options) {
  SDVI_ASSIGN_OR_RETURN(RefinementPlan plan, MakePlan(image, options));
  const uint32_t num_base = plan.base.num_vertices();
  TaggedMesh mesh = std::move(plan.base);
  plan.base = TaggedMesh();
  // stencils: level-k vertices over base vertices (identity while k = 0).
  SparseRows stencils;
  const SparseRows* previous = nullptr;
  // Mask rows are computed as they are composed (AppendRefinementRow, AppendLimitRow), so
  // no level's masks are held in memory beside the tables (spec/SUBDIVISION.md, memory).
  auto refinement_row = [&mesh](size_t row, ComposeScratch& s) {
    AppendRefinementRow(mesh, row, s.row_indices, s.row_weights);
  };
  for (int k = 0; k + 1 < options.levels; ++k) {
    SparseRows next;
    Compose(options.threads, size_t{mesh.num_vertices()} + mesh.num_edges(), refinement_row, previous, num_base, {},
            next.offsets, next.indices, next.weights);
    stencils = std::move(next);
    previous = &stencils;
    mesh = mesh.Refine(options.threads);
  }
  // The last step: from level r-1 (mesh) to level r, or the limit at level r, computed
  // only for the output vertices, in float, over control vertices. The level-r topology is
  // never built: a vertex child's limit is its parent's (limit invariance), an edge
  // child's comes from AppendEdgeChildLimitMask.
  const bool refine_once = options.levels > 0;
  // A whole mesh's output vertices are all of the finest level's, in order; its triangles
  // and parents are selected after the table, once the previous level's stencils are freed
  // (less peak memory).
  const bool whole = plan.keep.empty();
  FineSelection selection;
  if (whole) {
    const size_t count = refine_once ? size_t{mesh.num_vertices()} + mesh.num_edges() : mesh.num_vertices();
    internal::ReserveLarge(selection.vertices, count);
    selection.vertices.resize(count);
    for (uint32_t v = 0; v < count; ++v) selection.vertices[v] = v;
  } else {
    selection = SelectOutput(plan, mesh, refine_once, options.levels, options.threads);
  }
  LimitSurface surface;
  surface.levels = options.levels;
  surface.stencils.num_control = static_cast<uint32_t>(image.vertices.size());
  StencilTable& table = surface.stencils;
  const size_t num_rows = selection.vertices.size();
  // Row r of the table is output vertex selection.vertices[r]: as a control vertex (level 0
  // without the limit), its refinement row, its limit row, or an edge child's limit.
  const std::vector<uint32_t>& output = selection.vertices;
  const uint32_t nv = mesh.num_vertices();
  auto output_row = [&](size_t r, ComposeScratch& s) {
    const uint32_t v = output[r];
    if (!refine_once && !options.to_limit) {
      s.row_indices.push_back(v);
      s.row_weights.push_back(1.0);
    } else if (!refine_once) {
      AppendLimitRow(mesh, v, s.row_indices, s.row_weights);
    } else if (!options.to_limit) {
      AppendRefinementRow(mesh, v, s.row_indices, s.row_weights);
    } else if (v < nv) {
      AppendLimitRow(mesh, v, s.row_indices, s.row_weights);  // the parent's limit
    } else {
      AppendMergedEdgeChildLimitMask(mesh, v - nv, s.row_indices, s.row_weights);
    }
  };
  Compose(options.threads, num_rows, output_row, previous, num_base, plan.vertex_map,
          table.offsets, table.indices, table.weights);
  if (whole) {
    stencils = SparseRows();  // the previous level's: used by the table only
    selection = SelectOutput(plan, mesh, refine_once, options.levels, options.threads);
  }
  surface.triangles = std::move(selection.triangles);
  surface.parent_triangle = std::move(selection.parent_triangle);
  surface.vertex_tags = std::move(selection.vertex_tags);
  surface.crease_edges = std::move(selection.crease_edges);
  return surface;
}

std::vector<Vertex> EvaluateSurface(const LimitSurface& surface, const std::vector<Vertex>& control) {
  if (control.size() < surface.stencils.num_control) return {};
  std::vector<Vertex> fine;
  internal::ReserveLarge(fine, surface.stencils.rows());
  fine.resize(surface.stencils.rows());
  static_assert(sizeof(Vertex) == 5 * sizeof(float));
  surface.stencils.Apply(reinterpret_cast<const float*>(control.data()), 5,
                         reinterpret_cast<float*>(fine.data()), 5, 5);
  return fine;
}

StatusOr<RefinedMesh> RefineImage(const Image& image, const LimitSurfaceOptions& options) {
  SDVI_ASSIGN_OR_RETURN(RefinementPlan plan, MakePlan(image, options));
  TaggedMesh mesh = std::move(plan.base);
  plan.base = TaggedMesh();
  // Values of the current level, 5 doubles a vertex. A level's array is written wholly by
  // the threads that compute it (DefaultInitAllocator: no zero fill first), so its first
  // touch is spread over them.
  using Values = std::vector<double, DefaultInitAllocator<double>>;
  Values values(5 * size_t{mesh.num_vertices()});
  for (uint32_t i = 0; i < mesh.num_vertices(); ++i) {
    const Vertex& v = image.vertices[plan.vertex_map.empty() ? i : plan.vertex_map[i]];
    const double src[5] = {v.x, v.y, v.r, v.g, v.b};
    std::copy(src, src + 5, values.begin() + 5 * i);
  }
  // The next level's values: every refinement row of mesh applied to the current values
  // (the masks are not built: ApplyRefinementRows), rows split over threads.
  auto refine_values = [&]() {
    const size_t rows = size_t{mesh.num_vertices()} + mesh.num_edges();
    Values next;
    internal::ReserveLarge(next, 5 * rows);
    next.resize(5 * rows);
    ForRowBlocks(rows, options.threads, [&](size_t begin, size_t end) {
      ApplyRefinementRows(mesh, values.data(), begin, end, &next[5 * begin]);
    });
    return next;
  };
  for (int k = 0; k + 1 < options.levels; ++k) {
    values = refine_values();
    mesh = mesh.Refine(options.threads);
  }
  // The last step, as in BuildLimitSurface: only the output vertices, without the level-r
  // topology.
  const bool refine_once = options.levels > 0;
  FineSelection selection = SelectOutput(plan, mesh, refine_once, options.levels, options.threads);
  RefinedMesh out;
  out.levels = options.levels;
  internal::ReserveLarge(out.vertices, selection.vertices.size());
  out.vertices.resize(selection.vertices.size());
  const uint32_t nv = mesh.num_vertices();
  // An edge child's limit comes from its one-ring at level r (EdgeChildLimitRing): the
  // level-r values are computed once, not once per ring they belong to.
  Values children;
  if (options.to_limit && refine_once) children = refine_values();
  ForRowBlocks(selection.vertices.size(), options.threads, [&](size_t begin, size_t end) {
    double v[5];
    for (size_t i = begin; i < end; ++i) {
      const uint32_t fine = selection.vertices[i];
      if (!options.to_limit && !refine_once) {
        std::copy(&values[5 * size_t{fine}], &values[5 * size_t{fine}] + 5, v);
      } else if (!options.to_limit) {
        ApplyRefinementRows(mesh, values.data(), fine, size_t{fine} + 1, v);
      } else if (fine < nv) {
        ApplyLimitRows(mesh, values.data(), fine, fine + 1, v);  // the parent's limit
      } else {
        uint32_t ring[7];
        double lambda[7];
        const int n = EdgeChildLimitRing(mesh, fine - nv, ring, lambda);
        for (int c = 0; c < 5; ++c) v[c] = 0;
        for (int k = 0; k < n; ++k) {
          const double* src = &children[5 * size_t{ring[k]}];
          for (int c = 0; c < 5; ++c) v[c] += lambda[k] * src[c];
        }
      }
      out.vertices[i] = Vertex{static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                               static_cast<float>(v[3]), static_cast<float>(v[4])};
    }
  });
  out.triangles = std::move(selection.triangles);
  out.parent_triangle = std::move(selection.parent_triangle);
  out.vertex_tags = std::move(selection.vertex_tags);
  out.crease_edges = std::move(selection.crease_edges);
  return out;
}

}  // namespace sdvi
