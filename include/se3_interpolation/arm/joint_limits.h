// arm/: the serial arm model of joint-space planning (library se3_interpolation_arm: Eigen,
// urdfdom, yaml-cpp; no ROS). joint_limits.h (this header): a joint's limits and MoveIt's
// joint_limits.yaml format; arm_model.h: the kinematic chain, forward kinematics, Jacobian.
//
// Units: a revolute or continuous joint's position is in rad, its rates in rad/s, rad/s², rad/s³;
// a prismatic joint's in m, m/s, m/s², m/s³. A limit that does not apply is infinite (a continuous
// joint's position, a rate the URDF and the limits file leave unset).
//
// The limits file is MoveIt's joint_limits.yaml (moveit_setup_assistant writes it beside the SRDF):
//   joint_limits:
//     <joint name>:
//       has_velocity_limits: true        max_velocity: 2.175
//       has_acceleration_limits: true    max_acceleration: 15.0
//       has_jerk_limits: true            max_jerk: 7500.0
//       has_position_limits: false       (min_position, max_position when true)
//       has_effort_limits: false         (max_effort: read and checked, not kept: no dynamics here)
// A value counts only when its has_* flag is true, as in MoveIt; it then replaces the URDF's.
// Other top-level keys (default_velocity_scaling_factor, ...) are MoveIt's and are ignored; an
// unknown key inside a joint's entry is refused (a misspelt limit would otherwise be lost).
#pragma once

#include <limits>
#include <map>
#include <optional>
#include <string>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace arm
{
/// Bad input to the arm model (URDF, links, limits file, joint positions): the message names the
/// file, link, joint or field. An InvalidInputError, so an InterpolationError (exceptions.h).
class ArmModelError : public InvalidInputError
{
public:
  using InvalidInputError::InvalidInputError;
};

/// One joint's limits (units in the file comment); +∞ (−∞ for min_position) where none applies.
struct JointLimits
{
  static constexpr double kNone = std::numeric_limits<double>::infinity();

  double min_position = -kNone;     ///< rad or m
  double max_position = kNone;      ///< rad or m
  double max_velocity = kNone;      ///< rad/s or m/s, > 0
  double max_acceleration = kNone;  ///< rad/s² or m/s², > 0
  double max_jerk = kNone;          ///< rad/s³ or m/s³, > 0

  bool hasPositionLimits() const { return min_position > -kNone || max_position < kNone; }
  bool hasVelocityLimit() const { return max_velocity < kNone; }
  bool hasAccelerationLimit() const { return max_acceleration < kNone; }
  bool hasJerkLimit() const { return max_jerk < kNone; }
};

/// One joint's entry of a limits file: the values whose has_* flag is true, each already checked
/// (finite; rates positive; has_position_limits gives both positions, min_position ≤ max_position).
struct JointLimitsEntry
{
  std::optional<double> min_position;
  std::optional<double> max_position;
  std::optional<double> max_velocity;
  std::optional<double> max_acceleration;
  std::optional<double> max_jerk;
};

/// A parsed limits file: `source` (the file name, or the caller's label for a string) names it
/// in later messages (ArmModel::applyLimits refuses an entry for a joint the URDF lacks).
struct JointLimitsFile
{
  std::string source;
  std::map<std::string, JointLimitsEntry> joints;
};

/// Parses joint_limits.yaml text (format in the file comment). Throws ArmModelError naming
/// `source` and the field ("<source>: joint_limits.<joint>.max_velocity: -1 must be positive") on
/// YAML syntax errors, a missing or non-map `joint_limits`, a value that is not a number or a bool,
/// a has_* flag true without its value, a non-finite value, a rate ≤ 0, min_position > max_position
/// or an unknown key in a joint's entry.
JointLimitsFile parseJointLimits(const std::string& yaml_text, const std::string& source = "joint limits");

/// parseJointLimits of the file at `path` (messages name the path); throws ArmModelError if it
/// cannot be read.
JointLimitsFile readJointLimitsFile(const std::string& path);

}  // namespace arm
}  // namespace se3_interpolation
