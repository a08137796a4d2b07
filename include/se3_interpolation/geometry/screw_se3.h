// SE(3) with its Ad-invariant (screw) metric: everything the geometry ScrewSe3 provides.
//
// Points: poses (pose.h). Tangent: the body twist (ω, v) of a⁻¹b, rotation first (se(3),
// thesis ch. 5); exp/log through se3Exp/se3Log (math/lie_groups.h). Geodesics are screw
// motions a · Exp(λ Log(a⁻¹ b)). Twist conversion (tangent = body twist (ω_b, v_b) of x⁻¹ y):
//   velocity      (ω_b, v_b) = (Rᵀω, Rᵀṗ)                            (V1)
//     since d/ds x Exp(s ξ) = x ξ^, whose rotation part is Ṙ = R [ω_b]× = [R ω_b]× R and
//     whose translation part is R v_b;
//   acceleration  d/dt (Rᵀω, Rᵀṗ) = (Rᵀω̇, Rᵀ(p̈ − ω × ṗ))            (A1)
//     using Ṙᵀ = −Rᵀ[ω]×, so d/dt(Rᵀω) = Rᵀω̇ − Rᵀ(ω × ω) and d/dt(Rᵀṗ) = Rᵀ(p̈ − ω × ṗ);
//   the inverse map needs the velocity: p̈ = R a_v + ω × ṗ.
// The three-point curve of blended splines is the generic one (curves/blended_spline.h).
#pragma once

#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
/// SE(3) with its Ad-invariant (screw) metric: a · Exp(λ Log(a⁻¹ b)). Bi-invariant.
struct ScrewSe3 : PoseGeometryTypes
{
  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    return se3Log(a.inverseTimes(b));
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return a * se3Exp(v);
  }
  /// exp(a, α v) at a second-order jet α of time, constant a and v, in closed form: g(α) =
  /// a Exp(α ξ) is a one-parameter subgroup through a, dg/dα = g ξ^ and d²g/dα² = g ξ^ ξ^, i.e.
  /// (quaternion, translation) derivatives (q (0, ω/2), R v) and (−|ω|²/4 q, R (ω × v)).
  static Point<Jet<2>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    const Point<double> g = a * se3Exp(Tangent<double>(v * alpha.value()));
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> lin = v.template tail<3>();
    return Point<Jet<2>>(detail::rotationLineJet(g.q, omega, alpha),
                         detail::vectorJet(g.p, g.q * lin, g.q * Vector3<double>(omega.cross(lin)), alpha));
  }
  /// kinematicsFromJet(expLine(a, v, α)) in closed form, without the quaternion jets: with g = a Exp(α ξ),
  /// ξ = (ω, v), the body twist is α̇ ξ, so the spatial angular velocity is α̇ R_g ω = α̇ R_a ω (the
  /// rotation turns about a fixed axis) and its derivative α̈ R_a ω; ṗ = α̇ R_g v and
  /// p̈ = α̇² R_g (ω × v) + α̈ R_g v (expLine's d²g/dα²). Tested to rounding against the jets.
  static Kinematics expLineKinematics(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> lin = v.template tail<3>();
    const double rate = alpha.coefficient(1);
    const double acceleration = 2.0 * alpha.coefficient(2);
    Kinematics out;
    out.pose = a * se3Exp(Tangent<double>(v * alpha.value()));
    const Vector3<double> axis = out.pose.q * omega;
    const Vector3<double> along = out.pose.q * lin;
    out.velocity.angular = rate * axis;
    out.velocity.linear = rate * along;
    out.acceleration.angular = acceleration * axis;
    out.acceleration.linear = acceleration * along + (rate * rate) * axis.cross(along);
    return out;
  }
};

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

}  // namespace se3_interpolation
