// The planner's joint space (docs/joint_space.md): the request's joint_seed validated against the
// arm, the arm's joint limits as the time-optimal timing's box constraint, and the arm following
// the timed motion: its joint limits held by a uniform stretch where the timing did not hold them
// (or refused where the motion's start may not change), and its joints in every sample.
#pragma once

#include <memory>
#include <type_traits>

#include "se3_interpolation/arm/joint_timing.h"
#include "se3_interpolation/planner/request.h"
#include "planned_motion.h"

namespace se3_interpolation
{
namespace planner_detail
{
/// The arm and joint_seed of a request: none without an arm and without a seed; a seed without an
/// arm, an arm without a seed, a seed of the wrong length or not finite, or a seed on the sphere are
/// refused naming joint_seed.
template <class Space>
std::optional<JointSpace> jointSpaceOf(const BasicRequest<Space>& request, std::shared_ptr<const arm::ArmModel> arm);

/// The arm's joint limits along the path `curve` (its time axis the path parameter), tracked from
/// the seed, as the time-optimal timing's box constraint; null without an arm. A refusal of the
/// arm names where it is among the waypoints, whose times on the path are `waypoint_times`.
template <class Space, class G>
std::shared_ptr<const timing::BoxConstraint> jointBoxesOf(const BasicValidatedRequest<Space>& r,
                                                          const std::shared_ptr<const Curve<G>>& curve,
                                                          const std::vector<double>& waypoint_times);

/// The jerk-limited timing's least window (s) for the arm's jerk limits (arm::jointJerkWindow); 0
/// without an arm or without a jerk limit: a request whose arm has one is timed by the jerk-limited
/// timing under `time_optimal`, as one with a Cartesian jerk bound.
template <class Space>
double jointJerkWindow(const BasicValidatedRequest<Space>& r)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
    return 0.0;
  else
    return r.joint_space ? arm::jointJerkWindow(*r.joint_space->arm) : 0.0;
}

/// The arm following the timed motion m (null without an arm): the joint path of the path under
/// m's clocks (the time-optimal timing's boxes', or tracked here) run on those clocks, checked by
/// the time-optimal timing's box check or else by arm::checkJointRates; the motion stretched
/// uniformly where a joint exceeds its limits (velocity, acceleration, and jerk where m has
/// third-order jets all along; its figures, time_scale and waypoint times with it),
/// refused naming the joint, time and waypoints where the motion starts moving or keeps a constant
/// speed (the arm's refusals of the path name the waypoints around too);
/// sets m's joint names and figures.
template <class Space, class G>
std::shared_ptr<const arm::JointMotion> followWithArm(const BasicValidatedRequest<Space>& r,
                                                      PlannedMotion<Space, G>* m);

/// The sample's joints from the arm's motion (its time, from `side` at a breakpoint).
void fillJoints(const arm::JointMotion& joints, TrajectorySample* s, Side side);

/// Scales the figures of a motion stretched uniformly by k (speeds 1/k, accelerations 1/k², jerks
/// 1/k³, the energy 1/k³).
void stretchFigures(double k, CurveFigures* fig);
}  // namespace planner_detail
}  // namespace se3_interpolation
