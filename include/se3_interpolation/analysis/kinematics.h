// Velocities and accelerations of pose curves (both SE(3) geometries), from their jets.
//
// From the second-order jet of a pose (q(t), p(t)) at t:
//   linear velocity  ṗ,            linear acceleration  p̈,
//   angular velocity ω = 2 vec(q̇ q*)  (so that Ṙ = [ω]× R: spatial, the waypoints' frame),
//   angular accel.   ω̇ = 2 vec(q̈ q*)  (vec(q̇ q̇*) = 0 for a unit quaternion).
// The integral figures of a curve over its domain are in figures.h.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/geometry/se3_velocity.h"

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

/// The four rates of a motion the figures and the bounds look at, in this order.
enum RateIndex
{
  kLinearSpeed,
  kAngularSpeed,
  kLinearAcceleration,
  kAngularAcceleration
};
using Rates = std::array<double, 4>;

/// |ṗ|, |ω|, |p̈|, |ω̇| of a pose motion.
inline Rates rates(const Kinematics& k)
{
  return { k.velocity.linear.norm(), k.velocity.angular.norm(), k.acceleration.linear.norm(),
           k.acceleration.angular.norm() };
}

/// The energy density |p̈|² + (ρ|ω̇|)² (Crouch et al. eq. 32 with the product metric; ρ the
/// rotation scale in m/rad). (ρ ω̇)², not ρ² |ω̇|²: a huge ρ times ω̇ = 0 is 0, not ∞ · 0 = NaN.
inline double energyDensity(const Kinematics& k, double rotation_scale)
{
  return k.acceleration.linear.squaredNorm() + (rotation_scale * k.acceleration.angular).squaredNorm();
}

}  // namespace se3_interpolation
