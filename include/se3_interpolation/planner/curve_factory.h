// Builds the curve a validated request asks for, in geometry G (SPEC, Curves).
#pragma once

#include <memory>
#include <vector>

#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/corner_blend.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/geometry/se3_velocity.h"

namespace se3_interpolation
{
template <class G>
std::shared_ptr<const Curve<G>> makeCurve(const ValidatedRequest& r, const std::vector<double>& times)
{
  const auto& x = r.waypoints;
  switch (r.curve)
  {
    case CurveType::kPiecewiseGeodesic:
      if (r.blend_radius > 0.0)
        return std::make_shared<CornerBlendedGeodesic<G>>(x, times, r.blend_radius, r.rotation_scale);
      return std::make_shared<PiecewiseGeodesic<G>>(x, times);
    case CurveType::kBezier:
      return std::make_shared<BezierCurve<G>>(x, times.front(), times.back());
    case CurveType::kBspline:
    {
      std::vector<double> knots =
          r.knots.empty() ? clampedUniformKnots(x.size(), r.degree, times.front(), times.back()) : r.knots;
      return std::make_shared<BSplineCurve<G>>(x, r.degree, std::move(knots));
    }
    case CurveType::kInterpolating:
      // Request twists → G's tangents at the first / last waypoint (se3_velocity.h).
      return makeInterpolatingSpline<G>(
          x, times, r.end_condition, velocityToTangent<G>(x.front(), r.start_velocity),
          velocityToTangent<G>(x.back(), r.end_velocity),
          accelerationToTangent<G>(x.front(), r.start_velocity, r.start_acceleration));
    case CurveType::kHermite:
    {
      std::vector<typename G::template Tangent<double>> tangents;
      if (r.velocities.empty())
        tangents = estimateTangents<G>(x, times);
      for (std::size_t i = 0; i < r.velocities.size(); ++i)
        tangents.push_back(velocityToTangent<G>(x[i], r.velocities[i]));
      return std::make_shared<HermiteSpline<G>>(
          x, times, std::move(tangents), r.velocities.empty() ? "the velocity estimated at waypoints" : "velocities");
    }
    case CurveType::kBlended:
      return std::make_shared<BlendedSpline<G>>(x, times, r.continuity);
    default:
      break;
  }
  throw InvalidInputError(std::string("curve: '") + toString(r.curve) + "' is not available in this build");
}

}  // namespace se3_interpolation
