// The family `piecewise_geodesic`: the geodesic polyline through the waypoints (curves/bezier.h),
// its interior corners blended within `blend_radius` on poses (curves/corner_blend.h).
#pragma once

#include <type_traits>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/corner_blend.h"
#include "se3_interpolation/planner/curve_family.h"

namespace se3_interpolation
{
/// `piecewise_geodesic` (planner/curve_family.h): with a blend radius, legs and blends in turn.
struct PiecewiseGeodesicFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kPiecewiseGeodesic;
  static constexpr const char* kName = "piecewise_geodesic";
  static constexpr unsigned kFields = kBlendRadiusField;
  /// Work units of one evaluation of a corner-blended polyline (blend_radius): its legs are one
  /// geodesic step, its blends one exp and the blend parameter's Newton steps; the seconds per
  /// unit of secondsPerUnit's corner-blend row are calibrated against this count.
  static constexpr double kBlendEvaluationCost = 3.0;

  /// @param r a validated request of the family
  /// @param times the waypoints' times (s)
  /// @return the polyline, corner-blended (with its radii) when r.blend_radius > 0 on poses
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    if constexpr (std::is_same_v<typename Space::Waypoint, Pose<double>>)
      if (r.blend_radius > 0.0)
      {
        auto blended = std::make_shared<CornerBlendedGeodesic<G>>(r.waypoints, times, r.blend_radius, r.rotation_scale);
        return { blended, blended->radii() };
      }
    return { std::make_shared<PiecewiseGeodesic<G>>(r.waypoints, times), {} };
  }

  /// @param shape the request's shape
  /// @return the legs and, with corner blends, the blends between them (2N − 3)
  static double pieces(const WorkShape& shape)
  {
    if (shape.corner_blends)
      return std::max(1.0, 2.0 * static_cast<double>(shape.waypoints) - 3.0);
    return CurveFamilyDefaults::pieces(shape);
  }

  /// @param shape the request's shape
  /// @return one geodesic step per evaluation; kBlendEvaluationCost with corner blends
  static double evaluationCost(const WorkShape& shape) { return shape.corner_blends ? kBlendEvaluationCost : 1.0; }

  /// @param shape the request's shape
  /// @return the polyline's calibration, or the corner blends' with a blend radius
  static SecondsPerUnit secondsPerUnit(const WorkShape& shape)
  {
    if (shape.corner_blends)
      return { 3.54e-08, 4.01e-08, 4.89e-08, 4.8e-08 };
    return { 3.7e-08, 2.62e-08, 7.3e-08, 3.62e-08 };
  }
};

}  // namespace se3_interpolation
