// SPDX-License-Identifier: GPL-3.0-or-later
// Control mesh construction (paper IV steps 3-4): pairs, no crossings, constrained
// Delaunay triangulation without Steiner points on features, tags.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <random>
#include <set>

#include "sdvi/features.h"

namespace {

using sdvi::Edge;
using sdvi::FeatureCurve;
using sdvi::Image;
using sdvi::Point2;

double Dist(const sdvi::Vertex& a, const sdvi::Vertex& b) { return std::hypot(a.x - b.x, a.y - b.y); }

double MinAngleDeg(const Image& m, const sdvi::Triangle& t) {
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const auto &a = m.vertices[t.v[k]], &b = m.vertices[t.v[(k + 1) % 3]], &c = m.vertices[t.v[(k + 2) % 3]];
    double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
    double cosv = (ux * vx + uy * vy) / (std::hypot(ux, uy) * std::hypot(vx, vy));
    best = std::min(best, std::acos(std::clamp(cosv, -1.0, 1.0)) * 180 / M_PI);
  }
  return best;
}

double SignedArea(const Image& m, const sdvi::Triangle& t) {
  const auto &a = m.vertices[t.v[0]], &b = m.vertices[t.v[1]], &c = m.vertices[t.v[2]];
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

bool SegmentsCross(const sdvi::Vertex& a, const sdvi::Vertex& b, const sdvi::Vertex& c, const sdvi::Vertex& d) {
  auto cross = [](const sdvi::Vertex& o, const sdvi::Vertex& p, const sdvi::Vertex& q) {
    return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x);
  };
  double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// The invariants BuildLimitSurface relies on; returns the mesh edge -> triangle count.
std::map<Edge, int> CheckValidMesh(const Image& m) {
  std::map<Edge, int> edges;
  std::set<std::array<uint32_t, 3>> seen;
  double orientation = 0;
  for (const auto& t : m.triangles) {
    for (uint32_t v : t.v) REQUIRE(v < m.vertices.size());
    REQUIRE(t.v[0] != t.v[1]);
    REQUIRE(t.v[1] != t.v[2]);
    REQUIRE(t.v[0] != t.v[2]);
    std::array<uint32_t, 3> key = t.v;
    std::sort(key.begin(), key.end());
    REQUIRE(seen.insert(key).second);
    double a = SignedArea(m, t);
    REQUIRE(std::fabs(a) > 1e-6);
    if (orientation == 0) orientation = a;
    REQUIRE(a * orientation > 0);  // consistent orientation, no fold
    for (int k = 0; k < 3; ++k) edges[Edge::Of(t.v[k], t.v[(k + 1) % 3])]++;
  }
  for (const auto& [e, n] : edges) REQUIRE(n <= 2);
  for (const Edge& e : m.crease_edges) REQUIRE(edges.count(e) == 1);
  REQUIRE(std::is_sorted(m.crease_edges.begin(), m.crease_edges.end()));
  REQUIRE(std::is_sorted(m.corners.begin(), m.corners.end()));
  // Every boundary edge of the mesh is a crease edge.
  std::set<Edge> creases(m.crease_edges.begin(), m.crease_edges.end());
  for (const auto& [e, n] : edges)
    if (n == 1) REQUIRE(creases.count(e) == 1);
  // Feature polylines are chains of crease edges (so no Steiner point sits on them).
  for (const auto& pl : m.polylines) {
    const size_t k = pl.vertices.size();
    for (size_t i = 0; i + (pl.closed ? 0 : 1) < k; ++i)
      REQUIRE(creases.count(Edge::Of(pl.vertices[i], pl.vertices[(i + 1) % k])) == 1);
  }
  for (const auto& v : m.vertices) {
    REQUIRE((v.r == 0 && v.g == 0 && v.b == 0));
  }
  // Manifold vertices: each vertex is used, and has 0 (interior) or 2 boundary edges.
  std::vector<int> boundary_degree(m.vertices.size(), 0), used(m.vertices.size(), 0);
  for (const auto& t : m.triangles)
    for (uint32_t v : t.v) used[v] = 1;
  for (const auto& [e, n] : edges)
    if (n == 1) {
      boundary_degree[e.a]++;
      boundary_degree[e.b]++;
    }
  for (size_t v = 0; v < m.vertices.size(); ++v) {
    REQUIRE(used[v] == 1);
    REQUIRE((boundary_degree[v] == 0 || boundary_degree[v] == 2));
  }
  return edges;
}

// Crease segments of different polylines never cross.
void CheckNoCrossings(const Image& m) {
  std::vector<std::pair<uint32_t, uint32_t>> segs;
  for (const auto& pl : m.polylines) {
    const size_t k = pl.vertices.size();
    for (size_t i = 0; i + (pl.closed ? 0 : 1) < k; ++i) segs.push_back({pl.vertices[i], pl.vertices[(i + 1) % k]});
  }
  for (size_t i = 0; i < segs.size(); ++i)
    for (size_t j = i + 1; j < segs.size(); ++j)
      REQUIRE(!SegmentsCross(m.vertices[segs[i].first], m.vertices[segs[i].second], m.vertices[segs[j].first],
                             m.vertices[segs[j].second]));
}

FeatureCurve Circle(double cx, double cy, double r, int n, float sharpness) {
  FeatureCurve c;
  c.closed = true;
  c.sharpness = sharpness;
  for (int i = 0; i < n; ++i) c.points.push_back({cx + r * std::cos(2 * M_PI * i / n), cy + r * std::sin(2 * M_PI * i / n)});
  return c;
}

FeatureCurve Line(Point2 a, Point2 b, int n, float sharpness) {
  FeatureCurve c;
  c.sharpness = sharpness;
  for (int i = 0; i <= n; ++i) c.points.push_back({a.x + (b.x - a.x) * i / n, a.y + (b.y - a.y) * i / n});
  return c;
}

// A jittered lattice (an exact lattice makes right triangles whose circumcentres lie on
// an edge, which the mesher without edge refinement cannot insert).
std::vector<Point2> Grid(int w, int h, int step) {
  std::vector<Point2> s;
  uint32_t state = 12345;
  auto jitter = [&] {
    state = state * 1664525u + 1013904223u;
    return (double(state >> 8) / double(1u << 24) - 0.5) * 0.3 * step;
  };
  for (int y = step / 2; y < h; y += step)
    for (int x = step / 2; x < w; x += step) s.push_back({x + jitter(), y + jitter()});
  return s;
}

}  // namespace

TEST_CASE("control mesh of an image is a valid tagged manifold mesh", "[triangulate]") {
  std::vector<FeatureCurve> curves{Circle(100, 90, 40, 30, 0.9f), Line({20, 160}, {180, 150}, 16, 0.3f)};
  curves[1].corners = {8};
  sdvi::ControlMeshOptions o;
  o.max_edge = 20;
  o.min_angle_deg = 20;  // the paper's bound (the vectorizer's default is lower)
  auto mesh = sdvi::BuildControlMesh(200, 180, curves, Grid(200, 180, 15), o);
  REQUIRE(mesh.ok());
  const Image& m = *mesh;
  REQUIRE(m.width == 200);
  REQUIRE(m.height == 180);
  CheckValidMesh(m);
  CheckNoCrossings(m);
  // The domain is the whole rectangle.
  double area = 0;
  for (const auto& t : m.triangles) area += std::fabs(SignedArea(m, t));
  REQUIRE(area == Approx(200.0 * 180.0).epsilon(1e-6));
  // Four image corners are vertices tagged corner.
  for (Point2 c : {Point2{0, 0}, Point2{200, 0}, Point2{200, 180}, Point2{0, 180}}) {
    bool found = false;
    for (uint32_t k : m.corners)
      if (m.vertices[k].x == float(c.x) && m.vertices[k].y == float(c.y)) found = true;
    REQUIRE(found);
  }
  // The interior kink of the line is a corner on both sides of its pair.
  REQUIRE(m.pairs.size() == 2);
  REQUIRE(m.corners.size() == 4 + 2);
  // Quality: triangles away from features meet the angle bound (the mesher never
  // splits crease edges, so triangles touching them may be thinner).
  std::set<uint32_t> on_feature;
  for (const auto& pl : m.polylines)
    for (uint32_t v : pl.vertices) on_feature.insert(v);
  size_t free = 0, good = 0;
  for (const auto& t : m.triangles) {
    if (on_feature.count(t.v[0]) || on_feature.count(t.v[1]) || on_feature.count(t.v[2])) continue;
    ++free;
    if (MinAngleDeg(m, t) >= o.min_angle_deg - 0.5) ++good;
  }
  REQUIRE(free > 20);
  REQUIRE(good == free);
  // Size bound on the same triangles: no edge longer than max_edge.
  for (const auto& t : m.triangles) {
    if (on_feature.count(t.v[0]) || on_feature.count(t.v[1]) || on_feature.count(t.v[2])) continue;
    for (int k = 0; k < 3; ++k) REQUIRE(Dist(m.vertices[t.v[k]], m.vertices[t.v[(k + 1) % 3]]) <= 20.0 * 1.01);
  }
}

TEST_CASE("pairs sit at rho (1 - sharpness) with a floor, ablation switches", "[triangulate]") {
  auto pair_distance = [](const Image& m, size_t p) {
    const auto& a = m.polylines[m.pairs[p].first].vertices;
    const auto& b = m.polylines[m.pairs[p].second].vertices;
    REQUIRE(a.size() == b.size());
    double d = 0;
    for (size_t i = 0; i < a.size(); ++i) d = std::max(d, Dist(m.vertices[a[i]], m.vertices[b[i]]));
    return d;
  };
  std::vector<FeatureCurve> curves{Line({20, 40}, {180, 40}, 10, 0.4f)};
  sdvi::ControlMeshOptions o;
  o.max_edge = 40;  // no segment gets split
  auto full = sdvi::BuildControlMesh(200, 100, curves, {}, o);
  REQUIRE(full.ok());
  CheckValidMesh(*full);
  REQUIRE(full->pairs.size() == 1);
  REQUIRE(full->pairs[0].sharpness == 0.4f);
  REQUIRE(pair_distance(*full, 0) == Approx(5.0 * 0.6).epsilon(1e-4));

  curves[0].sharpness = 1.0f;  // crisp: the floor keeps the pair apart
  auto crisp = sdvi::BuildControlMesh(200, 100, curves, {}, o);
  REQUIRE(crisp.ok());
  REQUIRE(pair_distance(*crisp, 0) == Approx(o.min_distance).epsilon(1e-4));

  o.use_sharpness = false;  // ablation (paper Fig. 14): every pair at rho
  auto no_sharp = sdvi::BuildControlMesh(200, 100, curves, {}, o);
  REQUIRE(no_sharp.ok());
  REQUIRE(pair_distance(*no_sharp, 0) == Approx(5.0).epsilon(1e-4));
  REQUIRE(no_sharp->pairs[0].sharpness == 0.0f);

  o.pairs = false;  // ablation (paper Fig. 9): one polyline per feature
  auto single = sdvi::BuildControlMesh(200, 100, curves, {}, o);
  REQUIRE(single.ok());
  CheckValidMesh(*single);
  REQUIRE(single->pairs.empty());
  REQUIRE(single->polylines.size() == 2);  // the boundary and the feature
  const auto& fv = single->polylines[1].vertices;
  REQUIRE(fv.size() == curves[0].points.size());
  for (size_t i = 0; i < fv.size(); ++i) REQUIRE(single->vertices[fv[i]].y == Approx(40.0));
}

TEST_CASE("crossing and near features are trimmed, never crossed", "[triangulate]") {
  std::vector<FeatureCurve> curves{Line({5, 5}, {195, 195}, 20, 0.5f), Line({10, 190}, {190, 10}, 18, 1.0f),
                                   Line({10, 100}, {60, 100.5}, 6, 0.0f), Circle(100, 100, 30, 24, 0.8f),
                                   Line({-5, 50}, {40, 50}, 6, 1.0f)};  // leaves the frame
  sdvi::ControlMeshOptions o;
  o.max_edge = 40;  // no segment gets split
  const bool junctions = GENERATE(false, true);
  o.junctions = junctions;
  INFO("junctions " << junctions);
  auto mesh = sdvi::BuildControlMesh(200, 200, curves, Grid(200, 200, 10), o);
  REQUIRE(mesh.ok());
  CheckValidMesh(*mesh);
  CheckNoCrossings(*mesh);
  for (const auto& v : mesh->vertices) {
    REQUIRE(v.x >= 0);
    REQUIRE(v.x <= 200);
    REQUIRE(v.y >= 0);
    REQUIRE(v.y <= 200);
  }
  // The longest feature (the first diagonal) survives whole as a pair; with junctions the
  // features crossing it add their junction corners (crease-degree >= 3) to it.
  REQUIRE(mesh->polylines.size() >= 3);
  std::vector<int> degree(mesh->vertices.size(), 0);
  for (const Edge& e : mesh->crease_edges) ++degree[e.a], ++degree[e.b];
  for (size_t k : {1, 2}) {
    size_t plain = 0, joined = 0;
    for (uint32_t v : mesh->polylines[k].vertices) (degree[v] >= 3 ? joined : plain) += 1;
    CHECK(plain == 21);
    if (junctions) CHECK(joined > 0);
    else CHECK(joined == 0);
  }
}

TEST_CASE("interior samples become vertices unless too close to a feature", "[triangulate]") {
  std::vector<FeatureCurve> curves{Line({20, 50}, {180, 50}, 8, 1.0f)};
  std::vector<Point2> samples{{100, 20}, {100, 50.2}, {30, 80}, {30, 80.1}, {-3, 5}, {150, 90}};
  auto mesh = sdvi::BuildControlMesh(200, 100, curves, samples, {});
  REQUIRE(mesh.ok());
  auto has = [&](double x, double y) {
    for (const auto& v : mesh->vertices)
      if (std::fabs(v.x - x) < 1e-4 && std::fabs(v.y - y) < 1e-4) return true;
    return false;
  };
  REQUIRE(has(100, 20));
  REQUIRE(has(30, 80));
  REQUIRE(has(150, 90));
  REQUIRE(!has(100, 50.2));  // on the feature
  REQUIRE(!has(30, 80.1));   // duplicate within the clearance
  REQUIRE(!has(-3, 5));      // outside
}

TEST_CASE("object mode: boundary curves with a hole bound the mesh", "[triangulate]") {
  FeatureCurve outer = Circle(100, 100, 80, 40, 1.0f), hole = Circle(100, 100, 30, 20, 1.0f);
  outer.boundary = hole.boundary = true;
  FeatureCurve inner = Circle(100, 100, 55, 28, 0.5f);
  sdvi::ControlMeshOptions o;
  o.max_edge = 30;  // no boundary segment gets split
  auto mesh = sdvi::BuildControlMesh(200, 200, {outer, hole, inner}, Grid(200, 200, 12), o);
  REQUIRE(mesh.ok());
  const Image& m = *mesh;
  CheckValidMesh(m);
  CheckNoCrossings(m);
  // Triangles lie in the annulus (the polygons are inscribed: radius bounds are loose).
  for (const auto& t : m.triangles) {
    double cx = 0, cy = 0;
    for (uint32_t v : t.v) {
      cx += m.vertices[v].x / 3;
      cy += m.vertices[v].y / 3;
    }
    double r = std::hypot(cx - 100, cy - 100);
    REQUIRE(r > 29);
    REQUIRE(r < 80.5);
  }
  REQUIRE(m.pairs.size() == 1);
  // Mesh boundary edges are exactly the two boundary polylines (creases).
  auto edges = CheckValidMesh(m);
  size_t border = 0;
  for (const auto& [e, n] : edges) border += n == 1;
  REQUIRE(border == 40 + 20);
}

TEST_CASE("control mesh from detected features of a drawn image", "[triangulate]") {
  cv::Mat img(256, 256, CV_8UC3, cv::Scalar(20, 40, 60));
  cv::circle(img, {90, 100}, 50, cv::Scalar(220, 180, 40), -1, cv::LINE_AA);
  cv::rectangle(img, {120, 130}, {230, 220}, cv::Scalar(40, 200, 90), -1);
  cv::line(img, {0, 250}, {255, 5}, cv::Scalar(250, 250, 250), 2, cv::LINE_AA);
  sdvi::Raster r(256, 256, 3);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      for (int c = 0; c < 3; ++c) r.at(x, y, c) = img.at<cv::Vec3b>(y, x)[c];
  auto curves = sdvi::DetectFeatures(r, nullptr, {});
  REQUIRE(curves.ok());
  REQUIRE(curves->size() >= 3);
  auto mesh = sdvi::BuildControlMesh(256, 256, *curves, Grid(256, 256, 16), {});
  REQUIRE(mesh.ok());
  CheckValidMesh(*mesh);
  CheckNoCrossings(*mesh);
  REQUIRE(mesh->pairs.size() >= 3);
}

TEST_CASE("bad curves and options are rejected", "[triangulate]") {
  FeatureCurve nan = Line({1, 1}, {5, 5}, 2, 1.0f);
  nan.points[1].x = std::nan("");
  REQUIRE(sdvi::BuildControlMesh(10, 10, {nan}, {}, {}).status().code() == sdvi::StatusCode::kInvalidArgument);
  FeatureCurve corner = Line({1, 1}, {5, 5}, 2, 1.0f);
  corner.corners = {7};
  REQUIRE(sdvi::BuildControlMesh(10, 10, {corner}, {}, {}).status().code() == sdvi::StatusCode::kInvalidArgument);
  FeatureCurve lone;
  lone.points = {{1, 1}};
  REQUIRE(sdvi::BuildControlMesh(10, 10, {lone}, {}, {}).status().code() == sdvi::StatusCode::kInvalidArgument);
  REQUIRE(sdvi::BuildControlMesh(0, 10, {}, {}, {}).status().code() == sdvi::StatusCode::kInvalidArgument);
  sdvi::ControlMeshOptions o;
  o.min_distance = 0;
  REQUIRE(sdvi::BuildControlMesh(10, 10, {}, {}, o).status().code() == sdvi::StatusCode::kInvalidArgument);
  // A boundary curve that crosses itself cannot bound anything.
  FeatureCurve bow;
  bow.boundary = bow.closed = true;
  bow.points = {{10, 10}, {90, 90}, {90, 10}, {10, 90}};
  REQUIRE(sdvi::BuildControlMesh(100, 100, {bow}, {}, {}).status().code() == sdvi::StatusCode::kInvalidMesh);
  // An empty feature list still gives the rectangle.
  auto plain = sdvi::BuildControlMesh(64, 32, {}, {}, {});
  REQUIRE(plain.ok());
  CheckValidMesh(*plain);
}

TEST_CASE("random drawn images always give valid meshes", "[triangulate]") {
  std::mt19937 rng(2024);
  for (int round = 0; round < 60; ++round) {
    const int w = 8 + int(rng() % 150), h = 8 + int(rng() % 150);
    const int channels = 1 + int(rng() % 4);
    cv::Mat grey(h, w, CV_32FC1, cv::Scalar(double(rng() % 256)));
    cv::Mat alpha(h, w, CV_32FC1, cv::Scalar(1.0));
    for (int k = 0; k < 10; ++k) {
      cv::Point p(int(rng() % (w + 1)), int(rng() % (h + 1))), q(int(rng() % (w + 1)), int(rng() % (h + 1)));
      double colour = double(rng() % 256);
      switch (rng() % 3) {
        case 0: cv::circle(grey, p, int(rng() % 50), colour, -1); break;
        case 1: cv::line(grey, p, q, colour, 1 + int(rng() % 3)); break;
        default: cv::rectangle(grey, p, q, colour, -1); break;
      }
      if (k < 4) cv::circle(alpha, p, int(rng() % 40), (rng() % 2) ? 1.0 : 0.0, -1);
    }
    sdvi::Raster r(w, h, channels);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < channels; ++c) {
          bool is_alpha = (channels == 2 && c == 1) || (channels == 4 && c == 3);
          r.at(x, y, c) = is_alpha ? alpha.at<float>(y, x) : grey.at<float>(y, x) * (0.4f + 0.2f * c);
        }
    auto curves = sdvi::DetectFeatures(r, nullptr, {});
    if (!curves.ok()) {
      REQUIRE(curves.status().code() == sdvi::StatusCode::kEmptyInput);  // nothing opaque enough
      continue;
    }
    std::vector<Point2> samples;
    if (rng() % 2)
      for (int y = 0; y <= h; y += 5)
        for (int x = 0; x <= w; x += 5) samples.push_back({double(x), double(y)});  // exact lattice
    for (int i = 0; i < 100; ++i) samples.push_back({double(rng() % (100 * w)) / 100, double(rng() % (100 * h)) / 100});
    sdvi::ControlMeshOptions o;
    o.pairs = rng() % 4 != 0;
    o.max_edge = float(4 + rng() % 30);
    auto mesh = sdvi::BuildControlMesh(w, h, *curves, samples, o);
    CAPTURE(round, w, h, channels);
    REQUIRE(mesh.ok());
    CheckValidMesh(*mesh);
    CheckNoCrossings(*mesh);
  }
}

TEST_CASE("a pair whose side would turn back along itself loses that point on both sides", "[triangulate]") {
  // The end of a glyph's outline from an SVG import (shapes-intro-01-t of the W3C suite with
  // the system's fonts), shifted by (dx, dy): after a sharp corner (point 3), two steps of
  // 0.3 px straight up. Offset by half the pair distance (0.5 px), the inner side's corner
  // lies beyond its next point, so that side ran down and back up one line: two overlapping
  // constraints, and the triangulation split one ("crease edge ... was split").
  const double dx = GENERATE(0.0, -380.0), dy = GENERATE(0.0, -100.0);
  INFO("shift " << dx << ", " << dy);
  FeatureCurve glyph;
  glyph.points = {{418.75426136363632 + dx, 132.36363636363635 + dy}, {417.51655148226979 + dx, 134.45494943575963 + dy},
                  {418.09191882845221 + dx, 136.07756183198865 + dy}, {415.59375 + dx, 136.671875 + dy},
                  {415.59375 + dx, 136.3671875 + dy},                 {415.59375 + dx, 136.0625 + dy}};
  glyph.corners = {3};
  glyph.sharpness = 1;
  sdvi::ControlMeshOptions options;
  options.max_edge = 32;
  auto mesh = sdvi::BuildControlMesh(480, 360, {glyph}, {}, options);
  INFO((mesh.ok() ? std::string() : mesh.status().ToString()));
  REQUIRE(mesh.ok());
  CheckValidMesh(*mesh);
  // One pair whose sides still correspond vertex by vertex: the midpoints are the curve's
  // points but the spike's (point 4), in order, and the corner is kept.
  REQUIRE(mesh->pairs.size() == 1);
  const auto& right = mesh->polylines[mesh->pairs[0].first].vertices;
  const auto& left = mesh->polylines[mesh->pairs[0].second].vertices;
  REQUIRE(right.size() == 5);
  REQUIRE(left.size() == 5);
  const size_t kept[5] = {0, 1, 2, 3, 5};
  for (size_t i = 0; i < 5; ++i) {
    const auto &a = mesh->vertices[right[i]], &b = mesh->vertices[left[i]];
    CHECK(std::hypot((a.x + b.x) / 2 - glyph.points[kept[i]].x, (a.y + b.y) / 2 - glyph.points[kept[i]].y) < 1e-3);
    CHECK(std::hypot(a.x - b.x, a.y - b.y) >= 1 - 1e-3);  // the pair distance, mitred at the corner
  }
  CHECK(std::count(mesh->corners.begin(), mesh->corners.end(), right[3]) == 1);
  CHECK(std::count(mesh->corners.begin(), mesh->corners.end(), left[3]) == 1);
  // No feature polyline turns back: consecutive segments never run in opposite directions
  // along one line.
  for (const auto& polyline : mesh->polylines) {
    const auto& ids = polyline.vertices;
    for (size_t i = 1; i + 1 < ids.size(); ++i) {
      const auto &a = mesh->vertices[ids[i - 1]], &b = mesh->vertices[ids[i]], &c = mesh->vertices[ids[i + 1]];
      const double dot = double(b.x - a.x) * (c.x - b.x) + double(b.y - a.y) * (c.y - b.y);
      const double cross = double(b.x - a.x) * (c.y - b.y) - double(b.y - a.y) * (c.x - b.x);
      CHECK(!(dot < 0 && std::abs(cross) < 1e-3 * std::hypot(b.x - a.x, b.y - a.y)));
    }
  }
}
