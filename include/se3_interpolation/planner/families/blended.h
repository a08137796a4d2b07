// The family `blended`: Pobegailo's C^n spline of three-point curves through every waypoint,
// n = `continuity` (curves/blended_spline.h).
#pragma once

#include <vector>

#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/planner/curve_family.h"

namespace se3_interpolation
{
/// `blended` (planner/curve_family.h): the family that takes `continuity`.
struct BlendedFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kBlended;
  static constexpr const char* kName = "blended";
  static constexpr unsigned kFields = kContinuityField;

  /// @param r a validated request of the family
  /// @param times the waypoints' times (s)
  /// @return the C^n blended spline, n = r.continuity
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    return { std::make_shared<BlendedSpline<G>>(r.waypoints, times, r.continuity), {} };
  }

  /// Two geodesic steps per evaluation: its three-point curves are cheap closed forms (measured).
  static double evaluationCost(const WorkShape& /*shape*/) { return 2.0; }

  static SecondsPerUnit secondsPerUnit(const WorkShape& /*shape*/) { return { 1.89e-07, 1.86e-07, 2.9e-07, 2.38e-07 }; }
};

}  // namespace se3_interpolation
