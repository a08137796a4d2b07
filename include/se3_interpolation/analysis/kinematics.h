// Velocities, accelerations and integral figures of SE(3) curves.
//
// From the second-order jet of a pose (q(t), p(t)) at t:
//   linear velocity  ṗ,            linear acceleration  p̈,
//   angular velocity ω = 2 vec(q̇ q*)  (so that Ṙ = [ω]× R: spatial, the waypoints' frame),
//   angular accel.   ω̇ = 2 vec(q̈ q*)  (vec(q̇ q̇*) = 0 for a unit quaternion).
// The integrals (length, rotation length, energy) use 8-point Gauss–Legendre rules on
// subintervals of each analytic piece (between breakpoints), so they are accurate to
// near machine precision for the smooth curves here; the maxima are located on those
// nodes and the piece ends, then refined by golden-section search.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
struct Kinematics
{
  Pose<double> pose;
  Twist velocity;
  Twist acceleration;
};

inline Kinematics kinematicsFromJet(const Pose<Jet<2>>& x)
{
  Kinematics k;
  const Quaternion<double> q0(x.q.w().value(), x.q.x().value(), x.q.y().value(), x.q.z().value());
  const Quaternion<double> q1(x.q.w().coefficient(1), x.q.x().coefficient(1), x.q.y().coefficient(1),
                              x.q.z().coefficient(1));
  const Quaternion<double> q2(x.q.w().coefficient(2), x.q.x().coefficient(2), x.q.y().coefficient(2),
                              x.q.z().coefficient(2));
  k.pose.q = q0;
  for (int i = 0; i < 3; ++i)
  {
    k.pose.p[i] = x.p[i].value();
    k.velocity.linear[i] = x.p[i].coefficient(1);
    k.acceleration.linear[i] = 2.0 * x.p[i].coefficient(2);
  }
  const Quaternion<double> q0c = q0.conjugate();
  k.velocity.angular = 2.0 * (q1 * q0c).vec();
  k.acceleration.angular = 4.0 * (q2 * q0c).vec();
  return k;
}

template <class G>
Kinematics kinematicsAt(const Curve<G>& curve, double t, Side side = Side::kRight)
{
  return kinematicsFromJet(curve.jet(Jet<2>::variable(t), side));
}

/// Length, rotation length, energy and peak rates of a curve over its whole domain.
struct CurveFigures
{
  double length = 0.0;
  double rotation_length = 0.0;
  double energy = 0.0;
  double max_linear_speed = 0.0;
  double max_angular_speed = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
};

namespace detail
{
/// 8-point Gauss–Legendre nodes and weights on [−1, 1].
constexpr std::array<double, 8> kGaussNodes = { -0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                                -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                                0.7966664774136267,  0.9602898564975363 };
constexpr std::array<double, 8> kGaussWeights = { 0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                                  0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                                  0.2223810344533745, 0.1012285362903763 };

/// Maximises f on [a, b] around an initial best point by golden-section search.
inline double goldenMax(const std::function<double(double)>& f, double a, double b, double best)
{
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - r * (b - a);
  double x2 = a + r * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int i = 0; i < 60 && b - a > 1e-13 * (1.0 + std::abs(a)); ++i)
  {
    if (f1 > f2)
    {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - r * (b - a);
      f1 = f(x1);
    }
    else
    {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + r * (b - a);
      f2 = f(x2);
    }
  }
  return std::max({ best, f1, f2 });
}
}  // namespace detail

template <class G>
CurveFigures measureCurve(const Curve<G>& curve, double rotation_scale)
{
  CurveFigures fig;
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  const std::size_t pieces = b.size() - 1;
  const std::size_t sub = std::max<std::size_t>(4, 64 / std::max<std::size_t>(pieces, 1));

  // The four peak quantities, each with the node where it was largest.
  std::array<double, 4> peak{};
  std::array<double, 4> where{};
  std::array<std::pair<double, double>, 4> bracket{};
  auto rates = [](const Kinematics& k) {
    return std::array<double, 4>{ k.velocity.linear.norm(), k.velocity.angular.norm(), k.acceleration.linear.norm(),
                                  k.acceleration.angular.norm() };
  };
  auto consider = [&](const Kinematics& k, double t, double lo, double hi) {
    const auto r = rates(k);
    for (int j = 0; j < 4; ++j)
      if (r[j] > peak[j])
      {
        peak[j] = r[j];
        where[j] = t;
        bracket[j] = { lo, hi };
      }
  };

  for (std::size_t i = 0; i < pieces; ++i)
  {
    const double h = (b[i + 1] - b[i]) / static_cast<double>(sub);
    consider(kinematicsAt(curve, b[i], Side::kRight), b[i], b[i], b[i] + h);
    consider(kinematicsAt(curve, b[i + 1], Side::kLeft), b[i + 1], b[i + 1] - h, b[i + 1]);
    for (std::size_t s = 0; s < sub; ++s)
    {
      const double a = b[i] + s * h;
      for (std::size_t g = 0; g < detail::kGaussNodes.size(); ++g)
      {
        const double t = a + 0.5 * h * (1.0 + detail::kGaussNodes[g]);
        const double w = 0.5 * h * detail::kGaussWeights[g];
        const Kinematics k = kinematicsAt(curve, t);
        fig.length += w * k.velocity.linear.norm();
        fig.rotation_length += w * k.velocity.angular.norm();
        // (ρ ω̇)², not ρ² |ω̇|²: a huge ρ times ω̇ = 0 is 0, not ∞ · 0 = NaN.
        fig.energy += w * (k.acceleration.linear.squaredNorm() +
                           (rotation_scale * k.acceleration.angular).squaredNorm());
        consider(k, t, std::max(b[i], t - h / 4.0), std::min(b[i + 1], t + h / 4.0));
      }
    }
  }
  for (int j = 0; j < 4; ++j)
  {
    if (peak[j] <= 0.0 || bracket[j].second <= bracket[j].first)
      continue;
    const double lo = bracket[j].first;
    const double hi = bracket[j].second;
    // Evaluate from the side of the bracket so that a peak at a breakpoint is kept.
    const Side side = where[j] >= hi ? Side::kLeft : Side::kRight;
    peak[j] = detail::goldenMax([&](double t) { return rates(kinematicsAt(curve, t, side))[j]; }, lo, hi, peak[j]);
  }
  fig.max_linear_speed = peak[0];
  fig.max_angular_speed = peak[1];
  fig.max_linear_acceleration = peak[2];
  fig.max_angular_acceleration = peak[3];
  return fig;
}

}  // namespace se3_interpolation
