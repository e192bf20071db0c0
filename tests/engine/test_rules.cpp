// SPDX-License-Identifier: GPL-3.0-or-later
// The masks of spec/SUBDIVISION.md (subdiv_rules.h).
#include <catch2/catch.hpp>

#include "sdvi/subdiv_rules.h"

namespace rules = sdvi::rules;

TEST_CASE("Loop a(n) is 3/8 for the regular valence 6", "[rules]") {
  CHECK(rules::LoopAlpha(6) == Approx(3.0 / 8.0));
  CHECK(rules::LoopAlpha(3) == Approx(5.0 / 8.0 - 4.0 / 64.0));
}

TEST_CASE("Every smooth mask sums to 1 for valences 3..12", "[rules]") {
  for (int n = 3; n <= 12; ++n) {
    const auto r = rules::SmoothVertexRule(n);
    const auto l = rules::SmoothLimitRule(n);
    CHECK(r.self + n * r.neighbour == Approx(1.0).margin(1e-15));
    CHECK(l.self + n * l.neighbour == Approx(1.0).margin(1e-15));
    CHECK(r.neighbour > 0);
    CHECK(l.neighbour > 0);
  }
  // Regular limit mask: (6 v + sum) / 12.
  CHECK(rules::SmoothLimitRule(6).self == Approx(0.5));
}

TEST_CASE("Crease masks sum to 1 and mirror", "[rules]") {
  for (bool c0 : {false, true})
    for (bool c1 : {false, true}) {
      const auto r = rules::CreaseVertexRule(c0, c1);
      const auto l = rules::CreaseLimitRule(c0, c1);
      CHECK(r.c0 + r.self + r.c1 == Approx(1.0).margin(1e-15));
      CHECK(l.c0 + l.self + l.c1 == Approx(1.0).margin(1e-15));
      const auto rm = rules::CreaseVertexRule(c1, c0);
      CHECK(rm.c0 == r.c1);
      CHECK(rm.c1 == r.c0);
      const auto e = rules::CreaseEdgeRule(c0, c1);
      CHECK(e.end0 + e.end1 == Approx(1.0));
    }
  CHECK(rules::CreaseEdgeRule(true, false).end0 == 0.75);
  CHECK(rules::CreaseLimitRule(true, false).c0 == Approx(3.0 / 12));
  CHECK(rules::CreaseVertexRule(false, true).c1 == Approx(3.0 / 16));
  const auto s = rules::SmoothEdgeRule();
  CHECK(s.end0 + s.end1 + 2 * s.opposite == 1.0);
}
