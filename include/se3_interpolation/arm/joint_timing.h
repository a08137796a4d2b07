// arm/: joint_timing.h (this header): an arm's joint limits as constraints of the timing, and the
// check of a timed motion's joint rates against them.
//
// Along a path C(s) that the arm follows (arm/joint_path.h, the path's own time axis s as the path
// parameter), joint k moves at q̇_k = q′_k ṡ and accelerates at q̈_k = q′_k s̈ + q″_k ṡ², so its
// limits are the box constraint (4), (5) of timing/time_optimal.h with w = q′_k, a = q″_k,
// V = max_velocity, A = max_acceleration (JointBoxes): linear in (x = ṡ², u = s̈), held by the
// time-optimal passes together with the Cartesian norm bounds.
//
// A timing runs the path on its clock s(t), so the arm's timed motion is the path's joint path on
// that clock (RetimedJointPath): q(t) = q(s(t)), q̇ = q′ ṡ, q̈ = q′ s̈ + q″ ṡ², no second inverse
// kinematics along the timed motion. The time-optimal timing holds and checks the boxes itself
// (its final check's peaks per joint: TimingProfile::box_peaks, turned into a JointRatesCheck by
// jointRatesOf); every other timing's motion is checked on the timed motion (checkJointRates):
// the joint velocities and accelerations at the ends and middle of every interval between the
// motion's breakpoints, each analytic piece cut into at least kJointCheckIntervals intervals and
// each interval into four times as many as the joint path's tracked points inside it (the tracking's
// steps shrink where the joints vary fast: near a singular configuration, a sliver of a piece), and,
// where a parabola through a joint's three values peaks inside, at its peak found by successive
// parabolic interpolation on the exact rates (timing/peak_search.h). A motion from rest that
// exceeds a limit is stretched uniformly by k = max(1, v/V, √(a/A)) over every joint (velocities
// scale by 1/k, accelerations by 1/k²: stretchJointRates); where a stretch would change the
// motion's start (a moving start) the excess is refused.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "se3_interpolation/arm/joint_path.h"
#include "se3_interpolation/math/jet.h"
#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace arm
{
/// The least number of intervals per analytic piece of the timed motion that checkJointRates
/// evaluates (ends and middle each, then the searched peaks).
constexpr std::size_t kJointCheckIntervals = 16;

/// The joint limits of `path`'s arm as the box constraint (4), (5) of the time-optimal timing:
/// w = q′, a = q″ of `path` (whose time axis is the path parameter). Joints without a velocity or
/// acceleration limit leave that limit 0 (none); held joints (redundancy) never move.
class JointBoxes final : public timing::BoxConstraint
{
public:
  explicit JointBoxes(JointPath path);
  std::size_t size() const override;
  double velocityLimit(std::size_t k) const override;
  double accelerationLimit(std::size_t k) const override;
  void jet(double s, Side side, double* w, double* a) const override;
  /// The joint path whose rates the boxes are.
  const std::shared_ptr<const JointPath>& path() const { return path_; }

private:
  std::shared_ptr<const JointPath> path_;
};

/// A joint path run on a timing's clock: q(t) = P(s(t)), q̇ = P′(s) ṡ, q̈ = P′(s) s̈ + P″(s) ṡ²
/// (the chain rule), P′ and P″ the path's rates on its own time axis s.
class RetimedJointPath final : public JointMotion
{
public:
  /// s(t) as a 2-jet in t, and the side of s the path is evaluated from (given t's side).
  using Clock = std::function<Jet<2>(double t, Side side, Side* path_side)>;
  /// The timed pose motion's jerk [ω̈; p⃛] at t (base frame).
  using TipJerk = std::function<TipVector(double t, Side side)>;
  /// @param path the joint path on the path's time axis
  /// @param clock s(t) on [start, end] into [path->start(), path->end()]
  /// @param start the first time of the timed motion (s)
  /// @param end its last time (s)
  /// @param tip_jerk the timed motion's jerk, from which at() gives q⃛ (JointPath::jerk); none:
  /// the motion has no finite jerk, and at() leaves JointState::jerk empty
  RetimedJointPath(std::shared_ptr<const JointPath> path, Clock clock, double start, double end,
                   TipJerk tip_jerk = nullptr);
  bool hasJerk() const override { return static_cast<bool>(tip_jerk_); }
  JointState at(double t, Side side = Side::kRight) const override;
  const ArmModel& arm() const override { return path_->arm(); }
  double start() const override { return start_; }
  double end() const override { return end_; }
  std::size_t trackedPointsWithin(double t0, double t1) const override;
  const JointPath& path() const { return *path_; }

private:
  std::shared_ptr<const JointPath> path_;
  Clock clock_;
  double start_, end_;
  TipJerk tip_jerk_;
};

/// One joint's peak rates over a timed motion (max |q̇|, rad/s or m/s; max |q̈|, rad/s² or m/s²),
/// and when they occur (s): a box component's peaks; and, where the motion has a jerk, max |q⃛|
/// (rad/s³ or m/s³) and when.
struct JointPeak : timing::BoxPeak
{
  double jerk = 0.0;
  double jerk_time = 0.0;
};

/// The joint rates of a timed motion against the arm's limits.
struct JointRatesCheck
{
  std::vector<JointPeak> peaks;  ///< per movable joint, in chain order
  /// Whether the peaks include the jerk (the motion has one, JointMotion::hasJerk, and its
  /// joint accelerations are continuous).
  bool has_jerk = false;
  /// The first time (s) at which a joint's acceleration steps (between the start state and the
  /// motion, or across a breakpoint: an unbounded jerk); NaN where none does.
  double acceleration_step_time = std::numeric_limits<double>::quiet_NaN();
  /// The uniform stretch k ≥ 1 that brings every joint within its limits:
  /// max(1, v/V, √(a/A), ∛(j/J)).
  double stretch = 1.0;
  /// The joint, quantity ("velocity", "acceleration" or "jerk") and time of the largest ratio to
  /// its limit (v/V, a/A or j/J); joint −1 where no joint has a limit.
  int binding_joint = -1;
  std::string binding_quantity;
  double binding_ratio = 0.0;
  double binding_time = 0.0;
};

/// Whether a joint of `arm` has a jerk limit (the limits file's max_jerk).
bool hasJerkLimits(const ArmModel& arm);

/// The window of the jerk-limited timing (timing/jerk_limited.h, JerkLimitedOptions::window) for
/// the arm's jerk limits: max over joints of 2a′/j, a′ = max_acceleration, or √(max_velocity · j)
/// for a joint without an acceleration limit (as for a channel, jerk_limited.h); 0 if no joint has
/// a jerk limit. The factor 2: the window's jerk is the change of the underlying timing's joint
/// acceleration q′s̈ over τ (eq. 2), up to 2a′ where it switches from full acceleration to full
/// braking (the joint boxes have no plateaus, which the Cartesian channels' jerk bounds get).
double jointJerkWindow(const ArmModel& arm);

/// A joint acceleration step that checkJointRates reports: |q̈⁺ − q̈⁻| above this fraction of
/// |q̈⁺| + |q̈⁻| plus kAccelerationStepFloor (rad/s², m/s²), far above the rounding of the joints'
/// rates on either side of a breakpoint of a C² motion.
constexpr double kAccelerationStepTolerance = 1e-6;
constexpr double kAccelerationStepFloor = 1e-9;

/// Checks the timed motion `motion` (arm/joint_path.h: the arm following the timed pose motion;
/// header comment for the points it evaluates), and where its joint accelerations step.
JointRatesCheck checkJointRates(const JointMotion& motion, const std::vector<double>& breakpoints);

/// The check of a timing's box peaks (one per joint, chain order; no jerk): their ratios to the
/// arm's limits, the binding joint and the stretch.
JointRatesCheck jointRatesOf(const ArmModel& arm, const std::vector<timing::BoxPeak>& peaks);

/// The check of the same motion stretched uniformly by k ≥ 1 from its start t0: velocities by
/// 1/k, accelerations by 1/k², jerks by 1/k³, the peaks' times t0 + (t − t0) k.
JointRatesCheck stretchJointRates(const ArmModel& arm, const JointRatesCheck& check, double k, double t0);

/// The message that names the joint, its limit and the time where `check` exceeds a limit (for a
/// motion that cannot be stretched), e.g. "joint 'elbow_joint': velocity 3.4 rad/s at t = 1.2 s,
/// above its limit 3.14 rad/s".
std::string jointExcessMessage(const ArmModel& arm, const JointRatesCheck& check);

}  // namespace arm
}  // namespace se3_interpolation
