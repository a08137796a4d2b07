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
    : n_(size)
    , kl_(lower)
    , ku_(upper)
    , width_(2 * lower + upper + 1)
    , a_(size * width_, 0.0)
    , pivot_(size, 0)
    , last_(size, 0)
  {
  }

  Eigen::Index size() const { return n_; }

  /// Back to the zero matrix (same size and bands, no allocation), to be filled again.
  /// Only the entries that can be nonzero are cleared: columns r − lower … r + upper of each
  /// row r, and after a factorisation up to the row's last column of U (the rest of the fill
  /// space is zero still).
  void setZero()
  {
    for (Eigen::Index r = 0; r < n_; ++r)
    {
      const Eigen::Index first = std::max<Eigen::Index>(0, r - kl_);
      const Eigen::Index last = std::max(last_[static_cast<std::size_t>(r)], lastStored(r));
      std::fill(a_.begin() + static_cast<std::ptrdiff_t>(index(r, first)),
                a_.begin() + static_cast<std::ptrdiff_t>(index(r, last)) + 1, 0.0);
    }
  }

  /// Entry (row, column); −lower ≤ column − row ≤ upper before factorize().
  double& operator()(Eigen::Index row, Eigen::Index column) { return a_[index(row, column)]; }
  double operator()(Eigen::Index row, Eigen::Index column) const { return a_[index(row, column)]; }

  /// In-place P A = L U. Throws ConvergenceError if a pivot is zero or not finite.
  void factorize()
  {
    const Eigen::Index j = tryFactorize();
    if (j < n_)
      throw ConvergenceError("the linearised system is singular or not finite (pivot " + std::to_string(j) + ")");
  }

  /// factorize() without the exception: n if it succeeded, else the column whose pivot is zero
  /// or not finite (the factors are then incomplete). Each row's last nonzero column is
  /// tracked (an interchange or an elimination extends it to the pivot row's), so that rows are
  /// only updated as far as they can be nonzero: in a block tridiagonal matrix, about half of
  /// the band that interchanges could fill.
  Eigen::Index tryFactorize()
  {
    for (Eigen::Index r = 0; r < n_; ++r)
      last_[static_cast<std::size_t>(r)] = lastStored(r);
    for (Eigen::Index r = 0; r < n_; ++r)
    {
      // The last stored nonzero of row r (at most r + upper before any interchange).
      Eigen::Index& last = last_[static_cast<std::size_t>(r)];
      while (last > r && a_[index(r, last)] == 0.0)
        --last;
    }
    double* const a = a_.data();
    for (Eigen::Index j = 0; j < n_; ++j)
    {
      const Eigen::Index last_row = std::min(j + kl_, n_ - 1);
      Eigen::Index p = j;
      for (Eigen::Index r = j + 1; r <= last_row; ++r)
        if (std::abs(a[index(r, j)]) > std::abs(a[index(p, j)]))
          p = r;
      const double pivot = a[index(p, j)];
      if (pivot == 0.0 || !std::isfinite(pivot))
        return j;
      pivot_[static_cast<std::size_t>(j)] = p;
      // Row r's columns c ≥ j are contiguous from a + index(r, j) on.
      if (p != j)
      {
        const Eigen::Index last = std::max(last_[static_cast<std::size_t>(j)], last_[static_cast<std::size_t>(p)]);
        std::swap_ranges(a + index(j, j), a + index(j, last) + 1, a + index(p, j));
        last_[static_cast<std::size_t>(p)] = last;
        last_[static_cast<std::size_t>(j)] = last;
      }
      const Eigen::Index last = last_[static_cast<std::size_t>(j)];
      const Eigen::Index count = last - j;
      const double* __restrict pivot_row = a + index(j, j) + 1;
      for (Eigen::Index r = j + 1; r <= last_row; ++r)
      {
        double* __restrict row = a + index(r, j);
        const double l = row[0] / pivot;
        row[0] = l;
        if (l == 0.0)
          continue;
        ++row;
        for (Eigen::Index c = 0; c < count; ++c)
          row[c] -= l * pivot_row[c];
        Eigen::Index& row_last = last_[static_cast<std::size_t>(r)];
        row_last = std::max(row_last, last);
      }
    }
    return n_;
  }

  /// x with A x = b, after factorize().
  Eigen::VectorXd solve(Eigen::VectorXd b) const
  {
    solveInPlace(&b);
    return b;
  }

  /// *b ← A⁻¹ *b, after factorize() (no allocation).
  void solveInPlace(Eigen::VectorXd* x) const
  {
    Eigen::VectorXd& b = *x;
    for (Eigen::Index j = 0; j < n_; ++j)
    {
      std::swap(b[j], b[pivot_[static_cast<std::size_t>(j)]]);
      const Eigen::Index last_row = std::min(j + kl_, n_ - 1);
      const double bj = b[j];
      if (bj == 0.0)
        continue;
      for (Eigen::Index r = j + 1; r <= last_row; ++r)
        b[r] -= a_[index(r, j)] * bj;
    }
    double* const x_data = b.data();
    for (Eigen::Index j = n_ - 1; j >= 0; --j)
    {
      const Eigen::Index count = last_[static_cast<std::size_t>(j)] - j;
      const double* row = a_.data() + index(j, j);
      const double* tail = x_data + j + 1;
      double s = x_data[j];
      for (Eigen::Index c = 0; c < count; ++c)
        s -= row[c + 1] * tail[c];
      x_data[j] = s / row[0];
    }
  }

private:
  std::size_t index(Eigen::Index row, Eigen::Index column) const
  {
    return static_cast<std::size_t>(row * width_ + (column - row + kl_));
  }

  /// The last column row r can hold before factorize(): r + upper, within the matrix.
  Eigen::Index lastStored(Eigen::Index r) const { return std::min(r + ku_, n_ - 1); }

  Eigen::Index n_;
  Eigen::Index kl_;
  Eigen::Index ku_;
  Eigen::Index width_;
  std::vector<double> a_;
  std::vector<Eigen::Index> pivot_;
  std::vector<Eigen::Index> last_;  ///< per row, the last column that may be nonzero in U
};

}  // namespace se3_interpolation
