// The family `interpolating`: the C² spline through every waypoint with the request's
// end_condition (natural, clamped or start; curves/interpolating_spline.h).
#pragma once

#include <vector>

#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/planner/curve_family.h"

namespace se3_interpolation
{
/// `interpolating` (planner/curve_family.h): with end_condition `start` its spline continues the
/// start state's velocity and acceleration itself.
struct InterpolatingFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kInterpolating;
  static constexpr const char* kName = "interpolating";
  static constexpr unsigned kFields = kEndConditionField;

  /// @param r a validated request of the family
  /// @param times the waypoints' times (s)
  /// @return the solved spline
  /// @throws ConvergenceError if its C² conditions cannot be solved
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    const auto& x = r.waypoints;
    return {
      makeInterpolatingSpline<G>(x, times, r.end_condition, detail::velocityTangent<G>(x.front(), r.start_velocity),
                                 detail::velocityTangent<G>(x.back(), r.end_velocity),
                                 detail::accelerationTangent<G>(x.front(), r.start_velocity, r.start_acceleration)),
      {}
    };
  }

  /// Six geodesic steps per evaluation (a cubic de Casteljau per piece).
  static double evaluationCost(const WorkShape& /*shape*/) { return 6.0; }

  static SecondsPerUnit secondsPerUnit(const WorkShape& /*shape*/)
  {
    return { 2.06e-08, 2.35e-08, 3.99e-08, 3.68e-08 };
  }

  /// @param request a validated request
  /// @return whether its end_condition is `start` (the spline is solved forward from the start data)
  template <class Request>
  static bool continuesStartState(const Request& request)
  {
    return request.end_condition == EndCondition::kStart;
  }
};

}  // namespace se3_interpolation
