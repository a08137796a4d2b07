// R^n: everything the geometry Euclidean provides. The abelian case, where every construction
// of the library reduces to its classical form (the tests' independent reference).
//
// Points and tangents: vectors of R^n; log(a, b) = b − a, exp(a, v) = a + v.
#pragma once

#include "se3_interpolation/geometry/geodesic.h"

namespace se3_interpolation
{
/// R^n: the abelian case, where every construction reduces to its classical form.
struct Euclidean : VectorGeometryTypes
{
  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    return b - a;
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return a + v;
  }
};

}  // namespace se3_interpolation
