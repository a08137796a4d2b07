// arm/: arm_model.h (this header): the serial chain of a URDF from a base link to a tip link, its
// forward kinematics, Jacobian and the Jacobian's time derivative (limits: joint_limits.h).
//
// Chain. Every URDF joint on the path from `base_link` down to `tip_link` (the tip a descendant of
// the base; it may be a TCP frame fixed to the flange). Fixed joints are folded into the fixed
// transform before the next movable joint (or into last_T_tip); movable joints are revolute,
// continuous (revolute without position limits) and prismatic, in chain order from the base.
// Movable joint i contributes (URDF semantics: the child link's frame in the parent's)
//   prev_T_child_i(q_i) = prev_T_joint_i · M_i(q_i),   M_i = Rot(a_i, q_i) or Trans(a_i q_i),
// a_i the unit axis in joint i's frame, prev_T_joint_i the joint's <origin> after the fixed joints
// since the previous movable joint's child frame (or the base). Forward kinematics (FK):
//   base_T_tip(q) = Π_i prev_T_joint_i M_i(q_i) · last_T_tip.                                 (FK)
//
// Jacobian: the base-frame geometric Jacobian at the tip origin, with the project's twist order,
// rotation first (math/lie_groups.h: ξ = (ω, v)):
//   [ω; ṗ] = J(q) q̇,  rows 0–2: ω, the tip's angular velocity (rad/s, base frame, Ṙ = [ω]× R);
//                     rows 3–5: ṗ, the velocity of the tip's origin (m/s, base frame),
// the (ṗ, ω) of geometry/pose.h's spatial Twist. With z_i = base_R_joint_i a_i and o_i the origin
// of joint i's frame, both in the base frame, and p the tip's origin:
//   revolute:  J_i = [z_i; z_i × (p − o_i)],   prismatic: J_i = [0; z_i].                       (J)
// KDL's ChainJntToJacSolver gives the same columns in the order [ṗ; ω]; the spatial Jacobian of
// Murray, Li & Sastry (1994, §3.4) has ṗ − ω × p in place of ṗ.
// Time derivative along q̇: with ω_i⁻ = Σ_{j<i, revolute} z_j q̇_j the angular velocity of joint i's
// parent link, ż_i = ω_i⁻ × z_i; ȯ_i the velocity of o_i (a point of that link) and ṗ = J_v q̇:
//   revolute:  J̇_i = [ż_i; ż_i × (p − o_i) + z_i × (ṗ − ȯ_i)],   prismatic: J̇_i = [0; ż_i],   (J̇)
//   ȯ_{i+1} = ȯ_i + ω_i⁺ × (o_{i+1} − o_i) (+ z_i q̇_i if joint i is prismatic), ω_i⁺ = ω_{i+1}⁻.
// Tip jerk (ArmModel::tipJerk): [ω̈; p⃛] = J q⃛ + 2 J̇ q̈ + J̈ q̇, by the same forward recursion one
// order higher: each link's ω, α = ω̇ and ζ = ω̈, and each joint origin's velocity, acceleration
// and jerk. A revolute joint adds z q̇, ż q̇ + z q̈, z̈ q̇ + 2 ż q̈ + z q⃛ to the link's ω, α, ζ
// (ż = ω⁻ × z, z̈ = α⁻ × z + ω⁻ × ż); a vector d between two points of one link moves as
// ḋ = ω × d, d̈ = α × d + ω × ḋ, d⃛ = ζ × d + 2 α × ḋ + ω × d̈, plus, across a prismatic joint,
// z q̇, ż q̇ + z q̈, z̈ q̇ + 2 ż q̈ + z q⃛ (the sliding origin's motion along the moving axis).
//
// Cost: the kinematics allocate nothing (q is an Eigen::Ref, the Jacobian a fixed-capacity matrix
// of at most kMaxArmJoints columns); a chain with more movable joints is refused.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "se3_interpolation/arm/joint_limits.h"
#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
namespace arm
{
/// Most movable joints a chain may have (the kinematics' buffers live on the stack).
constexpr int kMaxArmJoints = 16;

/// A Jacobian or its time derivative: 6 rows (ω then ṗ, header comment), one column per movable
/// joint; fixed capacity, so returning one allocates nothing.
using ArmJacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxArmJoints>;

/// A rate of the tip in the Jacobian's row order: angular part (rad/s^k) then linear (m/s^k).
using TipVector = Eigen::Matrix<double, 6, 1>;

/// Joint positions, velocities, ...: any Eigen column vector of doubles (VectorXd, Matrix<double, 7, 1>).
using JointVectorRef = Eigen::Ref<const Eigen::VectorXd>;

/// The chain's frames at joint positions q (one FK pass, ArmModel::frames): the tip's pose and
/// each movable joint's axis z_i and origin o_i in the base frame, from which (J) and (J̇) follow
/// without another pass. On the stack (kMaxArmJoints entries, the first n used).
struct ArmFrames
{
  Eigen::Isometry3d base_T_tip = Eigen::Isometry3d::Identity();
  std::array<Eigen::Vector3d, kMaxArmJoints> z;
  std::array<Eigen::Vector3d, kMaxArmJoints> o;
};

/// A movable joint's kind (URDF's continuous: revolute without position limits).
enum class JointType
{
  kRevolute,
  kContinuous,
  kPrismatic,
};

/// One movable joint of the chain.
struct ArmJoint
{
  std::string name;  ///< the URDF joint's name
  JointType type = JointType::kRevolute;
  /// Fixed transform from the previous movable joint's child frame (the base for the first joint)
  /// to this joint's frame: the URDF `<origin>`s of the fixed joints between and of this joint (m).
  Eigen::Isometry3d prev_T_joint = Eigen::Isometry3d::Identity();
  /// Unit axis in this joint's frame (the URDF `<axis>`, normalised).
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  /// From the URDF's `<limit>` (lower, upper except for continuous joints; velocity), then the limits
  /// file (applyLimits).
  JointLimits limits;

  bool isPrismatic() const { return type == JointType::kPrismatic; }
};

/// A serial chain of a URDF between two links (header comment: frames, FK, J, J̇).
class ArmModel
{
public:
  /// The chain from `base_link` to `tip_link` of the URDF `urdf_text`; `source` names the URDF in
  /// messages (a file name). Throws ArmModelError naming the source, link or joint: the text is not
  /// a URDF; either link is missing; the tip is not a descendant of the base (or is the base); a
  /// joint on the chain is floating, planar or a mimic joint, has a zero or non-finite axis or
  /// origin, a revolute or prismatic joint has lower > upper or non-finite bounds, a velocity limit
  /// ≤ 0 or non-finite; the chain has no movable joint or more than kMaxArmJoints.
  ArmModel(const std::string& urdf_text, const std::string& base_link, const std::string& tip_link,
           const std::string& source = "URDF");

  /// The constructor on the URDF file at `path` (messages name the path; ArmModelError if the file
  /// cannot be read).
  static ArmModel fromUrdfFile(const std::string& path, const std::string& base_link, const std::string& tip_link);

  /// Replaces the chain joints' limits by the file's values (JointLimitsFile). An entry naming a
  /// joint the URDF lacks is refused (ArmModelError naming the file and joint); entries for URDF
  /// joints off the chain are ignored (a MoveIt file covers the whole robot). A position range
  /// given for a continuous joint is refused.
  void applyLimits(const JointLimitsFile& limits);

  const std::string& baseLink() const { return base_link_; }
  const std::string& tipLink() const { return tip_link_; }
  /// Number of movable joints, n.
  int dof() const { return static_cast<int>(joints_.size()); }
  /// The movable joints in chain order (base to tip).
  const std::vector<ArmJoint>& joints() const { return joints_; }
  /// Their names in chain order.
  std::vector<std::string> jointNames() const;
  /// Fixed transform from the last movable joint's child frame to the tip (m).
  const Eigen::Isometry3d& last_T_tip() const { return last_T_tip_; }

  /// (FK): the tip's pose in the base frame at joint positions q (rad, m). Throws ArmModelError
  /// if q has not n entries or one is not finite.
  Eigen::Isometry3d base_T_tip(const JointVectorRef& q) const;
  /// base_T_tip as the project's pose type (math/lie_groups.h: x_base = R(q) x_tip + p).
  Pose<double> basePoseOfTip(const JointVectorRef& q) const;
  /// (J): 6 × n, rows [ω; ṗ] in the base frame at the tip origin. Throws as base_T_tip.
  ArmJacobian jacobian(const JointVectorRef& q) const;
  /// (J̇): dJ/dt along joint velocities qd (6 × n, same rows). Throws as base_T_tip, for q and qd.
  ArmJacobian jacobianDerivative(const JointVectorRef& q, const JointVectorRef& qd) const;
  /// FK, J and J̇ in one pass (each output may be null). Throws as jacobianDerivative (qd is read
  /// only when jacobian_derivative is given).
  void kinematics(const JointVectorRef& q, const JointVectorRef& qd, Eigen::Isometry3d* base_T_tip,
                  ArmJacobian* jacobian, ArmJacobian* jacobian_derivative) const;
  /// The frames at q (FK with the joints' axes and origins). Throws as base_T_tip.
  void frames(const JointVectorRef& q, ArmFrames* frames) const;
  /// (J) from frames at q.
  ArmJacobian jacobian(const ArmFrames& frames) const;
  /// (J̇) from frames at q and J at q, along joint velocities qd (n entries, unchecked).
  ArmJacobian jacobianDerivative(const ArmFrames& frames, const ArmJacobian& jacobian, const JointVectorRef& qd) const;
  /// The tip's angular and linear jerk [ω̈; p⃛] (rad/s³, m/s³, base frame; header comment) from
  /// frames at q along joint velocities qd, accelerations qdd and jerks qddd (n entries each,
  /// unchecked). With qddd = 0 it is 2 J̇ q̈ + J̈ q̇, the bias a joint jerk solve subtracts.
  TipVector tipJerk(const ArmFrames& frames, const JointVectorRef& qd, const JointVectorRef& qdd,
                    const JointVectorRef& qddd) const;

  /// Throws ArmModelError ("<field>: 5 entries, the chain 'base_link' → 'tool0' has 6 joints",
  /// "<field>[2] (joint 'elbow_joint'): not finite (nan)") unless v has n finite entries.
  void checkJointVector(const JointVectorRef& v, const std::string& field) const;

private:
  /// FK into base_T_tip; the joints' base-frame axes z_i and origins o_i into z and o when given.
  void forward(const JointVectorRef& q, Eigen::Isometry3d* base_T_tip, Eigen::Vector3d* z, Eigen::Vector3d* o) const;

  std::string source_;
  std::string base_link_;
  std::string tip_link_;
  std::vector<ArmJoint> joints_;
  Eigen::Isometry3d last_T_tip_ = Eigen::Isometry3d::Identity();
  /// Every joint name of the URDF (applyLimits refuses others).
  std::vector<std::string> urdf_joint_names_;
};

}  // namespace arm
}  // namespace se3_interpolation
