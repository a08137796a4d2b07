// execution/goal_trajectory.h: the motion of an action goal (a trajectory_msgs/MultiDOFJointTrajectory
// of one joint, the node's `~follow_trajectory`), without ROS: its points validated, the motion
// through them, and the checks of that motion against the node's bounds before it runs.
//
// Conventions (the same as the planner's, planner/request.h). A point is a world_T_body pose
// x_i = (R_i, p_i) in the trajectory's frame (header.frame_id): p in m, R as a unit quaternion
// (x, y, z, w; q and −q are the same rotation and give the same motion), reached at
// t_i = time_from_start (s after the goal's stamp). Its velocity is the spatial twist (ṗ, ω) with
// Ṙ = [ω]× R (m/s, rad/s) and its acceleration (p̈, ω̇) (m/s², rad/s²), both in that frame.
//
// The motion. Between x_i and x_{i+1}, h = t_{i+1} − t_i, τ = t − t_i, it is the chart polynomial
//   c(t) = G::exp(x_i, P_i(τ)),  P_i(τ) = Σ_k c_k τ^k ∈ T_{x_i},                                  (G1)
// in the chart at x_i of the geometry G (the node's ~geometry: double_geodesic, SO(3) × R³; screw,
// SE(3); geometry/), whose coefficients are the two-point Hermite interpolant of
// curves/chart_hermite.h (H1): P_i has at 0 the chart jet of τ ↦ G::log(x_i, X_i(τ)) and at h that
// of τ ↦ G::log(x_i, X_{i+1}(τ)), X_j(τ) the second-order jet of the pose moving with the point's
// velocity and acceleration (poseJet). So, by what the points carry:
//   velocities and accelerations at every point: a quintic (order 2): c passes every x_i at t_i
//                                  with its velocity and acceleration from both sides, C²;
//   velocities only:               a cubic (order 1), C¹ (the acceleration jumps at the points);
//   neither:                       the geodesic x_i → x_{i+1} of G at constant rate (order 0,
//                                  P_i(τ) = (τ/h) G::log(x_i, x_{i+1})), C⁰ (the velocity jumps).
// In the abelian cases (a pure translation, a rotation about one fixed axis) the chart is linear
// and (G1) is the classical Hermite polynomial of the coordinates. Velocities, accelerations and
// jerks of the motion are exact (jet arithmetic through (G1), math/jet.h), not finite differences.
// A segment is found by binary search: construction is O(N), a state O(log N).
//
// The bounds (checkLimits). |ṗ|, |ω|, |p̈|, |ω̇|, |p⃛|, |ω̈| of the motion are searched for their peaks
// on each segment: kPeakSubintervals subintervals evaluated at their ends (one-sided) and middle,
// refined by successive parabolic interpolation (timing/peak_search.h) where a value or the
// parabola through the three values comes within kPeakRefineMargin of the largest value so far,
// i.e. between the points, not only at them. Where the velocity jumps (order 0) the acceleration is
// an impulse, where the acceleration jumps (orders 0, 1) the jerk is: a bound on those is refused
// there, naming the point.
// Velocity and acceleration bounds hold for the interpolated motion itself; a jerk bound holds for
// each segment's mean jerk, |Δp̈| / h and |Δω̇| / h between its points (what a controller
// differentiating the setpoints at the points' rate sees). The quintic's own jerk cannot be held
// to the bound: sampled from a jerk-limited motion whose jerk switches sign between two points, the
// quintic through them reaches ~1.4 times the jerk of the motion sampled, however dense the
// samples (the overshoot of a polynomial through a kink of the derivative it fits); likewise its
// acceleration overshoots where the sampled motion's acceleration jumps (time_optimal without a
// jerk bound), which the acceleration bound then refuses, suggesting a jerk bound.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/execution/playback.h"
#include "se3_interpolation/geometry/trajectory_sample.h"

namespace se3_interpolation
{
/// The FollowJointTrajectory error codes a goal can be refused with before it runs
/// (control_msgs/FollowJointTrajectoryResult's error_code values).
enum class GoalError
{
  kInvalidGoal = -1,
  kInvalidJoints = -2,
  kOldHeaderTimestamp = -3
};

/// A refused goal: its message names the field and index ("trajectory.points[3]..."), code() says
/// which FollowJointTrajectory error code to answer with.
class InvalidGoalError : public InvalidInputError
{
public:
  /// @param code the error code of the result
  /// @param what the message, starting with the field it is about
  InvalidGoalError(GoalError code, const std::string& what);
  /// @return the error code of the result
  GoalError code() const;

private:
  GoalError code_;
};

/// One point of the goal's trajectory, as the message gives it (file comment: frames and units).
struct GoalPoint
{
  double time_from_start = 0.0;  ///< s after the goal's stamp
  /// world_T_body; the quaternion as given (validated and normalised by GoalTrajectory)
  Pose<double> pose;
  /// The spatial twist (ṗ, ω) (m/s, rad/s); absent when the message has none
  std::optional<Twist> velocity;
  /// (p̈, ω̇) (m/s², rad/s²); absent when the message has none
  std::optional<Twist> acceleration;
};

/// Limits the interpolated motion must respect (0 = unbounded): the node's ~max_* parameters.
struct MotionLimits
{
  double max_linear_velocity = 0.0;       ///< m/s, bound on |ṗ|
  double max_angular_velocity = 0.0;      ///< rad/s, bound on |ω|
  double max_linear_acceleration = 0.0;   ///< m/s², bound on |p̈|
  double max_angular_acceleration = 0.0;  ///< rad/s², bound on |ω̇|
  double max_linear_jerk = 0.0;           ///< m/s³, bound on |p⃛|
  double max_angular_jerk = 0.0;          ///< rad/s³, bound on |ω̈|
};

/// The six bounds of anything that names them as the ~generate request and the node's ~max_*
/// parameters do (max_linear_velocity … max_angular_jerk): TrajectoryRequest, a validated request,
/// NodeParameters.
template <class Bounds>
MotionLimits motionLimitsOf(const Bounds& b)
{
  MotionLimits l;
  l.max_linear_velocity = b.max_linear_velocity;
  l.max_angular_velocity = b.max_angular_velocity;
  l.max_linear_acceleration = b.max_linear_acceleration;
  l.max_angular_acceleration = b.max_angular_acceleration;
  l.max_linear_jerk = b.max_linear_jerk;
  l.max_angular_jerk = b.max_angular_jerk;
  return l;
}

/// The peak of one rate of the motion.
struct RatePeak
{
  double value = 0.0;       ///< the rate's largest value (its unit: m/s … rad/s³)
  double time = 0.0;        ///< where it is reached (s of time_from_start)
  std::size_t segment = 0;  ///< the segment i (points[i] → points[i + 1]) that reaches it
};

/// The peaks of the six rates, in the order of MotionLimits: |ṗ|, |ω|, |p̈|, |ω̇|, |p⃛|, |ω̈|.
using MotionPeaks = std::array<RatePeak, 6>;

/// The relative tolerance of the node's bounds check of a goal (checkLimits' `tolerance`): sampled
/// every 10 ms from a motion that holds its velocity and acceleration bounds exactly (jerk-limited
/// time_optimal at its acceleration bound), the quintic between the samples overshoots them by up
/// to ~0.3 % (measured: test_goal_trajectory's planner samples, test_node_action); 1 % lets such
/// goals through and still refuses the ~40 % overshoot of a sampled acceleration jump.
constexpr double kGoalLimitTolerance = 0.01;

/// The cost of checking a goal per point (s): building, checkLimits and requireEndsAtRest measured
/// at ~21 µs per point on 10⁴ points (test_goal_trajectory's TenThousandPointsAreCheap, this
/// machine), doubled as the work estimates of planner/work_estimate.h are (within 2× of measured).
/// The action server refuses a goal whose points × this exceeds ~max_work_seconds.
constexpr double kGoalCheckSecondsPerPoint = 4e-5;

/// The end of a motion counts as at rest below these speeds (m/s, rad/s): far below what a robot
/// executes, far above the rounding of a motion planned to stop (~1e-12).
constexpr double kRestLinear = 1e-6;
constexpr double kRestAngular = 1e-6;

/// Subintervals per segment of the peak search, and the margin (fraction of the largest value so
/// far) within which a subinterval is refined (as the jerk peaks of timing/jerk_peaks.h).
constexpr std::size_t kPeakSubintervals = 8;
constexpr double kPeakRefineMargin = 0.1;

/// The validated motion of a goal (file comment).
class GoalTrajectory
{
public:
  /// Validates the points and builds the motion through them.
  /// @param points the trajectory's points, in order
  /// @param geometry the geometry of the interpolation between them (the node's ~geometry)
  /// @throws InvalidGoalError (kInvalidGoal) naming the field and point, e.g.
  ///         "trajectory.points[3].transforms[0].rotation: quaternion norm 0.5 is outside [0.99, 1.01] ...",
  ///         for: no points; a number that is not finite or beyond kMaxMagnitude; a time_from_start that
  ///         is negative or not after the previous one; a quaternion norm outside [kMinUnitNorm,
  ///         kMaxUnitNorm]; velocities at some points only; accelerations at some points only or without
  ///         velocities; two consecutive points half a turn apart (naming both); a segment too short for
  ///         its data (its polynomial overflows)
  GoalTrajectory(std::vector<GoalPoint> points, GeometryType geometry);

  /// @return the first point's time_from_start (s)
  double startTime() const;
  /// @return the last point's time_from_start (s)
  double endTime() const;
  /// @return the number of points
  std::size_t size() const;

  /// The state of the motion at t (s of time_from_start), clamped to [startTime(), endTime()]: the
  /// pose, velocity and acceleration (spatial twists; at a point the limit from the right, at the
  /// end from the left). sample.time is the clamped t.
  TrajectorySample stateAt(double t) const;

  /// The motion for execution/playback.h: state_at = stateAt (sharing the motion, so it may outlive
  /// this object), start_time = startTime(), duration = endTime() − startTime().
  /// @param frame_id the frame of the poses (the goal's header.frame_id)
  /// @param child_frame_id the moving frame (the goal's joint name)
  Motion motion(const std::string& frame_id, const std::string& child_frame_id) const;

  /// The peaks of the motion's six rates over its whole span (file comment), each within 1e-6
  /// relative of the true peak (the search refines to ~1e-12).
  MotionPeaks peaks() const;

  /// Checks the motion, between the points as well as at them, against `limits` (jerk: the
  /// segments' mean jerk, file comment).
  /// @param limits the bounds (0 = unbounded)
  /// @param tolerance a peak up to bound × (1 + tolerance) is accepted
  /// @throws InvalidGoalError (kInvalidGoal) naming the segment "trajectory.points[i]" (segment
  ///         i → i + 1), the bound ("~max_linear_acceleration" …), the value and the time of the
  ///         largest excess; or naming the point where the velocity (with an acceleration bound) or
  ///         the acceleration (with a jerk bound) jumps
  void checkLimits(const MotionLimits& limits, double tolerance = 0.0) const;

  /// How far the motion exceeds `limits`, as checkLimits counts the peaks, searched only as far as
  /// telling whether the excess is above `tolerance`: a subinterval is refined only where a bounded
  /// rate comes within kPeakRefineMargin below bound × (1 + tolerance) without exceeding it
  /// (execution/sample_refinement.h asks this of every interval it tests). Unlike checkLimits it
  /// does not look for jumps at the points (a two-point goal has none).
  /// @return the largest peak / bound − 1 over the bounded rates: exact within the peak search's
  ///         1e-6 where it is near `tolerance`, a lower bound of the true excess elsewhere; −1
  ///         without bounds
  double boundExcess(const MotionLimits& limits, double tolerance) const;

  /// Checks that the motion ends at rest: the velocity at the end (from the left) within
  /// kRestLinear and kRestAngular.
  /// @throws InvalidGoalError (kInvalidGoal) naming the last point and its speeds
  void requireEndsAtRest() const;

  /// The motion's evaluation, shared with the Motions handed out (defined in the source).
  class Interpolant;

private:
  std::shared_ptr<const Interpolant> interpolant_;
};

}  // namespace se3_interpolation
