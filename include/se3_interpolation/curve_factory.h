// Builds the curve a validated request asks for, in geometry G (SPEC, Curves).
#pragma once

#include <memory>
#include <vector>

#include "se3_interpolation/bspline.h"
#include "se3_interpolation/planner.h"
#include "se3_interpolation/polynomial_curves.h"

namespace se3_interpolation
{
template <class G>
std::shared_ptr<const Curve<G>> makeCurve(const ValidatedRequest& r, const std::vector<double>& times)
{
  const auto& x = r.waypoints;
  switch (r.curve)
  {
    case CurveType::kPiecewiseGeodesic:
      return std::make_shared<PiecewiseGeodesic<G>>(x, times);
    case CurveType::kBezier:
      return std::make_shared<BezierCurve<G>>(x, times.front(), times.back());
    case CurveType::kBspline:
    {
      std::vector<double> knots =
          r.knots.empty() ? clampedUniformKnots(x.size(), r.degree, times.front(), times.back()) : r.knots;
      return std::make_shared<BSplineCurve<G>>(x, r.degree, std::move(knots));
    }
    default:
      break;
  }
  throw InvalidInputError(std::string("curve: '") + toString(r.curve) + "' is not available in this build");
}

}  // namespace se3_interpolation
