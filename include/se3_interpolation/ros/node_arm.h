// ros/: node_arm.h (this header): the node's arm (docs/joint_space.md), read at start-up from its
// parameters: with ~tip_link set, the chain from ~base_link to ~tip_link of the URDF held by the
// parameter that ~robot_description names (found by searchParam from the node's namespace, as
// robot_state_publisher finds `robot_description`), with the joint limits of ~joint_limits
// (MoveIt's joint_limits.yaml format below that name, e.g. loaded by
// `<rosparam command="load" file="ur5e_joint_limits.yaml"/>` inside the node's element).
#pragma once

#include <memory>
#include <string>

#include <ros/node_handle.h>

#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/ros/node_parameters.h"

namespace se3_interpolation
{
/// The arm's joint limits below the node's private namespace (~joint_limits/<joint>/max_velocity, ...):
/// a dictionary, not a row of the parameter table.
constexpr const char* kJointLimitsParameter = "joint_limits";

/// The arm the node's requests are followed by, or why it could not be loaded.
class NodeArm
{
public:
  /// Loads the arm of `p` (none when p.tip_link is empty). A URDF or limits that cannot serve are
  /// kept as an error, not thrown: the node serves on, and refuses every request with it.
  NodeArm(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeParameters& p);

  /// The arm for a request: null without one; throws InvalidInputError with the load's error when
  /// it is configured but could not be loaded.
  std::shared_ptr<const arm::ArmModel> forRequest() const;

  /// One line for the node's ready message: "arm base_link -> tool0 (6 joints)", or "no arm".
  std::string summary() const;

private:
  std::shared_ptr<const arm::ArmModel> model_;
  std::string error_;  ///< non-empty: configured, not loaded
};
}  // namespace se3_interpolation
