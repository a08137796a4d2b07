// analysis/: what a curve does, measured. This header: the kinematics of a curve at an instant
// (poses: Kinematics of geometry/pose.h; the sphere: SphereKinematics of geometry/sphere.h; both
// from the curve's second-order jet), the four rates the figures and the bounds look at, and the
// energy density. figures.h integrates them over a curve's domain (length, rotation length,
// energy, peak rates).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <type_traits>
#include <typeinfo>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/geometry/geometry.h"

namespace se3_interpolation
{
/// Whether the geometry G gives the kinematics of its exp in closed form (G::expKinematics, and its
/// rates alone, G::expRates, and with the jerk, G::expRates3, as DoubleGeodesicSe3 does).
template <class G, class = void>
struct HasExpKinematics : std::false_type
{
};
template <class G>
struct HasExpKinematics<G, std::void_t<decltype(&G::expKinematics)>> : std::true_type
{
};

/// `curve` as the final curve class C, or null: an exact type check, which for a final class finds
/// what dynamic_cast would, without dynamic_cast's search of the class hierarchy (a failed one
/// cost about 750 instructions, as much as a closed-form evaluation of the kinematics).
template <class C, class G>
const C* asFinalCurve(const Curve<G>& curve)
{
  static_assert(std::is_final<C>::value, "an exact type check finds only the final class");
  return typeid(curve) == typeid(C) ? static_cast<const C*>(&curve) : nullptr;
}

/// `curve` as the C² spline whose kinematics are closed-form (its pieces in a geometry with
/// HasExpKinematics), or null: what kinematicsAt asks of every curve, and what a caller that
/// evaluates one curve many times asks once.
template <class G>
const ChartCubicSpline<G>* closedFormKinematicsSpline(const Curve<G>& curve)
{
  if constexpr (HasExpKinematics<G>::value)
    return asFinalCurve<ChartCubicSpline<G>>(curve);
  else
    return nullptr;
}

/// The one place that finds a curve's closed-form kinematics: `closed(c)` with the curve as the
/// class whose kinematics(t, side) are closed-form (the C² spline's pieces in a geometry whose exp
/// has them, or the geodesic polygon of a geometry with closed-form line kinematics), else
/// `otherwise()`. Both return the same type, handed back without a copy (kinematicsAt, speedsAt).
template <class G, class Closed, class Otherwise>
auto withClosedFormKinematics(const Curve<G>& curve, Closed&& closed, Otherwise&& otherwise)
{
  if constexpr (HasExpKinematics<G>::value)
    if (const ChartCubicSpline<G>* chart = closedFormKinematicsSpline(curve))
      return closed(*chart);
  if constexpr (detail::HasExpLineKinematics<G>::value)
    if (const auto* polygon = asFinalCurve<PiecewiseGeodesic<G>>(curve))
      return closed(*polygon);
  return otherwise();
}

/// The pose kinematics at t (both SE(3) geometries; one-sided at a breakpoint): the closed form
/// where there is one, else from the second-order jet.
template <class G>
Kinematics kinematicsAt(const Curve<G>& curve, double t, Side side = Side::kRight)
{
  return withClosedFormKinematics(
      curve, [t, side](const auto& c) { return c.kinematics(t, side); },
      [&curve, t, side] { return kinematicsFromJet(curve.jet(Jet<2>::variable(t), side)); });
}

/// The sphere kinematics at t: velocity and covariant acceleration (sphere.h).
inline SphereKinematics kinematicsAt(const Curve<Sphere>& curve, double t, Side side = Side::kRight)
{
  return sphereKinematicsFromJet(curve.jet(Jet<2>::variable(t), side));
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

/// |ṗ| and |ω| of a first-order pose jet (ω = 2 vec(q̇ q*), as kinematicsFromJet), in the first two
/// entries of the rates (the accelerations' are 0).
inline Rates speedsFromJet(const Pose<Jet<1>>& x)
{
  const Quaternion<double> q0(x.q.w().value(), x.q.x().value(), x.q.y().value(), x.q.z().value());
  const Quaternion<double> q1(x.q.w().coefficient(1), x.q.x().coefficient(1), x.q.y().coefficient(1),
                              x.q.z().coefficient(1));
  const Eigen::Vector3d linear(x.p[0].coefficient(1), x.p[1].coefficient(1), x.p[2].coefficient(1));
  return { linear.norm(), 2.0 * (q1 * q0.conjugate()).vec().norm(), 0.0, 0.0 };
}

/// The speeds |ṗ| and |ω| at t (the first two entries of rates(kinematicsAt(curve, t, side)), the
/// others 0): kinematicsAt's closed forms where it has them, else the curve's first-order jets
/// (Curve::jet1), about half the arithmetic of its second-order ones.
template <class G>
Rates speedsAt(const Curve<G>& curve, double t, Side side = Side::kRight)
{
  return withClosedFormKinematics(
      curve,
      [t, side](const auto& c) {
        const Rates r = rates(c.kinematics(t, side));
        return Rates{ r[kLinearSpeed], r[kAngularSpeed], 0.0, 0.0 };
      },
      [&curve, t, side] { return speedsFromJet(curve.jet1(Jet<1>::variable(t), side)); });
}

/// The energy density |p̈|² + (ρ|ω̇|)² (Crouch et al. eq. 32 with the product metric; ρ the
/// rotation scale in m/rad). (ρ ω̇)², not ρ² |ω̇|²: a huge ρ times ω̇ = 0 is 0, not ∞ · 0 = NaN.
inline double energyDensity(const Kinematics& k, double rotation_scale)
{
  return k.acceleration.linear.squaredNorm() + (rotation_scale * k.acceleration.angular).squaredNorm();
}

/// The figures' rates of a sphere motion (analysis/figures.h): the motion is angular (rad on the
/// unit sphere), so |ẋ| and |D²x/dt²| are the angular channel and the linear one is 0.
inline Rates rates(const SphereKinematics& k)
{
  return { 0.0, k.velocity.norm(), 0.0, k.acceleration.norm() };
}

/// The sphere speeds at t (rates(kinematicsAt(curve, t, side)) without the accelerations): |ẋ| of
/// the curve's first-order jet in the angular channel.
inline Rates speedsAt(const Curve<Sphere>& curve, double t, Side side = Side::kRight)
{
  const VectorX<Jet<1>> x = curve.jet1(Jet<1>::variable(t), side);
  double speed2 = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i)
    speed2 += x[i].coefficient(1) * x[i].coefficient(1);
  return { 0.0, std::sqrt(speed2), 0.0, 0.0 };
}

/// The energy density ⟨D²x/dt², D²x/dt²⟩ of eq. 32 (the round metric: no rotation scale).
inline double energyDensity(const SphereKinematics& k, double /*rotation_scale*/)
{
  return k.acceleration.squaredNorm();
}

}  // namespace se3_interpolation
