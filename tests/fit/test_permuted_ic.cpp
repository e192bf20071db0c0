// SPDX-License-Identifier: GPL-3.0-or-later
// The colour fit's preconditioner (engine/fit/src/permuted_ic.h) is Eigen's
// IncompleteCholesky<double> with AMD ordering bit for bit, on matrices shaped like the fit's
// normal matrix: symmetric pattern stored in full with ascending rows, values whose two
// triangles may differ in the last bits (A is summed per triangle in two orders).
#include <catch2/catch.hpp>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

#include <cstdint>
#include <vector>

#include "permuted_ic.h"

namespace {

// A w x h grid's vertices joined to their 8 neighbours (and 2 steps right on every third
// row, so that the graph is not a plain stencil), weights from a fixed pseudo-random
// sequence; diagonally dominant, so positive definite. asymmetry > 0 perturbs the upper
// triangle's values by that relative amount.
Eigen::SparseMatrix<double> GridMatrix(int w, int h, uint32_t seed, double asymmetry) {
  uint32_t state = seed;
  auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return double(state >> 8) / double(1u << 24);
  };
  const int n = w * h;
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<double> diagonal(size_t(n), 1e-3);
  auto link = [&](int a, int b) {
    const double v = 0.1 + next();
    entries.emplace_back(a, b, -v);
    entries.emplace_back(b, a, -v * (1 + asymmetry * (next() - 0.5)));
    diagonal[size_t(a)] += v;
    diagonal[size_t(b)] += v;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      if (x + 1 < w) link(i, i + 1);
      if (y + 1 < h) link(i, i + w);
      if (x + 1 < w && y + 1 < h) link(i, i + w + 1);
      if (x > 0 && y + 1 < h) link(i, i + w - 1);
      if (y % 3 == 0 && x + 2 < w) link(i, i + 2);
    }
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, diagonal[size_t(i)] * (1 + 0.5 * next()));
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  m.makeCompressed();
  return m;
}

}  // namespace

TEST_CASE("PermutedIncompleteCholesky equals Eigen's IncompleteCholesky bit for bit", "[color_fit]") {
  for (double asymmetry : {0.0, 1e-12}) {
    for (int size : {7, 40}) {
      const Eigen::SparseMatrix<double> a = GridMatrix(size, size + 3, uint32_t(size), asymmetry);
      Eigen::IncompleteCholesky<double> eigen;
      eigen.compute(a);
      sdvi::fit_internal::PermutedIncompleteCholesky ours;
      ours.compute(a);
      REQUIRE(eigen.info() == Eigen::Success);
      REQUIRE(ours.info() == Eigen::Success);
      REQUIRE(eigen.permutationP().size() == a.rows());  // the AMD path, not the identity
      for (int k = 0; k < 3; ++k) {
        const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(a.rows(), [&](Eigen::Index i) {
          return double((i * 7919 + k * 104729) % 1000) / 100.0 - 5.0;
        });
        const Eigen::VectorXd expected = eigen.solve(b);
        const Eigen::VectorXd got = ours.solve(b);
        INFO("size " << size << " asymmetry " << asymmetry << " right-hand side " << k);
        CHECK((got.array() == expected.array()).all());
      }
      // And as CG's preconditioner: the same iterates, so the same solution bit for bit.
      Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                               Eigen::IncompleteCholesky<double>>
          cg_eigen;
      Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                               sdvi::fit_internal::PermutedIncompleteCholesky>
          cg_ours;
      cg_eigen.setTolerance(1e-12);
      cg_ours.setTolerance(1e-12);
      cg_eigen.compute(a);
      cg_ours.compute(a);
      const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
      const Eigen::VectorXd x_eigen = cg_eigen.solve(b);
      const Eigen::VectorXd x_ours = cg_ours.solve(b);
      CHECK(cg_eigen.iterations() == cg_ours.iterations());
      CHECK(cg_eigen.iterations() > 1);
      CHECK((x_eigen.array() == x_ours.array()).all());
    }
  }
}
