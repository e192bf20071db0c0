// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/subdiv_rules.h"

#include <array>
#include <cmath>
#include <numbers>

namespace sdvi::rules {

namespace {
double ComputeLoopAlpha(int valence) {
  const double c = 3.0 + 2.0 * std::cos(2.0 * std::numbers::pi / valence);
  return 5.0 / 8.0 - c * c / 64.0;
}
}  // namespace

double LoopAlpha(int valence) {
  // The common valences come from a table computed once (the masks are asked for per vertex).
  constexpr int kTabulated = 32;
  static const std::array<double, kTabulated + 1> table = [] {
    std::array<double, kTabulated + 1> t{};
    for (int n = 1; n <= kTabulated; ++n) t[n] = ComputeLoopAlpha(n);
    return t;
  }();
  return valence >= 1 && valence <= kTabulated ? table[valence] : ComputeLoopAlpha(valence);
}

SmoothVertexMask SmoothVertexRule(int valence) {
  const double a = LoopAlpha(valence);
  return {1.0 - a, a / valence};
}

CreaseVertexMask CreaseVertexRule(bool c0_is_corner, bool c1_is_corner) {
  if (c0_is_corner && c1_is_corner) return {3.0 / 16, 10.0 / 16, 3.0 / 16};
  if (c0_is_corner) return {3.0 / 16, 11.0 / 16, 2.0 / 16};
  if (c1_is_corner) return {2.0 / 16, 11.0 / 16, 3.0 / 16};
  return {1.0 / 8, 6.0 / 8, 1.0 / 8};
}

EdgeMask SmoothEdgeRule() { return {3.0 / 8, 3.0 / 8, 1.0 / 8}; }

EdgeMask CreaseEdgeRule(bool v0_is_corner, bool v1_is_corner) {
  if (v0_is_corner && !v1_is_corner) return {3.0 / 4, 1.0 / 4, 0};
  if (v1_is_corner && !v0_is_corner) return {1.0 / 4, 3.0 / 4, 0};
  return {0.5, 0.5, 0};
}

SmoothVertexMask SmoothLimitRule(int valence) {
  const double w = 3.0 * valence / (8.0 * LoopAlpha(valence));
  return {w / (w + valence), 1.0 / (w + valence)};
}

CreaseVertexMask CreaseLimitRule(bool c0_is_corner, bool c1_is_corner) {
  if (c0_is_corner && c1_is_corner) return {1.0 / 4, 2.0 / 4, 1.0 / 4};
  if (c0_is_corner) return {3.0 / 12, 7.0 / 12, 2.0 / 12};
  if (c1_is_corner) return {2.0 / 12, 7.0 / 12, 3.0 / 12};
  return {1.0 / 6, 4.0 / 6, 1.0 / 6};
}

}  // namespace sdvi::rules
