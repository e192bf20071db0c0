// BuildLimitSurface (stencils), RefineImage (direct), EvaluateSurface, StencilTable::Apply.
#include "sdvi/subdiv.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdvi/tagged_mesh.h"

namespace sdvi {
namespace {

// Rings of control triangles kept around a region so that the region's fine vertices
// see exactly the neighbourhood they would see in the whole mesh (a level-r limit point
// depends on control vertices at most two rings away; one more for safety).
constexpr int kRegionMarginRings = 3;

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
  if (fine > options.max_fine_triangles)
    return Status(StatusCode::kLimitExceeded,
                  std::to_string(region_size) + " control triangles at level " +
                      std::to_string(options.levels) + " need " + std::to_string(fine) +
                      " fine triangles (with margin); the limit is " +
                      std::to_string(options.max_fine_triangles));
  return plan;
}

// The output part of the finest level: kept triangles (renumbered), their parents, and the
// kept fine vertices (sorted finest-level indices).
struct FineSelection {
  std::vector<Triangle> triangles;
  std::vector<uint32_t> parent_triangle;
  std::vector<uint32_t> vertices;  // output vertex i = finest-level vertex vertices[i]
  std::vector<VertexTag> vertex_tags;
  std::vector<Edge> crease_edges;
};

FineSelection SelectOutput(const RefinementPlan& plan, const TaggedMesh& fine, int levels) {
  FineSelection out;
  const size_t nt = fine.num_triangles();
  const int shift = 2 * levels;
  auto parent = [&](size_t f) {
    const size_t base = f >> shift;
    return plan.triangle_map.empty() ? static_cast<uint32_t>(base) : plan.triangle_map[base];
  };
  if (plan.keep.empty()) {
    out.triangles = fine.triangles();
    out.parent_triangle.resize(nt);
    for (size_t f = 0; f < nt; ++f) out.parent_triangle[f] = parent(f);
    out.vertices.resize(fine.num_vertices());
    for (uint32_t v = 0; v < fine.num_vertices(); ++v) out.vertices[v] = v;
    out.vertex_tags = fine.vertex_tags();
    out.crease_edges = fine.CreaseEdges();
    return out;
  }
  std::vector<uint32_t> renumber(fine.num_vertices(), kNoIndex);
  std::vector<uint8_t> edge_kept(fine.num_edges(), 0);
  for (size_t f = 0; f < nt; ++f) {
    if (!plan.keep[f >> shift]) continue;
    for (uint32_t v : fine.triangles()[f].v) renumber[v] = 0;
    for (uint32_t e : fine.triangle_edges(f)) edge_kept[e] = 1;
  }
  for (uint32_t v = 0; v < fine.num_vertices(); ++v)
    if (renumber[v] == 0) {
      renumber[v] = static_cast<uint32_t>(out.vertices.size());
      out.vertices.push_back(v);
      out.vertex_tags.push_back(fine.tag(v));
    }
  for (size_t f = 0; f < nt; ++f) {
    if (!plan.keep[f >> shift]) continue;
    const auto& v = fine.triangles()[f].v;
    out.triangles.push_back(Triangle{{renumber[v[0]], renumber[v[1]], renumber[v[2]]}});
    out.parent_triangle.push_back(parent(f));
  }
  for (size_t e = 0; e < fine.num_edges(); ++e)
    if (edge_kept[e] && fine.is_crease(e))
      out.crease_edges.push_back(Edge::Of(renumber[fine.edges()[e].a], renumber[fine.edges()[e].b]));
  std::sort(out.crease_edges.begin(), out.crease_edges.end());
  return out;
}

// Rows of (mask x previous), or of mask alone when previous is null (level 0: identity).
// Computes the rows listed in row_list (all rows when null), each sorted by index, with
// indices mapped through index_map when it is non-empty.
template <typename Weight>
void Compose(const SparseRows& mask, const SparseRows* previous, const std::vector<uint32_t>* row_list,
             uint32_t num_columns, const std::vector<uint32_t>& index_map,
             std::vector<uint32_t>& offsets, std::vector<uint32_t>& indices, std::vector<Weight>& weights) {
  const size_t num_rows = row_list ? row_list->size() : mask.rows();
  std::vector<double> accumulator(num_columns, 0.0);
  std::vector<uint32_t> stamp(num_columns, kNoIndex);
  std::vector<uint32_t> touched;
  offsets.assign(1, 0);
  offsets.reserve(num_rows + 1);
  indices.clear();
  weights.clear();
  const size_t estimate = num_rows * (previous ? 16 : 5);
  indices.reserve(estimate);
  weights.reserve(estimate);
  for (size_t r = 0; r < num_rows; ++r) {
    const uint32_t row = row_list ? (*row_list)[r] : static_cast<uint32_t>(r);
    touched.clear();
    for (uint32_t k = mask.offsets[row]; k < mask.offsets[row + 1]; ++k) {
      const uint32_t p = mask.indices[k];
      const double w = mask.weights[k];
      if (!previous) {
        if (stamp[p] != r) {
          stamp[p] = static_cast<uint32_t>(r);
          accumulator[p] = 0;
          touched.push_back(p);
        }
        accumulator[p] += w;
        continue;
      }
      for (uint32_t j = previous->offsets[p]; j < previous->offsets[p + 1]; ++j) {
        const uint32_t c = previous->indices[j];
        if (stamp[c] != r) {
          stamp[c] = static_cast<uint32_t>(r);
          accumulator[c] = 0;
          touched.push_back(c);
        }
        accumulator[c] += w * previous->weights[j];
      }
    }
    std::sort(touched.begin(), touched.end());
    for (uint32_t c : touched) {
      if (accumulator[c] == 0) continue;
      indices.push_back(index_map.empty() ? c : index_map[c]);
      weights.push_back(static_cast<Weight>(accumulator[c]));
    }
    offsets.push_back(static_cast<uint32_t>(indices.size()));
  }
}

}  // namespace

void StencilTable::Apply(const float* in, size_t in_stride, float* out, size_t out_stride, int dims) const {
  constexpr int kBlock = 8;
  const size_t n = rows();
  for (int d0 = 0; d0 < dims; d0 += kBlock) {
    const int nd = std::min(kBlock, dims - d0);
    for (size_t i = 0; i < n; ++i) {
      double sum[kBlock] = {};
      for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
        const float* src = in + indices[k] * in_stride + d0;
        const double w = weights[k];
        for (int c = 0; c < nd; ++c) sum[c] += w * src[c];
      }
      float* dst = out + i * out_stride + d0;
      for (int c = 0; c < nd; ++c) dst[c] = static_cast<float>(sum[c]);
    }
  }
}

StatusOr<LimitSurface> BuildLimitSurface(const Image& image, const LimitSurfaceOptions& options) {
  SDVI_ASSIGN_OR_RETURN(RefinementPlan plan, MakePlan(image, options));
  const uint32_t num_base = plan.base.num_vertices();
  TaggedMesh mesh = std::move(plan.base);
  plan.base = TaggedMesh();
  SparseRows stencils;  // level-k vertices over base vertices
  bool identity = true;
  // Levels 1 .. r-1 (and r when the last step is the limit) are full intermediate rows.
  const int full_steps = options.to_limit ? options.levels : options.levels - 1;
  for (int k = 0; k < full_steps; ++k) {
    SparseRows next;
    Compose(RefinementMasks(mesh), identity ? nullptr : &stencils, nullptr, num_base, {}, next.offsets,
            next.indices, next.weights);
    stencils = std::move(next);
    identity = false;
    mesh = mesh.Refine();
  }
  // The last step computes only the output rows, in float, over control vertices.
  SparseRows last_masks;
  TaggedMesh fine;
  if (options.to_limit) {
    last_masks = LimitMasks(mesh);
    fine = std::move(mesh);
  } else if (options.levels > 0) {
    last_masks = RefinementMasks(mesh);
    fine = mesh.Refine();
  } else {
    last_masks.offsets.resize(size_t{num_base} + 1);
    for (uint32_t v = 0; v < num_base; ++v) {
      last_masks.indices.push_back(v);
      last_masks.weights.push_back(1.0);
      last_masks.offsets[v + 1] = v + 1;
    }
    fine = std::move(mesh);
  }
  FineSelection selection = SelectOutput(plan, fine, options.levels);
  LimitSurface surface;
  surface.levels = options.levels;
  surface.stencils.num_control = static_cast<uint32_t>(image.vertices.size());
  Compose(last_masks, identity ? nullptr : &stencils, &selection.vertices, num_base, plan.vertex_map,
          surface.stencils.offsets, surface.stencils.indices, surface.stencils.weights);
  surface.triangles = std::move(selection.triangles);
  surface.parent_triangle = std::move(selection.parent_triangle);
  surface.vertex_tags = std::move(selection.vertex_tags);
  surface.crease_edges = std::move(selection.crease_edges);
  return surface;
}

std::vector<Vertex> EvaluateSurface(const LimitSurface& surface, const std::vector<Vertex>& control) {
  if (control.size() < surface.stencils.num_control) return {};
  std::vector<Vertex> fine(surface.stencils.rows());
  static_assert(sizeof(Vertex) == 5 * sizeof(float));
  surface.stencils.Apply(reinterpret_cast<const float*>(control.data()), 5,
                         reinterpret_cast<float*>(fine.data()), 5, 5);
  return fine;
}

StatusOr<RefinedMesh> RefineImage(const Image& image, const LimitSurfaceOptions& options) {
  SDVI_ASSIGN_OR_RETURN(RefinementPlan plan, MakePlan(image, options));
  TaggedMesh mesh = std::move(plan.base);
  plan.base = TaggedMesh();
  // Values of the current level, 5 doubles a vertex.
  std::vector<double> values(5 * size_t{mesh.num_vertices()});
  for (uint32_t i = 0; i < mesh.num_vertices(); ++i) {
    const Vertex& v = image.vertices[plan.vertex_map.empty() ? i : plan.vertex_map[i]];
    const double src[5] = {v.x, v.y, v.r, v.g, v.b};
    std::copy(src, src + 5, values.begin() + 5 * i);
  }
  auto apply = [&values](const SparseRows& masks) {
    std::vector<double> next(5 * masks.rows(), 0.0);
    for (size_t i = 0; i < masks.rows(); ++i)
      for (uint32_t k = masks.offsets[i]; k < masks.offsets[i + 1]; ++k)
        for (int c = 0; c < 5; ++c) next[5 * i + c] += masks.weights[k] * values[5 * masks.indices[k] + c];
    values = std::move(next);
  };
  for (int k = 0; k < options.levels; ++k) {
    apply(RefinementMasks(mesh));
    mesh = mesh.Refine();
  }
  if (options.to_limit) apply(LimitMasks(mesh));
  FineSelection selection = SelectOutput(plan, mesh, options.levels);
  RefinedMesh out;
  out.levels = options.levels;
  out.vertices.resize(selection.vertices.size());
  for (size_t i = 0; i < selection.vertices.size(); ++i) {
    const double* v = &values[5 * size_t{selection.vertices[i]}];
    out.vertices[i] = Vertex{static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                             static_cast<float>(v[3]), static_cast<float>(v[4])};
  }
  out.triangles = std::move(selection.triangles);
  out.parent_triangle = std::move(selection.parent_triangle);
  out.vertex_tags = std::move(selection.vertex_tags);
  out.crease_edges = std::move(selection.crease_edges);
  return out;
}

}  // namespace sdvi
