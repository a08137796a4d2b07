// Helpers shared by the unit tests: random points, distances, central differences.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/math/lie_groups.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace test
{
/// The default planner limits with a work limit (max_work_seconds) that no run of these tests
/// reaches, under the sanitizers or on a loaded machine: for tests of what a request computes,
/// not of how long it may take (test_work_estimate and test_deadline test the limit itself).
inline PlannerLimits unhurriedLimits()
{
  PlannerLimits limits;
  limits.max_work_seconds = 60.0;
  return limits;
}

template <int N>
Eigen::Matrix<double, N, 1> randomUnitVector(std::mt19937& rng)
{
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, N, 1> v;
  do
  {
    for (int i = 0; i < N; ++i)
      v[i] = n(rng);
  } while (v.norm() < 1e-3);
  return v.normalized();
}

inline Eigen::VectorXd randomUnitVectorX(std::mt19937& rng, int n)
{
  std::normal_distribution<double> d(0.0, 1.0);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i)
    v[i] = d(rng);
  return v.normalized();
}

/// A random pose: rotation angle below `max_angle`, translation components ~ N(0, scale²).
inline Pose<double> randomPose(std::mt19937& rng, double max_angle = 2.5, double scale = 1.0)
{
  std::normal_distribution<double> n(0.0, scale);
  const double angle = std::uniform_real_distribution<double>(0.0, max_angle)(rng);
  return Pose<double>(so3Exp<double>(angle * randomUnitVector<3>(rng)), Eigen::Vector3d(n(rng), n(rng), n(rng)));
}

/// A sequence of poses whose consecutive rotations stay well below π.
inline std::vector<Pose<double>> randomPolygon(std::mt19937& rng, std::size_t n, double step_angle = 1.0)
{
  std::vector<Pose<double>> p{ randomPose(rng) };
  for (std::size_t i = 1; i < n; ++i)
    p.push_back(p.back() * randomPose(rng, step_angle));
  return p;
}

/// Distance between poses: |Δp| + rotation angle (sign-independent).
inline double poseDistance(const Pose<double>& a, const Pose<double>& b)
{
  return (a.p - b.p).norm() + rotationAngle(Quaternion<double>(a.q.conjugate() * b.q));
}

/// Central-difference velocity and acceleration of a pose curve f at t (spatial frame).
template <class F>
Kinematics centralDifferences(const F& f, double t, double h)
{
  const Pose<double> m2 = f(t - 2 * h), m1 = f(t - h), c = f(t), p1 = f(t + h), p2 = f(t + 2 * h);
  Kinematics k;
  k.pose = c;
  // Fourth-order stencils.
  k.velocity.linear = (-p2.p + 8.0 * p1.p - 8.0 * m1.p + m2.p) / (12.0 * h);
  k.acceleration.linear = (-p2.p + 16.0 * p1.p - 30.0 * c.p + 16.0 * m1.p - m2.p) / (12.0 * h * h);
  // Spatial rotation vectors relative to R(t): φ(s) = Log(R(s) R(t)ᵀ); ω = φ', ω̇ = φ'' at s = t
  // (φ'' = ω̇ because the second-order term of the BCH series, ½[φ, φ'], vanishes at φ = 0).
  auto phi = [&](const Pose<double>& x) { return so3Log(Quaternion<double>(x.q * c.q.conjugate())); };
  const Eigen::Vector3d a2 = phi(m2), a1 = phi(m1), b1 = phi(p1), b2 = phi(p2);
  k.velocity.angular = (-b2 + 8.0 * b1 - 8.0 * a1 + a2) / (12.0 * h);
  k.acceleration.angular = (-b2 + 16.0 * b1 + 16.0 * a1 - a2) / (12.0 * h * h);
  return k;
}

/// A random valid knot vector for n control points of degree m: gaps in [0.3, 1.5] from
/// `start`, interior multiplicities 1 … m; clamped (m + 1 equal end knots) or not.
inline std::vector<double> randomKnots(std::mt19937& rng, std::size_t n, int m, bool clamped, double start = 0.0)
{
  std::uniform_real_distribution<double> gap(0.3, 1.5);
  std::uniform_int_distribution<int> mult(1, m);
  std::bernoulli_distribution repeat(0.3);
  const std::size_t mm = static_cast<std::size_t>(m);
  const std::size_t length = n + mm + 1;
  for (;;)
  {
    std::vector<double> u;
    double value = start;
    if (clamped)
      u.assign(mm + 1, value);
    const std::size_t body = clamped ? n - mm - 1 : length;
    std::size_t added = 0;
    while (added < body)
    {
      value += gap(rng);
      const std::size_t k = std::min<std::size_t>(repeat(rng) ? static_cast<std::size_t>(mult(rng)) : 1, body - added);
      u.insert(u.end(), k, value);
      added += k;
    }
    if (clamped)
      u.insert(u.end(), mm + 1, value + gap(rng));
    if (u[mm] < u[n])
      return u;
  }
}

/// Bézier knots: m + 1 copies of t0 and of t1, nothing inside.
inline std::vector<double> bezierKnots(int m, double t0, double t1)
{
  std::vector<double> u(static_cast<std::size_t>(m) + 1, t0);
  u.insert(u.end(), static_cast<std::size_t>(m) + 1, t1);
  return u;
}

}  // namespace test
}  // namespace se3_interpolation
