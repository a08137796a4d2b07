// ros/frame_memory.h: what the moving frame showed, kept on the parameter server so that a node
// that crashes and is respawned (roslaunch's respawn) takes the setpoint up where it was instead of
// accepting any start. The parameter ~executed_frame (a struct: frame_id, pose [x, y, z, qx, qy,
// qz, qw] world_T_body, at_rest) is written by the action server whenever the frame executing goals
// comes to rest or starts moving (a few writes per goal), and read once at start-up:
//  - at rest: the node holds the frame at that pose and ~command carries it again, the same
//    setpoint as before the crash (a goal then starts there, as after any goal);
//  - moving (the node died during a goal): where the setpoint was is unknown, and goals are refused
//    until the node has a state: the measured frame ~actual_frame in TF (the frame is held at its
//    pose), or a ~generate publication that places the frame.
// The parameter lives while the master runs; `rosparam delete ~executed_frame` forgets it.
#pragma once

#include <ros/ros.h>

#include <optional>
#include <string>

#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
/// The parameter's name in the node's private namespace.
constexpr const char* kFrameMemoryParameter = "executed_frame";

/// What the frame executing goals showed.
struct RememberedFrame
{
  std::string frame_id;
  Pose<double> pose;
  bool at_rest = true;
};

/// Writes `frame` as ~executed_frame (one call: the struct replaces the previous one whole).
void rememberFrame(const ros::NodeHandle& private_nh, const RememberedFrame& frame);

/// ~executed_frame as the previous instance left it; empty when absent or malformed (warned).
std::optional<RememberedFrame> recallFrame(const ros::NodeHandle& private_nh);

}  // namespace se3_interpolation
