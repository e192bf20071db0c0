// SPDX-License-Identifier: GPL-3.0-or-later
// The split of the vertex budget between the feature layer and the interior samples
// (spec/METHOD.md section 6 step 3, "The feature budget").
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/features.h"

namespace sdvi {

struct FeatureBudgetOptions {
  double vertex_budget = 0;     // control vertices the features may take (pairs counted twice)
  double interior_spacing = 8;  // mean spacing of the interior samples, px: sqrt(pixels / budget)
  bool pairs = true;            // a feature costs its polygon twice (a thin structure four times)
  int coarse_levels = 3;        // coarser fits tried: tolerance and spacing x 2, x 4, x 8
  bool junctions = true;        // a feature also costs its junctions: half of (its polylines x
                                // the other's) per crossing of two control polygons
  int threads = 1;              // worker threads for the coarser fits; the choice does not
                                // depend on it (spec/METHOD.md section 6 step 1, "Threads")
};

struct FeatureBudgetStats {
  double vertices_detected = 0;  // cost of all non-boundary features as given
  double vertices_kept = 0;      // cost of what was kept
  uint32_t coarsened = 0;        // features kept with a coarser control polygon
  uint32_t dropped = 0;          // features dropped
};

// Polyline vertices a feature costs: its deBoor points, x 2 when paired, x 2 again for a
// thin structure (FeatureCurve::width > 0).
double FeatureVertexCost(const FeatureCurve& curve, bool pairs);

// Keeps the features within options.vertex_budget by their value per vertex. Boundary
// curves are always kept as they are; when every feature fits, all are kept unchanged.
// Otherwise each feature has options: dropped, as given (level 0) or refitted to its own
// spline at level k = 1..coarse_levels (FitChain with tolerance 1.5 x 2^k px, initial
// spacing 8 x 2^k, max spacing 12 x 2^k; corners kept), each with a cost (FeatureVertexCost,
// plus its junction vertices when options.junctions)
// and a value, the squared error the feature removes from the interior's reconstruction:
//   value = contrast^2 x length x max(0, 1 - 12 e / interior_spacing)
// (an edge the interior represents is a ramp about the sample spacing s wide, squared error
// contrast^2 s / 12 per unit length; one placed e px off, e the coarse spline's mean distance
// from the given one, leaves an e px band wrong, contrast^2 e; contrast 0, i.e. unknown,
// counts as 1). The choice is the greedy solution of this
// multiple-choice knapsack: the steps along each feature's upper convex hull of (cost,
// value), from "dropped" to finer levels, taken in decreasing value per vertex while they
// fit. The kept curves stay in input order.
std::vector<FeatureCurve> FitFeaturesToBudget(const std::vector<FeatureCurve>& curves,
                                              const FeatureBudgetOptions& options,
                                              FeatureBudgetStats* stats = nullptr);

}  // namespace sdvi
