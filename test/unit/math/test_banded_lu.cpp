// math/banded_lu.h: the banded LU against Eigen's dense LU with pivoting, and its singular case.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/math/banded_lu.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

// ---- banded_lu.h --------------------------------------------------------------------------

TEST(BandedLu, MatchesDenseLuWithPivoting)
{
  std::mt19937 rng(110);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial)
  {
    const Eigen::Index size = 30 + trial, lower = 1 + trial % 4, upper = 2 + trial % 3;
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(size, size);
    BandedLu banded(size, lower, upper);
    for (Eigen::Index r = 0; r < size; ++r)
      for (Eigen::Index c = std::max<Eigen::Index>(0, r - lower); c <= std::min(size - 1, r + upper); ++c)
      {
        // Zero diagonal every third row: elimination without row interchanges would fail.
        const double value = (r == c && r % 3 == 0) ? 0.0 : n(rng);
        dense(r, c) = value;
        banded(r, c) = value;
      }
    const Eigen::VectorXd b = Eigen::VectorXd::Random(size);
    banded.factorize();
    const Eigen::VectorXd x = banded.solve(b);
    const Eigen::VectorXd ref = dense.partialPivLu().solve(b);
    EXPECT_LT((x - ref).norm(), 1e-9 * (1.0 + ref.norm()));
    EXPECT_LT((dense * x - b).norm(), 1e-10 * (1.0 + b.norm()));
  }
}

TEST(BandedLu, SingularMatrixThrows)
{
  BandedLu banded(4, 1, 1);
  banded(0, 0) = 1.0;
  banded(1, 1) = 2.0;
  banded(3, 3) = 1.0;  // row and column 2 empty
  EXPECT_THROW(banded.factorize(), ConvergenceError);
}
