// SPDX-License-Identifier: GPL-3.0-or-later
// Fold repair by edge flips (EditOptions::repair_folds; rules in sdvi/edit.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "edit_internal.h"

namespace sdvi::edit_internal {
namespace {

// Position of v in t (0..2), or -1.
int Slot(const Triangle& t, uint32_t v) {
  for (int k = 0; k < 3; ++k)
    if (t.v[k] == v) return k;
  return -1;
}

double Height(const Image& image, const Triangle& t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const Vertex &a = image.vertices[t.v[k]], &b = image.vertices[t.v[(k + 1) % 3]];
    longest = std::max(longest, std::hypot(double(b.x) - a.x, double(b.y) - a.y));
  }
  return longest > 0 ? std::fabs(SignedArea2(image, t)) / longest : 0;
}

}  // namespace

int MeshOrientation(const Image& image) {
  size_t positive = 0, negative = 0;
  for (const Triangle& t : image.triangles) {
    const double a = SignedArea2(image, t);
    positive += a > 0;
    negative += a < 0;
  }
  return positive >= negative ? 1 : -1;
}

int RepairFolds(int orientation, Image* image) {
  std::map<Edge, std::vector<uint32_t>> faces;
  for (size_t t = 0; t < image->triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      faces[Edge::Of(image->triangles[t].v[k], image->triangles[t].v[(k + 1) % 3])].push_back(uint32_t(t));
  auto good = [&](const Triangle& t) {
    return SignedArea2(*image, t) * orientation > 0 && Height(*image, t) >= kMinTriangleHeight;
  };
  auto inverted = [&](const Triangle& t) { return SignedArea2(*image, t) * orientation <= 0; };
  const std::vector<Edge>& creases = image->crease_edges;
  int flips = 0;
  for (int pass = 0; pass < 64; ++pass) {
    bool changed = false;
    for (uint32_t t1 = 0; t1 < image->triangles.size(); ++t1) {
      if (!inverted(image->triangles[t1])) continue;
      for (int k = 0; k < 3; ++k) {
        const Triangle tri = image->triangles[t1];
        // t1 = (a, b, c) in cyclic order; t2 = (b, a, d) across the edge (a, b).
        const uint32_t a = tri.v[k], b = tri.v[(k + 1) % 3], c = tri.v[(k + 2) % 3];
        const Edge ab = Edge::Of(a, b);
        if (std::binary_search(creases.begin(), creases.end(), ab)) continue;
        const std::vector<uint32_t>& adj = faces[ab];
        if (adj.size() != 2) continue;
        const uint32_t t2 = adj[0] == t1 ? adj[1] : adj[0];
        const Triangle& other = image->triangles[t2];
        const int sb = Slot(other, b);
        if (sb < 0 || other.v[(sb + 1) % 3] != a) continue;  // inconsistent orientation: leave it
        const uint32_t d = other.v[(sb + 2) % 3];
        if (d == c || faces.count(Edge::Of(c, d))) continue;  // the new diagonal exists already
        const Triangle n1{{c, a, d}}, n2{{d, b, c}};
        const int before = int(inverted(tri)) + int(inverted(other));
        if (!good(n1) || !good(n2) || before == 0) continue;
        // Flip (a, b) -> (c, d): (c, a) stays with t1, (d, b) with t2.
        auto replace = [&](Edge e, uint32_t from, uint32_t to) {
          for (uint32_t& f : faces[e])
            if (f == from) f = to;
        };
        faces.erase(ab);
        replace(Edge::Of(a, d), t2, t1);  // (a, d) moves to t1 = (c, a, d)
        replace(Edge::Of(b, c), t1, t2);  // (b, c) moves to t2
        faces[Edge::Of(c, d)] = {t1, t2};
        image->triangles[t1] = n1;
        image->triangles[t2] = n2;
        ++flips;
        changed = true;
        break;
      }
    }
    if (!changed) break;
  }
  return flips;
}

}  // namespace sdvi::edit_internal
