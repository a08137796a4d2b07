// The Jacobians of the exponentials of the two groups the fit works on (bspline_fit_detail.h's
// So3Group and Se3Group): SO(3)'s right Jacobian and its inverse, and Barfoot's Q, the coupling
// block of SE(3)'s. Out of line, so that the header keeps only what the templates need.
#include <cmath>

#include "bspline_fit_detail.h"

namespace se3_interpolation
{
namespace fitting_detail
{
namespace
{
/// Below this θ² the Jacobians' coefficients are their Taylor series (to θ⁴; the next term is
/// below 1e-15 relative there), above it their closed forms (whose cancellation costs at most
/// about 1e-10 relative at θ = 0.1).
constexpr double kJacobianSeriesThetaSquared = 1e-2;

/// The SO(3) right Jacobian's coefficients: J_r(w) = I − a W + b W² with W = [w]×,
/// a = (1 − cos θ)/θ², b = (θ − sin θ)/θ³.
void so3JacobianCoefficients(double theta2, double* a, double* b)
{
  if (theta2 < kJacobianSeriesThetaSquared)
  {
    *a = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0;
    *b = 1.0 / 6.0 - theta2 / 120.0 + theta2 * theta2 / 5040.0;
    return;
  }
  const double theta = std::sqrt(theta2);
  const double s = std::sin(0.5 * theta);
  *a = 2.0 * s * s / theta2;
  *b = (theta - std::sin(theta)) / (theta2 * theta);
}

}  // namespace

Mat<3> so3RightJacobian(const Vec<3>& w)
{
  double a, b;
  so3JacobianCoefficients(w.squaredNorm(), &a, &b);
  const Mat<3> h = hat(w);
  return Mat<3>::Identity() - a * h + b * h * h;
}

Mat<3> so3RightJacobianInverse(const Vec<3>& w)
{
  const double theta2 = w.squaredNorm();
  double c;
  if (theta2 < kJacobianSeriesThetaSquared)
    c = 1.0 / 12.0 + theta2 / 720.0 + theta2 * theta2 / 30240.0;
  else
  {
    const double theta = std::sqrt(theta2);
    c = 1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  const Mat<3> h = hat(w);
  return Mat<3>::Identity() + 0.5 * h + c * h * h;
}

Mat<3> barfootQ(const Vec<3>& rho, const Vec<3>& phi)
{
  const double theta2 = phi.squaredNorm();
  double c1, c2, c3;
  if (theta2 < kJacobianSeriesThetaSquared)
  {
    c1 = 1.0 / 6.0 - theta2 / 120.0 + theta2 * theta2 / 5040.0;
    c2 = 1.0 / 24.0 - theta2 / 720.0 + theta2 * theta2 / 40320.0;
    c3 = 1.0 / 120.0 - theta2 / 2520.0 + theta2 * theta2 / 120960.0;
  }
  else
  {
    const double theta = std::sqrt(theta2);
    const double s = std::sin(theta);
    const double c = std::cos(theta);
    c1 = (theta - s) / (theta2 * theta);
    c2 = (theta2 + 2.0 * c - 2.0) / (2.0 * theta2 * theta2);
    c3 = (2.0 * theta - 3.0 * s + theta * c) / (2.0 * theta2 * theta2 * theta);
  }
  const Mat<3> p = hat(phi);
  const Mat<3> r = hat(rho);
  const Mat<3> pr = p * r;
  const Mat<3> prp = pr * p;
  return 0.5 * r + c1 * (pr + r * p + prp) + c2 * (p * pr + r * p * p - 3.0 * prp) + c3 * (prp * p + p * prp);
}
}  // namespace fitting_detail
}  // namespace se3_interpolation
