// References and data shared by the spline tests (test_interpolating_spline, test_hermite,
// test_pose, test_tangent_space, test_chart_cubic, test_planner): classical Euclidean splines
// written here, independent of the code under test, and random data.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/geometry/geometry.h"

namespace se3_interpolation
{
namespace test
{
// ---- Independent references ------------------------------------------------------------

/// The classical cubic spline through y_i at t_i in second-derivative form: M_i = S''(t_i) from
/// h_{i−1} M_{i−1} + 2(h_{i−1} + h_i) M_i + h_i M_{i+1} = 6 (Δ_i/h_i − Δ_{i−1}/h_{i−1}), with
/// M_0 = M_{N−1} = 0 (natural) or the end-slope rows (clamped); solved by the Thomas algorithm.
class ClassicalSpline
{
public:
  ClassicalSpline(std::vector<double> t, std::vector<Eigen::VectorXd> y, bool clamped = false,
                  const Eigen::VectorXd& v0 = Eigen::VectorXd(), const Eigen::VectorXd& v1 = Eigen::VectorXd())
    : t_(std::move(t)), y_(std::move(y))
  {
    const std::size_t n = t_.size();
    const Eigen::Index dim = y_[0].size();
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 0.0);
    std::vector<Eigen::VectorXd> r(n, Eigen::VectorXd::Zero(dim));
    auto h = [&](std::size_t i) { return t_[i + 1] - t_[i]; };
    auto slope = [&](std::size_t i) -> Eigen::VectorXd { return (y_[i + 1] - y_[i]) / h(i); };
    for (std::size_t i = 1; i + 1 < n; ++i)
    {
      a[i] = h(i - 1);
      b[i] = 2.0 * (h(i - 1) + h(i));
      c[i] = h(i);
      r[i] = 6.0 * (slope(i) - slope(i - 1));
    }
    if (clamped)
    {
      b[0] = 2.0 * h(0);
      c[0] = h(0);
      r[0] = 6.0 * (slope(0) - v0);
      a[n - 1] = h(n - 2);
      b[n - 1] = 2.0 * h(n - 2);
      r[n - 1] = 6.0 * (v1 - slope(n - 2));
    }
    for (std::size_t i = 1; i < n; ++i)
    {
      const double w = a[i] / b[i - 1];
      b[i] -= w * c[i - 1];
      r[i] -= w * r[i - 1];
    }
    m_.assign(n, Eigen::VectorXd());
    m_[n - 1] = r[n - 1] / b[n - 1];
    for (std::size_t i = n - 1; i-- > 0;)
      m_[i] = (r[i] - c[i] * m_[i + 1]) / b[i];
  }

  Eigen::VectorXd operator()(double s) const
  {
    std::size_t i = 0;
    while (i + 2 < t_.size() && s > t_[i + 1])
      ++i;
    const double h = t_[i + 1] - t_[i];
    const double l = t_[i + 1] - s;
    const double r = s - t_[i];
    return m_[i] * (l * l * l / (6.0 * h)) + m_[i + 1] * (r * r * r / (6.0 * h)) +
           (y_[i] / h - m_[i] * (h / 6.0)) * l + (y_[i + 1] / h - m_[i + 1] * (h / 6.0)) * r;
  }

private:
  std::vector<double> t_;
  std::vector<Eigen::VectorXd> y_;
  std::vector<Eigen::VectorXd> m_;
};

/// Classical cubic Hermite interpolation.
inline Eigen::VectorXd classicalHermite(const std::vector<double>& t, const std::vector<Eigen::VectorXd>& y,
                                 const std::vector<Eigen::VectorXd>& v, double s)
{
  std::size_t i = 0;
  while (i + 2 < t.size() && s > t[i + 1])
    ++i;
  const double h = t[i + 1] - t[i];
  const double u = (s - t[i]) / h;
  const double h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u;
  const double h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  return h00 * y[i] + h10 * h * v[i] + h01 * y[i + 1] + h11 * h * v[i + 1];
}

/// Classical forward cubic spline from p(t_0), p'(t_0), p''(t_0): on each segment the cubic
/// p(t_i + s) = x_i + v s + a s²/2 + c s³ through x_{i+1}, its end slope and curvature carried on.
inline Eigen::VectorXd classicalForward(const std::vector<double>& t, const std::vector<Eigen::VectorXd>& y,
                                 Eigen::VectorXd v, Eigen::VectorXd a, double s)
{
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
  {
    const double h = t[i + 1] - t[i];
    const Eigen::VectorXd c = (y[i + 1] - y[i] - v * h - a * (h * h / 2.0)) / (h * h * h);
    if (s <= t[i + 1] || i + 2 == t.size())
    {
      const double r = s - t[i];
      return y[i] + v * r + a * (r * r / 2.0) + c * (r * r * r);
    }
    v = v + a * h + c * (3.0 * h * h);
    a = a + c * (6.0 * h);
  }
  return y.back();
}

// ---- Data --------------------------------------------------------------------------------

inline std::vector<double> randomTimes(std::mt19937& rng, std::size_t n)
{
  std::uniform_real_distribution<double> step(0.5, 1.5);
  std::vector<double> t{ 0.3 };
  for (std::size_t i = 1; i < n; ++i)
    t.push_back(t.back() + step(rng));
  return t;
}

inline Twist randomTwist(std::mt19937& rng, double scale)
{
  std::normal_distribution<double> n(0.0, scale);
  Twist v;
  v.linear = Eigen::Vector3d(n(rng), n(rng), n(rng));
  v.angular = Eigen::Vector3d(n(rng), n(rng), n(rng));
  return v;
}

inline double relativeError(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return (a - b).norm() / std::max(1.0, b.norm());
}

inline double twistError(const Twist& a, const Twist& b)
{
  return std::max(relativeError(a.linear, b.linear), relativeError(a.angular, b.angular));
}

inline Vector6<double> zero6()
{
  return Vector6<double>::Zero();
}

template <class G>
std::shared_ptr<const Curve<G>> spline(const std::vector<Pose<double>>& x, const std::vector<double>& t, EndCondition c,
                                       const Twist& v0 = Twist(), const Twist& v1 = Twist(), const Twist& a0 = Twist())
{
  return makeInterpolatingSpline<G>(x, t, c, velocityToTangent<G>(x.front(), v0), velocityToTangent<G>(x.back(), v1),
                                    accelerationToTangent<G>(x.front(), v0, a0));
}

using Se3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;

/// The spatial kinematics of the motion t ↦ G::exp(x, t v + t² a/2) at t = 0, by kinematics.h.
template <class G>
Kinematics kinematicsOfExpCurve(const Pose<double>& x, const Vector6<double>& v, const Vector6<double>& a)
{
  Vector6<Jet<2>> y;
  for (int k = 0; k < 6; ++k)
  {
    y[k] = Jet<2>(0.0);
    y[k].coefficient(1) = v[k];
    y[k].coefficient(2) = a[k] / 2.0;
  }
  return kinematicsFromJet(G::exp(x.cast<Jet<2>>(), y));
}
}  // namespace test
}  // namespace se3_interpolation
