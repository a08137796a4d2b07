// SO(3) with its bi-invariant metric: everything the geometry So3 provides (the rotation part
// of DoubleGeodesicSe3 on its own).
//
// Points: unit quaternions (q and −q are the same rotation; log takes the short way). Tangent:
// the body rotation vector ω of q_a⁻¹ q_b (rad). Geodesics: slerp (math/lie_groups.h so3Slerp).
#pragma once

#include "se3_interpolation/geometry/geodesic.h"

namespace se3_interpolation
{
/// SO(3) with its bi-invariant metric (unit quaternions).
struct So3 : GeometryTypes<Quaternion, Vector3>
{
  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    return so3Log(Quaternion<S>(a.conjugate() * b));
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return a * so3Exp(v);
  }
  /// exp(a, α v) at a second-order jet α, constant a and v (detail::rotationLineJet).
  static Point<Jet<2>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    return detail::rotationLineJet(Quaternion<double>(a * so3Exp(Vector3<double>(v * alpha.value()))), v, alpha);
  }
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return Point<T>(T(a.w()), T(a.x()), T(a.y()), T(a.z()));
  }
};

/// The SO(3) step between two rotations in double precision, in slerp form (so3Slerp).
template <>
inline Quaternion<double> geodesic<So3, double>(const Quaternion<double>& a, const Quaternion<double>& b,
                                                const double& lambda)
{
  return so3Slerp(a, b, lambda);
}

/// The SO(3) step between jet rotations (as geodesic<DoubleGeodesicSe3, Jet<2>>).
template <>
inline Quaternion<Jet<2>> geodesic<So3, Jet<2>>(const Quaternion<Jet<2>>& a, const Quaternion<Jet<2>>& b,
                                                const Jet<2>& lambda)
{
  Quaternion<Jet<2>> q;
  if (!so3SlerpJet(a, b, lambda, &q))
    q = a * so3Exp(Vector3<Jet<2>>(so3Log(Quaternion<Jet<2>>(a.conjugate() * b)) * lambda));
  return q;
}

/// Whether every coordinate of a quaternion is finite.
inline bool allFinite(const Quaternion<double>& q)
{
  return q.coeffs().allFinite();
}

/// A scale for absolute tolerances on rotations: 1 (unit quaternions).
inline double pointMagnitude(const Quaternion<double>& /*q*/)
{
  return 1.0;
}

}  // namespace se3_interpolation
