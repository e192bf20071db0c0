// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the data-dependent edge flips (vectorize.h, FlipEdgesToData).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <utility>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/vectorize.h"

namespace {

// A valley along the anti-diagonal x + y = size: 0 on it, rising quadratically to 255 at the
// corners (0, 0) and (size, size); RGB.
sdvi::Raster AntiDiagonalValley(int size) {
  sdvi::Raster raster(size, size, 3);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float d = ((x + 0.5f) + (y + 0.5f) - float(size)) / float(size);
      const float v = 255.f * d * d;
      for (int c = 0; c < 3; ++c) raster.at(x, y, c) = v;
    }
  }
  return raster;
}

// A square with the diagonal (0,0)-(s,s), across the image's valley.
sdvi::Image Square(int size) {
  sdvi::Image mesh;
  mesh.width = mesh.height = uint32_t(size);
  const float s = float(size);
  mesh.vertices = {{0, 0, 0, 0, 0}, {s, 0, 0, 0, 0}, {s, s, 0, 0, 0}, {0, s, 0, 0, 0}};
  mesh.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  return mesh;
}

double SignedArea(const sdvi::Image& m, const sdvi::Triangle& t) {
  const sdvi::Vertex &a = m.vertices[t.v[0]], &b = m.vertices[t.v[1]], &c = m.vertices[t.v[2]];
  return (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
}

// Samples on a staggered grid: rows from `start` every `step` pixels, each row shifted right
// by y % stagger, every sample at (x + dx, y + dy).
std::vector<sdvi::Point2> StaggeredSamples(int width, int height, int start, int step, int stagger,
                                           double dx = 0.5, double dy = 0.5) {
  std::vector<sdvi::Point2> samples;
  for (int y = start; y < height; y += step) {
    for (int x = start + (y % stagger); x < width; x += step) samples.push_back({x + dx, y + dy});
  }
  return samples;
}

// The vectorizer's control mesh over the samples, with no features.
sdvi::Image ControlMesh(int width, int height, const std::vector<sdvi::Point2>& samples) {
  auto built = sdvi::BuildControlMesh(width, height, {}, samples, sdvi::ControlMeshOptions());
  INFO(built.status().ToString());
  REQUIRE(built.ok());
  return std::move(*built);
}

}  // namespace

TEST_CASE("vectorize edge flips align the diagonal with an image valley", "[vectorize][flip]") {
  const sdvi::Raster raster = AntiDiagonalValley(16);
  sdvi::Image mesh = Square(16);
  CHECK(sdvi::FlipEdgesToData(mesh, raster, nullptr, 4, 5.0) == 1);
  REQUIRE(mesh.triangles.size() == 2);
  for (const sdvi::Triangle& t : mesh.triangles) {
    // The new diagonal is (1, 3); the orientation (counter-clockwise here) is kept.
    CHECK(std::count(t.v.begin(), t.v.end(), 1u) == 1);
    CHECK(std::count(t.v.begin(), t.v.end(), 3u) == 1);
    CHECK(SignedArea(mesh, t) > 0);
  }
  // Converged: nothing more to flip.
  CHECK(sdvi::FlipEdgesToData(mesh, raster, nullptr, 4, 5.0) == 0);
}

TEST_CASE("vectorize edge flips keep crease edges and zero passes change nothing", "[vectorize][flip]") {
  const sdvi::Raster raster = AntiDiagonalValley(16);
  sdvi::Image mesh = Square(16);
  const sdvi::Image before = mesh;
  CHECK(sdvi::FlipEdgesToData(mesh, raster, nullptr, 0, 5.0) == 0);
  CHECK(mesh == before);
  mesh.crease_edges = {sdvi::Edge::Of(0, 2)};
  CHECK(sdvi::FlipEdgesToData(mesh, raster, nullptr, 4, 5.0) == 0);
  CHECK(mesh.triangles == before.triangles);
}

TEST_CASE("vectorize edge flips of a control mesh keep a valid oriented manifold", "[vectorize][flip]") {
  const sdvi::Raster raster = sdvi::MakeSampleImage(128, 96);
  const std::vector<sdvi::Point2> samples = StaggeredSamples(128, 96, 4, 7, 2);
  const sdvi::Image built = ControlMesh(128, 96, samples);
  sdvi::Image mesh = built;
  const size_t triangles = mesh.triangles.size();
  const double sign = SignedArea(mesh, mesh.triangles[0]);
  const int flips = sdvi::FlipEdgesToData(mesh, raster, nullptr, 8, 2.0);
  CHECK(flips > 0);
  CHECK(mesh.triangles.size() == triangles);
  double area = 0;
  std::map<sdvi::Edge, int> uses;
  for (const sdvi::Triangle& t : mesh.triangles) {
    const double a = SignedArea(mesh, t);
    CHECK(a * sign > 0);  // consistent orientation, no fold, no degenerate triangle
    area += std::abs(a) / 2;
    for (int k = 0; k < 3; ++k) ++uses[sdvi::Edge::Of(t.v[k], t.v[(k + 1) % 3])];
  }
  CHECK(area == Approx(128.0 * 96.0).epsilon(1e-6));  // still tiles the rectangle
  for (const auto& [edge, count] : uses) CHECK(count <= 2);
  for (const sdvi::Edge& e : mesh.crease_edges) CHECK(uses.count(e) == 1);
  // Deterministic.
  sdvi::Image again = built;
  sdvi::FlipEdgesToData(again, raster, nullptr, 8, 2.0);
  CHECK(again.triangles == mesh.triangles);
}

TEST_CASE("vectorize edge flips give the same mesh for any thread count", "[vectorize][flip]") {
  // Enough edges for many of the fixed chunks the errors are computed in.
  const sdvi::Raster raster = sdvi::MakeSampleImage(160, 120);
  const std::vector<sdvi::Point2> samples = StaggeredSamples(160, 120, 3, 4, 3);
  const sdvi::Image built = ControlMesh(160, 120, samples);
  REQUIRE(built.triangles.size() > 2000);
  sdvi::Image one = built;
  const int flips = sdvi::FlipEdgesToData(one, raster, nullptr, 16, 1.0, 1);
  CHECK(flips > 100);
  for (int threads : {2, 3, 8}) {
    sdvi::Image many = built;
    CHECK(sdvi::FlipEdgesToData(many, raster, nullptr, 16, 1.0, threads) == flips);
    CHECK(many.triangles == one.triangles);
  }
}

TEST_CASE("vectorize edge flips give the same meshes with the error cache of earlier calls", "[vectorize][flip]") {
  // Two triangulations of one image sharing most triangles (the second adds samples in one
  // corner), as the vectorizer's rounds do: flipping both with one cache gives the meshes
  // flipping each without it gives, and the cache holds the last call's errors.
  const sdvi::Raster raster = sdvi::MakeSampleImage(160, 120);
  const std::vector<sdvi::Point2> samples = StaggeredSamples(160, 120, 3, 5, 3);
  std::vector<sdvi::Point2> more = samples;
  for (int y = 5; y < 40; y += 5) {
    for (int x = 5; x < 40; x += 5) more.push_back({x + 0.25, y + 0.75});
  }
  const sdvi::Image first = ControlMesh(160, 120, samples), second = ControlMesh(160, 120, more);
  sdvi::Image a = first, b = second;
  const int flips_a = sdvi::FlipEdgesToData(a, raster, nullptr, 16, 1.0, 1);
  const int flips_b = sdvi::FlipEdgesToData(b, raster, nullptr, 16, 1.0, 1);
  for (int threads : {1, 3}) {
    sdvi::FlipErrorCache cache;
    sdvi::Image ca = first, cb = second;
    CHECK(sdvi::FlipEdgesToData(ca, raster, nullptr, 16, 1.0, threads, &cache) == flips_a);
    CHECK(cache.size() > ca.triangles.size());
    CHECK(sdvi::FlipEdgesToData(cb, raster, nullptr, 16, 1.0, threads, &cache) == flips_b);
    CHECK(ca.triangles == a.triangles);
    CHECK(cb.triangles == b.triangles);
  }
}

TEST_CASE("vectorize edge flips do not depend on how the mesh lists a triangle", "[vectorize][flip]") {
  // A triangle's error is computed with its corners in one canonical order: rotating every
  // triangle's corners and reversing its orientation gives the same flips, and with the
  // error cache of the first call the second finds every error it needs there.
  const sdvi::Raster raster = sdvi::MakeSampleImage(128, 96);
  const std::vector<sdvi::Point2> samples = StaggeredSamples(128, 96, 4, 6, 3, 0.5, 0.25);
  const sdvi::Image built = ControlMesh(128, 96, samples);
  sdvi::Image listed = built;
  for (sdvi::Triangle& t : listed.triangles) t.v = {t.v[2], t.v[1], t.v[0]};
  auto corner_sets = [](const sdvi::Image& m) {
    std::vector<std::array<uint32_t, 3>> sets;
    for (const sdvi::Triangle& t : m.triangles) {
      std::array<uint32_t, 3> s = t.v;
      std::sort(s.begin(), s.end());
      sets.push_back(s);
    }
    return sets;
  };
  sdvi::FlipErrorCache cache;
  sdvi::Image mesh = built;
  const int flips = sdvi::FlipEdgesToData(mesh, raster, nullptr, 16, 1.0, 1, &cache);
  CHECK(flips > 20);
  const size_t hits_before = cache.hits();
  CHECK(sdvi::FlipEdgesToData(listed, raster, nullptr, 16, 1.0, 1, &cache) == flips);
  CHECK(corner_sets(listed) == corner_sets(mesh));
  // Every triangle of the first sweep, and every flipped pair, came from the cache.
  CHECK(cache.hits() - hits_before >= mesh.triangles.size() + 2 * size_t(flips));
}

TEST_CASE("vectorize edge flips leave a flat image's triangulation alone", "[vectorize][flip]") {
  // Constant colour: the interpolation is exactly the colour on every pixel whatever the
  // diagonal, both errors are 0, and no flip is better than 0.98 x 0.
  sdvi::Raster raster(96, 64, 3);
  for (size_t i = 0; i < raster.data.size(); ++i) raster.data[i] = i % 3 == 0 ? 40.f : i % 3 == 1 ? 170.f : 93.f;
  const std::vector<sdvi::Point2> samples = StaggeredSamples(96, 64, 3, 5, 2, 0.37, 0.61);
  const sdvi::Image built = ControlMesh(96, 64, samples);
  sdvi::Image mesh = built;
  CHECK(sdvi::FlipEdgesToData(mesh, raster, nullptr, 16, 1.0, 2) == 0);
  CHECK(mesh.triangles == built.triangles);
}

TEST_CASE("the flip error cache finds exactly what the last call recorded", "[vectorize][flip]") {
  // Keys as FlipEdgesToData makes them (float bits of three positions), many sharing words so
  // that the hash table's probes collide; errors 0 and positive; every key recorded twice.
  auto key_of = [](uint32_t i) {
    std::array<uint32_t, 6> key;
    for (uint32_t k = 0; k < 6; ++k) key[k] = 0x42000000u + (i >> (k % 3)) + k * 7;
    return key;
  };
  auto error_of = [](uint32_t i) { return i % 5 == 0 ? 0.0 : 0.25 * double(i); };
  sdvi::FlipErrorCache cache;
  CHECK(cache.Find(key_of(1)) == nullptr);  // nothing before the first call ends
  std::map<std::array<uint32_t, 6>, double> recorded;
  for (int copy = 0; copy < 2; ++copy) {
    for (uint32_t i = 0; i < 20000; ++i) {
      cache.Add(key_of(i), error_of(i));
      recorded.emplace(key_of(i), error_of(i));
    }
  }
  CHECK(cache.Find(key_of(1)) == nullptr);  // recorded, not yet ended
  cache.EndCall();
  CHECK(cache.size() == recorded.size());
  for (const auto& [key, error] : recorded) {
    const double* found = cache.Find(key);
    REQUIRE(found != nullptr);
    CHECK(*found == error);
  }
  CHECK(cache.hits() == recorded.size());
  for (uint32_t i = 20000; i < 25000; ++i) {
    if (recorded.count(key_of(i)) == 0) CHECK(cache.Find(key_of(i)) == nullptr);
  }
  // A later call replaces what an earlier one recorded.
  cache.Add(key_of(30000), 1.5);
  cache.EndCall();
  CHECK(cache.size() == 1);
  CHECK(cache.Find(key_of(0)) == nullptr);
  REQUIRE(cache.Find(key_of(30000)) != nullptr);
  CHECK(*cache.Find(key_of(30000)) == 1.5);
}
