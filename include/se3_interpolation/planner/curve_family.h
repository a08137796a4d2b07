// A curve family's descriptor: everything the planner knows of one value of the request's
// `curve`, in one struct per family (planner/families/<family>.h), registered in
// planner/curve_families.h. A descriptor derives from CurveFamilyDefaults and gives:
//   kType, kName        its CurveType and the name the request spells it with;
//   kFields             the request fields only it takes (FamilyField): validation refuses the
//                       exclusive ones (kExclusiveFields) for every other family and applies the
//                       rules of the others (degree bounded by the waypoints) to it;
//   make<G>(r, times)   the factory: the curve of a validated request in geometry G, with the
//                       blend radius of every waypoint where the family blends corners;
//   continuesStartState whether its curve starts in the request's start state itself (instead of
//                       being entered by the joining segment of curves/start_join.h);
//   kRequiresTimes      whether the request must give `times`;
//   the cost model      pieces, evaluationCost, constructionUnits, secondsPerUnit and costlyField, read by the work
//                       estimate (work_estimate.h), which sums them the same way for every family.
// The defaults are those of a family of one piece per waypoint step that takes none of the
// exclusive fields.
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/planner/request.h"
#include "se3_interpolation/planner/work_estimate.h"

namespace se3_interpolation
{
/// The request fields that shape the curve of some families only (a descriptor's kFields).
enum FamilyField : unsigned
{
  kNoFields = 0u,
  kDegreeField = 1u << 0,        ///< `degree`: at most N − 1 for N waypoints
  kKnotsField = 1u << 1,         ///< `knots`
  kContinuityField = 1u << 2,    ///< `continuity`
  kEndConditionField = 1u << 3,  ///< `end_condition` and the end velocities and acceleration it reads
  kVelocitiesField = 1u << 4,    ///< `velocities`
  kBlendRadiusField = 1u << 5,   ///< `blend_radius`
  kFitField = 1u << 6,           ///< `control_period`, `smoothing`, `loss`, `loss_scale`
};

/// The fields a family that does not take them refuses when they are set (knots, blend_radius);
/// the others keep their defaults whatever the curve, and only the families that take them read them.
constexpr unsigned kExclusiveFields = kKnotsField | kBlendRadiusField | kFitField;

/// Seconds per work unit of a family (work_estimate.h, secondsPerUnit): double geodesic
/// (stretch, time_optimal), screw (stretch, time_optimal); the sphere uses the screw's. Measured
/// as the CPU time of generate() over the estimate's units at N = 1000 waypoints (a bezier 100)
/// on one core of the development machine by bench/bench_work_estimate.cpp, then lowered where
/// the smallest size would be over-estimated more than about 1.8 times (time_optimal's fixed
/// costs weigh least there) or raised where a ratio came near 0.5: from 100 to 10⁴ waypoints (a
/// bezier 20 to 400) the estimate is within 0.5 … 2 of the measured time (docs/timing.md,
/// Bounded work; re-measured after each change of the estimate's model or of the timings' speed).
using SecondsPerUnit = std::array<double, 4>;

/// What a fit reports besides its curve (BasicResult::residual_linear, residual_angular, knots).
struct FitSummary
{
  double residual_linear = 0.0;   ///< m, RMS at the waypoints' times
  double residual_angular = 0.0;  ///< rad, RMS at the waypoints' times
  std::vector<double> knots;
};

/// What a family's factory builds: the curve and, for corner-blending families, the radius r_i
/// of each waypoint's blend (empty otherwise; BasicResult::blend_radii); for `fit`, its figures.
template <class G>
struct FamilyCurve
{
  FamilyCurve() = default;
  /// @param built the curve
  /// @param radii the waypoints' blend radii (corner-blending families)
  FamilyCurve(std::shared_ptr<const Curve<G>> built, std::vector<double> radii = {})  // NOLINT: { curve, radii }
    : curve(std::move(built)), blend_radii(std::move(radii))
  {
  }

  std::shared_ptr<const Curve<G>> curve;
  std::vector<double> blend_radii;
  std::optional<FitSummary> fit;
};

/// The defaults of a curve family's descriptor (file comment).
struct CurveFamilyDefaults
{
  static constexpr unsigned kFields = kNoFields;
  /// Whether the family needs the request's `times` (validation refuses a request without them).
  static constexpr bool kRequiresTimes = false;

  /// @param shape the request's shape (work_estimate.h)
  /// @return the curve's analytic pieces, over which the figures integrate: one per waypoint step
  static double pieces(const WorkShape& shape) { return std::max(1.0, static_cast<double>(shape.waypoints) - 1.0); }

  /// @param shape the request's shape
  /// @return the work of building the curve, in work units (work_estimate.h): about
  ///         kConstructionUnitsPerWaypoint per waypoint (times, logs, the C² solve's sweeps)
  static double constructionUnits(const WorkShape& shape)
  {
    return kConstructionUnitsPerWaypoint * static_cast<double>(shape.waypoints);
  }

  /// The field a refused work estimate names when neither the samples nor time_optimal dominate.
  /// @param shape the request's shape
  /// @param name the family's name
  /// @return "waypoints: N waypoints for curve 'name'"
  static std::string costlyField(const WorkShape& shape, const char* name)
  {
    return "waypoints: " + std::to_string(shape.waypoints) + " waypoints for curve '" + name + "'";
  }

  /// @param request a validated request of the family
  /// @return whether the family's curve starts in request.start_state itself (false: the joining
  ///         segment enters it)
  template <class Request>
  static bool continuesStartState([[maybe_unused]] const Request& request)
  {
    return false;
  }
};

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

}  // namespace se3_interpolation
