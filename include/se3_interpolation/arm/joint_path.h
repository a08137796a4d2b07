// arm/: joint_path.h (this header): inverse kinematics along a pose motion of the tip, continuous by
// construction: the joint path q(t) whose forward kinematics (arm_model.h) is the motion's pose.
//
// Pose error. At joint positions q with tip pose (R(q), p(q)) and a target (R*, p*), both in the base
// frame, the error has the Jacobian's row order (arm_model.h: [ω; ṗ]):
//   e(q) = [ log(R* R(q)ᵀ)∨ ; p* − p(q) ]   (rad, m; log∨ the rotation vector),
// so that to first order e(q + Δq) = e(q) − J(q) Δq.
//
// Redundancy. With n movable joints, n − 6 of them are held at the seed's value for the whole motion;
// the other six columns of J form J_r (6 × 6). The rule depends on the path only (not on its timing),
// so the joint path of a retimed motion is the same path. Default choice (options.held_joints empty):
// greedily, one joint at a time, hold the joint whose column's removal leaves the Jacobian of the
// remaining columns at the seed with the largest smallest singular value. A chain with n < 6 cannot
// follow a pose motion and is refused.
//
// IK of one pose near a start q (Newton):  Δq_r = J_r(q)⁻¹ e(q),  q_r ← q_r + Δq_r,
// to |e|∞ ≤ kPoseTolerance = 1e-12 (m and rad: about 10⁴ roundoffs of a 1 m arm's FK, 1000 times
// tighter than the 1e-9 the tests ask for); where the rounding floor of the FK is above that (long
// chains, large positions), an error ≤ 1e-10 that no longer halves per iteration is accepted.
// The first solve, from the seed (up to about 1 rad per joint away from the start pose's solution),
// is damped: Levenberg–Marquardt steps Δq_r = (J_rᵀJ_r + λI)⁻¹ J_rᵀ e, each limited to 0.5 rad per
// joint, λ divided by 10 after a step that lowers |e|₂ and multiplied by 10 after one that does not;
// it ends in full Newton (λ = 0) on the solution's branch. A pose the damped solve cannot bring to
// the tolerance is out of reach.
//
// Tracking. The motion is followed piece by piece between the breakpoints, each piece evaluated
// one-sided at its ends (a breakpoint is never stepped across). From a tracked point (t, q, q̇, q̈)
// a step h predicts q_pred = q + q̇ h + ½ q̈ h² and runs Newton at t + h from q_pred. The step is
// accepted if Newton converges within kStepIterations iterations and
//   |q_new − q_pred|∞ ≤ min(1e-3 rad, 0.1 (|q̇ h|∞ + |q̈ h²|∞) + 1e-9),
// the predictor's error (O(h³)) being small beside the step itself: a larger correction means that
// Newton went to another branch of the IK (an elbow or wrist flip), which is detected and never
// taken. Otherwise h is halved; h doubles after a step that converged in ≤ 2 iterations, capped at
// the piece's length / 4. The tracked points are stored. A step over which det J_r changes sign
// has stepped over a singular configuration (det J_r = 0 in between), and one after which a joint
// is past its limit has passed it: both are refused at the crossing time, found by bisection of the
// step (Newton at each midpoint) to 1e-9 of the motion's span.
//
// Rates at known q:  q̇_r = J_r⁻¹ V,  q̈_r = J_r⁻¹ (A − J̇(q, q̇) q̇),  V = [ω; ṗ], A = [ω̇; p̈] the
// motion's spatial twist and acceleration in the base frame; the held joints' rates are 0.
//
// Evaluation at(t): in the tracked interval [t_i, t_i+1] containing t, the cubic Hermite of
// (q, q̇) at its ends predicts q(t), Newton brings it to the pose, and the result must stay within
// 1e-3 rad of the predictor (else the evaluation would change branch: refused).
//
// Refusals (JointPathError, an InvalidInputError, naming what and where): the seed's length or
// finiteness; a pose out of reach ("at t = 1.5 s (position (0.9, 0, 0.3) m)"); a singular
// configuration on the path (J_r's reciprocal condition number below 1e-8 at a tracked point: the
// LU's L1 estimate, within a factor 6 of σ_min(J_r) / σ_max(J_r); det J_r changing
// sign over a step, or the step halved below 1e-9 of the motion's span); a joint passing its position limit (every tracked point and
// every at()). A path near a singularity is followed (its joint rates are large).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/curves/curve.h"

namespace se3_interpolation
{
namespace arm
{
/// A pose motion the arm cannot follow, or bad input to the joint path: the message names the
/// field, time, pose or joint. An InvalidInputError.
class JointPathError : public InvalidInputError
{
public:
  using InvalidInputError::InvalidInputError;
  /// @param what the message
  /// @param time the time on the pose motion at which the arm cannot follow it (s)
  JointPathError(const std::string& what, double time) : InvalidInputError(what), time_(time) {}
  /// The time on the pose motion at which the arm cannot follow it, where the refusal is about one
  /// (reach, a singular configuration, a position limit, a branch change).
  const std::optional<double>& time() const { return time_; }

private:
  std::optional<double> time_;
};

/// Joint positions (rad, m), velocities and accelerations of the movable joints in chain order.
struct JointState
{
  Eigen::VectorXd position, velocity, acceleration;
  /// q⃛ (rad/s³, m/s³) where the motion gives one (RetimedJointPath with the timed pose motion's
  /// jerk), else empty.
  Eigen::VectorXd jerk;
};

/// The tip's motion to follow: base_T_tip pose, spatial twist and acceleration in the base frame at
/// time t (one-sided at a breakpoint).
using PoseMotion = std::function<Kinematics(double t, Side side)>;

/// Options of a joint path.
struct JointPathOptions
{
  /// Joints (chain indices) held at the seed's value (redundancy, n > 6): exactly n − 6 distinct
  /// indices; empty: chosen by the header comment's rule.
  std::vector<int> held_joints;
};

/// One tracked point of a joint path: time (s) and the joint state there.
struct TrackedPoint
{
  double t = 0.0;
  Eigen::VectorXd q, qd, qdd;
};

/// t, or the end of [start, end] that t is past by the rounding of a time computed from the ends
/// (4 ulp of the larger end's magnitude, at least of 1 s). Throws JointPathError for a t farther
/// outside or not finite.
double timeWithin(double t, double start, double end);

/// The arm's joints moving on a time axis: q, q̇, q̈ at t (JointPath: tracked on a pose motion;
/// RetimedJointPath, arm/joint_timing.h: a joint path on a timing's clock).
class JointMotion
{
public:
  virtual ~JointMotion() = default;
  /// q, q̇, q̈ at t in [start, end] (one-sided at breakpoints). Throws JointPathError.
  virtual JointState at(double t, Side side = Side::kRight) const = 0;
  virtual const ArmModel& arm() const = 0;
  virtual double start() const = 0;
  virtual double end() const = 0;
  /// The number of tracked points (JointPath::trackedPoints) strictly inside (t0, t1), t0 ≤ t1:
  /// where the tracking took small steps the joints vary fast, and a check samples as densely.
  virtual std::size_t trackedPointsWithin(double t0, double t1) const = 0;
  /// Whether at() gives the joints' jerk (JointState::jerk).
  virtual bool hasJerk() const = 0;
};

/// The joint path of a pose motion (header comment: method and refusals).
class JointPath final : public JointMotion
{
public:
  /// Tracks `motion` on [breakpoints.front(), breakpoints.back()], analytic between `breakpoints`
  /// (sorted, ends included), starting on the IK branch nearest `seed`. Throws JointPathError
  /// (header comment's refusals), or ArmModelError for a seed of the wrong length or non-finite.
  JointPath(const ArmModel& arm, PoseMotion motion, std::vector<double> breakpoints, const Eigen::VectorXd& seed,
            const JointPathOptions& options = {});

  /// q, q̇, q̈ at t in [start, end] (one-sided at breakpoints); never leaves the tracked branch.
  /// Throws JointPathError for t outside [start, end] or not finite, a joint past its limit, or an
  /// evaluation that would leave the branch.
  JointState at(double t, Side side = Side::kRight) const override;
  /// q̇ = J_r⁻¹V, q̈ = J_r⁻¹(A − J̇q̇) at known joint positions q (the held joints' rates 0).
  JointState rates(const Eigen::VectorXd& q, const Kinematics& k) const;
  /// q⃛ = J_r⁻¹([ω̈; p⃛] − 2 J̇ q̈ − J̈ q̇) at the joint state `state` (positions, velocities,
  /// accelerations) whose tip moves with the jerk `tip_jerk` ([ω̈; p⃛], base frame; the held
  /// joints' jerk 0).
  Eigen::VectorXd jerk(const JointState& state, const TipVector& tip_jerk) const;

  const ArmModel& arm() const override { return *arm_; }
  double start() const override { return breakpoints_.front(); }
  double end() const override { return breakpoints_.back(); }
  std::size_t trackedPointsWithin(double t0, double t1) const override;
  bool hasJerk() const override { return false; }
  const std::vector<double>& breakpoints() const { return breakpoints_; }
  /// The joints held at the seed's value, ascending.
  const std::vector<int>& heldJoints() const { return held_; }
  /// The tracked points of each piece [b_k, b_k+1], the first one-sided right at b_k, the last
  /// one-sided left at b_k+1.
  const std::vector<std::vector<TrackedPoint>>& trackedPoints() const { return pieces_; }

private:
  /// det J_r and its reciprocal condition estimate at a point (from the LU of its rates).
  struct FreeJacobian
  {
    double determinant = 0.0;
    double rcond = 0.0;
  };

  void chooseHeldJoints(const Eigen::VectorXd& seed, const JointPathOptions& options);
  void trackPiece(std::size_t k, TrackedPoint& point);
  TrackedPoint trackedPoint(double t, const Eigen::VectorXd& q, const ArmFrames& f, const Kinematics& k,
                            FreeJacobian* free_jacobian) const;
  /// rates() from the frames f at q; J_r's determinant and condition into free_jacobian if given.
  JointState ratesAt(const Eigen::VectorXd& q, const ArmFrames& f, const Kinematics& k,
                     FreeJacobian* free_jacobian) const;
  /// Newton on the free joints from q to `target` (at most max_iterations); the iterations used,
  /// or −1 if it did not converge. On convergence, *frames (if given) are the frames at q.
  int newton(const Pose<double>& target, Eigen::VectorXd& q, int max_iterations, ArmFrames* frames = nullptr) const;
  Eigen::VectorXd solveFromSeed(const Eigen::VectorXd& seed, const Pose<double>& target, double t) const;
  void checkPoint(const TrackedPoint& point, const FreeJacobian& free_jacobian) const;
  void checkLimits(double t, const Eigen::VectorXd& q) const;
  /// The limit refusal at t for q, which has a joint past its limits.
  JointPathError limitError(double t, const Eigen::VectorXd& q) const;
  /// The first time in (from.t, t] at which past(q(t)) holds (it holds at t for the given q), by
  /// bisection; q becomes the joint positions there, *q_before (if given) those at the latest time
  /// found before it.
  double firstTimeWhere(const TrackedPoint& from, double t, Eigen::VectorXd& q,
                        const std::function<bool(const Eigen::VectorXd&)>& past,
                        Eigen::VectorXd* q_before = nullptr) const;
  /// det J_r(q) (its sign changes only through a singular configuration).
  double freeDeterminant(const Eigen::VectorXd& q) const;

  std::shared_ptr<const ArmModel> arm_;
  PoseMotion motion_;
  std::vector<double> breakpoints_;
  std::vector<int> held_;
  std::vector<int> free_;
  std::vector<std::vector<TrackedPoint>> pieces_;
  std::vector<double> tracked_times_;  ///< every tracked point's time, ascending
};

/// The joint path of a pose curve on its own time axis: its breakpoints (with its start and end
/// times) and kinematicsAt (analysis/kinematics.h). Throws as JointPath, and JointPathError for a
/// null curve.
template <class G>
JointPath jointPathOf(const ArmModel& arm, std::shared_ptr<const Curve<G>> curve, const Eigen::VectorXd& seed,
                      const JointPathOptions& options = {})
{
  if (!curve)
    throw JointPathError("jointPathOf: no curve given");
  const double t0 = curve->startTime(), t1 = curve->endTime();
  std::vector<double> b{ t0 };
  for (double t : curve->breakpoints())
    if (t > b.back() && t < t1)
      b.push_back(t);
  b.push_back(t1);
  PoseMotion motion = [curve](double t, Side side) { return kinematicsAt(*curve, t, side); };
  return JointPath(arm, std::move(motion), std::move(b), seed, options);
}

}  // namespace arm
}  // namespace se3_interpolation
