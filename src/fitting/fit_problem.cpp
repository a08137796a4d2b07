// The problem of curve fit (bspline_fit_detail.h's FitProblem), what both parts of the unknowns
// read: the knot layout (M uniform intervals, clamped: fitIntervals), the Euclidean B-spline basis
// and its derivatives, the jerk term's quadrature and the checks of the input.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "bspline_fit_detail.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/quadrature.h"

namespace se3_interpolation
{
namespace fitting_detail
{
Eigen::MatrixXd basisDerivatives(const std::vector<double>& u, int m, std::size_t k, double t, int order)
{
  const std::size_t p = static_cast<std::size_t>(m);
  Eigen::MatrixXd ndu(p + 1, p + 1);
  std::vector<double> left(p + 1), right(p + 1);
  ndu(0, 0) = 1.0;
  for (std::size_t j = 1; j <= p; ++j)
  {
    left[j] = t - u[k + 1 - j];
    right[j] = u[k + j] - t;
    double saved = 0.0;
    for (std::size_t r = 0; r < j; ++r)
    {
      ndu(j, r) = right[r + 1] + left[j - r];  // lower triangle: knot differences
      const double temp = ndu(r, j - 1) / ndu(j, r);
      ndu(r, j) = saved + right[r + 1] * temp;  // upper triangle: basis functions
      saved = left[j - r] * temp;
    }
    ndu(j, j) = saved;
  }
  const int n = std::min(order, m);
  Eigen::MatrixXd ders = Eigen::MatrixXd::Zero(order + 1, m + 1);
  for (std::size_t j = 0; j <= p; ++j)
    ders(0, static_cast<Eigen::Index>(j)) = ndu(j, p);
  Eigen::MatrixXd a(2, p + 1);
  for (int r = 0; r <= m; ++r)
  {
    int s1 = 0, s2 = 1;
    a(0, 0) = 1.0;
    for (int kk = 1; kk <= n; ++kk)
    {
      double d = 0.0;
      const int rk = r - kk, pk = m - kk;
      if (r >= kk)
      {
        a(s2, 0) = a(s1, 0) / ndu(pk + 1, rk);
        d = a(s2, 0) * ndu(rk, pk);
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? kk - 1 : m - r;
      for (int j = j1; j <= j2; ++j)
      {
        a(s2, j) = (a(s1, j) - a(s1, j - 1)) / ndu(pk + 1, rk + j);
        d += a(s2, j) * ndu(rk + j, pk);
      }
      if (r <= pk)
      {
        a(s2, kk) = -a(s1, kk - 1) / ndu(pk + 1, r);
        d += a(s2, kk) * ndu(r, pk);
      }
      ders(kk, r) = d;
      std::swap(s1, s2);
    }
  }
  double factor = m;
  for (int kk = 1; kk <= n; ++kk)
  {
    ders.row(kk) *= factor;
    factor *= (m - kk);
  }
  return ders;
}

std::string formatSeconds(double t)
{
  std::ostringstream s;
  s.precision(9);
  s << t;
  return s.str();
}

namespace
{
/// The Schoenberg–Whitney condition for the least-squares system of n control points to be
/// nonsingular without smoothing: increasing waypoints i_0 < … < i_{n−1} with t_{i_j} inside the
/// support (u_j, u_{j+m+1}) of N_j (closed at the domain's ends). Matched greedily; the first
/// control point without a waypoint names the gap.
void checkSchoenbergWhitney(const std::vector<double>& times, const std::vector<double>& u, std::size_t n, int m)
{
  const std::size_t p = static_cast<std::size_t>(m);
  const double t0 = u[p], t1 = u[n];
  std::size_t i = 0;
  for (std::size_t j = 0; j < n; ++j)
  {
    const double lo = u[j], hi = u[j + p + 1];
    while (i < times.size() && !(times[i] > lo || (lo == t0 && times[i] >= lo)))
      ++i;
    if (i == times.size() || !(times[i] < hi || (hi == t1 && times[i] <= hi)))
    {
      // The knot interval of the support with the fewest waypoints is the gap.
      double gap_lo = lo, gap_hi = hi;
      for (std::size_t s = j; s <= j + p && s + 1 < u.size(); ++s)
      {
        if (!(u[s] < u[s + 1]))
          continue;
        const auto first = std::lower_bound(times.begin(), times.end(), u[s]);
        if (first == times.end() || *first > u[s + 1])
        {
          gap_lo = u[s];
          gap_hi = u[s + 1];
          break;
        }
      }
      throw InvalidInputError("control_period: the waypoints leave control pose " + std::to_string(j) +
                              " of the fit undetermined: too few waypoints between t = " + formatSeconds(gap_lo) +
                              " and t = " + formatSeconds(gap_hi) +
                              " s (a gap in the recording); a longer control_period, or smoothing > 0");
    }
    ++i;
  }
}

/// The Gauss–Legendre nodes of the jerk term (QuadraturePoint): none below degree 3, where the
/// B-spline has no jerk between its knots.
std::vector<QuadraturePoint> jerkQuadrature(const std::vector<double>& u, std::size_t n, int m)
{
  std::vector<QuadraturePoint> q;
  if (m < 3)
    return q;
  for (std::size_t k = static_cast<std::size_t>(m); k < n; ++k)
  {
    const double a = u[k], b = u[k + 1];
    if (!(a < b))
      continue;
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (std::size_t g = 0; g < kGauss4Nodes.size(); ++g)
      q.push_back({ k, mid + half * kGauss4Nodes[g], half * kGauss4Weights[g] });
  }
  return q;
}

/// The checks of the waypoints, the times and the options that fitBSpline documents (bspline_fit.h).
void validateOptions(const std::vector<Pose<double>>& poses, const std::vector<double>& times, const FitOptions& o)
{
  if (times.size() != poses.size())
    throw InvalidInputError("times: curve 'fit' needs one time per waypoint (" + std::to_string(times.size()) +
                            " times for " + std::to_string(poses.size()) + " waypoints)");
  if (poses.size() < 2)
    throw InvalidInputError("waypoints: curve 'fit' needs at least 2 waypoints");
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!std::isfinite(times[i]) || (i > 0 && !(times[i] > times[i - 1])))
      throw InvalidInputError(indexedField("times", i) + ": times must be finite and strictly increasing");
  if (o.degree < 1 || o.degree > kMaxFitDegree)
    throw InvalidInputError("degree: " + std::to_string(o.degree) + " for curve 'fit'; expected 1 … " +
                            std::to_string(kMaxFitDegree));
  if (!std::isfinite(o.smoothing) || o.smoothing < 0.0)
    throw InvalidInputError("smoothing: must be a finite number ≥ 0");
  if (o.smoothing > 0.0 && o.degree < 3)
    throw InvalidInputError("smoothing: penalises the jerk, which a B-spline of degree " + std::to_string(o.degree) +
                            " does not have between its knots; use degree 3 or more");
  if (o.loss == FitLoss::kHuber && !(std::isfinite(o.loss_scale) && o.loss_scale > 0.0))
    throw InvalidInputError("loss_scale: loss 'huber' needs a positive loss_scale (m of chord distance)");
  if (!(std::isfinite(o.rotation_scale) && o.rotation_scale > 0.0))
    throw InvalidInputError("rotation_scale: must be positive");
}

}  // namespace

FitProblem makeProblem(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                       const FitOptions& options)
{
  validateOptions(poses, times, options);
  FitProblem pb;
  pb.poses = &poses;
  pb.times = &times;
  pb.options = options;
  const std::size_t intervals =
      fitIntervals(times.front(), times.back(), options.control_period, options.degree, poses.size());
  pb.n = intervals + static_cast<std::size_t>(options.degree);
  pb.knots = clampedUniformKnots(pb.n, options.degree, times.front(), times.back());
  pb.spans.resize(times.size());
  for (std::size_t i = 0; i < times.size(); ++i)
    pb.spans[i] = knotSpan(pb.knots, pb.n, options.degree, times[i], Side::kRight);
  if (options.smoothing == 0.0)
    checkSchoenbergWhitney(times, pb.knots, pb.n, options.degree);
  pb.quadrature = jerkQuadrature(pb.knots, pb.n, options.degree);
  pb.weights.assign(times.size(), 1.0);
  pb.inverse_count = 1.0 / static_cast<double>(times.size());
  return pb;
}

}  // namespace fitting_detail

std::size_t fitIntervals(double t0, double t1, double control_period, int degree, std::size_t max_control)
{
  using fitting_detail::formatSeconds;
  if (!(std::isfinite(control_period) && control_period > 0.0))
    throw InvalidInputError("control_period: must be a positive number of seconds (0 takes the default " +
                            formatSeconds(kDefaultControlPeriod) + " s)");
  const double ratio = (t1 - t0) / control_period;
  const double intervals = std::max(1.0, std::ceil(ratio - 1e-9));
  if (!(intervals + degree <= static_cast<double>(max_control)))
    throw InvalidInputError("control_period: " + formatSeconds(control_period) + " s over the waypoints' " +
                            formatSeconds(t1 - t0) + " s makes " + formatSeconds(intervals + degree) +
                            " control poses of degree " + std::to_string(degree) + " for " +
                            std::to_string(max_control) +
                            " waypoints (at most one per waypoint): a longer "
                            "control_period or more waypoints");
  return static_cast<std::size_t>(intervals);
}

}  // namespace se3_interpolation
