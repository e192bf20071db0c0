// SPDX-License-Identifier: GPL-3.0-or-later
// Colour least squares through the limit stencils (paper eq. 2-3); see color_fit.h.
//
// Assembly, per control triangle T (the parent of a set of fine triangles):
//   F_T (local fine vertices x local fine vertices) = sum over T's fine triangles and their
//       domain pixels of w_a w_b, g_T = sum of w_a I(p);
//   S_T = the stencil rows of those fine vertices restricted to the support U_T (the
//       control vertices any of them depends on, plus T's own three vertices; ascending);
//   A += S_T^T F_T S_T, b += S_T^T g_T, scattered into the global sparse pattern.
// Since every fine triangle has exactly one parent, summing over T gives S^T F S exactly.
// Blocks of a batch of control triangles are computed in parallel and scattered serially
// in triangle order, so the result does not depend on the thread count.
#include "sdvi/color_fit.h"

#include "parallel.h"
#include "permuted_ic.h"
#include "prefetch.h"

#include <Eigen/Sparse>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace sdvi {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// R, G, B of pixel index p of raster (grey counts as R = G = B).
inline void PixelRgb(const Raster& raster, size_t p, double rgb[3]) {
  const float* px = &raster.data[p * size_t(raster.channels)];
  if (raster.channels <= 2) {
    rgb[0] = rgb[1] = rgb[2] = px[0];
  } else {
    rgb[0] = px[0];
    rgb[1] = px[1];
    rgb[2] = px[2];
  }
}

// Index sets of a run of consecutive elements, built by one thread: set k has counts[k]
// items, in order.
struct ChunkSets {
  std::vector<uint32_t> counts;
  std::vector<uint32_t> items;
};

// Elements per chunk when per-element index sets are built on the threads.
constexpr size_t kSetChunk = 2048;

// Builds sorted index sets without duplicates, one after another, into a chunk's items: a
// mark per control vertex (one builder per worker, made on its first chunk).
class SortedSetBuilder {
 public:
  // Starts a set at the end of items.
  void Begin(size_t num_control, const std::vector<uint32_t>& items) {
    if (seen_.empty()) seen_.assign(num_control, 0);
    first_ = items.size();
  }
  // Appends c unless the set holds it already.
  void Add(std::vector<uint32_t>& items, uint32_t c) {
    if (!seen_[c]) {
      seen_[c] = 1;
      items.push_back(c);
    }
  }
  // Ends the set: clears its marks, sorts it, records its size in counts.
  void End(ChunkSets& chunk) {
    for (size_t k = first_; k < chunk.items.size(); ++k) seen_[chunk.items[k]] = 0;
    std::sort(chunk.items.begin() + first_, chunk.items.end());
    chunk.counts.push_back(uint32_t(chunk.items.size() - first_));
  }

 private:
  std::vector<uint8_t> seen_;
  size_t first_ = 0;
};

// Flat lists of per-control-triangle index sets: set t = [offsets[t], offsets[t+1]).
struct IndexSets {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> items;
  size_t size() const { return offsets.size() - 1; }
  uint32_t count(size_t t) const { return offsets[t + 1] - offsets[t]; }
  const uint32_t* begin(size_t t) const { return items.data() + offsets[t]; }
  // Appends the chunks' sets in chunk order, releasing each chunk once copied.
  void Concatenate(std::vector<ChunkSets>& chunks) {
    size_t sets = 0, total = 0;
    for (const ChunkSets& c : chunks) sets += c.counts.size(), total += c.items.size();
    offsets.reserve(offsets.size() + sets);
    items.reserve(items.size() + total);
    for (ChunkSets& c : chunks) {
      for (uint32_t count : c.counts) offsets.push_back(offsets.back() + count);
      items.insert(items.end(), c.items.begin(), c.items.end());
      c = ChunkSets();
    }
  }
};

// Scratch memory of one assembly thread.
struct BlockScratch {
  std::vector<int> local_of_control;  // control vertex -> column in U_T, or -1
  std::vector<double> f, g, tmp;
  std::vector<uint32_t> s_offsets;    // sparse S_T rows: [s_offsets[l], s_offsets[l+1])
  std::vector<uint32_t> s_columns;
  std::vector<double> s_weights;
  std::vector<PixelSample> samples;  // one fine triangle's (AppendOwnedSamples)
};

// Control triangles per chunk of the assembly's blocks (taken in turn by the threads).
constexpr size_t kBlockChunk = 16;

// Asks for the stencil table's offsets of control triangle t's local fine vertices.
inline void PrefetchStencilOffsets(const StencilTable& stencils, const IndexSets& local_fine, size_t t) {
  for (const uint32_t* l = local_fine.begin(t); l != local_fine.begin(t + 1); ++l) {
    __builtin_prefetch(&stencils.offsets[*l]);
  }
}

// Asks for the stencil rows (indices and weights, first and last entries: a row of about 17
// entries spans one or two cache lines) of control triangle t's local fine vertices.
inline void PrefetchStencilRows(const StencilTable& stencils, const IndexSets& local_fine, size_t t) {
  for (const uint32_t* l = local_fine.begin(t); l != local_fine.begin(t + 1); ++l) {
    const uint32_t k = stencils.offsets[*l], last = stencils.offsets[*l + 1] - 1;
    __builtin_prefetch(&stencils.indices[k]);
    __builtin_prefetch(&stencils.weights[k]);
    __builtin_prefetch(&stencils.indices[last]);
    __builtin_prefetch(&stencils.weights[last]);
  }
}

// Computes A_T = S_T^T F_T S_T (u x u, row-major) and b_T = S_T^T g_T (u x 3) for control
// triangle t into a_out / b_out. S_T is kept sparse (a stencil row touches about half of
// U_T); F_T and the products are dense and small.
void ComputeBlock(size_t t, const IndexSets& fine_of_control, const IndexSets& local_fine,
                  const IndexSets& support, const std::vector<Triangle>& fine_triangles,
                  const PixelOwners& owners, const Raster& target, const Raster* mask,
                  const StencilTable& stencils, BlockScratch& scratch, double* a_out, double* b_out) {
  const uint32_t nl = local_fine.count(t);
  const uint32_t u = support.count(t);
  const uint32_t* lf = local_fine.begin(t);
  const uint32_t* us = support.begin(t);
  scratch.f.assign(size_t(nl) * nl, 0.0);
  scratch.g.assign(size_t(nl) * 3, 0.0);
  double* f = scratch.f.data();
  double* g = scratch.g.data();
  bool any = false;
  const bool whole = mask == nullptr && !target.has_alpha();
  const int width = target.width;
  std::vector<PixelSample>& samples = scratch.samples;
  for (const uint32_t* ft = fine_of_control.begin(t); ft != fine_of_control.begin(t + 1); ++ft) {
    // The fine triangle's domain samples, in pixel order.
    samples.clear();
    AppendOwnedSamples(owners, fine_triangles, *ft, samples);
    if (!whole) {
      std::erase_if(samples, [&](const PixelSample& sm) {
        return !InDomain(target, mask, int(sm.pixel % width), int(sm.pixel / width));
      });
    }
    if (samples.empty()) continue;
    any = true;
    uint32_t la[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = fine_triangles[*ft].v[k];
      la[k] = uint32_t(std::find(lf, lf + nl, v) - lf);
    }
    double m[3][3] = {}, r[3][3] = {};
    for (const PixelSample& sm : samples) {
      const double w[3] = {sm.w0, sm.w1, sm.w2};
      double rgb[3];
      PixelRgb(target, sm.pixel, rgb);
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) m[a][b] += w[a] * w[b];
        for (int c = 0; c < 3; ++c) r[a][c] += w[a] * rgb[c];
      }
    }
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) f[la[a] * nl + la[b]] += m[a][b];
      for (int c = 0; c < 3; ++c) g[la[a] * 3 + c] += r[a][c];
    }
  }
  std::fill(a_out, a_out + size_t(u) * u, 0.0);
  std::fill(b_out, b_out + size_t(u) * 3, 0.0);
  if (!any) return;
  // Sparse S_T rows in local columns.
  for (uint32_t k = 0; k < u; ++k) scratch.local_of_control[us[k]] = int(k);
  scratch.s_offsets.assign(1, 0);
  scratch.s_columns.clear();
  scratch.s_weights.clear();
  for (uint32_t l = 0; l < nl; ++l) {
    const uint32_t row = lf[l];
    for (uint32_t k = stencils.offsets[row]; k < stencils.offsets[row + 1]; ++k) {
      scratch.s_columns.push_back(uint32_t(scratch.local_of_control[stencils.indices[k]]));
      scratch.s_weights.push_back(stencils.weights[k]);
    }
    scratch.s_offsets.push_back(uint32_t(scratch.s_columns.size()));
  }
  for (uint32_t k = 0; k < u; ++k) scratch.local_of_control[us[k]] = -1;
  const uint32_t* so = scratch.s_offsets.data();
  const uint32_t* sc = scratch.s_columns.data();
  const double* sw = scratch.s_weights.data();
  // tmp = F_T S_T (nl x u, dense).
  scratch.tmp.assign(size_t(nl) * u, 0.0);
  double* tmp = scratch.tmp.data();
  for (uint32_t i = 0; i < nl; ++i) {
    double* ti = tmp + size_t(i) * u;
    for (uint32_t j = 0; j < nl; ++j) {
      const double fij = f[i * nl + j];
      if (fij == 0.0) continue;
      for (uint32_t k = so[j]; k < so[j + 1]; ++k) ti[sc[k]] += fij * sw[k];
    }
  }
  // A_T = S_T^T tmp, b_T = S_T^T g.
  for (uint32_t i = 0; i < nl; ++i) {
    const double* ti = tmp + size_t(i) * u;
    for (uint32_t k = so[i]; k < so[i + 1]; ++k) {
      const uint32_t a = sc[k];
      const double sia = sw[k];
      double* arow = a_out + size_t(a) * u;
      for (uint32_t b = 0; b < u; ++b) arow[b] += sia * ti[b];
      for (int c = 0; c < 3; ++c) b_out[a * 3 + c] += sia * g[i * 3 + c];
    }
  }
}

// Solves A X = B (three right-hand sides) by conjugate gradients preconditioned with an
// incomplete Cholesky factor, started from the vertices' current colours (see FitColors and
// ColorFitOptions::warm_start), to a relative residual of
// kSolveTolerance; falls back to a sparse LDL^T when CG does not get there within
// kSolveMaxIterations. The channels' solves run on up to three threads, each exactly the
// single-threaded solve, so the result does not depend on the thread count. ordering, when
// given, is the preconditioner's AMD ordering of matrix's pattern, found beforehand.
constexpr double kSolveTolerance = 1e-8;
constexpr int kSolveMaxIterations = 2000;

StatusOr<Eigen::MatrixXd> SolveNormalEquations(const Eigen::SparseMatrix<double>& matrix,
                                               const Eigen::MatrixXd& rhs,
                                               const std::vector<Vertex>& start, int threads,
                                               fit_internal::PermutedIncompleteCholesky::Permutation* ordering) {
  const Eigen::Index n = matrix.rows();
  Eigen::MatrixXd guess(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vertex& v = start[size_t(i)];
    const bool finite = std::isfinite(v.r) && std::isfinite(v.g) && std::isfinite(v.b);
    guess(i, 0) = finite ? v.r : 0.0;
    guess(i, 1) = finite ? v.g : 0.0;
    guess(i, 2) = finite ? v.b : 0.0;
  }
  // The preconditioner is Eigen's IncompleteCholesky<double> bit for bit, computed with
  // less memory (PermutedIncompleteCholesky).
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                           fit_internal::PermutedIncompleteCholesky>
      cg;
  cg.setTolerance(kSolveTolerance);
  cg.setMaxIterations(kSolveMaxIterations);
  if (ordering != nullptr) cg.preconditioner().PresetOrdering(std::move(*ordering));
  cg.compute(matrix);
  if (cg.info() == Eigen::Success) {
    // The three colour channels are three independent solves with the same matrix and
    // preconditioner: one per thread, each what cg.solveWithGuess computes (the same
    // expressions: the matrix's transpose as ConjugateGradient reads it, the column blocks
    // of rhs and colors), so the result does not depend on the thread count.
    Eigen::MatrixXd colors = guess;
    const Eigen::Ref<const Eigen::SparseMatrix<double>> ref(matrix);
    const Eigen::Transpose<const Eigen::Ref<const Eigen::SparseMatrix<double>>> row_major(ref);
    bool converged[3] = {false, false, false};
    fit_internal::ForEachChunk(3, 1, threads, [&](size_t c, size_t, size_t) {
      Eigen::Index iterations = cg.maxIterations();
      double error = cg.tolerance();
      auto x = colors.col(Eigen::Index(c));
      Eigen::internal::conjugate_gradient(row_major, rhs.col(Eigen::Index(c)), x, cg.preconditioner(),
                                          iterations, error);
      converged[c] = error <= cg.tolerance() && x.allFinite();
    });
    if (converged[0] && converged[1] && converged[2]) return colors;
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  ldlt.compute(matrix);
  if (ldlt.info() != Eigen::Success) {
    return Status(StatusCode::kInternal, "colour fit: sparse LDL^T factorisation of the " +
                                             std::to_string(n) + "-vertex normal equations failed");
  }
  Eigen::MatrixXd colors = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !colors.allFinite()) {
    return Status(StatusCode::kInternal, "colour fit: the normal equations gave no finite solution");
  }
  return colors;
}

}  // namespace

bool InDomain(const Raster& target, const Raster* mask, int x, int y) {
  if (target.has_alpha() && !(target.at(x, y, target.channels - 1) > 0.5f)) return false;
  if (mask != nullptr) {
    if (mask->has_alpha()) return mask->at(x, y, mask->channels - 1) > 0.5f;
    return mask->at(x, y, 0) > 127.5f;
  }
  return true;
}

StatusOr<ColorFit> FitColors(Image& image, const Raster& target, const Raster* mask,
                             const ColorFitOptions& options, ColorFitBuffers* buffers) {
  const int width = target.width, height = target.height;
  if (target.empty() || target.channels < 1 || target.channels > 4 ||
      target.data.size() != size_t(width) * height * target.channels) {
    return Status(StatusCode::kInvalidArgument,
                  "colour fit: target raster is empty or malformed (" + std::to_string(width) +
                      "x" + std::to_string(height) + ", " + std::to_string(target.channels) +
                      " channels)");
  }
  if (int64_t(image.width) != width || int64_t(image.height) != height) {
    return Status(StatusCode::kInvalidArgument,
                  "colour fit: image frame is " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + " but the target raster is " +
                      std::to_string(width) + "x" + std::to_string(height));
  }
  if (mask != nullptr &&
      (mask->width != width || mask->height != height || mask->channels < 1 ||
       mask->data.size() != size_t(width) * height * mask->channels)) {
    return Status(StatusCode::kInvalidArgument,
                  "colour fit: mask is " + std::to_string(mask->width) + "x" +
                      std::to_string(mask->height) + ", expected " + std::to_string(width) + "x" +
                      std::to_string(height));
  }
  if (!(options.regularization >= 0) || !std::isfinite(options.regularization)) {
    return Status(StatusCode::kInvalidArgument,
                  "colour fit: regularization must be a finite value >= 0");
  }
  if (image.vertices.empty() || image.triangles.empty()) {
    return Status(StatusCode::kEmptyInput, "colour fit: the control mesh has no triangles");
  }

  ColorFit fit;
  Clock::time_point start = Clock::now();
  SDVI_ASSIGN_OR_RETURN(fit.surface, BuildLimitSurface(image, options.surface));
  fit.fine = EvaluateSurface(fit.surface, image.vertices);
  fit.seconds_surface = SecondsSince(start);

  start = Clock::now();
  if (buffers != nullptr) fit.coverage.owner = std::move(buffers->coverage);
  MapPixelOwnersInto(fit.surface.triangles, fit.fine, Viewport::Identity(width, height), fit.coverage);
  fit.seconds_coverage = SecondsSince(start);

  start = Clock::now();
  const LimitSurface& surface = fit.surface;
  const size_t num_control = image.vertices.size();
  const size_t num_fine_tris = surface.triangles.size();
  const size_t num_control_tris = image.triangles.size();
  const StencilTable& stencils = surface.stencils;
  if (surface.parent_triangle.size() != num_fine_tris ||
      stencils.rows() != fit.fine.size() || stencils.num_control != num_control) {
    return Status(StatusCode::kInternal,
                  "colour fit: limit surface tables disagree (parents, stencil rows, controls)");
  }
  // The fine vertices were needed by the coverage only; they are evaluated again with the
  // fitted colours after the solve (less memory in the assembly and the solve).
  std::vector<Vertex>().swap(fit.fine);

  // Fine triangles grouped by control triangle.
  IndexSets fine_of_control;
  fine_of_control.offsets.assign(num_control_tris + 1, 0);
  for (uint32_t parent : surface.parent_triangle) {
    if (parent >= num_control_tris) {
      return Status(StatusCode::kInternal, "colour fit: fine triangle parent out of range");
    }
    ++fine_of_control.offsets[parent + 1];
  }
  for (size_t t = 0; t < num_control_tris; ++t) {
    fine_of_control.offsets[t + 1] += fine_of_control.offsets[t];
  }
  fine_of_control.items.resize(num_fine_tris);
  {
    std::vector<uint32_t> cursor(fine_of_control.offsets.begin(), fine_of_control.offsets.end() - 1);
    for (size_t f = 0; f < num_fine_tris; ++f) {
      fine_of_control.items[cursor[surface.parent_triangle[f]]++] = uint32_t(f);
    }
  }

  // Local fine vertices (first-appearance order) and stencil support U_T (ascending) of
  // each control triangle: chunks of triangles on the threads, concatenated in order.
  const int threads = std::max(1, options.threads);
  IndexSets local_fine, support;
  {
    const size_t chunks = fit_internal::ChunkCount(num_control_tris, kSetChunk);
    std::vector<ChunkSets> fine_chunks(chunks), support_chunks(chunks);
    std::vector<SortedSetBuilder> builders(threads);
    fit_internal::ForEachChunkOnWorkers(num_control_tris, kSetChunk, threads,
                                        [&](size_t worker, size_t chunk, size_t t0, size_t t1) {
      SortedSetBuilder& set = builders[worker];
      ChunkSets& lf = fine_chunks[chunk];
      ChunkSets& sup = support_chunks[chunk];
      lf.counts.reserve(t1 - t0);
      sup.counts.reserve(t1 - t0);
      for (size_t t = t0; t < t1; ++t) {
        // The triangle's stencil rows lie anywhere in the table: ask for those of the
        // triangles ahead (their fine vertices are known from the fine triangles).
        if (t + 4 < t1) {
          for (const uint32_t* ft = fine_of_control.begin(t + 4); ft != fine_of_control.begin(t + 5); ++ft) {
            for (uint32_t v : surface.triangles[*ft].v) __builtin_prefetch(&stencils.offsets[v]);
          }
        }
        if (t + 2 < t1) {
          for (const uint32_t* ft = fine_of_control.begin(t + 2); ft != fine_of_control.begin(t + 3); ++ft) {
            for (uint32_t v : surface.triangles[*ft].v) __builtin_prefetch(&stencils.indices[stencils.offsets[v]]);
          }
        }
        const size_t lf_first = lf.items.size();
        for (const uint32_t* ft = fine_of_control.begin(t); ft != fine_of_control.begin(t + 1); ++ft) {
          for (uint32_t v : surface.triangles[*ft].v) {
            if (std::find(lf.items.begin() + lf_first, lf.items.end(), v) == lf.items.end()) lf.items.push_back(v);
          }
        }
        lf.counts.push_back(uint32_t(lf.items.size() - lf_first));
        set.Begin(num_control, sup.items);
        for (uint32_t c : image.triangles[t].v) set.Add(sup.items, c);
        for (size_t l = lf_first; l < lf.items.size(); ++l) {
          const uint32_t v = lf.items[l];
          for (uint32_t k = stencils.offsets[v]; k < stencils.offsets[v + 1]; ++k) set.Add(sup.items, stencils.indices[k]);
        }
        set.End(sup);
      }
    });
    local_fine.Concatenate(fine_chunks);
    support.Concatenate(support_chunks);
  }

  // Sparsity pattern of A (symmetric, full): row i holds every j sharing some U_T with i.
  // A is assembled in place in the solver's matrix (column-major; A is symmetric, so its
  // row-major pattern read as column-major is the same matrix): no second copy is held.
  Eigen::SparseMatrix<double> matrix{Eigen::Index(num_control), Eigen::Index(num_control)};
  {
    IndexSets tris_of_control;
    tris_of_control.offsets.assign(num_control + 1, 0);
    for (uint32_t c : support.items) ++tris_of_control.offsets[c + 1];
    for (size_t c = 0; c < num_control; ++c) tris_of_control.offsets[c + 1] += tris_of_control.offsets[c];
    tris_of_control.items.resize(support.items.size());
    std::vector<uint32_t> cursor(tris_of_control.offsets.begin(), tris_of_control.offsets.end() - 1);
    for (size_t t = 0; t < num_control_tris; ++t) {
      for (const uint32_t* c = support.begin(t); c != support.begin(t + 1); ++c) {
        tris_of_control.items[cursor[*c]++] = uint32_t(t);
      }
    }
    // Rows in chunks on the threads, concatenated in order.
    const size_t chunks = fit_internal::ChunkCount(num_control, kSetChunk);
    std::vector<ChunkSets> row_chunks(chunks);
    std::vector<SortedSetBuilder> builders(threads);
    fit_internal::ForEachChunkOnWorkers(num_control, kSetChunk, threads,
                                        [&](size_t worker, size_t chunk, size_t i0, size_t i1) {
      SortedSetBuilder& set = builders[worker];
      ChunkSets& rows = row_chunks[chunk];
      rows.counts.reserve(i1 - i0);
      for (size_t i = i0; i < i1; ++i) {
        set.Begin(num_control, rows.items);
        set.Add(rows.items, uint32_t(i));  // the diagonal always exists (regulariser)
        for (const uint32_t* t = tris_of_control.begin(i); t != tris_of_control.begin(i + 1); ++t) {
          for (const uint32_t* c = support.begin(*t); c != support.begin(*t + 1); ++c) set.Add(rows.items, *c);
        }
        set.End(rows);
      }
    });
    builders.clear();
    tris_of_control = IndexSets();
    size_t nonzeros = 0;
    for (const ChunkSets& rows : row_chunks) nonzeros += rows.items.size();
    matrix.resizeNonZeros(Eigen::Index(nonzeros));
    int* starts = matrix.outerIndexPtr();
    int* inner = matrix.innerIndexPtr();
    size_t i = 0, at = 0;
    starts[0] = 0;
    for (ChunkSets& rows : row_chunks) {
      for (uint32_t count : rows.counts) {
        starts[i + 1] = starts[i] + int(count);
        ++i;
      }
      std::copy(rows.items.begin(), rows.items.end(), inner + at);
      at += rows.items.size();
      rows = ChunkSets();
    }
  }
  // The preconditioner's AMD ordering depends on A's pattern alone: with threads, it is found
  // on a thread of its own while the values are assembled (the same permutation,
  // fit/src/permuted_ic.h).
  fit_internal::PermutedIncompleteCholesky::Permutation ordering;
  BackgroundTask ordering_task;
  if (threads > 1) {
    ordering_task.Start([&ordering, &matrix] {
      ordering = fit_internal::PermutedIncompleteCholesky::Ordering(matrix.rows(), matrix.nonZeros(),
                                                                    matrix.outerIndexPtr(), matrix.innerIndexPtr());
    });
  }
  const int* row_start = matrix.outerIndexPtr();
  const int* columns = matrix.innerIndexPtr();
  double* values = matrix.valuePtr();
  std::fill(values, values + matrix.nonZeros(), 0.0);
  // The domain pixels: covered by the fine mesh and in the domain. Each block reads its
  // fine triangles' samples from the owners (AppendOwnedSamples): no per-pixel grouping is
  // held.
  const PixelOwners& owners = fit.coverage;
  const bool whole = mask == nullptr && !target.has_alpha();
  {
    constexpr size_t kCountRows = 64;
    std::vector<uint64_t> counts(fit_internal::ChunkCount(size_t(height), kCountRows), 0);
    fit_internal::ForEachChunk(size_t(height), kCountRows, threads, [&](size_t chunk, size_t y0, size_t y1) {
      uint64_t n = 0;
      for (size_t y = y0; y < y1; ++y) {
        const uint32_t* row = owners.owner.data() + y * size_t(width);
        for (int x = 0; x < width; ++x) {
          if (row[x] != PixelOwners::kNoOwner && (whole || InDomain(target, mask, x, int(y)))) ++n;
        }
      }
      counts[chunk] = n;
    });
    for (uint64_t n : counts) fit.domain_pixels += n;
  }

  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(Eigen::Index(num_control), 3);
  auto position = [&](uint32_t row, uint32_t col) {
    const int* b = columns + row_start[row];
    const int* e = columns + row_start[row + 1];
    return size_t(std::lower_bound(b, e, int(col)) - columns);
  };

  // Blocks in parallel per batch, scattered serially in triangle order.
  const size_t batch = 2048;  // blocks of one batch: a few megabytes
  std::vector<BlockScratch> scratch(threads);
  for (BlockScratch& s : scratch) s.local_of_control.assign(num_control, -1);
  std::vector<size_t> block_offset(batch + 1);
  std::vector<double> blocks;
  for (size_t t0 = 0; t0 < num_control_tris; t0 += batch) {
    const size_t t1 = std::min(num_control_tris, t0 + batch);
    block_offset[0] = 0;
    for (size_t t = t0; t < t1; ++t) {
      const size_t u = support.count(t);
      block_offset[t - t0 + 1] = block_offset[t - t0] + u * u + u * 3;
    }
    blocks.resize(block_offset[t1 - t0]);
    // Dynamic chunks of a few triangles: a block's cost follows its pixels and support.
    fit_internal::ForEachChunkOnWorkers(t1 - t0, kBlockChunk, threads,
                                        [&](size_t worker, size_t, size_t lo, size_t hi) {
      for (size_t t = t0 + lo; t < t0 + hi; ++t) {
        // The stencil rows of the next triangles lie anywhere in the table: ask for the
        // offsets four triangles ahead and the rows two ahead (fit/src/prefetch.h).
        if (t + 4 < t1) PrefetchStencilOffsets(stencils, local_fine, t + 4);
        if (t + 2 < t1) PrefetchStencilRows(stencils, local_fine, t + 2);
        const size_t u = support.count(t);
        double* a = blocks.data() + block_offset[t - t0];
        ComputeBlock(t, fine_of_control, local_fine, support, surface.triangles, owners, target, mask, stencils,
                     scratch[worker], a, a + u * u);
      }
    });
    // Scatter: each thread owns a set of rows of A and adds the blocks' rows in triangle
    // order, so every entry is summed in the same order for any thread count. The rows are
    // dealt in groups of kScatterRows in turn (a batch's triangles are near each other and
    // touch rows near each other: contiguous ranges of rows left all of a batch's rows to
    // one thread).
    constexpr uint32_t kScatterRowsLog2 = 4;
    auto owns = [&](uint32_t row, int id) {
      return threads == 1 || int((row >> kScatterRowsLog2) % uint32_t(threads)) == id;
    };
    auto scatter = [&](int id) {
      for (size_t t = t0; t < t1; ++t) {
        // The rows of A the triangle two ahead adds to lie anywhere in the matrix: ask for
        // their first columns and values now (fit/src/prefetch.h; nothing computed changes).
        if (t + 2 < t1) {
          for (const uint32_t* c = support.begin(t + 2); c != support.begin(t + 3); ++c) {
            if (!owns(*c, id)) continue;
            __builtin_prefetch(columns + row_start[*c]);
            __builtin_prefetch(values + row_start[*c]);
          }
        }
        const size_t u = support.count(t);
        const uint32_t* us = support.begin(t);  // ascending: merge with the sorted row columns
        const double* a = blocks.data() + block_offset[t - t0];
        const double* b = a + u * u;
        for (size_t i = 0; i < u; ++i) {
          if (!owns(us[i], id)) continue;
          for (int c = 0; c < 3; ++c) rhs(us[i], c) += b[i * 3 + c];
          const double* arow = a + i * u;
          int p = row_start[us[i]];
          for (size_t j = 0; j < u; ++j) {
            while (columns[p] < int(us[j])) ++p;
            values[p] += arow[j];
          }
        }
      }
    };
    if (threads == 1 || t1 - t0 < 64) {
      for (int id = 0; id < threads; ++id) scatter(id);
    } else {
      RunTasks(threads, scatter);
    }
  }
  // The grouping tables are not needed by the solve: release them before it.
  std::vector<double>().swap(blocks);
  scratch.clear();
  fine_of_control = IndexSets();
  local_fine = IndexSets();
  support = IndexSets();

  // Regulariser: lambda * s * (graph Laplacian of the control edges) + 1e-9 s I. Row by row
  // on the threads: a row's diagonal gets + lambda s once per distinct control edge at its
  // vertex (equal terms, so their order does not matter), each edge's two off-diagonal
  // entries - lambda s once, then the diagonal + 1e-9 s: the values of the serial pass over
  // the sorted edges.
  std::vector<size_t> diagonal_at(num_control);
  fit_internal::ForEachChunk(num_control, kSetChunk, threads, [&](size_t, size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) diagonal_at[i] = position(uint32_t(i), uint32_t(i));
  });
  double diagonal_sum = 0;
  size_t diagonal_count = 0;
  for (size_t i = 0; i < num_control; ++i) {
    const double d = values[diagonal_at[i]];
    if (d > 0) {
      diagonal_sum += d;
      ++diagonal_count;
    }
  }
  const double scale = diagonal_count > 0 ? diagonal_sum / double(diagonal_count) : 1.0;
  {
    // Each vertex's neighbours along the control triangles' sides (with repeats).
    IndexSets neighbours;
    neighbours.offsets.assign(num_control + 1, 0);
    for (const Triangle& tri : image.triangles) {
      for (uint32_t c : tri.v) neighbours.offsets[c + 1] += 2;
    }
    for (size_t c = 0; c < num_control; ++c) neighbours.offsets[c + 1] += neighbours.offsets[c];
    neighbours.items.resize(neighbours.offsets.back());
    {
      std::vector<uint32_t> cursor(neighbours.offsets.begin(), neighbours.offsets.end() - 1);
      for (const Triangle& tri : image.triangles) {
        for (int k = 0; k < 3; ++k) {
          const uint32_t c = tri.v[k];
          neighbours.items[cursor[c]++] = tri.v[(k + 1) % 3];
          neighbours.items[cursor[c]++] = tri.v[(k + 2) % 3];
        }
      }
    }
    const double weight = options.regularization * scale;
    fit_internal::ForEachChunk(num_control, kSetChunk, threads, [&](size_t, size_t i0, size_t i1) {
      for (size_t i = i0; i < i1; ++i) {
        if (weight > 0) {
          uint32_t* first = neighbours.items.data() + neighbours.offsets[i];
          uint32_t* last = neighbours.items.data() + neighbours.offsets[i + 1];
          std::sort(first, last);
          last = std::unique(first, last);
          for (const uint32_t* j = first; j != last; ++j) {
            if (*j == i) continue;
            values[diagonal_at[i]] += weight;
            values[position(uint32_t(i), *j)] -= weight;
          }
        }
        values[diagonal_at[i]] += 1e-9 * scale;
      }
    });
  }
  fit.seconds_assemble = SecondsSince(start);

  start = Clock::now();
  if (!options.warm_start) {
    // Start from the target under each vertex (nearest pixel), whatever the entry colours.
    for (Vertex& v : image.vertices) {
      const int x = std::clamp(int(std::floor(v.x)), 0, width - 1);
      const int y = std::clamp(int(std::floor(v.y)), 0, height - 1);
      double rgb[3];
      PixelRgb(target, size_t(y) * width + x, rgb);
      v.r = float(rgb[0]), v.g = float(rgb[1]), v.b = float(rgb[2]);
    }
  }
  ordering_task.Wait();
  SDVI_ASSIGN_OR_RETURN(const Eigen::MatrixXd colors,
                        SolveNormalEquations(matrix, rhs, image.vertices, threads, threads > 1 ? &ordering : nullptr));
  for (size_t i = 0; i < num_control; ++i) {
    image.vertices[i].r = float(colors(Eigen::Index(i), 0));
    image.vertices[i].g = float(colors(Eigen::Index(i), 1));
    image.vertices[i].b = float(colors(Eigen::Index(i), 2));
  }
  fit.seconds_solve = SecondsSince(start);

  start = Clock::now();
  fit.fine = EvaluateSurface(fit.surface, image.vertices);
  // Sum of squared errors: partial sums of fixed chunks of samples (covered pixels), added
  // in chunk order (the same for any thread count). Chunk c: pixels [chunk_pixel[c],
  // chunk_pixel[c + 1]), holding kSseChunk samples (the last one fewer).
  constexpr size_t kSseChunk = size_t(1) << 16;
  const size_t pixels = size_t(width) * height;
  std::vector<size_t> chunk_pixel{0};
  {
    size_t covered = 0;
    for (size_t p = 0; p < pixels; ++p) {
      if (owners.owner[p] == PixelOwners::kNoOwner) continue;
      if (covered > 0 && covered % kSseChunk == 0) chunk_pixel.push_back(p);
      ++covered;
    }
    if (covered == 0) chunk_pixel.clear();
    chunk_pixel.push_back(pixels);
  }
  const size_t sse_chunks = chunk_pixel.size() - 1;
  std::vector<double> partial(sse_chunks, 0.0);
  std::vector<std::vector<PixelSample>> chunk_samples(static_cast<size_t>(threads));
  fit_internal::ForEachChunkOnWorkers(sse_chunks, 1, threads, [&](size_t worker, size_t chunk, size_t, size_t) {
    std::vector<PixelSample>& samples = chunk_samples[worker];
    samples.clear();
    AppendSamplesInRange(owners, surface.triangles, chunk_pixel[chunk], chunk_pixel[chunk + 1], samples);
    double sse = 0;
    const size_t q1 = samples.size();
    for (size_t q = 0; q < q1; ++q) {
      fit_internal::PrefetchSampleData(samples, q, q1, surface.triangles, fit.fine);
      const PixelSample& sm = samples[q];
      if (!whole && !InDomain(target, mask, int(sm.pixel % width), int(sm.pixel / width))) continue;
      const Triangle& tri = surface.triangles[sm.triangle];
      const Vertex& p0 = fit.fine[tri.v[0]];
      const Vertex& p1 = fit.fine[tri.v[1]];
      const Vertex& p2 = fit.fine[tri.v[2]];
      double rgb[3];
      PixelRgb(target, sm.pixel, rgb);
      const double rec[3] = {sm.w0 * p0.r + sm.w1 * p1.r + sm.w2 * p2.r,
                             sm.w0 * p0.g + sm.w1 * p1.g + sm.w2 * p2.g,
                             sm.w0 * p0.b + sm.w1 * p1.b + sm.w2 * p2.b};
      for (int c = 0; c < 3; ++c) {
        const double d = std::clamp(rec[c], 0.0, 255.0) - rgb[c];
        sse += d * d;
      }
    }
    partial[chunk] = sse;
  });
  double sse = 0;
  for (double v : partial) sse += v;
  fit.sum_squared_error = sse;
  fit.seconds_surface += SecondsSince(start);
  return fit;
}

Raster ReconstructRaster(const ColorFit& fit) {
  Raster out(fit.coverage.width, fit.coverage.height, 4);
  const size_t pixels = size_t(out.width) * out.height;
  if (fit.coverage.owner.size() != pixels) return out;
  std::vector<PixelSample> samples;
  for (int y = 0; y < out.height; ++y) {
    samples.clear();
    AppendSamplesInRange(fit.coverage, fit.surface.triangles, size_t(y) * out.width, size_t(y + 1) * out.width,
                         samples);
    for (const PixelSample& sm : samples) {
      const Triangle& tri = fit.surface.triangles[sm.triangle];
      const Vertex& p0 = fit.fine[tri.v[0]];
      const Vertex& p1 = fit.fine[tri.v[1]];
      const Vertex& p2 = fit.fine[tri.v[2]];
      float* px = &out.data[size_t(sm.pixel) * 4];
      px[0] = std::clamp(sm.w0 * p0.r + sm.w1 * p1.r + sm.w2 * p2.r, 0.f, 255.f);
      px[1] = std::clamp(sm.w0 * p0.g + sm.w1 * p1.g + sm.w2 * p2.g, 0.f, 255.f);
      px[2] = std::clamp(sm.w0 * p0.b + sm.w1 * p1.b + sm.w2 * p2.b, 0.f, 255.f);
      px[3] = 1.f;
    }
  }
  return out;
}

}  // namespace sdvi
