// SPDX-License-Identifier: GPL-3.0-or-later
// Public contract of the subdivision engine (spec/SUBDIVISION.md, spec/METHOD.md section 3), used by the
// renderer, the colour fit and the exporters. The engine module owns the implementation
// and may add declarations; the names below are what other modules rely on.
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

enum class VertexTag : uint8_t { kSmooth = 0, kCrease = 1, kCorner = 2 };

// Sparse linear combinations of control vertices (CSR). Row i is a fine vertex (or its
// limit point); its weights sum to 1.
struct StencilTable {
  uint32_t num_control = 0;        // number of control vertices the rows refer to
  std::vector<uint32_t> offsets;   // rows + 1 entries; row i = [offsets[i], offsets[i+1])
  std::vector<uint32_t> indices;   // control vertex of each weight
  std::vector<float> weights;

  size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  // out[i * out_stride + c] = sum_k weights[k] * in[indices[k] * in_stride + c], c < dims,
  // summed in double in row order and stored as float; every index < num_control.
  void Apply(const float* in, size_t in_stride, float* out, size_t out_stride, int dims) const;

  // Apply's kernels (spec/SUBDIVISION.md section 4), all giving the same floats: kAuto picks
  // one for the processor and the table; the others force one (tests compare them). A
  // forced kernel the processor lacks runs the portable one.
  enum class Kernel { kAuto, kPortable, kAvx2, kAvx512 };
  static bool KernelSupported(Kernel kernel);
  void Apply(const float* in, size_t in_stride, float* out, size_t out_stride, int dims, Kernel kernel) const;
};

struct LimitSurfaceOptions {
  int levels = 2;          // subdivision level r (0 = the control mesh itself)
  bool to_limit = true;    // push fine vertices to their limit positions; false keeps
                           // level-r positions (with levels = 0: piecewise-linear control mesh)
  // When non-empty, only fine triangles descending from these control triangles are
  // produced (region rendering); stencils still refer to all control vertices.
  std::vector<uint32_t> control_triangles;
  // Refuses (kLimitExceeded) to build more fine triangles than this (never more than
  // 2^27, which keeps stencil offsets within uint32).
  uint64_t max_fine_triangles = uint64_t{1} << 25;
  // Worker threads for large builds: 0 = the hardware's (at most 8). The result does not
  // depend on it.
  int threads = 0;
};

// Levels accepted by BuildLimitSurface and RefineImage: 0 .. kMaxLevels.
inline constexpr int kMaxLevels = 6;

// Fine-level numbering (tagged_mesh.h): the first control-vertex-count fine vertices
// are the control vertices' descendants, in order (for a region: those it uses, in
// increasing order); a fine triangle f of the whole mesh descends from control
// triangle f >> 2r.
//
// The fine mesh at level r, as stencils over the control vertices: built once per
// topology, then evaluated for any control positions/colours.
struct LimitSurface {
  int levels = 0;
  std::vector<Triangle> triangles;          // fine triangles, orientation of their parent
  std::vector<uint32_t> parent_triangle;    // control triangle containing each fine triangle
  std::vector<VertexTag> vertex_tags;       // tag of each fine vertex
  std::vector<Edge> crease_edges;           // fine crease edges (boundary included)
  StencilTable stencils;                    // one row per fine vertex (limit or level-r point)
};

// Validates the topology of image (manifold, no degenerate/duplicate triangles, crease
// edges are mesh edges, indices in range) and builds its limit surface. Errors:
// kEmptyInput, kIndexOutOfRange, kDegenerateTriangle, kDuplicateTriangle,
// kNonManifoldEdge, kCreaseNotAnEdge, kNonFinite (a NaN/inf control coordinate),
// kInvalidArgument (levels outside 0..kMaxLevels), kLimitExceeded (max_fine_triangles).
StatusOr<LimitSurface> BuildLimitSurface(const Image& image, const LimitSurfaceOptions& options);

// The fine vertices (x, y, R, G, B) of surface for the given control vertices; empty when
// control has fewer than surface.stencils.num_control vertices.
std::vector<Vertex> EvaluateSurface(const LimitSurface& surface, const std::vector<Vertex>& control);

// Direct (non-stencil) refinement: the same fine mesh as BuildLimitSurface with the same
// options and numbering, computed by applying the masks level by level to the control
// values in double precision. For tests, PLY export and one-off evaluation; repeated
// evaluation of one topology is cheaper through the stencils.
struct RefinedMesh {
  int levels = 0;
  std::vector<Vertex> vertices;             // fine vertices (limit or level-r points)
  std::vector<Triangle> triangles;          // fine triangles
  std::vector<uint32_t> parent_triangle;    // control triangle containing each
  std::vector<VertexTag> vertex_tags;       // tag of each fine vertex
  std::vector<Edge> crease_edges;           // fine crease edges (boundary included)
};
StatusOr<RefinedMesh> RefineImage(const Image& image, const LimitSurfaceOptions& options);

}  // namespace sdvi
