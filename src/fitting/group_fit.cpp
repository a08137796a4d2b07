// The group part of the fit's unknowns (bspline_fit_detail.h's GroupFit): its start at the
// Greville abscissae and its Levenberg–Marquardt steps on the group, with the data residuals'
// analytic Jacobians (de Boor's triangle) and the jerk residuals' central differences of exact
// jets. Instantiated for So3Group (the double geodesic's rotation) and Se3Group (screw).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "bspline_fit_detail.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/banded_lu.h"

namespace se3_interpolation
{
namespace fitting_detail
{
namespace
{
/// The step of the central difference of the exact angular jerk in a control pose's tangent
/// (rad, m): truncation ~h² ≈ 1e-12 and rounding ~1e-16/h ≈ 1e-10 relative to the jerk.
constexpr double kJerkDifferenceStep = 1e-6;

/// The third-order jet of the B-spline in L's geometry at t in span k (de Boor in Jet<3>).
template <class L>
auto deBoorJet(const std::vector<typename L::Element>& d, const std::vector<double>& u, int m, std::size_t k, double t)
{
  using G = typename L::Geometry;
  using JetPoint = decltype(L::castJet(d[0]));
  const std::size_t p = static_cast<std::size_t>(m);
  std::array<JetPoint, kMaxFitDegree + 1> node;
  for (std::size_t j = 0; j <= p; ++j)
    node[j] = L::castJet(d[k - p + j]);
  const Jet<3> tj = Jet<3>::variable(t);
  for (std::size_t r = 1; r <= p; ++r)
    for (std::size_t j = p; j >= r; --j)
    {
      const std::size_t i = k - p + j;
      const Jet<3> alpha = (tj - Jet<3>(u[i])) * Jet<3>(1.0 / (u[i + p + 1 - r] - u[i]));
      node[j] = geodesic<G>(node[j - 1], node[j], alpha);
    }
  return node[p];
}

}  // namespace

template <class L>
std::vector<double> GroupFit<L>::squaredDistances(const std::vector<Element>& control)
{
  std::vector<double> s(pb_.size());
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    checkDeadlineEvery(i, 4096, "fit");
    const Element c = tri_.evaluate(control, pb_.knots, pb_.options.degree, pb_.spans[i], (*pb_.times)[i], false);
    s[i] = L::residual(c, L::ofPose((*pb_.poses)[i]), pb_.options.rotation_scale, nullptr).squaredNorm();
  }
  return s;
}

template <class L>
double GroupFit<L>::jerkTerm(const std::vector<Element>& control) const
{
  if (pb_.options.smoothing == 0.0)
    return 0.0;
  double sum = 0.0;
  for (const QuadraturePoint& q : pb_.quadrature)
    sum += q.weight *
           L::jerk(deBoorJet<L>(control, pb_.knots, pb_.options.degree, q.span, q.t), pb_.options.rotation_scale)
               .squaredNorm();
  return pb_.options.smoothing * sum;
}

template <class L>
double GroupFit<L>::objective(const std::vector<Element>& control, const std::vector<double>& other)
{
  std::vector<double> s;
  try
  {
    s = squaredDistances(control);
  }
  catch (const NonUniqueGeodesicError&)
  {
    return std::numeric_limits<double>::infinity();
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    sum += loss(other[i] + s[i]);
  return pb_.inverse_count * sum + jerkTerm(control);
}

template <class L>
BandedNormalEquations GroupFit<L>::normalEquations()
{
  const int m = pb_.options.degree;
  BandedNormalEquations eq;
  eq.dim = static_cast<Eigen::Index>(pb_.n) * D;
  eq.band = D * (m + 1) - 1;
  eq.h.assign((static_cast<std::size_t>(eq.dim)) * static_cast<std::size_t>(2 * eq.band + 1), 0.0);
  eq.g = Eigen::VectorXd::Zero(eq.dim);
  typename DeBoorTriangle<L>::Jacobians jac;
  const std::size_t p = static_cast<std::size_t>(m);
  auto accumulate = [&](std::size_t k, const Vec<D>& r, double w) {
    const Eigen::Index first = static_cast<Eigen::Index>(k - p) * D;
    for (std::size_t a = 0; a <= p; ++a)
    {
      const Mat<D>& ja = jac[a];
      eq.g.template segment<D>(first + static_cast<Eigen::Index>(a) * D) += w * ja.transpose() * r;
      for (std::size_t b = a; b <= p; ++b)
      {
        const Mat<D> block = w * ja.transpose() * jac[b];
        const Eigen::Index r0 = first + static_cast<Eigen::Index>(a) * D;
        const Eigen::Index c0 = first + static_cast<Eigen::Index>(b) * D;
        for (int x = 0; x < D; ++x)
          for (int y = 0; y < D; ++y)
          {
            eq.entry(r0 + x, c0 + y) += block(x, y);
            if (b != a)
              eq.entry(c0 + y, r0 + x) += block(x, y);
          }
      }
    }
  };
  for (std::size_t i = 0; i < pb_.size(); ++i)
  {
    checkDeadlineEvery(i, 2048, "fit");
    const std::size_t k = pb_.spans[i];
    const Element c = tri_.evaluate(control_, pb_.knots, m, k, (*pb_.times)[i], true);
    Mat<D> e;
    const Vec<D> r = L::residual(c, L::ofPose((*pb_.poses)[i]), pb_.options.rotation_scale, &e);
    tri_.pullBack(e, &jac);
    accumulate(k, r, pb_.inverse_count * pb_.weights[i]);
  }
  if (pb_.options.smoothing > 0.0)
    for (const QuadraturePoint& q : pb_.quadrature)
    {
      checkDeadline("fit");
      jerkJacobian(q, &jac);
      const Vec<D> r = L::jerk(deBoorJet<L>(control_, pb_.knots, m, q.span, q.t), pb_.options.rotation_scale);
      accumulate(q.span, r, pb_.options.smoothing * q.weight);
    }
  return eq;
}

template <class L>
double GroupFit<L>::step(const std::vector<double>& other, double* objective_value)
{
  BandedNormalEquations eq = normalEquations();
  const Eigen::Index dim = eq.dim;
  const Eigen::Index band = eq.band;
  const double current = *objective_value;
  for (;;)
  {
    BandedLu lu(dim, band, band);
    for (Eigen::Index r = 0; r < dim; ++r)
      for (Eigen::Index c = std::max<Eigen::Index>(0, r - band); c <= std::min(dim - 1, r + band); ++c)
        lu(r, c) = eq.entry(r, c) + (r == c ? damping_ * (eq.entry(r, r) + 1e-12) : 0.0);
    Eigen::VectorXd delta = -eq.g;
    if (lu.tryFactorize() == dim)
    {
      lu.solveInPlace(&delta);
      std::vector<Element> trial(control_.size());
      for (std::size_t j = 0; j < control_.size(); ++j)
        trial[j] = L::exp(control_[j], Vec<D>(delta.template segment<D>(static_cast<Eigen::Index>(j) * D)));
      ++iterations_;
      const double value = objective(trial, other);
      const double size = delta.lpNorm<Eigen::Infinity>();
      if (std::isfinite(value) && value <= current)
      {
        control_ = std::move(trial);
        *objective_value = value;
        damping_ = std::max(damping_ / 3.0, kInitialDamping * 1e-6);
        // An improvement at the objective's rounding is convergence, whatever the step.
        return current - value <= kRoundingImprovement * current ? 0.0 : size;
      }
      // A step this small that does not improve: the objective is at its rounding floor.
      if (size < kConvergedStep)
        return 0.0;
    }
    damping_ *= 4.0;
    if (damping_ > kMaxDamping)
      return 0.0;
  }
}

template <class L>
void GroupFit<L>::jerkJacobian(const QuadraturePoint& q, typename DeBoorTriangle<L>::Jacobians* jac)
{
  const std::size_t p = static_cast<std::size_t>(pb_.options.degree);
  std::vector<Element>& work = control_;
  for (std::size_t a = 0; a <= p; ++a)
  {
    const std::size_t j = q.span - p + a;
    const Element saved = work[j];
    for (int x = 0; x < D; ++x)
    {
      Vec<D> h = Vec<D>::Zero();
      h[x] = kJerkDifferenceStep;
      work[j] = L::exp(saved, h);
      const Vec<D> plus =
          L::jerk(deBoorJet<L>(work, pb_.knots, pb_.options.degree, q.span, q.t), pb_.options.rotation_scale);
      work[j] = L::exp(saved, Vec<D>(-h));
      const Vec<D> minus =
          L::jerk(deBoorJet<L>(work, pb_.knots, pb_.options.degree, q.span, q.t), pb_.options.rotation_scale);
      work[j] = saved;
      (*jac)[a].col(x) = (plus - minus) / (2.0 * kJerkDifferenceStep);
    }
  }
}

template <class L>
std::vector<typename L::Element> grevilleStart(const FitProblem& pb)
{
  const std::vector<double>& t = *pb.times;
  const std::size_t p = static_cast<std::size_t>(pb.options.degree);
  std::vector<typename L::Element> d(pb.n);
  for (std::size_t j = 0; j < pb.n; ++j)
  {
    double tau = 0.0;
    for (std::size_t s = 1; s <= p; ++s)
      tau += pb.knots[j + s];
    tau = p == 0 ? pb.knots[j] : tau / static_cast<double>(p);
    const std::size_t i = static_cast<std::size_t>(
        std::max<std::ptrdiff_t>(0, (std::upper_bound(t.begin(), t.end(), tau) - t.begin()) - 1));
    const typename L::Element a = L::ofPose((*pb.poses)[i]);
    if (i + 1 >= t.size())
    {
      d[j] = a;
      continue;
    }
    const typename L::Element b = L::ofPose((*pb.poses)[i + 1]);
    const double alpha = std::clamp((tau - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0);
    try
    {
      d[j] = L::exp(a, Vec<L::kDof>(alpha * L::log(a, b)));
    }
    catch (const NonUniqueGeodesicError&)
    {
      d[j] = alpha < 0.5 ? a : b;
    }
  }
  return d;
}

template class GroupFit<So3Group>;
template class GroupFit<Se3Group>;
template std::vector<So3Group::Element> grevilleStart<So3Group>(const FitProblem& pb);
template std::vector<Se3Group::Element> grevilleStart<Se3Group>(const FitProblem& pb);

}  // namespace fitting_detail
}  // namespace se3_interpolation
