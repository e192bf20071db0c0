// SPDX-License-Identifier: GPL-3.0-or-later
// Control mesh construction (paper section IV step 4): constrained Delaunay triangulation
// of the placed boundary, feature polylines and interior samples with CGAL, refined to a
// minimum angle without Steiner points on constrained edges (DEPENDENCIES.md trap 5).
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "pairs.h"
#include "sdvi/features.h"

namespace sdvi {
namespace {

constexpr uint32_t kNoIndex = std::numeric_limits<uint32_t>::max();

struct VertexInfo {
  uint32_t index = kNoIndex;  // our vertex index (kNoIndex: a Steiner point of the mesher)
};

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K, CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// CGAL's angle + size criteria, except that
//  - a triangle with an edge shorter than min_length is never bad: the mesher cannot split
//    constrained edges, so near small input angles (feature ends, kinks, pair strips) its
//    circumcentre insertions would otherwise cascade into ever smaller triangles;
//  - with content blocks, the size bound applies only to triangles whose bounding box meets
//    a busy block (ContentBlocks, features.h).
class MeshCriteria : public CGAL::Delaunay_mesh_size_criteria_2<CDT> {
  using Size = CGAL::Delaunay_mesh_size_criteria_2<CDT>;

 public:
  explicit MeshCriteria(double aspect_bound = 0.125, double size_bound = 0, double min_length = 0,
                        const ContentBlocks* content = nullptr)
      : CGAL::Delaunay_mesh_criteria_2<CDT>(aspect_bound), Size(aspect_bound, size_bound),
        min_length_(min_length), content_(content) {}

  class Is_bad : public Size::Is_bad {
   public:
    Is_bad(double aspect_bound, double size_bound, double min_length, const ContentBlocks* content,
           const K& traits)
        : Size::Is_bad(aspect_bound, size_bound, traits), min_squared_(min_length * min_length),
          content_(content), unbounded_(aspect_bound, 0, traits) {}
    using Size::Is_bad::operator();
    CGAL::Mesh_2::Face_badness operator()(const CDT::Face_handle& fh, typename Size::Quality& q) const {
      const K::Point_2 &a = fh->vertex(0)->point(), &b = fh->vertex(1)->point(), &c = fh->vertex(2)->point();
      double shortest = std::min({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c),
                                  CGAL::squared_distance(c, a)});
      if (shortest < min_squared_) {
        q = typename Size::Quality(1, 0);
        return CGAL::Mesh_2::NOT_BAD;
      }
      if (content_ != nullptr &&
          !content_->AnyBusy(std::min({a.x(), b.x(), c.x()}), std::min({a.y(), b.y(), c.y()}),
                             std::max({a.x(), b.x(), c.x()}), std::max({a.y(), b.y(), c.y()}))) {
        return unbounded_(fh, q);  // flat: the angle bound only
      }
      return Size::Is_bad::operator()(fh, q);
    }

   private:
    double min_squared_;
    const ContentBlocks* content_;
    typename Size::Is_bad unbounded_;  // the same criteria with no size bound
  };
  Is_bad is_bad_object() const {
    return Is_bad(this->bound(), this->size_bound(), min_length_, content_, this->traits);
  }

 private:
  double min_length_;
  const ContentBlocks* content_;
};
using Mesher = CGAL::Delaunay_mesher_no_edge_refinement_2<CDT, MeshCriteria>;

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

bool IsBoundaryEdge(const CDT& cdt, CDT::Face_handle f, int i, const std::unordered_set<uint64_t>& boundary) {
  if (!f->is_constrained(i)) return false;
  CDT::Vertex_handle a = f->vertex(CDT::cw(i)), b = f->vertex(CDT::ccw(i));
  if (cdt.is_infinite(a) || cdt.is_infinite(b)) return false;
  uint32_t ia = a->info().index, ib = b->info().index;
  return ia != kNoIndex && ib != kNoIndex && boundary.count(EdgeKey(ia, ib)) > 0;
}

// Marks the faces of the domain: nesting level = number of boundary edges crossed from
// the infinite face; odd levels are inside (outer contours are level 1, holes level 2).
void MarkDomain(CDT& cdt, const std::unordered_set<uint64_t>& boundary) {
  std::unordered_map<CDT::Face_handle, int, CGAL::Handle_hash_function> level;
  std::vector<CDT::Face_handle> frontier{cdt.infinite_face()}, next;
  for (int depth = 0; !frontier.empty(); ++depth) {
    next.clear();
    for (CDT::Face_handle seed : frontier) {
      if (level.count(seed)) continue;
      level[seed] = depth;
      std::vector<CDT::Face_handle> stack{seed};
      while (!stack.empty()) {
        CDT::Face_handle f = stack.back();
        stack.pop_back();
        for (int i = 0; i < 3; ++i) {
          CDT::Face_handle nb = f->neighbor(i);
          if (level.count(nb)) continue;
          if (IsBoundaryEdge(cdt, f, i, boundary)) {
            next.push_back(nb);
          } else {
            level[nb] = depth;
            stack.push_back(nb);
          }
        }
      }
    }
    std::swap(frontier, next);
  }
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
    auto it = level.find(f);
    f->set_in_domain(!cdt.is_infinite(f) && it != level.end() && it->second % 2 == 1);
  }
}

}  // namespace

bool ContentBlocks::AnyBusy(double x0, double y0, double x1, double y1) const {
  if (block <= 0 || columns <= 0 || rows <= 0) return true;
  auto column = [&](double x) { return std::clamp(int(std::floor(x / block)), 0, columns - 1); };
  auto row = [&](double y) { return std::clamp(int(std::floor(y / block)), 0, rows - 1); };
  const int c0 = column(x0), c1 = column(x1), r0 = row(y0), r1 = row(y1);
  const size_t stride = size_t(columns) + 1;
  auto sum = [&](int r, int c) { return busy_sum[size_t(r) * stride + size_t(c)]; };
  return sum(r1 + 1, c1 + 1) - sum(r0, c1 + 1) - sum(r1 + 1, c0) + sum(r0, c0) > 0;
}

double ContentBlocks::BusyShare() const {
  if (block <= 0 || busy_sum.empty() || domain_blocks == 0) return 1.0;
  return std::min(1.0, double(busy_sum.back()) / double(domain_blocks));
}

StatusOr<Image> BuildControlMesh(int width, int height, const std::vector<FeatureCurve>& curves,
                                 const std::vector<Point2>& interior_samples,
                                 const ControlMeshOptions& options) {
  SDVI_ASSIGN_OR_RETURN(PlacedFeatures placed, PlaceFeatures(width, height, curves, interior_samples, options));

  // Our vertices: polyline points, then samples. A junction is the same point in the
  // polylines that meet there (src/pairs.h): equal coordinates give one vertex.
  std::vector<Point2> points;
  std::vector<std::vector<uint32_t>> polyline_vertices;
  std::unordered_map<uint64_t, std::vector<uint32_t>> by_position;
  auto position_key = [](const Point2& p) {
    return std::hash<double>{}(p.x) * 1000003u ^ std::hash<double>{}(p.y);
  };
  for (const PlacedPolyline& l : placed.polylines) {
    std::vector<uint32_t> ids;
    for (const Point2& p : l.points) {
      std::vector<uint32_t>& same = by_position[position_key(p)];
      auto it = std::find_if(same.begin(), same.end(),
                             [&](uint32_t v) { return points[v].x == p.x && points[v].y == p.y; });
      if (it != same.end()) {
        ids.push_back(*it);
        continue;
      }
      same.push_back(uint32_t(points.size()));
      ids.push_back(uint32_t(points.size()));
      points.push_back(p);
    }
    polyline_vertices.push_back(std::move(ids));
  }
  for (const Point2& p : placed.samples) points.push_back(p);

  CDT cdt;
  std::vector<CDT::Vertex_handle> handles(points.size());
  try {
    // Insert in Hilbert order (deterministic) so that each point is located near the last.
    std::vector<K::Point_2> cgal_points;
    cgal_points.reserve(points.size());
    for (const Point2& p : points) cgal_points.emplace_back(p.x, p.y);
    std::vector<std::size_t> order(points.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    using SortTraits = CGAL::Spatial_sort_traits_adapter_2<K, CGAL::Pointer_property_map<K::Point_2>::type>;
    CGAL::hilbert_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(cgal_points)));
    CDT::Face_handle hint;
    for (const size_t i : order) {
      CDT::Vertex_handle v = cdt.insert(cgal_points[i], hint);
      if (v->info().index != kNoIndex)
        return Status(StatusCode::kInternal, "BuildControlMesh: vertex " + std::to_string(i) + " at (" +
                                                 std::to_string(points[i].x) + ", " + std::to_string(points[i].y) +
                                                 ") coincides with vertex " + std::to_string(v->info().index));
      v->info().index = uint32_t(i);
      handles[i] = v;
      hint = v->face();
    }
    std::unordered_set<uint64_t> boundary_edges;
    for (size_t k = 0; k < placed.polylines.size(); ++k) {
      const auto& ids = polyline_vertices[k];
      const size_t m = ids.size();
      const size_t segs = placed.polylines[k].closed ? m : m - 1;
      for (size_t i = 0; i < segs; ++i) {
        uint32_t a = ids[i], b = ids[(i + 1) % m];
        cdt.insert_constraint(handles[a], handles[b]);
        if (placed.polylines[k].boundary) boundary_edges.insert(EdgeKey(a, b));
      }
    }
    // The image rectangle is the convex hull: every finite face is in the domain.
    if (placed.object_mode) MarkDomain(cdt, boundary_edges);
    Mesher mesher(cdt);
    const double angle = options.min_angle_deg * 3.14159265358979323846 / 180.0;
    const double bound = std::sin(angle) * std::sin(angle);  // 20 deg -> ~0.117 (CGAL: B <= 0.125)
    const double min_length = 0.5 * std::min(options.clearance, options.min_distance);
    mesher.set_criteria(MeshCriteria(std::min(0.125, bound), placed.max_edge, min_length, options.content));
    // CGAL leaves the mesher's seeds_mark uninitialised until seeds are set or cleared;
    // init reads it (an invalid bool load under UBSan): clear the (empty) seeds first.
    mesher.clear_seeds();
    mesher.init(placed.object_mode);  // false: marks the convex hull
    mesher.refine_mesh();
    if (placed.object_mode) {
      MarkDomain(cdt, boundary_edges);
    } else {
      for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->set_in_domain(!cdt.is_infinite(f));
    }
  } catch (const std::exception& e) {
    return Status(StatusCode::kInternal, std::string("BuildControlMesh: CGAL failed: ") + e.what());
  }

  // Number Steiner points after our vertices, in the triangulation's (deterministic) order.
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    if (v->info().index != kNoIndex) continue;
    v->info().index = uint32_t(points.size());
    points.push_back({v->point().x(), v->point().y()});
  }
  Image image;
  image.width = uint32_t(width);
  image.height = uint32_t(height);
  std::vector<uint8_t> used(points.size(), 0);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    Triangle t;
    for (int i = 0; i < 3; ++i) {
      t.v[i] = f->vertex(i)->info().index;
      used[t.v[i]] = 1;
    }
    image.triangles.push_back(t);
  }
  if (image.triangles.empty())
    return Status(StatusCode::kInvalidMesh, "BuildControlMesh: the domain has no triangle");
  // Compact: drop vertices of no domain triangle (Steiner points or samples outside).
  std::vector<uint32_t> remap(points.size(), kNoIndex);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!used[i]) continue;
    remap[i] = uint32_t(image.vertices.size());
    Vertex v;
    v.x = float(points[i].x);
    v.y = float(points[i].y);
    image.vertices.push_back(v);
  }
  for (Triangle& t : image.triangles)
    for (uint32_t& v : t.v) v = remap[v];

  // Feature layer and tags.
  for (size_t k = 0; k < placed.polylines.size(); ++k) {
    const PlacedPolyline& l = placed.polylines[k];
    FeaturePolyline fp;
    fp.closed = l.closed;
    const auto& ids = polyline_vertices[k];
    for (size_t i = 0; i < ids.size(); ++i) {
      if (remap[ids[i]] == kNoIndex)
        return Status(StatusCode::kInternal, "BuildControlMesh: feature vertex " + std::to_string(ids[i]) +
                                                 " is in no domain triangle");
      fp.vertices.push_back(remap[ids[i]]);
    }
    const size_t m = ids.size();
    const size_t segs = l.closed ? m : m - 1;
    for (size_t i = 0; i < segs; ++i) {
      uint32_t a = ids[i], b = ids[(i + 1) % m];
      if (!cdt.is_edge(handles[a], handles[b]))
        return Status(StatusCode::kInternal, "BuildControlMesh: crease edge (" + std::to_string(a) + ", " +
                                                 std::to_string(b) + ") was split by the triangulation");
      image.crease_edges.push_back(Edge::Of(remap[a], remap[b]));
    }
    for (uint32_t c : l.corners) image.corners.push_back(remap[ids[c]]);
    image.polylines.push_back(std::move(fp));
  }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                           image.crease_edges.end());
  std::sort(image.corners.begin(), image.corners.end());
  image.corners.erase(std::unique(image.corners.begin(), image.corners.end()), image.corners.end());
  image.pairs = placed.pairs;
  return image;
}

}  // namespace sdvi
