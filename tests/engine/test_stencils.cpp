// SPDX-License-Identifier: GPL-3.0-or-later
// Stencil tables: evaluation equals direct refinement, weights sum to 1, regions equal
// the whole, numbering follows tagged_mesh.h.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <thread>

#include "sdvi/subdiv.h"
#include "sdvi/tagged_mesh.h"
#include "test_meshes.h"

using namespace sdvi;

namespace {

Image FeatureGrid(uint32_t seed) {
  const int nx = 9, ny = 7;
  Image image = test::GridImage(nx, ny, 3, seed);
  auto g = [](int i, int j) { return test::GridIndex(9, i, j); };
  // An open polyline with implicit corners, a junction, a tagged corner and a closed loop.
  for (int i = 1; i < 8; ++i) image.crease_edges.push_back(Edge::Of(g(i, 2), g(i + 1, 2)));
  image.crease_edges.push_back(Edge::Of(g(5, 2), g(5, 1)));
  image.crease_edges.push_back(Edge::Of(g(2, 4), g(3, 4)));
  image.crease_edges.push_back(Edge::Of(g(3, 4), g(3, 5)));
  image.crease_edges.push_back(Edge::Of(g(3, 5), g(2, 5)));
  image.crease_edges.push_back(Edge::Of(g(2, 5), g(2, 4)));
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.corners = {g(3, 2), g(0, 0), g(9, 7)};
  return image;
}

float MaxDiff(const Vertex& a, const Vertex& b) {
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.r - b.r), std::abs(a.g - b.g),
                   std::abs(a.b - b.b)});
}

}  // namespace

TEST_CASE("Stencil evaluation equals direct refinement", "[stencils]") {
  const Image image = FeatureGrid(4);
  for (int levels = 0; levels <= 4; ++levels)
    for (bool to_limit : {false, true}) {
      LimitSurfaceOptions options;
      options.levels = levels;
      options.to_limit = to_limit;
      auto surface = BuildLimitSurface(image, options);
      auto direct = RefineImage(image, options);
      REQUIRE(surface.ok());
      REQUIRE(direct.ok());
      const auto fine = EvaluateSurface(*surface, image.vertices);
      REQUIRE(fine.size() == direct->vertices.size());
      CHECK(surface->triangles == direct->triangles);
      CHECK(surface->parent_triangle == direct->parent_triangle);
      CHECK(surface->vertex_tags == direct->vertex_tags);
      CHECK(surface->crease_edges == direct->crease_edges);
      CHECK(surface->triangles.size() == image.triangles.size() << (2 * levels));
      // Each crease edge splits in two per level; corners stay the control corners.
      auto control = TaggedMesh::FromImage(image);
      REQUIRE(control.ok());
      CHECK(surface->crease_edges.size() == control->CreaseEdges().size() << levels);
      const auto corners = std::count(surface->vertex_tags.begin(), surface->vertex_tags.end(), VertexTag::kCorner);
      CHECK(corners == std::count(control->vertex_tags().begin(), control->vertex_tags().end(), VertexTag::kCorner));
      for (uint32_t v = 0; v < image.vertices.size(); ++v) CHECK(surface->vertex_tags[v] == control->tag(v));
      float worst = 0;
      for (size_t i = 0; i < fine.size(); ++i) worst = std::max(worst, MaxDiff(fine[i], direct->vertices[i]));
      INFO("levels " << levels << " to_limit " << to_limit);
      CHECK(worst < 2e-4f);
      // Both against a reference built here from the full level-r topology and masks.
      auto mesh = TaggedMesh::FromImage(image);
      REQUIRE(mesh.ok());
      TaggedMesh m = *mesh;
      std::vector<double> values = test::Values(image);
      for (int k = 0; k < levels; ++k) {
        values = test::ApplyRows(RefinementMasks(m), values);
        m = m.Refine();
      }
      if (to_limit) values = test::ApplyRows(LimitMasks(m), values);
      REQUIRE(values.size() == 5 * fine.size());
      CHECK(m.triangles() == surface->triangles);
      double worst_reference = 0;
      for (size_t i = 0; i < fine.size(); ++i) {
        const float* f = &fine[i].x;
        const float* d = &direct->vertices[i].x;
        for (int c = 0; c < 5; ++c)
          worst_reference = std::max({worst_reference, std::abs(f[c] - values[5 * i + c]),
                                      std::abs(d[c] - values[5 * i + c])});
      }
      CHECK(worst_reference < 2e-4);
      // Level 0 without limit is the control mesh; control vertices come first.
      if (levels == 0 && !to_limit)
        for (size_t i = 0; i < image.vertices.size(); ++i) CHECK(fine[i] == image.vertices[i]);
    }
}

TEST_CASE("Every stencil's weights sum to 1 and refer to control vertices", "[stencils]") {
  const Image image = FeatureGrid(5);
  for (int levels : {1, 3}) {
    LimitSurfaceOptions options;
    options.levels = levels;
    auto surface = BuildLimitSurface(image, options);
    REQUIRE(surface.ok());
    const StencilTable& s = surface->stencils;
    CHECK(s.num_control == image.vertices.size());
    REQUIRE(s.offsets.size() == s.rows() + 1);
    double worst = 0;
    for (size_t i = 0; i < s.rows(); ++i) {
      double sum = 0;
      for (uint32_t k = s.offsets[i]; k < s.offsets[i + 1]; ++k) {
        REQUIRE(s.indices[k] < s.num_control);
        if (k > s.offsets[i]) REQUIRE(s.indices[k - 1] < s.indices[k]);  // sorted, unique
        sum += s.weights[k];
      }
      worst = std::max(worst, std::abs(sum - 1));
    }
    CHECK(worst < 1e-6);
  }
}

TEST_CASE("Apply handles strides and any number of dimensions", "[stencils]") {
  StencilTable t;
  t.num_control = 3;
  t.offsets = {0, 2, 3};
  t.indices = {0, 2, 1};
  t.weights = {0.25f, 0.75f, 1.0f};
  std::vector<float> in(3 * 11);
  for (size_t i = 0; i < in.size(); ++i) in[i] = float(i);
  std::vector<float> out(2 * 12, -1);
  t.Apply(in.data(), 11, out.data(), 12, 10);
  for (int c = 0; c < 10; ++c) {
    CHECK(out[c] == Approx(0.25 * c + 0.75 * (22 + c)));
    CHECK(out[12 + c] == Approx(11 + c));
  }
  CHECK(out[10] == -1);  // untouched beyond dims
  // Fewer control vertices than the table needs: EvaluateSurface returns nothing.
  LimitSurface surface;
  surface.stencils = t;
  CHECK(EvaluateSurface(surface, std::vector<Vertex>(2)).empty());
}

TEST_CASE("A region's fine mesh equals the same part of the whole", "[stencils]") {
  const Image image = FeatureGrid(6);
  for (bool to_limit : {true, false}) {
    LimitSurfaceOptions options;
    options.levels = 3;
    options.to_limit = to_limit;
    auto whole = BuildLimitSurface(image, options);
    REQUIRE(whole.ok());
    options.control_triangles = {40, 41, 12, 60, 61, 62, 0};  // unsorted, scattered, on the boundary too
    auto region = BuildLimitSurface(image, options);
    REQUIRE(region.ok());
    CHECK(region->stencils.num_control == image.vertices.size());
    const auto fw = EvaluateSurface(*whole, image.vertices);
    const auto fr = EvaluateSurface(*region, image.vertices);
    REQUIRE(region->triangles.size() == 7u * 64u);
    size_t r = 0;
    float worst = 0;
    for (size_t f = 0; f < whole->triangles.size(); ++f) {
      const uint32_t p = whole->parent_triangle[f];
      if (p != 0 && p != 12 && p != 40 && p != 41 && p != 60 && p != 61 && p != 62) continue;
      REQUIRE(region->parent_triangle[r] == p);
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, MaxDiff(fw[whole->triangles[f].v[k]], fr[region->triangles[r].v[k]]));
        CHECK(whole->vertex_tags[whole->triangles[f].v[k]] == region->vertex_tags[region->triangles[r].v[k]]);
      }
      ++r;
    }
    CHECK(r == region->triangles.size());
    CHECK(worst == 0.0f);
    // Region crease edges are those of the whole mesh inside the region.
    size_t region_creases = region->crease_edges.size();
    CHECK(region_creases > 0);
    // Direct refinement of the region agrees too.
    auto direct = RefineImage(image, options);
    REQUIRE(direct.ok());
    CHECK(direct->triangles == region->triangles);
    CHECK(direct->crease_edges == region->crease_edges);
  }
}

TEST_CASE("The stencil table does not depend on the number of threads", "[stencils]") {
  Image image = test::GridImage(30, 30, 3, 8);
  for (int i = 2; i < 28; ++i) image.crease_edges.push_back(Edge::Of(test::GridIndex(30, i, 15), test::GridIndex(30, i + 1, 15)));
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  LimitSurfaceOptions options;
  // The rows go in chunks of 4096 rows or more, taken in turn by the threads and appended
  // in order: level 3 makes a few dozen chunks, level 4 a few hundred.
  for (int levels : {3, 4}) {
    options.levels = levels;
    options.threads = 1;
    auto one = BuildLimitSurface(image, options);
    REQUIRE(one.ok());
    REQUIRE(one->stencils.rows() > 3 * 16384);
    for (int threads : {2, 3, 5}) {
      INFO("levels " << levels << ", threads " << threads);
      options.threads = threads;
      auto several = BuildLimitSurface(image, options);
      REQUIRE(several.ok());
      CHECK(one->stencils.offsets == several->stencils.offsets);
      CHECK(one->stencils.indices == several->stencils.indices);
      CHECK(one->stencils.weights == several->stencils.weights);
      CHECK(one->triangles == several->triangles);
      CHECK(one->parent_triangle == several->parent_triangle);
    }
  }
  options.levels = 3;
  auto direct_one = RefineImage(image, options);
  options.threads = 1;
  auto direct_three = RefineImage(image, options);
  REQUIRE(direct_one.ok());
  CHECK(direct_one->vertices == direct_three->vertices);
}

namespace {

// Rows of a table with double weights (test-side composition, below).
struct Rows {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;
  std::vector<double> weights;
};

// Row (indices, weights) through previous (null: the identity), summed as the stencil build
// sums: each term in order, through each of the previous row's terms in order, in double;
// then sorted by column with exact zeros dropped.
void ComposeRow(const std::vector<uint32_t>& indices, const std::vector<double>& weights, const Rows* previous,
                Rows& out) {
  std::map<uint32_t, double> sum;
  for (size_t k = 0; k < indices.size(); ++k) {
    if (!previous) {
      sum[indices[k]] += weights[k];
      continue;
    }
    for (uint32_t j = previous->offsets[indices[k]]; j < previous->offsets[indices[k] + 1]; ++j)
      sum[previous->indices[j]] += weights[k] * previous->weights[j];
  }
  for (const auto& [c, w] : sum) {
    if (w == 0) continue;
    out.indices.push_back(c);
    out.weights.push_back(w);
  }
  out.offsets.push_back(static_cast<uint32_t>(out.indices.size()));
}

}  // namespace

// BuildLimitSurface computes mask rows as it composes them (AppendRefinementRow,
// AppendLimitRow, AppendEdgeChildLimitMask) instead of building RefinementMasks and
// LimitMasks: the rows must be those masks' rows, and the table the one composed from them.
TEST_CASE("Mask rows computed on the fly equal the built masks, and the table their composition", "[stencils]") {
  const Image image = FeatureGrid(5);
  auto control = TaggedMesh::FromImage(image);
  REQUIRE(control.ok());
  TaggedMesh mesh = *control;
  Rows previous;  // level-k vertices over control vertices
  for (int level = 1; level <= 3; ++level) {
    INFO("level " << level);
    const SparseRows masks = RefinementMasks(mesh);
    const SparseRows limit = LimitMasks(mesh);
    std::vector<uint32_t> indices;
    std::vector<double> weights;
    // Row r of `built` equals what `append(mesh, r, indices, weights)` computes.
    auto require_rows = [&](const SparseRows& built, auto append) {
      for (size_t r = 0; r < built.rows(); ++r) {
        indices.clear();
        weights.clear();
        append(mesh, r, indices, weights);
        REQUIRE(indices == std::vector<uint32_t>(built.indices.begin() + built.offsets[r],
                                                 built.indices.begin() + built.offsets[r + 1]));
        REQUIRE(weights == std::vector<double>(built.weights.begin() + built.offsets[r],
                                               built.weights.begin() + built.offsets[r + 1]));
      }
    };
    REQUIRE(limit.rows() == mesh.num_vertices());
    require_rows(masks, [](const TaggedMesh& m, size_t r, auto& i, auto& w) { AppendRefinementRow(m, r, i, w); });
    require_rows(limit, [](const TaggedMesh& m, size_t r, auto& i, auto& w) { AppendLimitRow(m, uint32_t(r), i, w); });
    // The merged edge-child mask: AppendEdgeChildLimitMask's entries summed, in order, into a
    // dense accumulator cleared to 0 (each column where it first appears), bit for bit.
    for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
      indices.clear();
      weights.clear();
      AppendEdgeChildLimitMask(mesh, e, indices, weights);
      std::vector<uint32_t> columns;
      std::vector<double> sums;
      std::vector<double> dense(mesh.num_vertices(), 0.0);
      std::vector<uint8_t> seen(mesh.num_vertices(), 0);
      for (size_t k = 0; k < indices.size(); ++k) {
        if (!seen[indices[k]]) {
          seen[indices[k]] = 1;
          columns.push_back(indices[k]);
        }
        dense[indices[k]] += weights[k];
      }
      for (uint32_t c : columns) sums.push_back(dense[c]);
      std::vector<uint32_t> merged_indices{7};  // appended after what the vectors hold
      std::vector<double> merged_weights{0.5};
      AppendMergedEdgeChildLimitMask(mesh, e, merged_indices, merged_weights);
      REQUIRE(merged_indices.size() == columns.size() + 1);
      CHECK(merged_indices[0] == 7);
      CHECK(std::equal(columns.begin(), columns.end(), merged_indices.begin() + 1));
      REQUIRE(merged_weights.size() == sums.size() + 1);
      CHECK(std::memcmp(merged_weights.data() + 1, sums.data(), sums.size() * sizeof(double)) == 0);
    }
    // The level's table from the built masks: vertex children take their parent's limit
    // row, edge children the limit over their one-ring of refinement rows, repeated
    // columns merged first (in order of first appearance, summed in order).
    Rows table;
    const Rows* before = level == 1 ? nullptr : &previous;
    for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
      indices.assign(limit.indices.begin() + limit.offsets[v], limit.indices.begin() + limit.offsets[v + 1]);
      weights.assign(limit.weights.begin() + limit.offsets[v], limit.weights.begin() + limit.offsets[v + 1]);
      ComposeRow(indices, weights, before, table);
    }
    for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
      uint32_t ring[7];
      double lambda[7];
      const int n = EdgeChildLimitRing(mesh, e, ring, lambda);
      std::vector<uint32_t> merged;
      std::vector<double> merged_weights;
      for (int k = 0; k < n; ++k) {
        if (lambda[k] == 0) continue;
        for (uint32_t j = masks.offsets[ring[k]]; j < masks.offsets[ring[k] + 1]; ++j) {
          const double w = lambda[k] * masks.weights[j];
          const auto at = std::find(merged.begin(), merged.end(), masks.indices[j]);
          if (at == merged.end()) {
            merged.push_back(masks.indices[j]);
            merged_weights.push_back(w);
          } else {
            merged_weights[size_t(at - merged.begin())] += w;
          }
        }
      }
      ComposeRow(merged, merged_weights, before, table);
    }
    LimitSurfaceOptions options;
    options.levels = level;
    options.threads = 2;
    auto surface = BuildLimitSurface(image, options);
    REQUIRE(surface.ok());
    const StencilTable& built = surface->stencils;
    CHECK(built.offsets == table.offsets);
    CHECK(built.indices == table.indices);
    REQUIRE(built.weights.size() == table.weights.size());
    size_t differing = 0;
    for (size_t k = 0; k < table.weights.size(); ++k) differing += built.weights[k] != static_cast<float>(table.weights[k]);
    CHECK(differing == 0);
    // The next level's rows over the control vertices, for the next level's table.
    Rows next;
    for (size_t r = 0; r < masks.rows(); ++r) {
      indices.assign(masks.indices.begin() + masks.offsets[r], masks.indices.begin() + masks.offsets[r + 1]);
      weights.assign(masks.weights.begin() + masks.offsets[r], masks.weights.begin() + masks.offsets[r + 1]);
      ComposeRow(indices, weights, before, next);
    }
    previous = std::move(next);
    mesh = mesh.Refine();
  }
}

namespace {

// A random table: rows of 0 .. max_row weights over distinct control vertices (sorted),
// weights of mixed signs and magnitudes, some zero.
StencilTable RandomTable(std::mt19937& rng, uint32_t num_control, size_t rows, int max_row) {
  StencilTable t;
  t.num_control = num_control;
  t.offsets.push_back(0);
  std::uniform_int_distribution<int> length(0, max_row);
  std::uniform_int_distribution<uint32_t> vertex(0, num_control - 1);
  std::uniform_real_distribution<float> weight(-0.5f, 1.0f);
  for (size_t i = 0; i < rows; ++i) {
    std::vector<uint32_t> row;
    for (int k = length(rng); k > 0; --k) row.push_back(vertex(rng));
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (uint32_t v : row) {
      t.indices.push_back(v);
      t.weights.push_back(rng() % 16 == 0 ? 0.0f : weight(rng) * std::ldexp(1.0f, int(rng() % 9) - 4));
    }
    t.offsets.push_back(uint32_t(t.indices.size()));
  }
  return t;
}

}  // namespace

TEST_CASE("Apply's kernels give the same floats", "[stencils]") {
  // Every kernel the processor runs, forced, against the portable one (spec/SUBDIVISION.md
  // section 4): bit for bit, for 1 .. 13 dimensions, any strides, -0.0 and wide exponents.
  std::mt19937 rng(15);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  using Kernel = StencilTable::Kernel;
  for (Kernel kernel : {Kernel::kAuto, Kernel::kAvx2, Kernel::kAvx512}) {
    INFO("kernel " << int(kernel) << " supported " << StencilTable::KernelSupported(kernel));
    for (int dims = 1; dims <= 13; ++dims) {
      const uint32_t num_control = 1 + rng() % 300;
      const StencilTable t = RandomTable(rng, num_control, 1 + rng() % 700, 1 + int(rng() % 20));
      const size_t in_stride = size_t(dims) + rng() % 3, out_stride = size_t(dims) + rng() % 3;
      std::vector<float> in(num_control * in_stride);
      for (float& x : in) x = rng() % 50 == 0 ? -0.0f : value(rng) * std::ldexp(1.0f, int(rng() % 40) - 20);
      std::vector<float> expected(t.rows() * out_stride, 7.0f), got(expected);
      t.Apply(in.data(), in_stride, expected.data(), out_stride, dims, Kernel::kPortable);
      t.Apply(in.data(), in_stride, got.data(), out_stride, dims, kernel);
      INFO("dims " << dims << " rows " << t.rows() << " strides " << in_stride << " " << out_stride);
      CHECK(std::memcmp(expected.data(), got.data(), expected.size() * sizeof(float)) == 0);
    }
  }
}

TEST_CASE("Apply's threads and kernels give the floats of one thread", "[stencils]") {
  // Over 2^21 weights: Apply goes over threads (when the hardware has them) in chunks of rows.
  std::mt19937 rng(16);
  const uint32_t num_control = 50000;
  const StencilTable t = RandomTable(rng, num_control, 260000, 18);
  REQUIRE(t.indices.size() > (size_t{1} << 21));
  std::vector<float> in(5 * num_control);
  std::uniform_real_distribution<float> value(-100.0f, 100.0f);
  for (float& x : in) x = value(rng);
  std::vector<float> expected(5 * t.rows()), got(5 * t.rows(), -1.0f);
  for (size_t i = 0; i < t.rows(); ++i) {  // the reference sum, row by row
    double sum[5] = {};
    for (uint32_t k = t.offsets[i]; k < t.offsets[i + 1]; ++k)
      for (int c = 0; c < 5; ++c) sum[c] += double(t.weights[k]) * double(in[5 * t.indices[k] + c]);
    for (int c = 0; c < 5; ++c) expected[5 * i + c] = float(sum[c]);
  }
  using Kernel = StencilTable::Kernel;
  for (Kernel kernel : {Kernel::kAuto, Kernel::kPortable, Kernel::kAvx2, Kernel::kAvx512}) {
    std::fill(got.begin(), got.end(), -1.0f);
    t.Apply(in.data(), 5, got.data(), 5, 5, kernel);
    INFO("kernel " << int(kernel));
    CHECK(std::memcmp(expected.data(), got.data(), expected.size() * sizeof(float)) == 0);
  }
}

TEST_CASE("Apply's kept scratch gives the same floats across calls, sizes and threads", "[stencils]") {
  // The converted input is kept by each thread between calls (up to 16 MiB, larger ones
  // are allocated for the call): growing and shrinking tables, one over the kept size, and
  // two threads at once must each give the portable kernel's floats.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> value(-10.0f, 10.0f);
  std::vector<StencilTable> tables;
  for (uint32_t num_control : {40u, 3000u, 300000u, 7u, 20000u, 500u})
    tables.push_back(RandomTable(rng, num_control, 1 + rng() % 2000, 1 + int(rng() % 12)));
  std::vector<std::vector<float>> inputs, expected;
  for (const StencilTable& t : tables) {
    inputs.emplace_back(7 * size_t{t.num_control});
    for (float& x : inputs.back()) x = value(rng);
    expected.emplace_back(6 * t.rows(), 3.0f);
    t.Apply(inputs.back().data(), 7, expected.back().data(), 6, 5, StencilTable::Kernel::kPortable);
  }
  using Kernel = StencilTable::Kernel;
  auto run_all = [&](Kernel kernel, std::vector<int>& differing) {
    for (int pass = 0; pass < 2; ++pass)
      for (size_t i = 0; i < tables.size(); ++i) {
        std::vector<float> got(6 * tables[i].rows(), 3.0f);
        tables[i].Apply(inputs[i].data(), 7, got.data(), 6, 5, kernel);
        if (std::memcmp(got.data(), expected[i].data(), got.size() * sizeof(float)) != 0) differing[i] += 1;
      }
  };
  for (Kernel kernel : {Kernel::kAuto, Kernel::kAvx2, Kernel::kAvx512}) {
    INFO("kernel " << int(kernel));
    std::vector<int> here(tables.size()), there(tables.size());
    std::thread other([&] { run_all(kernel, there); });
    run_all(kernel, here);
    other.join();
    for (size_t i = 0; i < tables.size(); ++i) {
      INFO("table " << i << " control " << tables[i].num_control);
      CHECK(here[i] == 0);
      CHECK(there[i] == 0);
    }
  }
}
