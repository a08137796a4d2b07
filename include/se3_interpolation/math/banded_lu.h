// LU factorisation with partial pivoting of a banded matrix, in O(size · lower · (lower + upper)).
//
// The Newton systems of the interpolating spline are block tridiagonal (interpolating_spline.h),
// i.e. banded with lower = upper = 2·dof − 1. Row interchanges can widen the upper band to
// lower + upper, so every row r stores columns r − lower … r + lower + upper (the layout of
// LAPACK's dgbtrf). Multipliers of L are kept where they were computed and interchanges are
// replayed on the right-hand side in the same order, as in dgbtrs.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
class BandedLu
{
public:
  /// A zero matrix of size × size whose nonzeros lie in −lower ≤ column − row ≤ upper.
  BandedLu(Eigen::Index size, Eigen::Index lower, Eigen::Index upper)
    : n_(size), kl_(lower), ku_(upper), width_(2 * lower + upper + 1), a_(size * width_, 0.0), pivot_(size, 0)
  {
  }

  Eigen::Index size() const { return n_; }

  /// Entry (row, column); −lower ≤ column − row ≤ upper before factorize().
  double& operator()(Eigen::Index row, Eigen::Index column) { return a_[index(row, column)]; }
  double operator()(Eigen::Index row, Eigen::Index column) const { return a_[index(row, column)]; }

  /// In-place P A = L U. Throws ConvergenceError if a pivot is zero or not finite.
  void factorize()
  {
    for (Eigen::Index j = 0; j < n_; ++j)
    {
      const Eigen::Index last_row = std::min(j + kl_, n_ - 1);
      const Eigen::Index last_column = std::min(j + kl_ + ku_, n_ - 1);
      Eigen::Index p = j;
      for (Eigen::Index r = j + 1; r <= last_row; ++r)
        if (std::abs((*this)(r, j)) > std::abs((*this)(p, j)))
          p = r;
      const double pivot = (*this)(p, j);
      if (pivot == 0.0 || !std::isfinite(pivot))
        throw ConvergenceError("the linearised system is singular or not finite (pivot " + std::to_string(j) +
                               ")");
      pivot_[static_cast<std::size_t>(j)] = p;
      if (p != j)
        for (Eigen::Index c = j; c <= last_column; ++c)
          std::swap((*this)(j, c), (*this)(p, c));
      for (Eigen::Index r = j + 1; r <= last_row; ++r)
      {
        const double l = (*this)(r, j) / pivot;
        (*this)(r, j) = l;
        if (l == 0.0)
          continue;
        for (Eigen::Index c = j + 1; c <= last_column; ++c)
          (*this)(r, c) -= l * (*this)(j, c);
      }
    }
  }

  /// x with A x = b, after factorize().
  Eigen::VectorXd solve(Eigen::VectorXd b) const
  {
    for (Eigen::Index j = 0; j < n_; ++j)
    {
      std::swap(b[j], b[pivot_[static_cast<std::size_t>(j)]]);
      const Eigen::Index last_row = std::min(j + kl_, n_ - 1);
      for (Eigen::Index r = j + 1; r <= last_row; ++r)
        b[r] -= (*this)(r, j) * b[j];
    }
    for (Eigen::Index j = n_ - 1; j >= 0; --j)
    {
      const Eigen::Index last_column = std::min(j + kl_ + ku_, n_ - 1);
      double s = b[j];
      for (Eigen::Index c = j + 1; c <= last_column; ++c)
        s -= (*this)(j, c) * b[c];
      b[j] = s / (*this)(j, j);
    }
    return b;
  }

private:
  std::size_t index(Eigen::Index row, Eigen::Index column) const
  {
    return static_cast<std::size_t>(row * width_ + (column - row + kl_));
  }

  Eigen::Index n_;
  Eigen::Index kl_;
  Eigen::Index ku_;
  Eigen::Index width_;
  std::vector<double> a_;
  std::vector<Eigen::Index> pivot_;
};

}  // namespace se3_interpolation
