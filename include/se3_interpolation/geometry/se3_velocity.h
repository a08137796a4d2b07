// Request twists ↔ the SE(3) geometries' tangent representations.
//
// Requests (planner.h, SPEC "Sampling and outputs") give a velocity as the spatial twist
// (ṗ, ω) with Ṙ = [ω]× R, and an acceleration as (p̈, ω̇), all in the waypoints' frame.
// The curve constructions work with tangents in G's representation (geometry.h) at the
// point x = (R, p) where the motion happens, velocity (T1) and acceleration (T2) as
// defined in tangent_space.h:
//
//   ScrewSe3 (tangent = body twist (ω_b, v_b) of x⁻¹ y):
//     velocity      (ω_b, v_b) = (Rᵀω, Rᵀṗ)                            (V1)
//       since d/ds x Exp(s ξ) = x ξ^, whose rotation part is Ṙ = R [ω_b]× = [R ω_b]× R and
//       whose translation part is R v_b;
//     acceleration  d/dt (Rᵀω, Rᵀṗ) = (Rᵀω̇, Rᵀ(p̈ − ω × ṗ))            (A1)
//       using Ṙᵀ = −Rᵀ[ω]×, so d/dt(Rᵀω) = Rᵀω̇ − Rᵀ(ω × ω) and d/dt(Rᵀṗ) = Rᵀ(p̈ − ω × ṗ).
//   DoubleGeodesicSe3 (tangent = (body rotation vector, world Δp)):
//     velocity      (Rᵀω, ṗ)                                           (V2)
//     acceleration  (Rᵀω̇, p̈)                                          (A2)
//       (the rotation part as on SO(3) above; the translation part is a straight line).
//
// The inverse maps need the velocity for (A1): p̈ = R a_v + ω × ṗ.
#pragma once

#include <Eigen/Core>

#include "se3_interpolation/geometry/geometry.h"

namespace se3_interpolation
{
/// A spatial twist or its time derivative: linear (m/s or m/s²) and angular (rad/s or rad/s²)
/// parts, both in the waypoints' frame (Ṙ = [ω]× R).
struct Twist
{
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

/// The conversions for one SE(3) geometry (specialised below).
template <class G>
struct Se3TangentConversion;

template <>
struct Se3TangentConversion<ScrewSe3>
{
  /// (V1)
  static Vector6<double> velocity(const Pose<double>& x, const Twist& v)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Vector6<double> xi;
    xi << r.transpose() * v.angular, r.transpose() * v.linear;
    return xi;
  }
  static Twist twist(const Pose<double>& x, const Vector6<double>& xi)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Twist v;
    v.angular = r * xi.head<3>();
    v.linear = r * xi.tail<3>();
    return v;
  }
  /// (A1)
  static Vector6<double> acceleration(const Pose<double>& x, const Twist& v, const Twist& a)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Vector6<double> alpha;
    alpha << r.transpose() * a.angular, r.transpose() * (a.linear - v.angular.cross(v.linear));
    return alpha;
  }
  static Twist twistAcceleration(const Pose<double>& x, const Twist& v, const Vector6<double>& alpha)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Twist a;
    a.angular = r * alpha.head<3>();
    a.linear = r * alpha.tail<3>() + v.angular.cross(v.linear);
    return a;
  }
};

template <>
struct Se3TangentConversion<DoubleGeodesicSe3>
{
  /// (V2)
  static Vector6<double> velocity(const Pose<double>& x, const Twist& v)
  {
    Vector6<double> xi;
    xi << x.q.toRotationMatrix().transpose() * v.angular, v.linear;
    return xi;
  }
  static Twist twist(const Pose<double>& x, const Vector6<double>& xi)
  {
    Twist v;
    v.angular = x.q.toRotationMatrix() * xi.head<3>();
    v.linear = xi.tail<3>();
    return v;
  }
  /// (A2)
  static Vector6<double> acceleration(const Pose<double>& x, const Twist& /*v*/, const Twist& a)
  {
    Vector6<double> alpha;
    alpha << x.q.toRotationMatrix().transpose() * a.angular, a.linear;
    return alpha;
  }
  static Twist twistAcceleration(const Pose<double>& x, const Twist& /*v*/, const Vector6<double>& alpha)
  {
    Twist a;
    a.angular = x.q.toRotationMatrix() * alpha.head<3>();
    a.linear = alpha.tail<3>();
    return a;
  }
};

/// G's velocity tangent (T1) at x of the motion with spatial twist `velocity`.
template <class G>
Vector6<double> velocityToTangent(const Pose<double>& x, const Twist& velocity)
{
  return Se3TangentConversion<G>::velocity(x, velocity);
}

/// The spatial twist (ṗ, ω) of the motion with velocity tangent `tangent` at x.
template <class G>
Twist tangentToVelocity(const Pose<double>& x, const Vector6<double>& tangent)
{
  return Se3TangentConversion<G>::twist(x, tangent);
}

/// G's acceleration tangent (T2) at x of the motion with spatial velocity and acceleration.
template <class G>
Vector6<double> accelerationToTangent(const Pose<double>& x, const Twist& velocity, const Twist& acceleration)
{
  return Se3TangentConversion<G>::acceleration(x, velocity, acceleration);
}

/// The spatial acceleration (p̈, ω̇) of the motion with spatial velocity `velocity` and
/// acceleration tangent `tangent` (T2) at x.
template <class G>
Twist tangentToAcceleration(const Pose<double>& x, const Twist& velocity, const Vector6<double>& tangent)
{
  return Se3TangentConversion<G>::twistAcceleration(x, velocity, tangent);
}

}  // namespace se3_interpolation
