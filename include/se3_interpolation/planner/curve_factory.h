// Builds the curve a validated request asks for, in geometry G (docs/curves.md): the one switch
// from the request's `curve` to the constructions of curves/, for every space.
#pragma once

#include <memory>
#include <type_traits>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/corner_blend.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/planner/names.h"

namespace se3_interpolation
{
namespace detail
{
/// A request velocity as G's velocity tangent (T1) at x: twists through geometry/pose.h; sphere
/// tangents are already G's ambient vectors.
template <class G>
typename G::template Tangent<double> velocityTangent(const Pose<double>& x, const Twist& v)
{
  return velocityToTangent<G>(x, v);
}
template <class G>
Eigen::VectorXd velocityTangent(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& v)
{
  return v;
}

/// A request acceleration as G's acceleration tangent (T2) at x (the covariant one on S^m).
template <class G>
typename G::template Tangent<double> accelerationTangent(const Pose<double>& x, const Twist& v, const Twist& a)
{
  return accelerationToTangent<G>(x, v, a);
}
template <class G>
Eigen::VectorXd accelerationTangent(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& /*v*/,
                                    const Eigen::VectorXd& a)
{
  return a;
}
}  // namespace detail

template <class G, class Space>
std::shared_ptr<const Curve<G>> makeCurve(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
{
  const auto& x = r.waypoints;
  switch (r.curve)
  {
    case CurveType::kPiecewiseGeodesic:
      if constexpr (std::is_same_v<typename Space::Waypoint, Pose<double>>)
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
      return makeInterpolatingSpline<G>(
          x, times, r.end_condition, detail::velocityTangent<G>(x.front(), r.start_velocity),
          detail::velocityTangent<G>(x.back(), r.end_velocity),
          detail::accelerationTangent<G>(x.front(), r.start_velocity, r.start_acceleration));
    case CurveType::kHermite:
    {
      std::vector<typename G::template Tangent<double>> tangents;
      if (r.velocities.empty())
        tangents = estimateTangents<G>(x, times);
      for (std::size_t i = 0; i < r.velocities.size(); ++i)
        tangents.push_back(detail::velocityTangent<G>(x[i], r.velocities[i]));
      return std::make_shared<HermiteSpline<G>>(
          x, times, std::move(tangents), r.velocities.empty() ? "the velocity estimated at waypoints" : "velocities");
    }
    case CurveType::kBlended:
      return std::make_shared<BlendedSpline<G>>(x, times, r.continuity);
  }
  throw InvalidInputError(std::string("curve: '") + toString(r.curve) + "' is not available in this build");
}

}  // namespace se3_interpolation
