// The planner's private interface between its units: a request's motion before sampling
// (PlannedMotion), the curve of a request with its lengths (buildCurve), its timing (applyTiming,
// planner.cpp) and the motion from a start state (planWithStartState, start_state.cpp).
#pragma once

#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace planner_detail
{
/// A request's motion before sampling: the timed curve, its figures and the result's fields so far.
template <class Space, class G>
struct PlannedMotion
{
  std::shared_ptr<const Curve<G>> curve;
  CurveFigures figures;
  BasicResult<Space> out;
  /// A fit's control points (those of the fitted B-spline, not of the joined motion).
  std::optional<std::vector<typename Space::Waypoint>> fit_control;
};

/// The bounds' field names for an error about the span they stretch the motion to.
template <class Space>
const char* boundFields()
{
  return std::is_same_v<Space, SphereSpace> ? "max_angular_velocity or max_angular_acceleration" :
                                              "max_linear_velocity, max_angular_velocity or their accelerations";
}

/// The request's curve through `times` (untimed: its own clock), with the figures a timing needs of
/// it (all of them under `stretch`, the lengths otherwise) and out's blend radii, fit results and
/// waypoint times (planner.cpp).
template <class Space, class G>
PlannedMotion<Space, G> buildCurve(const BasicValidatedRequest<Space>& r, const std::vector<double>& times);

/// The request's timing (stretch, time_optimal or constant_speed) applied to a curve that starts at
/// waypoints[0] (planner.cpp).
template <class Space, class G>
void applyTiming(const BasicValidatedRequest<Space>& r, std::shared_ptr<const Curve<G>>* curve_io, CurveFigures* fig_io,
                 BasicResult<Space>* out_io);

/// The timed motion of a request (planner.cpp): from its start state if it has one.
template <class Space, class G>
PlannedMotion<Space, G> planMotion(const BasicValidatedRequest<Space>& r, const std::vector<double>& times);

/// The timed motion of a pose request with a start state (start_state.cpp, docs/timing.md "Start
/// states and replanning"): the joined motion, or braking to rest and the motion from there,
/// whichever is no longer.
template <class G>
PlannedMotion<PoseSpace, G> planWithStartState(const ValidatedRequest& r, const std::vector<double>& times);
}  // namespace planner_detail
}  // namespace se3_interpolation
