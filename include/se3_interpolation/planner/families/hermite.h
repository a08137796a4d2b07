// The family `hermite`: the C¹ piecewise cubic through every waypoint with its velocity, given
// (`velocities`) or estimated (curves/hermite.h).
#pragma once

#include <utility>
#include <vector>

#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/planner/curve_family.h"

namespace se3_interpolation
{
/// `hermite` (planner/curve_family.h): the family that takes `velocities`.
struct HermiteFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kHermite;
  static constexpr const char* kName = "hermite";
  static constexpr unsigned kFields = kVelocitiesField;

  /// @param r a validated request of the family
  /// @param times the waypoints' times (s)
  /// @return the spline with r.velocities, or with the velocities estimated at the waypoints
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    std::vector<typename G::template Tangent<double>> tangents;
    if (r.velocities.empty())
      tangents = estimateTangents<G>(r.waypoints, times);
    for (std::size_t i = 0; i < r.velocities.size(); ++i)
      tangents.push_back(detail::velocityTangent<G>(r.waypoints[i], r.velocities[i]));
    const char* label = r.velocities.empty() ? "the velocity estimated at waypoints" : "velocities";
    return { std::make_shared<HermiteSpline<G>>(r.waypoints, times, std::move(tangents), label), {} };
  }

  /// Six geodesic steps per evaluation (a cubic de Casteljau per piece).
  static double evaluationCost(const WorkShape& /*shape*/) { return 6.0; }

  static SecondsPerUnit secondsPerUnit(const WorkShape& /*shape*/)
  {
    return { 6.73e-08, 5.89e-08, 1.02e-07, 7.77e-08 };
  }
};

}  // namespace se3_interpolation
