// Curves on the sphere S^m ⊂ R^{m+1}, m ≥ 2 (Crouch, Kun, Silva Leite, seed 001, §4).
//
// Every construction of the library is generic over a geometry policy; S^m is the policy
// `Sphere` of geometry.h, with points unit vectors of R^{m+1} and tangent vectors the ambient
// vectors v ⊥ x:
//  - geodesics, eq. 17: β_1(λ, a, b) = sin((1 − λ)θ)/sin θ a + sin(λθ)/sin θ b, θ = ∠(a, b),
//    equivalently eq. 18, exp(λθ S_{a,b}) a with S_{a,b} the unit rotation generator of the plane
//    span(a, b) in so(m+1); implemented as exp(a, λ log(a, b)) with
//    log(a, b) = θ (b − cos θ a)/sin θ and exp(a, v) = cos|v| a + sin|v| v/|v| (geometry.h);
//  - generalised polynomials of any degree: deCasteljau<Sphere> / BezierCurve<Sphere>
//    (polynomial_curves.h), B-splines: BSplineCurve<Sphere> (bspline.h);
//  - Hermite cubics, Case 1: HermiteSpline<Sphere> (hermite.h): the control points
//    x_1 = exp(x_0, h V̂_0/3), x_2 = exp(x_3, −h V̂_1/3) are Crouch's exp(V_0^1) x_0 and
//    exp(−V_2^1) x_3 with V_0^1 = θ_0 S_{x_0, V̂_0} (eqs. 24–26): rotations in the planes
//    span(x_0, V̂_0) and span(x_3, V̂_1);
//  - C² interpolating splines, end conditions natural / clamped / start data (Case 2: initial
//    velocity V̂_0 and covariant acceleration Ŵ_0 = D²p/dt²(0)): makeInterpolatingSpline<Sphere>
//    (interpolating_spline.h), piecewise cubics exp(x_i, P_i(t)) in T_{x_i} S^m (chart_cubic.h),
//    whose chart acceleration at x_i is the covariant one (tangent_space.h);
//  - blended C^n splines of circles: BlendedSpline<Sphere> (blending.h, Pobegailo).
// This header adds the kinematics of sphere curves: the covariant acceleration
// D²x/dt² = ẍ − ⟨x, ẍ⟩ x (the projection of ẍ onto T_x S^m, §5) and the density of the energy
// ("average acceleration") of eq. 32,
//   E = ∫ ⟨D²x/dt², D²x/dt²⟩ dt = ∫ (⟨ẍ, ẍ⟩ − ⟨x, ẍ⟩²) dt     (|x| = 1),
// which measureCurve (analysis/figures.h) integrates as for poses.
//
// Unit quaternions are S³: the great circles of S³ through q are q Exp(s ω/2), so the
// de Casteljau curves on S³ and on SO(3) agree when the control quaternions are sign-chosen
// with positive consecutive dot products at every level (the double cover), with |q̇| = |ω|/2 and
// |D²q/dt²| = |ω̇|/2 (the metric factor ½; tested in test_sphere.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/analysis/kinematics.h"

namespace se3_interpolation
{
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

inline SphereKinematics sphereKinematicsAt(const Curve<Sphere>& curve, double t, Side side = Side::kRight)
{
  return sphereKinematicsFromJet(curve.jet(Jet<2>::variable(t), side));
}

/// The figures' rates of a sphere motion (analysis/figures.h): the motion is angular (rad on the
/// unit sphere), so |ẋ| and |D²x/dt²| are the angular channel and the linear one is 0.
inline Rates rates(const SphereKinematics& k)
{
  return { 0.0, k.velocity.norm(), 0.0, k.acceleration.norm() };
}

/// The energy density ⟨D²x/dt², D²x/dt²⟩ of eq. 32 (the round metric: no rotation scale).
inline double energyDensity(const SphereKinematics& k, double /*rotation_scale*/)
{
  return k.acceleration.squaredNorm();
}

/// The kinematics at t (overloads the pose kinematicsAt of kinematics.h for the sphere).
inline SphereKinematics kinematicsAt(const Curve<Sphere>& curve, double t, Side side = Side::kRight)
{
  return sphereKinematicsAt(curve, t, side);
}

}  // namespace se3_interpolation
