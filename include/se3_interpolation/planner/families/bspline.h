// The family `bspline`: a geodesic B-spline of `degree` (default 3, at most N − 1) on `knots`
// (default clamped uniform over the waypoints' times; curves/bspline.h, de Boor).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/planner/curve_family.h"

namespace se3_interpolation
{
/// `bspline` (planner/curve_family.h): the only family that takes degree and knots.
struct BsplineFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kBspline;
  static constexpr const char* kName = "bspline";
  static constexpr unsigned kFields = kDegreeField | kKnotsField;

  /// @param r a validated request of the family
  /// @param times the waypoints' times (s): the span of the default knots
  /// @return the B-spline with the waypoints as control points
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    std::vector<double> knots =
        r.knots.empty() ? clampedUniformKnots(r.waypoints.size(), r.degree, times.front(), times.back()) : r.knots;
    return { std::make_shared<BSplineCurve<G>>(r.waypoints, r.degree, std::move(knots)), {} };
  }

  /// @param shape the request's shape
  /// @return the knot spans N − m of degree m
  static double pieces(const WorkShape& shape)
  {
    return std::max(1.0, static_cast<double>(shape.waypoints) - static_cast<double>(shape.degree));
  }

  /// @param shape the request's shape
  /// @return de Boor's m (m + 1) / 2 geodesic steps
  static double evaluationCost(const WorkShape& shape)
  {
    const double m = static_cast<double>(shape.degree);
    return std::max(1.0, m * (m + 1.0) / 2.0);
  }

  static SecondsPerUnit secondsPerUnit(const WorkShape& /*shape*/)
  {
    return { 5.86e-08, 4.92e-08, 8.89e-08, 6.83e-08 };
  }

  /// @param shape the request's shape
  /// @param name the family's name
  /// @return the degree, with the waypoints
  static std::string costlyField(const WorkShape& shape, const char* name)
  {
    return "degree: " + std::to_string(shape.degree) + " for curve '" + name + "' with " +
           std::to_string(shape.waypoints) + " waypoints";
  }
};

}  // namespace se3_interpolation
