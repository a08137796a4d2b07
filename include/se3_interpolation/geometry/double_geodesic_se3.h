// SE(3) as SO(3) × R³ (the "double geodesic"): everything the geometry DoubleGeodesicSe3
// provides.
//
// Points: poses (pose.h). Tangent: (ω, Δp), ω the body rotation vector of R_aᵀ R_b, Δp = p_b − p_a
// in the world frame (product metric). Geodesics: the rotation along its great circle (slerp),
// the translation on a straight line: what tf2 and KDL do between two poses. Left-invariant,
// not right-invariant. Twist conversion:
//   velocity      (Rᵀω, ṗ)                                           (V2)
//   acceleration  (Rᵀω̇, p̈)                                          (A2)
//   (the rotation part as on SO(3), the translation part a straight line).
// The three-point curve of blended splines is the generic one (curves/blended_spline.h).
#pragma once

#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
/// SE(3) as SO(3) × R³: rotation along its geodesic, translation on a straight line.
/// Left-invariant, not right-invariant. What tf2 and KDL do between two poses.
struct DoubleGeodesicSe3 : PoseGeometryTypes
{
  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    Tangent<S> v;
    v.template head<3>() = so3Log(Quaternion<S>(a.q.conjugate() * b.q));
    v.template tail<3>() = b.p - a.p;
    return v;
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return Point<S>(a.q * so3Exp(Vector3<S>(v.template head<3>())), a.p + v.template tail<3>());
  }
  /// exp(e, v) from the identity, without the product with it.
  template <class S>
  static Point<S> expFromIdentity(const Tangent<S>& v)
  {
    return Point<S>(so3Exp(Vector3<S>(v.template head<3>())), Vector3<S>(v.template tail<3>()));
  }
  /// exp(a, α v) at a jet α of time (first or second order), constant a and v, in closed form:
  /// the rotation is a one-parameter subgroup through q_a (detail::rotationLineJet), the
  /// translation p_a + α Δp has derivatives Δp and 0.
  template <int K>
  static Point<Jet<K>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<K>& alpha)
  {
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> dp = v.template tail<3>();
    const Quaternion<double> q = a.q * so3Exp(Vector3<double>(omega * alpha.value()));
    return Point<Jet<K>>(detail::rotationLineJet(q, omega, alpha),
                         detail::vectorJet(Vector3<double>(a.p + alpha.value() * dp), dp, Vector3<double>::Zero(),
                                           alpha));
  }
  /// kinematicsFromJet(expLine(a, v, α)) in closed form, without the quaternion jets: the rotation
  /// R_a Exp(α ω) turns about the fixed world axis R_a ω (Exp(α ω) ω = ω), so the spatial angular
  /// velocity is α̇ R_a ω and its derivative α̈ R_a ω; p = p_a + α Δp, ṗ = α̇ Δp, p̈ = α̈ Δp (the
  /// jet holds α̈/2 as its second coefficient). A piecewise geodesic's kinematics (tested to
  /// rounding against the jets).
  static Kinematics expLineKinematics(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> dp = v.template tail<3>();
    const double rate = alpha.coefficient(1);
    const double acceleration = 2.0 * alpha.coefficient(2);
    const Vector3<double> axis = a.q * omega;
    Kinematics out;
    out.pose.q = a.q * so3Exp(Vector3<double>(omega * alpha.value()));
    out.pose.p = a.p + alpha.value() * dp;
    out.velocity.angular = rate * axis;
    out.velocity.linear = rate * dp;
    out.acceleration.angular = acceleration * axis;
    out.acceleration.linear = acceleration * dp;
    return out;
  }
  /// The kinematics (world frame) of t ↦ exp(a, v(t)) from the tangent v and its first two time
  /// derivatives v̇, v̈, in closed form: p = p_a + Δp, ṗ = Δṗ, p̈ = Δp̈; R = R_a Exp(φ), whose spatial
  /// angular velocity is ω = R_a V(φ) φ̇ (V the left Jacobian of SO(3), lie_groups.h's screwV:
  /// d/dt Exp(φ) Exp(φ)ᵀ = [V(φ) φ̇]×). With V(φ) w = w + A φ × w + B φ × (φ × w) and x = |φ|²,
  ///   ω̇ = R_a (φ̈ + Ȧ φ × φ̇ + A φ × φ̈ + Ḃ φ × (φ × φ̇) + B (φ̇ × (φ × φ̇) + φ × (φ × φ̈))),
  /// Ȧ = A′(x) ẋ, Ḃ = B′(x) ẋ, ẋ = 2 φ · φ̇ (detail::screwCoefficients). What the second-order
  /// jet of exp and kinematicsFromJet give (tested to rounding), without the quaternion jets'
  /// products (the time-optimal timing's path jets take the rates alone: expRates).
  static Kinematics expKinematics(const Point<double>& a, const Tangent<double>& v, const Tangent<double>& dv,
                                  const Tangent<double>& ddv)
  {
    const Vector3<double> phi = v.head<3>();
    const detail::ScrewCoefficients coefficients = detail::screwCoefficients(phi.squaredNorm());
    const MotionRates rates = expRates(coefficients, v, dv, ddv);
    Kinematics out;
    const double k = coefficients.sin_half_over_theta;
    out.pose.q = a.q * Quaternion<double>(coefficients.cos_half, k * phi.x(), k * phi.y(), k * phi.z());
    out.pose.p = a.p + v.tail<3>();
    const Eigen::Matrix3d r_a = a.q.toRotationMatrix();
    out.velocity.linear = rates.velocity.linear;
    out.velocity.angular = r_a * rates.velocity.angular;
    out.acceleration.linear = rates.acceleration.linear;
    out.acceleration.angular = r_a * rates.acceleration.angular;
    return out;
  }
  /// The rates of expKinematics without the pose: ṗ and p̈ in the world frame, and a_ω = V(φ) φ̇ and
  /// its derivative, the angular velocity and acceleration in the frame of a (R_aᵀ ω, R_aᵀ ω̇). A
  /// rotation keeps norms and inner products, so within each part they are those of
  /// expKinematics: what the time-optimal timing's path jets read (|C′|, C′ · C″, |C″|).
  /// (A rotation at rest, φ̇ = φ̈ = 0 exactly, as on a path of constant orientation, has ω = ω̇ = 0:
  /// every term has one of them. Without the coefficients' trigonometry there.)
  static MotionRates expRates(const Tangent<double>& v, const Tangent<double>& dv, const Tangent<double>& ddv)
  {
    if (dv.head<3>().isZero(0.0) && ddv.head<3>().isZero(0.0))
    {
      MotionRates still;
      still.velocity.linear = dv.tail<3>();
      still.acceleration.linear = ddv.tail<3>();
      return still;
    }
    return expRates(detail::screwCoefficients(v.head<3>().squaredNorm()), v, dv, ddv);
  }
  /// expRates with the jerk, from v⃛ too: p⃛ = Δp⃛, and ω̈ in the frame of a, expKinematics' ω̇
  /// differentiated once more. With u = φ × φ̇ and w = φ × u (so that R_aᵀ ω = φ̇ + A u + B w),
  ///   u̇ = φ × φ̈,  ü = φ̇ × φ̈ + φ × φ⃛,  ẇ = φ̇ × u + φ × u̇,  ẅ = φ̈ × u + 2 φ̇ × u̇ + φ × ü,
  ///   R_aᵀ ω̈ = φ⃛ + Ä u + 2 Ȧ u̇ + A ü + B̈ w + 2 Ḃ ẇ + B ẅ,
  /// Ä = A″(x) ẋ² + A′(x) ẍ (B̈ likewise), ẍ = 2 (|φ̇|² + φ · φ̈) (detail::screwSecondDerivatives).
  /// What the third-order jet of exp and kinematics3FromJet give, to rounding (tested): the
  /// jerk-limited timing's path jets read these (|C‴|, C′ · C‴, C″ · C‴).
  static MotionRates3 expRates3(const Tangent<double>& v, const Tangent<double>& dv, const Tangent<double>& ddv,
                                const Tangent<double>& dddv)
  {
    MotionRates3 out;
    out.velocity.linear = dv.tail<3>();
    out.acceleration.linear = ddv.tail<3>();
    out.jerk.linear = dddv.tail<3>();
    if (dv.head<3>().isZero(0.0) && ddv.head<3>().isZero(0.0) && dddv.head<3>().isZero(0.0))
      return out;  // a rotation at rest (expRates)
    const Vector3<double> phi = v.head<3>();
    const Vector3<double> dphi = dv.head<3>();
    const Vector3<double> ddphi = ddv.head<3>();
    const Vector3<double> dddphi = dddv.head<3>();
    const double x = phi.squaredNorm();
    const detail::ScrewCoefficients c = detail::screwCoefficients(x);
    const detail::ScrewSecondDerivatives d = detail::screwSecondDerivatives(x, c);
    const double dx = 2.0 * phi.dot(dphi);
    const double ddx = 2.0 * (dphi.squaredNorm() + phi.dot(ddphi));
    const Vector3<double> u = phi.cross(dphi);
    const Vector3<double> w = phi.cross(u);
    const Vector3<double> du = phi.cross(ddphi);
    const Vector3<double> ddu = dphi.cross(ddphi) + phi.cross(dddphi);
    const Vector3<double> dw = dphi.cross(u) + phi.cross(du);
    const Vector3<double> ddw = ddphi.cross(u) + 2.0 * dphi.cross(du) + phi.cross(ddu);
    // expRates' ω and ω̇ from the same products (its ω̇ is φ̈ + Ȧ u + A u̇ + Ḃ w + B ẇ).
    out.velocity.angular = dphi + c.a * u + c.b * w;
    out.acceleration.angular = ddphi + (c.da * dx) * u + c.a * du + (c.db * dx) * w + c.b * dw;
    out.jerk.angular = dddphi + (d.dda * dx * dx + c.da * ddx) * u + (2.0 * c.da * dx) * du + c.a * ddu +
                       (d.ddb * dx * dx + c.db * ddx) * w + (2.0 * c.db * dx) * dw + c.b * ddw;
    return out;
  }

private:
  static MotionRates expRates(const detail::ScrewCoefficients& coefficients, const Tangent<double>& v,
                              const Tangent<double>& dv, const Tangent<double>& ddv)
  {
    const Vector3<double> phi = v.head<3>();
    const Vector3<double> dphi = dv.head<3>();
    const Vector3<double> ddphi = ddv.head<3>();
    const double dx = 2.0 * phi.dot(dphi);
    const Vector3<double> wv = phi.cross(dphi);
    const Vector3<double> wwv = phi.cross(wv);
    const Vector3<double> wa = phi.cross(ddphi);
    MotionRates out;
    out.velocity.angular = dphi + coefficients.a * wv + coefficients.b * wwv;
    out.acceleration.angular = ddphi + (coefficients.da * dx) * wv + coefficients.a * wa +
                               (coefficients.db * dx) * wwv + coefficients.b * (dphi.cross(wv) + phi.cross(wa));
    out.velocity.linear = dv.tail<3>();
    out.acceleration.linear = ddv.tail<3>();
    return out;
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

/// The double-geodesic step between two poses in double precision: the rotation in slerp form
/// (so3Slerp, no Log → Exp round trip), the translation on its line. Equal to the generic
/// exp(a, λ log(a, b)) to rounding; tested against it and a long double reference.
template <>
inline Pose<double> geodesic<DoubleGeodesicSe3, double>(const Pose<double>& a, const Pose<double>& b,
                                                        const double& lambda)
{
  return Pose<double>(so3Slerp(a.q, b.q, lambda), a.p + lambda * (b.p - a.p));
}

namespace detail
{
/// The double-geodesic step between jet poses (levels ≥ 2 of the recursions when derivatives
/// are sampled): the rotation by so3SlerpJet, else (a far extrapolation at a small angle) by the
/// Log → Exp jet path; the translation on its line.
template <int K>
Pose<Jet<K>> doubleGeodesicJet(const Pose<Jet<K>>& a, const Pose<Jet<K>>& b, const Jet<K>& lambda)
{
  Quaternion<Jet<K>> q;
  if (!so3SlerpJet(a.q, b.q, lambda, &q))
    q = a.q * so3Exp(Vector3<Jet<K>>(so3Log(Quaternion<Jet<K>>(a.q.conjugate() * b.q)) * lambda));
  return Pose<Jet<K>>(q, a.p + lambda * (b.p - a.p));
}
}  // namespace detail

/// detail::doubleGeodesicJet at first order (the speeds of the path's length, analysis/figures.h).
template <>
inline Pose<Jet<1>> geodesic<DoubleGeodesicSe3, Jet<1>>(const Pose<Jet<1>>& a, const Pose<Jet<1>>& b,
                                                        const Jet<1>& lambda)
{
  return detail::doubleGeodesicJet(a, b, lambda);
}

/// detail::doubleGeodesicJet at second order.
template <>
inline Pose<Jet<2>> geodesic<DoubleGeodesicSe3, Jet<2>>(const Pose<Jet<2>>& a, const Pose<Jet<2>>& b,
                                                        const Jet<2>& lambda)
{
  return detail::doubleGeodesicJet(a, b, lambda);
}

}  // namespace se3_interpolation
