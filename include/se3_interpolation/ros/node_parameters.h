// Parameters of se3_interpolation_node, read at start-up from the private namespace `~`: one
// table, cfg/node_parameters.yaml (name, type, default, range, unit, run-time group, doc), from
// which the build generates NodeParameterValues and kNodeParameterSpecs
// (se3_interpolation/node_parameter_table.h), dynamic_reconfigure's server
// (cfg/InterpolationNode.cfg), docs/ros_interface.md's table and config/se3_interpolation.yaml.
// Everything here reads that table: nothing names a parameter twice.
#pragma once

#include <dynamic_reconfigure/Config.h>
#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "se3_interpolation/node_parameter_table.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
/// The parameters in effect: one member per row of the table, initialised to its default.
struct NodeParameters : NodeParameterValues
{
  /// The resource bounds of a request: ~max_samples, ~max_waypoints, ~max_work_seconds.
  PlannerLimits limits() const;
};

/// The row of `name` (without "~"); nullptr when the table has none.
const ParameterSpec* findNodeParameter(const std::string& name);

/// Why the parameter `spec` cannot take `value`, naming "~<name>" (a number outside its range,
/// a choice not among its names, a frame id breaking tf2's rules, quoted to at most
/// kMaxQuotedLength characters); "" when it can.
std::string parameterError(const ParameterSpec& spec, double value);
std::string parameterError(const ParameterSpec& spec, const std::string& value);

/// The int parameter `spec` as the parameter server holds it (`raw`) into `value`: an int, or a
/// double of a whole value within the int's range (YAML reads 2e5 as a double). Returns "", or
/// why not, naming "~<name>" and the value given (roscpp's own conversion turns 1e12 into
/// -2147483648). The row's range is checked apart (parameterError).
std::string intParameterFromServer(const ParameterSpec& spec, XmlRpc::XmlRpcValue& raw, int* value);

/// The same for a parameter given by name; "" for a name the table does not have.
std::string stringParameterError(const std::string& name, const std::string& value);
std::string numberParameterError(const std::string& name, double value);

/// The known name most like `name` (longest common subsequence), for the warning about an
/// unknown one.
std::string closestNodeParameter(const std::string& name);

/// The names under the private namespace `ns` (as ros::NodeHandle::getNamespace() gives it) in
/// `server_names` (every name on the parameter server) that are no parameter of the table, each
/// with a message naming it and the closest known name.
std::vector<std::string> unknownParameterWarnings(const std::vector<std::string>& server_names, const std::string& ns);

/// Reads every parameter from `nh` (the private handle). An invalid value (out of range, an
/// unknown name such as curve "bspine", or of the wrong type) is refused with a ROS warning
/// naming the parameter, and the default is kept; an unknown private parameter (a misspelling
/// such as ~max_velocity) is warned about with the closest known name.
NodeParameters loadNodeParameters(const ros::NodeHandle& nh);

/// Writes every parameter of `p` to `nh` (the private handle) under the names and types
/// loadNodeParameters reads, so that reading them back gives `p`: the values in effect, e.g.
/// after a master restart lost the launch file's parameters.
void writeNodeParameters(const ros::NodeHandle& nh, const NodeParameters& p);

/// The run-time parameters of `p` (the rows with a reconfigure group) as dynamic_reconfigure's
/// message, for the server's Config::__fromMessage__.
dynamic_reconfigure::Config toReconfigureMessage(const NodeParameters& p);

/// The table's lower (`upper` false) or upper bounds of the run-time numbers as dynamic_reconfigure's
/// message (an unbounded int as the int's limit), for the min and max of the server's description
/// that rqt_reconfigure shows. The generated server itself has no ranges, so that it clamps no
/// value before applyReconfigureMessage checks it (cfg/node_parameter_table.py).
dynamic_reconfigure::Config reconfigureRange(bool upper);

/// Takes the run-time parameters of `message` (a Config::__toMessage__) into `p`; a value its
/// row refuses keeps the value of `p`. Returns one message per refused value ("" when none
/// was refused), naming the parameter and the value kept.
std::string applyReconfigureMessage(const dynamic_reconfigure::Config& message, NodeParameters* p);

}  // namespace se3_interpolation
