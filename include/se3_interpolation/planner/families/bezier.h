// The family `bezier`: one geodesic Bézier curve of degree N − 1 over all waypoints
// (curves/bezier.h, de Casteljau).
#pragma once

#include <string>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/planner/curve_family.h"

namespace se3_interpolation
{
/// `bezier` (planner/curve_family.h): a single piece whose evaluation grows as N².
struct BezierFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kBezier;
  static constexpr const char* kName = "bezier";

  /// @param r a validated request of the family
  /// @param times the waypoints' times (s): the curve spans the first to the last
  /// @return the Bézier curve with the waypoints as control points
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    return { std::make_shared<BezierCurve<G>>(r.waypoints, times.front(), times.back()), {} };
  }

  static double pieces(const WorkShape& /*shape*/) { return 1.0; }

  /// @param shape the request's shape
  /// @return de Casteljau's d (d + 1) / 2 geodesic steps, d = N − 1
  static double evaluationCost(const WorkShape& shape)
  {
    const double d = static_cast<double>(shape.waypoints) - 1.0;
    return std::max(1.0, d * (d + 1.0) / 2.0);
  }

  static SecondsPerUnit secondsPerUnit(const WorkShape& /*shape*/)
  {
    return { 8.24e-08, 3.54e-08, 1.11e-07, 4.98e-08 };
  }

  /// @param shape the request's shape
  /// @param name the family's name (the message names the degree instead)
  /// @return the waypoints, naming the degree they make
  static std::string costlyField(const WorkShape& shape, [[maybe_unused]] const char* name)
  {
    return "waypoints: " + std::to_string(shape.waypoints) + " waypoints make a bezier of degree " +
           std::to_string(shape.waypoints - 1);
  }
};

}  // namespace se3_interpolation
