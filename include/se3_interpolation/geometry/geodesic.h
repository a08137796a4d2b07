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

/// The point and tangent types of a geometry (geometry.h), in every scalar type.
template <template <class> class PointType, template <class> class TangentType>
struct GeometryTypes
{
  template <class S>
  using Point = PointType<S>;
  template <class S>
  using Tangent = TangentType<S>;
};

/// The types of a geometry whose points are cast to another scalar coordinate by coordinate
/// (every geometry but So3, whose quaternions cast per coefficient).
template <template <class> class PointType, template <class> class TangentType>
struct CoordinateTypes : GeometryTypes<PointType, TangentType>
{
  template <class T>
  static PointType<T> cast(const PointType<double>& a)
  {
    return a.template cast<T>();
  }
};

/// R^n and S^m: points and tangents are coordinate vectors.
using VectorGeometryTypes = CoordinateTypes<VectorX, VectorX>;

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
