// execution/sample_refinement.h: samples a motion so that an action goal made of them executes it
// faithfully (the ~generate request's `sample_tolerance`), without ROS.
//
// A `~follow_trajectory` goal moves between its points along the quintic in the chart of the
// geometry (execution/goal_trajectory.h, (G1)): sampled sparsely, that quintic can leave the motion
// it was sampled from and exceed the bounds the motion holds (64 samples of a jerk-limited motion of
// 10⁴ s: 600 s apart, the quintic between them at 79 times the velocity bound). The refinement
// inserts samples between two consecutive ones, a and b (times t_a < t_b), halving [t_a, t_b]
// at its middle t_m = (t_a + t_b) / 2 while
//   (D) the goal's pose at t_m or another eighth of [t_a, t_b] is farther than `tolerance` from
//       the motion's, in chord distance √(|Δp|² + ρ² θ²) (m; θ the angle of the relative rotation,
//       ρ the rotation_scale), or the goal refuses the two points (half a turn apart, or a
//       polynomial that overflows). The middle is where the quintic's error τ³(h − τ)³ f⁽⁶⁾/6! of
//       a smooth motion peaks, and it is tested first; the other eighths catch the errors of
//       coarse intervals, where the motion is no polynomial on the quintic's scale, and of kinks
//       (the velocity jumps of piecewise_geodesic's corners), whose errors peak off the middle; or
//   (B) the goal's peaks between a and b (GoalTrajectory::boundExcess; the jerk as the mean
//       |Δa| / h, as checkLimits counts it) exceed a bound by more than kRefinementLimitTolerance, half the
//       node's kGoalLimitTolerance (room for the rounding of time_from_start to ns) — as long as
//       halving helps: an excess that has not fallen below kExcessConvergence times the smallest of
//       the intervals it was split from for kExcessPatience halvings stops (B). Where the motion
//       itself is smooth enough the excess falls with the interval (by half per halving where its
//       jerk is bounded and jumps, as a jerk-limited motion's does); where the motion's
//       acceleration jumps (time_optimal without a jerk bound) the quintic overshoots by a fixed
//       fraction of the jump however dense the samples, and where it exceeds a bound itself (the
//       recovery from a start state beyond one) no sampling can hold it.
// No interval is halved below kMinSampleSpacing. Each interval's test costs up to seven
// evaluations of the motion (the one at t_m kept as the new sample when it is halved), one quintic
// and, with a bound, its peak search.
#pragma once

#include <cstddef>
#include <functional>

#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/geometry/trajectory_sample.h"

namespace se3_interpolation
{
/// The bound excess the refinement leaves: half of the node's acceptance tolerance
/// (kGoalLimitTolerance), so that the node's check of the samples, with their times rounded to the
/// nanoseconds of time_from_start, accepts what the refinement accepted.
constexpr double kRefinementLimitTolerance = 0.5 * kGoalLimitTolerance;
/// The shortest interval the refinement halves (s): a thousand times the 1 ns resolution of
/// time_from_start, so that rounding moves a point by at most 1e-3 of its interval.
constexpr double kMinSampleSpacing = 1e-6;
/// (B) stops when the excess has not fallen below this fraction of the smallest excess of the
/// intervals it was split from for kExcessPatience halvings in a row. Where the excess falls with
/// the interval it halves per halving (a jerk that jumps) or faster, but only once the interval is
/// short against the motion's own time scale (a jerk-limited ramp lasts a / J: 0.33 s in the
/// request-space grid, whose 64 samples of a motion of minutes lie seconds apart); before that a
/// halving may not reduce it. Two halvings stopped 12 of the grid's 143 jerk-limited motions at up
/// to 6 % above a bound (a stop at a corner of piecewise_geodesic, its interval 1.7 times a / J);
/// six let intervals 64 times longer than that scale come down to it. An acceleration jump's
/// overshoot does not fall at all: six halvings at each of them cost a few samples.
constexpr double kExcessConvergence = 0.75;
constexpr int kExcessPatience = 6;

/// What the refinement holds a goal made of the samples to.
struct SampleRefinement
{
  double tolerance = 0.0;                                 ///< (D): m of chord distance (> 0)
  double rotation_scale = 1.0;                            ///< ρ, m per rad, of the chord distance
  GeometryType geometry = GeometryType::kDoubleGeodesic;  ///< the goal's interpolation (the node's ~geometry)
  MotionLimits limits;                                    ///< (B): the request's bounds (0 = unbounded)
};

/// The refinement of one motion's samples (file comment).
class SampleRefiner
{
public:
  /// @param settings the tolerance, geometry and bounds
  /// @param sample_at the motion's sample at a time (pose, velocity, acceleration; any quaternion sign)
  /// @param budget how many samples the refinement may insert in all; one more throws
  SampleRefiner(SampleRefinement settings, std::function<TrajectorySample(double)> sample_at, std::size_t budget);

  /// Inserts samples between two consecutive samples of the motion.
  /// @param a the earlier sample
  /// @param b the later sample
  /// @param emit receives the inserted samples in time order, strictly between a.time and b.time,
  ///        with the quaternion sign of sample_at
  /// @throws LimitExceededError naming sample_tolerance when the budget is spent
  void between(const TrajectorySample& a, const TrajectorySample& b,
               const std::function<void(const TrajectorySample&)>& emit);

private:
  /// The test of one interval: (D) and the bound excess of (B).
  struct Verdict
  {
    bool deviates = false;  ///< (D) holds: halve
    double excess = 0.0;    ///< the largest peak over its bound, minus 1 (≤ 0: within)
  };
  Verdict test(const TrajectorySample& a, const TrajectorySample& b, const TrajectorySample& middle) const;

  SampleRefinement settings_;
  std::function<TrajectorySample(double)> sample_at_;
  std::size_t budget_;
  std::size_t inserted_ = 0;
  std::size_t tests_ = 0;
  bool bounded_ = false;
};

}  // namespace se3_interpolation
