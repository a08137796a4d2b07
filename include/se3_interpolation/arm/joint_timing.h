// arm/: joint_timing.h (this header): an arm's joint limits as constraints of the timing, and the
// check of a timed motion's joint rates against them.
//
// Along a path C(s) that the arm follows (arm/joint_path.h, the path's own time axis s as the path
// parameter), joint k moves at q̇_k = q′_k ṡ and accelerates at q̈_k = q′_k s̈ + q″_k ṡ², so its
// limits are the box constraint (4), (5) of timing/time_optimal.h with w = q′_k, a = q″_k,
// V = max_velocity, A = max_acceleration (JointBoxes): linear in (x = ṡ², u = s̈), held by the
// time-optimal passes together with the Cartesian norm bounds.
//
// Every timing's motion is then checked on the timed motion itself (checkJointRates): the joint
// velocities and accelerations q̇ = J⁻¹V, q̈ = J⁻¹(A − J̇q̇) (J on the joints that move) at the
// ends and middle of every interval between the motion's breakpoints, each analytic piece cut
// into at least kJointCheckIntervals intervals, and, where a parabola through a joint's three
// values peaks inside, at its peak found by successive parabolic interpolation on the exact rates
// (timing/peak_search.h). A motion from rest that exceeds a limit is stretched uniformly by
// k = max(1, v/V, √(a/A)) over every joint (velocities scale by 1/k, accelerations by 1/k²);
// where a stretch would change the motion's start (a moving start) the excess is refused.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "se3_interpolation/arm/joint_path.h"
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
  const JointPath& path() const { return path_; }

private:
  JointPath path_;
};

/// One joint's peak rates over a timed motion, and when they occur (s).
struct JointPeak
{
  double velocity = 0.0;      ///< max |q̇| (rad/s or m/s)
  double acceleration = 0.0;  ///< max |q̈| (rad/s² or m/s²)
  double velocity_time = 0.0;
  double acceleration_time = 0.0;
};

/// The joint rates of a timed motion against the arm's limits.
struct JointRatesCheck
{
  std::vector<JointPeak> peaks;  ///< per movable joint, in chain order
  /// The uniform stretch k ≥ 1 that brings every joint within its limits: max(1, v/V, √(a/A)).
  double stretch = 1.0;
  /// The joint, quantity ("velocity" or "acceleration") and time of the largest ratio to its limit
  /// (v/V or a/A); joint −1 where no joint has a limit.
  int binding_joint = -1;
  std::string binding_quantity;
  double binding_ratio = 0.0;
  double binding_time = 0.0;
};

/// Checks the timed motion `motion` (arm/joint_path.h: the arm following the timed pose motion;
/// header comment for the points it evaluates).
JointRatesCheck checkJointRates(const JointPath& motion, const std::vector<double>& breakpoints);

/// The message that names the joint, its limit and the time where `check` exceeds a limit (for a
/// motion that cannot be stretched), e.g. "joint 'elbow_joint': velocity 3.4 rad/s at t = 1.2 s,
/// above its limit 3.14 rad/s".
std::string jointExcessMessage(const ArmModel& arm, const JointRatesCheck& check);

}  // namespace arm
}  // namespace se3_interpolation
