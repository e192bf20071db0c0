// SPDX-License-Identifier: GPL-3.0-or-later
// The colour fit's CG preconditioner (color_fit.cpp): Eigen's IncompleteCholesky<double>
// with its AMD ordering, computed with less memory (spec/METHOD.md section 5, memory).
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include <algorithm>
#include <utility>
#include <vector>

namespace sdvi::fit_internal {

// Bit for bit the preconditioner Eigen::IncompleteCholesky<double> (lower triangle, AMD
// ordering) computes for a symmetric matrix A stored in full (both triangles, each column's
// rows ascending, compressed), as a ConjugateGradient preconditioner. Eigen's class holds
// at once, for a 4K image's 5.8M-entry A: a valued copy of A grown by AMD's elbow room
// (about 2.2 A), then the permuted matrix P A P^T in full, twice (a row-major temporary and
// its column-major copy), beside the factor. Here:
//  - the AMD permutation comes from the same routine on the same pattern (A's own, which is
//    what AMDOrdering copies A into), held once, a byte a value, with the room reserved;
//  - the lower triangle of P A P^T, the only part IncompleteCholesky reads, is built
//    directly (each column's rows ascending, values from A's lower triangle as Eigen takes
//    them) and factored by IncompleteCholesky with the natural ordering: the same initial
//    factor, so the same factor and scaling;
//  - solve applies P and its inverse around that factor, as Eigen's solve does.
class PermutedIncompleteCholesky {
 public:
  using Permutation = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;

  template <typename Matrix>
  PermutedIncompleteCholesky& analyzePattern(const Matrix&) { return *this; }
  template <typename Matrix>
  PermutedIncompleteCholesky& factorize(const Matrix& a) { return compute(a); }

  // The AMD permutation compute finds for a matrix of this pattern (n x n, nnz entries,
  // compressed column starts outer and row indices inner, as A's): computed apart, it can
  // be found while A's values are still being assembled (PresetOrdering).
  static Permutation Ordering(Eigen::Index n, Eigen::Index nnz, const int* outer, const int* inner) {
    Eigen::SparseMatrix<signed char, Eigen::ColMajor, int> pattern(n, n);
    pattern.data().reserve(nnz + nnz / 5 + 2 * n);  // minimum_degree_ordering's room
    pattern.resizeNonZeros(nnz);
    std::copy(outer, outer + n + 1, pattern.outerIndexPtr());
    std::copy(inner, inner + nnz, pattern.innerIndexPtr());
    std::fill(pattern.valuePtr(), pattern.valuePtr() + nnz, static_cast<signed char>(1));
    Permutation inverse;
    Eigen::internal::minimum_degree_ordering(pattern, inverse);
    return inverse.inverse();
  }

  // The next compute uses `ordering` (Ordering of its matrix's pattern) instead of finding it.
  void PresetOrdering(Permutation ordering) {
    permutation_ = std::move(ordering);
    preset_ = true;
  }

  template <typename Matrix>
  PermutedIncompleteCholesky& compute(const Matrix& a) {
    const Eigen::Index n = a.cols();
    if (!preset_ || permutation_.size() != n) {
      permutation_ = Ordering(n, a.nonZeros(), a.outerIndexPtr(), a.innerIndexPtr());
    }
    preset_ = false;
    const int* p = permutation_.indices().data();
    // Entry (i, j) of A's lower triangle (i >= j) is entry (max, min) of (p[i], p[j]) of the
    // permuted lower triangle.
    Eigen::SparseMatrix<double> lower(n, n);
    {
      std::vector<int> count(size_t(n) + 1, 0);
      for (Eigen::Index j = 0; j < n; ++j)
        for (typename Matrix::InnerIterator it(a, j); it; ++it)
          if (it.row() >= j) ++count[size_t(std::min(p[it.row()], p[j])) + 1];
      for (Eigen::Index j = 0; j < n; ++j) count[size_t(j) + 1] += count[size_t(j)];
      lower.resizeNonZeros(count[size_t(n)]);
      std::copy(count.begin(), count.end(), lower.outerIndexPtr());
      for (Eigen::Index j = 0; j < n; ++j)
        for (typename Matrix::InnerIterator it(a, j); it; ++it) {
          if (it.row() < j) continue;
          const int r = p[it.row()], c = p[j];
          const int k = count[size_t(std::min(r, c))]++;
          lower.innerIndexPtr()[k] = std::max(r, c);
          lower.valuePtr()[k] = it.value();
        }
      std::vector<std::pair<int, double>> column;
      for (Eigen::Index j = 0; j < n; ++j) {
        int* rows = lower.innerIndexPtr() + lower.outerIndexPtr()[j];
        double* values = lower.valuePtr() + lower.outerIndexPtr()[j];
        const int size = lower.outerIndexPtr()[j + 1] - lower.outerIndexPtr()[j];
        column.clear();
        for (int k = 0; k < size; ++k) column.emplace_back(rows[k], values[k]);
        std::sort(column.begin(), column.end());
        for (int k = 0; k < size; ++k) rows[k] = column[size_t(k)].first, values[k] = column[size_t(k)].second;
      }
    }
    factor_.compute(lower);
    return *this;
  }

  // P^-1 (the factor's solve) P b, as IncompleteCholesky::solve with its permutation.
  template <typename Rhs>
  Eigen::VectorXd solve(const Eigen::MatrixBase<Rhs>& b) const {
    const Eigen::VectorXd permuted = permutation_ * b;
    const Eigen::VectorXd x = factor_.solve(permuted);
    return permutation_.inverse() * x;
  }

  Eigen::ComputationInfo info() const { return factor_.info(); }

 private:
  Permutation permutation_;
  bool preset_ = false;
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>> factor_;
};

}  // namespace sdvi::fit_internal
