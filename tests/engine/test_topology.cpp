// SPDX-License-Identifier: GPL-3.0-or-later
// Tagged topology: tags, refinement numbering, validation errors (tagged_mesh.h).
#include <catch2/catch.hpp>

#include <algorithm>

#include "sdvi/subdiv.h"
#include "sdvi/tagged_mesh.h"
#include "test_meshes.h"

using namespace sdvi;

namespace {
StatusCode CodeOf(const Image& image) {
  auto mesh = TaggedMesh::FromImage(image);
  return mesh.ok() ? StatusCode::kOk : mesh.status().code();
}
}  // namespace

TEST_CASE("Boundary is crease, and endpoints, junctions and tagged vertices are corners", "[topology]") {
  Image image = test::GridImage(4, 4, 0, 1);
  auto g = [](int i, int j) { return test::GridIndex(4, i, j); };
  // A polyline from interior (1,2) to (3,2), and a junction at (2,2) with a branch to (2,1).
  image.crease_edges = {Edge::Of(g(1, 2), g(2, 2)), Edge::Of(g(2, 2), g(3, 2)), Edge::Of(g(2, 2), g(2, 1))};
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.corners = {g(1, 3)};
  auto mesh = TaggedMesh::FromImage(image);
  REQUIRE(mesh.ok());
  CHECK(mesh->tag(g(1, 2)) == VertexTag::kCorner);   // endpoint
  CHECK(mesh->tag(g(2, 2)) == VertexTag::kCorner);   // junction (degree 3)
  CHECK(mesh->tag(g(1, 3)) == VertexTag::kCorner);   // tagged
  CHECK(mesh->tag(g(1, 1)) == VertexTag::kSmooth);
  CHECK(mesh->tag(g(2, 0)) == VertexTag::kCrease);   // boundary
  CHECK(mesh->tag(g(0, 0)) == VertexTag::kCrease);   // boundary corner of the grid, degree 2
  size_t boundary = 0;
  for (size_t e = 0; e < mesh->num_edges(); ++e)
    if (mesh->edge_triangles(e)[1] == kNoIndex) {
      ++boundary;
      CHECK(mesh->is_crease(e));
    }
  CHECK(boundary == 16);
  CHECK(mesh->CreaseEdges().size() == 16 + 3);
}

TEST_CASE("Refinement numbering and inherited tags", "[topology]") {
  test::Strip strip = test::StripImage(3, 5);
  auto mesh = TaggedMesh::FromImage(strip.image);
  REQUIRE(mesh.ok());
  TaggedMesh fine = mesh->Refine();
  CHECK(fine.num_vertices() == mesh->num_vertices() + mesh->num_edges());
  CHECK(fine.num_triangles() == 4 * mesh->num_triangles());
  CHECK(fine.num_edges() == 2 * mesh->num_edges() + 3 * mesh->num_triangles());
  for (uint32_t v = 0; v < mesh->num_vertices(); ++v) CHECK(fine.tag(v) == mesh->tag(v));
  for (size_t e = 0; e < mesh->num_edges(); ++e) {
    const uint32_t m = mesh->num_vertices() + static_cast<uint32_t>(e);
    CHECK(fine.tag(m) == (mesh->is_crease(e) ? VertexTag::kCrease : VertexTag::kSmooth));
    CHECK(fine.is_crease(2 * e) == mesh->is_crease(e));
    CHECK(fine.is_crease(2 * e + 1) == mesh->is_crease(e));
  }
  // Child triangles 4t..4t+3 keep the orientation (signed area sign) of triangle t.
  const auto values = test::Values(strip.image);
  const auto fine_values = test::ApplyRows(RefinementMasks(*mesh), values);
  auto area = [](const std::vector<double>& p, const Triangle& t) {
    const double* a = &p[5 * t.v[0]];
    const double* b = &p[5 * t.v[1]];
    const double* c = &p[5 * t.v[2]];
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  for (size_t t = 0; t < mesh->num_triangles(); ++t)
    for (int k = 0; k < 4; ++k)
      CHECK((area(values, mesh->triangles()[t]) > 0) == (area(fine_values, fine.triangles()[4 * t + k]) > 0));
  // Edge tables agree with triangles after refinement, twice.
  const TaggedMesh finer = fine.Refine();
  for (const TaggedMesh* m : std::array<const TaggedMesh*, 2>{&fine, &finer}) {
    std::vector<std::vector<uint32_t>> tris_of_edge(m->num_edges());
    for (uint32_t f = 0; f < m->num_triangles(); ++f)
      for (int k = 0; k < 3; ++k) {
        const uint32_t e = m->triangle_edges(f)[k];
        CHECK(m->edges()[e] == Edge::Of(m->triangles()[f].v[k], m->triangles()[f].v[(k + 1) % 3]));
        tris_of_edge[e].push_back(f);
      }
    // Neighbour tables: each edge appears once at each end, with the other end.
    size_t links = 0;
    for (uint32_t v = 0; v < m->num_vertices(); ++v) {
      links += m->neighbours(v).size();
      for (size_t i = 0; i < m->neighbours(v).size(); ++i)
        CHECK(m->edges()[m->neighbour_edges(v)[i]] == Edge::Of(v, m->neighbours(v)[i]));
    }
    CHECK(links == 2 * m->num_edges());
    for (size_t e = 0; e < m->num_edges(); ++e) {
      tris_of_edge[e].resize(2, kNoIndex);
      CHECK(m->edge_triangles(e)[0] == tris_of_edge[e][0]);
      CHECK(m->edge_triangles(e)[1] == tris_of_edge[e][1]);
      if (m->edge_triangles(e)[1] == kNoIndex) CHECK(m->is_crease(e));
    }
  }
}

TEST_CASE("Bad meshes give specific errors", "[topology]") {
  const Image good = test::GridImage(2, 2, 0, 3);
  REQUIRE(CodeOf(good) == StatusCode::kOk);
  {
    Image bad = good;
    bad.vertices.clear();
    CHECK(CodeOf(bad) == StatusCode::kEmptyInput);
  }
  {
    Image bad = good;
    bad.triangles.clear();
    CHECK(CodeOf(bad) == StatusCode::kEmptyInput);
  }
  {
    Image bad = good;
    bad.triangles[1].v[2] = 9;  // 9 vertices: 0..8
    CHECK(CodeOf(bad) == StatusCode::kIndexOutOfRange);
  }
  {
    Image bad = good;
    bad.triangles[2].v[1] = bad.triangles[2].v[0];
    CHECK(CodeOf(bad) == StatusCode::kDegenerateTriangle);
  }
  {
    Image bad = good;
    const Triangle t = bad.triangles[3];
    bad.triangles.push_back(Triangle{{t.v[1], t.v[0], t.v[2]}});  // same triangle, flipped
    CHECK(CodeOf(bad) == StatusCode::kDuplicateTriangle);
  }
  {
    Image bad = good;
    // A third and fourth triangle on the interior edge (0,4) of the first quad diagonal.
    bad.vertices.push_back(test::MakeVertex(5, 5, 1, 9));
    bad.triangles.push_back(Triangle{{0, 4, 9}});
    CHECK(CodeOf(bad) == StatusCode::kNonManifoldEdge);
  }
  {
    Image bad = good;
    bad.crease_edges = {Edge{0, 8}};  // opposite grid corners
    CHECK(CodeOf(bad) == StatusCode::kCreaseNotAnEdge);
    bad.crease_edges = {Edge{3, 3}};
    CHECK(CodeOf(bad) == StatusCode::kCreaseNotAnEdge);
    bad.crease_edges = {Edge{3, 30}};
    CHECK(CodeOf(bad) == StatusCode::kIndexOutOfRange);
  }
  {
    Image bad = good;
    bad.corners = {100};
    CHECK(CodeOf(bad) == StatusCode::kIndexOutOfRange);
  }
  {
    Image bad = good;
    bad.vertices[4].g = std::nanf("");
    auto surface = BuildLimitSurface(bad, {});
    REQUIRE_FALSE(surface.ok());
    CHECK(surface.status().code() == StatusCode::kNonFinite);
  }
  {
    LimitSurfaceOptions options;
    options.levels = 7;
    CHECK(BuildLimitSurface(good, options).status().code() == StatusCode::kInvalidArgument);
    options.levels = -1;
    CHECK(RefineImage(good, options).status().code() == StatusCode::kInvalidArgument);
    options.levels = 6;
    options.max_fine_triangles = 1000;
    CHECK(BuildLimitSurface(good, options).status().code() == StatusCode::kLimitExceeded);
    options = {};
    options.control_triangles = {8};
    CHECK(BuildLimitSurface(good, options).status().code() == StatusCode::kIndexOutOfRange);
  }
  // Error messages name the element.
  Image bad = good;
  bad.triangles[2].v[1] = bad.triangles[2].v[0];
  CHECK(TaggedMesh::FromImage(bad).status().message().find("triangle 2") != std::string::npos);
}

TEST_CASE("Random small meshes: a specific error or a consistent surface, never a crash", "[topology]") {
  int built = 0, refused = 0;
  for (uint32_t seed = 0; seed < 300; ++seed) {
    Image image;
    const uint32_t nv = 3 + static_cast<uint32_t>((test::Noise(seed, 0) + 1) * 5);
    const int nt = 1 + static_cast<int>((test::Noise(seed, 1) + 1) * 8);
    for (uint32_t i = 0; i < nv; ++i) image.vertices.push_back(test::MakeVertex(50 * test::Noise(seed, 10 + i), 50 * test::Noise(seed, 40 + i), seed, i));
    auto pick = [&](uint32_t k) { return static_cast<uint32_t>((test::Noise(seed, k) + 1) * 0.5 * nv) % nv; };
    // Mostly distinct corners (every fifth mesh may repeat one), crease edges mostly taken
    // from the triangles (one in four arbitrary).
    for (int t = 0; t < nt; ++t) {
      const uint32_t a = pick(100 + 3 * t);
      uint32_t b = pick(101 + 3 * t), c = pick(102 + 3 * t);
      if (seed % 5 != 0) {
        b = (a + 1 + b % (nv - 1)) % nv;
        while (c == a || c == b) c = (c + 1) % nv;
      }
      image.triangles.push_back(Triangle{{a, b, c}});
    }
    for (int c = 0; c < 3; ++c) {
      const Triangle& t = image.triangles[pick(200 + 2 * c) % image.triangles.size()];
      const int k = static_cast<int>(pick(201 + 2 * c) % 3);
      image.crease_edges.push_back(seed % 4 == 0 ? Edge::Of(pick(210 + c), pick(220 + c))
                                                 : Edge::Of(t.v[k], t.v[(k + 1) % 3]));
    }
    image.corners = {pick(300)};
    LimitSurfaceOptions options;
    options.levels = static_cast<int>(seed % 4);
    options.to_limit = seed % 2 == 0;
    auto surface = BuildLimitSurface(image, options);
    auto direct = RefineImage(image, options);
    REQUIRE(surface.ok() == direct.ok());
    if (!surface.ok()) {
      ++refused;
      const StatusCode code = surface.status().code();
      CHECK((code == StatusCode::kDegenerateTriangle || code == StatusCode::kDuplicateTriangle ||
             code == StatusCode::kNonManifoldEdge || code == StatusCode::kCreaseNotAnEdge));
      CHECK(direct.status().code() == code);
      CHECK_FALSE(surface.status().message().empty());
      continue;
    }
    ++built;
    const auto fine = EvaluateSurface(*surface, image.vertices);
    REQUIRE(fine.size() == direct->vertices.size());
    for (size_t i = 0; i < fine.size(); ++i) {
      CHECK(std::abs(fine[i].x - direct->vertices[i].x) < 1e-3f);
      CHECK(std::abs(fine[i].g - direct->vertices[i].g) < 1e-3f);
    }
    const StencilTable& s = surface->stencils;
    for (size_t r = 0; r < s.rows(); ++r) {
      double sum = 0;
      for (uint32_t k = s.offsets[r]; k < s.offsets[r + 1]; ++k) sum += s.weights[k];
      CHECK(std::abs(sum - 1) < 1e-5);
    }
  }
  CHECK(built > 10);
  CHECK(refused > 10);
}

TEST_CASE("Refine builds the same tables for any thread count", "[topology]") {
  // 2 x 170 x 120 triangles: several blocks of 16384 for the threads; a crease polyline
  // across and a corner, so that the tags are not all alike.
  Image image = test::GridImage(171, 121, 0.2, 3);
  auto g = [](int i, int j) { return test::GridIndex(171, i, j); };
  for (int i = 10; i < 150; ++i) image.crease_edges.push_back(Edge::Of(g(i, 60), g(i + 1, 60)));
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.corners = {g(80, 30)};
  auto mesh = TaggedMesh::FromImage(image);
  REQUIRE(mesh.ok());
  REQUIRE(mesh->num_triangles() > 2 * 16384);
  auto same = [](const TaggedMesh& a, const TaggedMesh& b) {
    REQUIRE(a.num_vertices() == b.num_vertices());
    REQUIRE(a.num_edges() == b.num_edges());
    CHECK(a.triangles() == b.triangles());
    CHECK(a.edges() == b.edges());
    CHECK(a.vertex_tags() == b.vertex_tags());
    size_t differ = 0;
    for (size_t t = 0; t < a.num_triangles(); ++t) differ += a.triangle_edges(t) != b.triangle_edges(t);
    for (size_t e = 0; e < a.num_edges(); ++e)
      differ += a.edge_triangles(e) != b.edge_triangles(e) || a.is_crease(e) != b.is_crease(e);
    for (uint32_t v = 0; v < a.num_vertices(); ++v) {
      const auto na = a.neighbours(v), nb = b.neighbours(v), ea = a.neighbour_edges(v), eb = b.neighbour_edges(v);
      differ += !std::equal(na.begin(), na.end(), nb.begin(), nb.end()) ||
                !std::equal(ea.begin(), ea.end(), eb.begin(), eb.end());
    }
    CHECK(differ == 0);
  };
  const TaggedMesh one = mesh->Refine(1);
  for (int threads : {2, 3, 0}) {
    INFO(threads << " threads");
    const TaggedMesh many = mesh->Refine(threads);
    same(one, many);
    CHECK(one.RefinedTriangles(1) == many.RefinedTriangles(threads));
    same(one.Refine(1), many.Refine(threads));
  }
}
