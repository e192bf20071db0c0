// SPDX-License-Identifier: GPL-3.0-or-later
// The extended Loop scheme of Zhou, Zheng, Wei (IEEE TIP 2014), spec/SUBDIVISION.md:
// every refinement and limit mask in one place. Masks only, no storage and no topology:
// callers gather a vertex's neighbourhood and ask here for the weights. Every mask's
// weights sum to 1, so masks apply to all five coordinates (x, y, R, G, B) alike.
//
// Tags (see tagged_mesh.h): a vertex is smooth (no crease edge), crease (exactly two
// crease edges, not tagged corner) or corner (crease-degree 1 or >= 3, or tagged).
// Crease masks use only the two crease neighbours c0, c1: the sides of a crease decouple.
// spec/SUBDIVISION.md derives the masks, including the two clamped crease limit masks
// that the paper does not print.
#pragma once

namespace sdvi::rules {

// Loop's a(n) = 5/8 - (3 + 2 cos(2 pi / n))^2 / 64 for a smooth vertex of valence n.
double LoopAlpha(int valence);

// Smooth vertex: self * v + neighbour * (sum of its n neighbours).
struct SmoothVertexMask {
  double self = 1, neighbour = 0;
};
// Crease vertex: c0 * c0 + self * v + c1 * c1 (c0, c1 its crease neighbours).
struct CreaseVertexMask {
  double c0 = 0, self = 1, c1 = 0;
};
// Edge point of edge (v0, v1): end0 * v0 + end1 * v1 + opposite * (v2 + v3).
struct EdgeMask {
  double end0 = 0.5, end1 = 0.5, opposite = 0;
};

// Refinement, smooth vertex of valence n >= 3: (1 - a(n)) v + a(n)/n * sum of neighbours.
SmoothVertexMask SmoothVertexRule(int valence);
// Refinement, crease vertex:
//   no corner neighbour  (c0 + 6 v + c1) / 8
//   c0 corner only       (3 c0 + 11 v + 2 c1) / 16   (mirrored when c1 is the corner)
//   both corners         (3 c0 + 10 v + 3 c1) / 16
CreaseVertexMask CreaseVertexRule(bool c0_is_corner, bool c1_is_corner);
// Refinement, corner vertex: v (fixed). Stated for completeness; weight 1 on itself.
inline constexpr double kCornerVertexWeight = 1.0;

// Refinement, smooth edge with opposite vertices v2, v3: 3/8 v0 + 3/8 v1 + 1/8 (v2 + v3).
EdgeMask SmoothEdgeRule();
// Refinement, crease edge: 1/2 v0 + 1/2 v1 when neither or both ends are corners,
// 3/4 c + 1/4 other when exactly one end c is a corner.
EdgeMask CreaseEdgeRule(bool v0_is_corner, bool v1_is_corner);

// Limit, smooth vertex of valence n: (w v + sum of neighbours) / (w + n), w = 3n / (8 a(n)).
SmoothVertexMask SmoothLimitRule(int valence);
// Limit, crease vertex (the cubic B-spline of spec/METHOD.md section 2 at the vertex's knot):
//   no corner neighbour  (c0 + 4 v + c1) / 6
//   c0 corner only       (3 c0 + 7 v + 2 c1) / 12  (mirrored when c1 is the corner)
//   both corners         (c0 + 2 v + c1) / 4
CreaseVertexMask CreaseLimitRule(bool c0_is_corner, bool c1_is_corner);
// Limit, corner vertex: v.

}  // namespace sdvi::rules
