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
// This header adds the kinematics and figures of sphere curves: the covariant acceleration
// D²x/dt² = ẍ − ⟨x, ẍ⟩ x (the projection of ẍ onto T_x S^m, §5) and the energy ("average
// acceleration") of eq. 32,
//   E = ∫ ⟨D²x/dt², D²x/dt²⟩ dt = ∫ (⟨ẍ, ẍ⟩ − ⟨x, ẍ⟩²) dt     (|x| = 1),
// evaluated from exact jet derivatives with Gauss–Legendre quadrature on each analytic piece.
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

inline SphereKinematics sphereKinematicsFromJet(const VectorX<Jet<2>>& x)
{
  SphereKinematics k;
  const Eigen::Index n = x.size();
  k.point.resize(n);
  k.velocity.resize(n);
  Eigen::VectorXd ambient(n);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    k.point[i] = x[i].value();
    k.velocity[i] = x[i].coefficient(1);
    ambient[i] = 2.0 * x[i].coefficient(2);
  }
  k.acceleration = ambient - k.point.dot(ambient) * k.point;
  return k;
}

inline SphereKinematics sphereKinematicsAt(const Curve<Sphere>& curve, double t, Side side = Side::kRight)
{
  return sphereKinematicsFromJet(curve.jet(Jet<2>::variable(t), side));
}

/// Length ∫|ẋ| dt (rad on the unit sphere), energy (eq. 32) and peak speed / covariant acceleration.
struct SphereCurveFigures
{
  double length = 0.0;
  double energy = 0.0;
  double max_speed = 0.0;
  double max_acceleration = 0.0;
};

inline SphereCurveFigures measureSphereCurve(const Curve<Sphere>& curve)
{
  SphereCurveFigures fig;
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  const std::size_t pieces = b.size() - 1;
  const std::size_t sub = std::max<std::size_t>(4, 64 / std::max<std::size_t>(pieces, 1));
  std::array<double, 2> peak{};
  std::array<double, 2> where{};
  std::array<std::pair<double, double>, 2> bracket{};
  auto rates = [](const SphereKinematics& k) {
    return std::array<double, 2>{ k.velocity.norm(), k.acceleration.norm() };
  };
  auto consider = [&](const SphereKinematics& k, double t, double lo, double hi) {
    const auto r = rates(k);
    for (std::size_t j = 0; j < 2; ++j)
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
    consider(sphereKinematicsAt(curve, b[i], Side::kRight), b[i], b[i], b[i] + h);
    consider(sphereKinematicsAt(curve, b[i + 1], Side::kLeft), b[i + 1], b[i + 1] - h, b[i + 1]);
    for (std::size_t s = 0; s < sub; ++s)
    {
      const double a = b[i] + static_cast<double>(s) * h;
      for (std::size_t g = 0; g < detail::kGaussNodes.size(); ++g)
      {
        const double t = a + 0.5 * h * (1.0 + detail::kGaussNodes[g]);
        const double w = 0.5 * h * detail::kGaussWeights[g];
        const SphereKinematics k = sphereKinematicsAt(curve, t);
        fig.length += w * k.velocity.norm();
        fig.energy += w * k.acceleration.squaredNorm();
        consider(k, t, std::max(b[i], t - h / 4.0), std::min(b[i + 1], t + h / 4.0));
      }
    }
  }
  for (std::size_t j = 0; j < 2; ++j)
  {
    if (peak[j] <= 0.0 || bracket[j].second <= bracket[j].first)
      continue;
    const Side side = where[j] >= bracket[j].second ? Side::kLeft : Side::kRight;
    peak[j] = detail::goldenMax([&](double t) { return rates(sphereKinematicsAt(curve, t, side))[j]; },
                                bracket[j].first, bracket[j].second, peak[j]);
  }
  fig.max_speed = peak[0];
  fig.max_acceleration = peak[1];
  return fig;
}

/// The energy ("average acceleration") of eq. 32 over the curve's whole domain.
inline double sphereEnergy(const Curve<Sphere>& curve)
{
  return measureSphereCurve(curve).energy;
}

}  // namespace se3_interpolation
