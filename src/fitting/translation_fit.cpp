// The translation of the double geodesic's fit (bspline_fit_detail.h's TranslationFit): the
// Euclidean B-spline Σ B_j(t) p_j is linear in its control positions, so its part of the objective
// is linear least squares, solved exactly from banded normal equations (no Lie groups involved).
#include "bspline_fit_detail.h"
#include "se3_interpolation/math/banded_lu.h"

namespace se3_interpolation
{
namespace fitting_detail
{
std::vector<Vector3<double>> TranslationFit::solve() const
{
  const int m = pb_.options.degree;
  const std::size_t p = static_cast<std::size_t>(m);
  const Eigen::Index n = static_cast<Eigen::Index>(pb_.n);
  BandedLu lu(n, m, m);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  for (std::size_t i = 0; i < pb_.size(); ++i)
  {
    const double w = pb_.inverse_count * pb_.weights[i];
    const Eigen::Index first = static_cast<Eigen::Index>(pb_.spans[i] - p);
    for (Eigen::Index a = 0; a <= m; ++a)
    {
      rhs.row(first + a) += w * basis_[i][a] * (*pb_.poses)[i].p.transpose();
      for (Eigen::Index b = 0; b <= m; ++b)
        lu(first + a, first + b) += w * basis_[i][a] * basis_[i][b];
    }
  }
  if (pb_.options.smoothing > 0.0)
    for (std::size_t q = 0; q < pb_.quadrature.size(); ++q)
    {
      const double w = pb_.options.smoothing * pb_.quadrature[q].weight;
      const Eigen::Index first = static_cast<Eigen::Index>(pb_.quadrature[q].span - p);
      for (Eigen::Index a = 0; a <= m; ++a)
        for (Eigen::Index b = 0; b <= m; ++b)
          lu(first + a, first + b) += w * jerk_basis_[q][a] * jerk_basis_[q][b];
    }
  lu.factorize();
  std::vector<Vector3<double>> out(pb_.n);
  for (int c = 0; c < 3; ++c)
  {
    Eigen::VectorXd x = rhs.col(c);
    lu.solveInPlace(&x);
    for (Eigen::Index j = 0; j < n; ++j)
      out[static_cast<std::size_t>(j)][c] = x[j];
  }
  return out;
}

std::vector<double> TranslationFit::squaredDistances(const std::vector<Vector3<double>>& control) const
{
  const std::size_t p = static_cast<std::size_t>(pb_.options.degree);
  std::vector<double> s(pb_.size());
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    Vector3<double> x = Vector3<double>::Zero();
    for (std::size_t a = 0; a <= p; ++a)
      x += basis_[i][static_cast<Eigen::Index>(a)] * control[pb_.spans[i] - p + a];
    s[i] = (x - (*pb_.poses)[i].p).squaredNorm();
  }
  return s;
}

double TranslationFit::jerkTerm(const std::vector<Vector3<double>>& control) const
{
  const std::size_t p = static_cast<std::size_t>(pb_.options.degree);
  double sum = 0.0;
  for (std::size_t q = 0; q < pb_.quadrature.size(); ++q)
  {
    Vector3<double> j = Vector3<double>::Zero();
    for (std::size_t a = 0; a <= p; ++a)
      j += jerk_basis_[q][static_cast<Eigen::Index>(a)] * control[pb_.quadrature[q].span - p + a];
    sum += pb_.quadrature[q].weight * j.squaredNorm();
  }
  return pb_.options.smoothing * sum;
}

}  // namespace fitting_detail
}  // namespace se3_interpolation
