// Reading a GenerateTrajectory request from YAML (the CLI's input format).
//
// Field names are those of srv/GenerateTrajectory.srv. A waypoint is
// {position: [x, y, z], orientation: [x, y, z, w]}, a twist {linear: [..], angular: [..]}; the
// spelling `rosservice call` takes is accepted too, so one file serves both: `waypoints` as a
// geometry_msgs/PoseArray {header: {..}, poses: [..]} and vectors/quaternions as maps {x, y, z(, w)}
// where a missing component is 0 ({w: 1} is the identity, {} the zero quaternion, which validation
// refuses). A waypoint without `orientation` is the identity rotation; `position` is required.
// Unknown keys are errors (they are usually typos), and so is a key given twice in one mapping
// (yaml-cpp would keep the first value silently): the error names the key and its line. Errors
// are InvalidInputError
// naming the field and index.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
namespace cli
{
/// The request from a parsed YAML document.
TrajectoryRequest requestFromYaml(const YAML::Node& root);

/// The request from a parsed YAML document whose waypoints and times are given elsewhere (a
/// recording: --waypoints or --bag), so the document carries the other fields only.
/// @param source the option that gave the waypoints, for messages, e.g. "--waypoints 'rec.csv'"
/// @throws InvalidInputError naming `waypoints` or `times` and `source` if the document gives them
///         too, or as requestFromYaml for the other fields
TrajectoryRequest requestFromYaml(const YAML::Node& root, std::vector<Pose<double>> waypoints,
                                  std::vector<double> times, const std::string& source);

/// For `--space sphere`: the waypoints as unit vectors of R^{m+1} (m ≥ 2), with the same
/// sibling fields; velocities become tangent vectors.
std::vector<std::vector<double>> vectorsFromYaml(const YAML::Node& node, const std::string& field);

/// The request for `--space sphere`: the same keys as requestFromYaml, with each waypoint a
/// vector [x1, …, x{m+1}] and start_velocity, end_velocity, start_acceleration and each entry of
/// velocities a vector of the same length (tangent to the sphere at its waypoint).
SphereRequest sphereRequestFromYaml(const YAML::Node& root);

}  // namespace cli
}  // namespace se3_interpolation
