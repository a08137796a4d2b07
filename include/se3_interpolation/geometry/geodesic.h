// The one operation every curve construction is built from: geodesic interpolation in a
// geometry G (the policy interface is described in geometry.h), and the helpers shared by the
// geometries whose points are coordinate vectors (R^n, S^m).
#pragma once

#include <Eigen/Core>

#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
template <class S>
using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

/// Geodesic interpolation interp_λ(a, b) = exp(a, λ log(a, b)) (thesis eq. 4.1).
template <class G, class S>
typename G::template Point<S> geodesic(const typename G::template Point<S>& a, const typename G::template Point<S>& b,
                                       const S& lambda)
{
  return G::exp(a, typename G::template Tangent<S>(G::log(a, b) * lambda));
}

/// The types of the geometries whose points and tangents are coordinate vectors (R^n, S^m).
struct VectorGeometryTypes
{
  template <class S>
  using Point = VectorX<S>;
  template <class S>
  using Tangent = VectorX<S>;
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return a.template cast<T>();
  }
};

/// Whether every coordinate of a coordinate-vector point (R^n, S^m) or tangent is finite.
template <class D>
bool allFinite(const Eigen::MatrixBase<D>& x)
{
  return x.allFinite();
}

/// A scale for absolute tolerances on points: 1 + the size of the point's coordinates
/// (overloaded by every point type: pose.h, so3.h).
inline double pointMagnitude(const Eigen::VectorXd& x)
{
  return 1.0 + x.norm();
}

}  // namespace se3_interpolation
