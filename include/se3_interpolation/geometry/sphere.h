// Curves on the sphere S^m ⊂ R^{m+1}, m ≥ 2 (Crouch, Kun, Silva Leite, §4).
//
// Every construction of the library is generic over a geometry policy; S^m is the policy
// `Sphere` below, with points unit vectors of R^{m+1} and tangent vectors the ambient
// vectors v ⊥ x:
//  - geodesics, eq. 17: β_1(λ, a, b) = sin((1 − λ)θ)/sin θ a + sin(λθ)/sin θ b, θ = ∠(a, b),
//    equivalently eq. 18, exp(λθ S_{a,b}) a with S_{a,b} the unit rotation generator of the plane
//    span(a, b) in so(m+1); implemented as exp(a, λ log(a, b)) with
//    log(a, b) = θ (b − cos θ a)/sin θ and exp(a, v) = cos|v| a + sin|v| v/|v| (below);
//  - generalised polynomials of any degree: deCasteljau<Sphere> / BezierCurve<Sphere>
//    (curves/bezier.h), B-splines: BSplineCurve<Sphere> (curves/bspline.h);
//  - Hermite cubics, Case 1: HermiteSpline<Sphere> (curves/hermite.h): the control points
//    x_1 = exp(x_0, h V̂_0/3), x_2 = exp(x_3, −h V̂_1/3) are Crouch's exp(V_0^1) x_0 and
//    exp(−V_2^1) x_3 with V_0^1 = θ_0 S_{x_0, V̂_0} (eqs. 24–26): rotations in the planes
//    span(x_0, V̂_0) and span(x_3, V̂_1);
//  - C² interpolating splines, end conditions natural / clamped / start data (Case 2: initial
//    velocity V̂_0 and covariant acceleration Ŵ_0 = D²p/dt²(0)): makeInterpolatingSpline<Sphere>
//    (curves/interpolating_spline.h), piecewise cubics exp(x_i, P_i(t)) in T_{x_i} S^m (curves/chart_cubic.h),
//    whose chart acceleration at x_i is the covariant one (tangent_space.h);
//  - blended C^n splines of circles: BlendedSpline<Sphere> (curves/blended_spline.h, Pobegailo).
// This header holds the geometry and the kinematics of sphere curves: the covariant acceleration
// D²x/dt² = ẍ − ⟨x, ẍ⟩ x (the projection of ẍ onto T_x S^m, §5) and the density of the energy
// ("average acceleration") of eq. 32,
//   E = ∫ ⟨D²x/dt², D²x/dt²⟩ dt = ∫ (⟨ẍ, ẍ⟩ − ⟨x, ẍ⟩²) dt     (|x| = 1),
// which measureCurve (analysis/figures.h) integrates as for poses.
//
// Unit quaternions are S³: the great circles of S³ through q are q Exp(s ω/2), so the
// de Casteljau curves on S³ and on SO(3) agree when the control quaternions are sign-chosen
// with positive consecutive dot products at every level (the double cover), with |q̇| = |ω|/2 and
// |D²q/dt²| = |ω̇|/2 (the metric factor ½; tested in test_sphere.cpp).
// The circle through three points that blended splines use is SphereCircle (below).
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/QR>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/geometry/tangent_space.h"

namespace se3_interpolation
{
/// The unit sphere S^m ⊂ R^{m+1} with its round metric (great circles).
struct Sphere : VectorGeometryTypes
{
  /// θ (b − cos θ a)/sin θ, θ = ∠(a, b); throws when b = −a.
  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    const S c = a.dot(b);
    const Tangent<S> w = b - c * a;
    const S n2 = w.squaredNorm();
    if (valueOf(c) < 0.0 && valueOf(n2) <= 4.0 * kAntipodalTolerance * kAntipodalTolerance)
      throw NonUniqueGeodesicError("the points are antipodal: the great circle between them is not unique");
    // atan2(|w|, c)/|w|, the quaternion log factor halved (same series near 0).
    if (valueOf(c) > 0.0)
      return w * (detail::logFactor(n2, c) / 2.0);
    using std::atan2;
    using std::sqrt;
    const S n = sqrt(n2);
    return w * (atan2(n, c) / n);
  }
  /// cos|v| a + sin|v| v/|v|.
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    const S theta2 = v.squaredNorm();
    S k, c;
    // sin(θ/2)/θ and cos(θ/2) at 2θ give sin θ/(2θ) and cos θ.
    detail::halfAngle(S(4.0 * theta2), &k, &c);
    return c * a + S(2.0) * k * v;
  }
};

/// S^m: T_x S^m = x^⊥ ⊂ R^{m+1}; the last m columns of the Householder reflection taking x
/// to a multiple of e_1.
template <>
struct TangentFrame<Sphere>
{
  static constexpr bool kIdentity = false;
  static Eigen::MatrixXd basis(const Eigen::VectorXd& x)
  {
    const Eigen::MatrixXd column = x;
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(column);
    const Eigen::MatrixXd q = qr.householderQ();
    return q.rightCols(x.size() - 1);
  }
};

/// Position, velocity ẋ and covariant acceleration D²x/dt² of a curve on S^m at one instant.
struct SphereKinematics
{
  Eigen::VectorXd point;
  Eigen::VectorXd velocity;
  Eigen::VectorXd acceleration;  ///< ẍ − ⟨x, ẍ⟩ x
};

/// The kinematics of the second-order jet x of a sphere curve at one instant, taken of x/|x|
/// as a jet: ẍ − ⟨x, ẍ⟩ x is the covariant acceleration only for a jet on the sphere to second
/// order, and a jet computed through exp near the conjugate point leaves it at first order by
/// rounding (a relative acceleration jump of 1e-4 at an interior waypoint of a C² spline at
/// 1e-7 rad from the antipode, 1e-7 normalised: interpolating_solver.h, kMinSphereConjugateGap).
/// With c_k the jet's coefficients divided by |c_0|, x/|x| has the coefficients
/// c_0, c_1 − ⟨c_0, c_1⟩ c_0 and c_2 − (⟨c_0, c_2⟩ + |c_1|²/2 − 3⟨c_0, c_1⟩²/2) c_0 − ⟨c_0, c_1⟩ c_1.
inline SphereKinematics sphereKinematicsFromJet(const VectorX<Jet<2>>& x)
{
  SphereKinematics k;
  const Eigen::Index n = x.size();
  k.point.resize(n);
  k.velocity.resize(n);
  Eigen::VectorXd c1(n), c2(n);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    k.point[i] = x[i].value();
    c1[i] = x[i].coefficient(1);
    c2[i] = x[i].coefficient(2);
  }
  const double r = k.point.norm();
  k.point /= r;
  c1 /= r;
  c2 /= r;
  const double a = k.point.dot(c1);
  k.velocity = c1 - a * k.point;
  const Eigen::VectorXd ambient =
      2.0 * (c2 - (k.point.dot(c2) + 0.5 * c1.squaredNorm() - 1.5 * a * a) * k.point - a * c1);
  k.acceleration = ambient - k.point.dot(ambient) * k.point;
  return k;
}

/// The circle through three points a, b, c of S^m: the sphere cut by their affine plane, the
/// orbit of b under the one-parameter subgroup exp(φ J) of SO(m+1), J = v uᵀ − u vᵀ, that rotates
/// the plane about the circle's centre (Pobegailo, §7). Oriented so that the angle from
/// b grows towards c and reaches a last: angleAtFirst() = θ_a ∈ (−2π, 0) is a's angle, angleAtLast()
/// = θ_c ∈ (0, 2π) c's, exp(θ_a J) b = a and exp(θ_c J) b = c. If two of the points coincide (a
/// dwell, closer than kCoincident) the circle is the great circle through b and the other distinct
/// point; if all three coincide, J = 0.
class SphereCircle
{
public:
  /// Below this distance two points on the unit sphere count as the same point (about 4500 ulps
  /// of a unit coordinate: well above the rounding of unit vectors).
  static constexpr double kCoincident = 1e-12;

  SphereCircle(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c)
  {
    const double two_pi = 6.283185307179586476925286766559;
    const Eigen::VectorXd dab = a - b, dcb = c - b;
    if (dab.norm() > kCoincident && dcb.norm() > kCoincident && (a - c).norm() > kCoincident)
    {
      // The affine plane through the three points: orthonormal directions f1, f2; its foot
      // point o (the circle's centre) is the projection of the sphere's centre 0.
      const Eigen::VectorXd f1 = dab.normalized();
      const Eigen::VectorXd f2 = (dcb - dcb.dot(f1) * f1).normalized();
      const Eigen::VectorXd o = b - b.dot(f1) * f1 - b.dot(f2) * f2;
      u_ = (b - o).normalized();
      v_ = -u_.dot(f2) * f1 + u_.dot(f1) * f2;  // u rotated by a right angle in the plane
      auto angle = [&](const Eigen::VectorXd& x) {
        const double phi = std::atan2((x - o).dot(v_), (x - o).dot(u_));
        return phi < 0.0 ? phi + two_pi : phi;
      };
      double angle_a = angle(a);
      double angle_c = angle(c);
      if (angle_c > angle_a)  // orient the circle so that b → c comes before reaching a
      {
        v_ = -v_;
        angle_a = two_pi - angle_a;
        angle_c = two_pi - angle_c;
      }
      theta_a_ = angle_a - two_pi;
      theta_c_ = angle_c;
    }
    else
    {
      // A dwell (two points equal): the great circle through b and the other distinct point.
      u_ = b;
      const Eigen::VectorXd& other = dab.norm() >= dcb.norm() ? a : c;
      const Eigen::VectorXd w = other - other.dot(b) * b;
      v_ = w.norm() > kCoincident ? Eigen::VectorXd(w.normalized()) : Eigen::VectorXd(Eigen::VectorXd::Zero(b.size()));
      theta_a_ = std::atan2(a.dot(v_), a.dot(u_));
      theta_c_ = std::atan2(c.dot(v_), c.dot(u_));
      if (v_.isZero())
        u_.setZero();
    }
  }

  double angleAtFirst() const { return theta_a_; }
  double angleAtLast() const { return theta_c_; }

  /// exp(φ J) y = y + sin φ J y + (1 − cos φ) J² y with J = v uᵀ − u vᵀ.
  template <class S>
  VectorX<S> rotate(const S& phi, const VectorX<S>& y) const
  {
    using std::sin;
    S s, c;
    sincos(phi, &s, &c);
    const S half = sin(S(phi * 0.5));
    const S one_minus_cos = S(2.0) * half * half;
    const VectorX<S> u = u_.template cast<S>();
    const VectorX<S> v = v_.template cast<S>();
    const S yu = u.dot(y);
    const S yv = v.dot(y);
    return y + VectorX<S>(v * S(s * yu) - u * S(s * yv)) -
           VectorX<S>(u * S(one_minus_cos * yu) + v * S(one_minus_cos * yv));
  }

private:
  Eigen::VectorXd u_, v_;  ///< orthonormal basis of the circle's plane, u along b − centre (zero: a = b = c)
  double theta_a_ = 0.0;
  double theta_c_ = 0.0;
};

}  // namespace se3_interpolation
