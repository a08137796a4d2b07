#include "se3_interpolation/ros/node_parameters.h"

#include <ros/console.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <type_traits>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/ros/node_arm.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/ros/frame_memory.h"

namespace se3_interpolation
{
namespace
{
std::string show(const std::string& value)
{
  return quotedText(value);
}
template <class T>
T show(const T& value)
{
  return value;
}

/// The error of a value of any member type.
std::string errorOf(const ParameterSpec& spec, const std::string& value)
{
  return parameterError(spec, value);
}
template <class T>
std::string errorOf(const ParameterSpec& spec, const T& value)
{
  return std::is_same_v<T, bool> ? std::string() : parameterError(spec, static_cast<double>(value));
}

/// Reads the parameter `spec` into `candidate`; "" when it is of the member's type, else why not.
template <class T>
std::string readCandidate(const ros::NodeHandle& nh, const ParameterSpec& spec, T* candidate)
{
  if constexpr (std::is_same_v<T, int>)
  {
    // roscpp's getParam(int) would convert a double beyond the int's range (1e12) to INT_MIN.
    XmlRpc::XmlRpcValue raw;
    nh.getParam(spec.name, raw);
    return intParameterFromServer(spec, raw, candidate);
  }
  else
  {
    if (nh.getParam(spec.name, *candidate))
      return "";
    return std::string("~") + spec.name + ": refused (not of the expected type)";
  }
}

/// Reads the parameter `spec` into `value` if it is set, of the member's type and within its
/// row; else warns naming the parameter and the value kept.
template <class T>
void read(const ros::NodeHandle& nh, const ParameterSpec& spec, T* value)
{
  if (!nh.hasParam(spec.name))
    return;
  T candidate;
  const std::string unread = readCandidate(nh, spec, &candidate);
  if (!unread.empty())
  {
    ROS_WARN_STREAM(unread << "; keeping " << show(*value));
    return;
  }
  const std::string why = errorOf(spec, candidate);
  if (!why.empty())
  {
    ROS_WARN_STREAM(why << "; keeping " << show(*value));
    return;
  }
  *value = candidate;
}

/// How alike two names are: 2 · (longest common subsequence) / (total length), as difflib's
/// ratio: a misspelling that drops a word (max_velocity) stays closest to the name it came from
/// (max_linear_velocity), which a plain edit distance would not (max_waypoints is fewer edits).
double similarity(const std::string& a, const std::string& b)
{
  std::vector<std::size_t> row(b.size() + 1, 0);
  for (std::size_t i = 1; i <= a.size(); ++i)
  {
    std::size_t diagonal = 0;
    for (std::size_t j = 1; j <= b.size(); ++j)
    {
      const std::size_t above = row[j];
      row[j] = a[i - 1] == b[j - 1] ? diagonal + 1 : std::max(row[j], row[j - 1]);
      diagonal = above;
    }
  }
  return 2.0 * static_cast<double>(row[b.size()]) / static_cast<double>(a.size() + b.size());
}

/// The values of dynamic_reconfigure's message by name, of the member's type.
bool fromMessage(const dynamic_reconfigure::Config& m, const std::string& name, bool* value)
{
  for (const auto& p : m.bools)
    if (p.name == name)
      return (*value = p.value), true;
  return false;
}
bool fromMessage(const dynamic_reconfigure::Config& m, const std::string& name, int* value)
{
  for (const auto& p : m.ints)
    if (p.name == name)
      return (*value = p.value), true;
  return false;
}
bool fromMessage(const dynamic_reconfigure::Config& m, const std::string& name, double* value)
{
  for (const auto& p : m.doubles)
    if (p.name == name)
      return (*value = p.value), true;
  return false;
}
bool fromMessage(const dynamic_reconfigure::Config& m, const std::string& name, std::string* value)
{
  for (const auto& p : m.strs)
    if (p.name == name)
      return (*value = p.value), true;
  return false;
}

void toMessage(const std::string& name, bool value, dynamic_reconfigure::Config* m)
{
  dynamic_reconfigure::BoolParameter p;
  p.name = name;
  p.value = value;
  m->bools.push_back(p);
}
void toMessage(const std::string& name, int value, dynamic_reconfigure::Config* m)
{
  dynamic_reconfigure::IntParameter p;
  p.name = name;
  p.value = value;
  m->ints.push_back(p);
}
void toMessage(const std::string& name, double value, dynamic_reconfigure::Config* m)
{
  dynamic_reconfigure::DoubleParameter p;
  p.name = name;
  p.value = value;
  m->doubles.push_back(p);
}
void toMessage(const std::string& name, const std::string& value, dynamic_reconfigure::Config* m)
{
  dynamic_reconfigure::StrParameter p;
  p.name = name;
  p.value = value;
  m->strs.push_back(p);
}
}  // namespace

PlannerLimits NodeParameters::limits() const
{
  PlannerLimits l;
  l.max_samples = static_cast<std::size_t>(max_samples);
  l.max_waypoints = static_cast<std::size_t>(max_waypoints);
  l.max_work_seconds = max_work_seconds;
  return l;
}

const ParameterSpec* findNodeParameter(const std::string& name)
{
  for (const ParameterSpec& spec : kNodeParameterSpecs)
    if (name == spec.name)
      return &spec;
  return nullptr;
}

std::string parameterError(const ParameterSpec& spec, double value)
{
  const bool above_min = spec.min_exclusive ? value > spec.min : value >= spec.min;
  if (std::isfinite(value) && above_min && value <= spec.max)
    return "";
  // "must be in [0, 10] s", "must be > 0 m", "must be >= 2".
  const bool interval = spec.range[0] == '(' || spec.range[0] == '[' || std::strstr(spec.range, " ... ") != nullptr;
  std::ostringstream why;
  why << "~" << spec.name << ": refused " << value << " (must be " << (interval ? "in " : "") << spec.range
      << (spec.unit[0] != '\0' ? " " : "") << spec.unit << ")";
  return why.str();
}

std::string parameterError(const ParameterSpec& spec, const std::string& value)
{
  const std::string field = std::string("~") + spec.name;
  if (spec.type == ParameterType::kOptionalFrame && value.empty())
    return "";
  if (spec.type == ParameterType::kFrame || spec.type == ParameterType::kOptionalFrame)
  {
    try
    {
      validateFrameId(value, field);
    }
    catch (const InvalidInputError& e)
    {
      return e.what();
    }
    return "";
  }
  if (value.empty())
    return field + ": refused (empty; expected one of: " + spec.choices + ")";
  // The names are words separated by ", ": a value matches one whole.
  const std::string names = std::string(", ") + spec.choices + ", ";
  if (value.find(',') == std::string::npos && names.find(", " + value + ", ") != std::string::npos)
    return "";
  return field + ": unknown value " + quotedText(value) + " (expected one of: " + spec.choices + ")";
}

std::string intParameterFromServer(const ParameterSpec& spec, XmlRpc::XmlRpcValue& raw, int* value)
{
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeInt)
  {
    *value = static_cast<int>(raw);
    return "";
  }
  if (raw.getType() != XmlRpc::XmlRpcValue::TypeDouble)
    return std::string("~") + spec.name + ": refused (not of the expected type)";
  const double given = static_cast<double>(raw);
  // A whole number within the int's range (YAML reads 2e5 as a double) is that int.
  if (std::isfinite(given) && std::floor(given) == given && given >= std::numeric_limits<int>::min() &&
      given <= std::numeric_limits<int>::max())
  {
    *value = static_cast<int>(given);
    return "";
  }
  std::ostringstream why;
  why << "~" << spec.name << ": refused " << given << " (must be a whole number from "
      << std::numeric_limits<int>::min() << " to " << std::numeric_limits<int>::max()
      << (spec.range[0] != '\0' ? std::string(", ") + spec.range : std::string()) << ")";
  return why.str();
}

std::string stringParameterError(const std::string& name, const std::string& value)
{
  const ParameterSpec* spec = findNodeParameter(name);
  return spec ? parameterError(*spec, value) : "";
}

std::string numberParameterError(const std::string& name, double value)
{
  const ParameterSpec* spec = findNodeParameter(name);
  return spec ? parameterError(*spec, value) : "";
}

std::string closestNodeParameter(const std::string& name)
{
  const ParameterSpec* best = &kNodeParameterSpecs.front();
  for (const ParameterSpec& spec : kNodeParameterSpecs)
    if (similarity(name, spec.name) > similarity(name, best->name))
      best = &spec;
  return best->name;
}

std::vector<std::string> unknownParameterWarnings(const std::vector<std::string>& server_names, const std::string& ns)
{
  const std::string prefix = ns + "/";
  std::vector<std::string> warned_names;
  std::vector<std::string> warnings;
  for (const std::string& full : server_names)
  {
    if (full.compare(0, prefix.size(), prefix) != 0)
      continue;
    // A nested name (~a/b) is the parameter a.
    const std::string name = full.substr(prefix.size(), full.find('/', prefix.size()) - prefix.size());
    // ~executed_frame is the node's own record for a respawn (ros/frame_memory.h), not a setting;
    // ~joint_limits the arm's limits (ros/node_arm.h), a dictionary beside the table.
    if (name.empty() || findNodeParameter(name) || name == kFrameMemoryParameter || name == kJointLimitsParameter ||
        std::find(warned_names.begin(), warned_names.end(), name) != warned_names.end())
      continue;
    warned_names.push_back(name);
    // Server names can be long: the message quotes a bounded prefix.
    const std::string shown = name.size() <= kMaxFrameIdLength ? name : name.substr(0, kMaxFrameIdLength) + "...";
    warnings.push_back("~" + shown + ": unknown parameter, ignored (did you mean ~" + closestNodeParameter(name) +
                       "?)");
  }
  return warnings;
}

NodeParameters loadNodeParameters(const ros::NodeHandle& nh)
{
  NodeParameters p;
  forEachNodeParameter(p, [&](const ParameterSpec& spec, auto& member) { read(nh, spec, &member); });
  std::vector<std::string> names;
  if (nh.getParamNames(names))
    for (const std::string& warning : unknownParameterWarnings(names, nh.getNamespace()))
      ROS_WARN_STREAM(warning);
  return p;
}

void writeNodeParameters(const ros::NodeHandle& nh, const NodeParameters& p)
{
  NodeParameters values = p;
  forEachNodeParameter(values, [&](const ParameterSpec& spec, const auto& member) { nh.setParam(spec.name, member); });
}

dynamic_reconfigure::Config toReconfigureMessage(const NodeParameters& p)
{
  dynamic_reconfigure::Config message;
  NodeParameters values = p;
  forEachNodeParameter(values, [&](const ParameterSpec& spec, const auto& member) {
    if (spec.reconfigure[0] != '\0')
      toMessage(spec.name, member, &message);
  });
  return message;
}

dynamic_reconfigure::Config reconfigureRange(bool upper)
{
  dynamic_reconfigure::Config message;
  for (const ParameterSpec& spec : kNodeParameterSpecs)
  {
    if (spec.reconfigure[0] == '\0')
      continue;
    const double bound = upper ? spec.max : spec.min;
    if (spec.type == ParameterType::kDouble)
      toMessage(spec.name, bound, &message);
    else if (spec.type == ParameterType::kInt)
      toMessage(spec.name,
                std::isfinite(bound) ? static_cast<int>(bound) :
                                       (upper ? std::numeric_limits<int>::max() : std::numeric_limits<int>::min()),
                &message);
  }
  return message;
}

std::string applyReconfigureMessage(const dynamic_reconfigure::Config& message, NodeParameters* p)
{
  std::ostringstream refused;
  forEachNodeParameter(*p, [&](const ParameterSpec& spec, auto& member) {
    using T = std::decay_t<decltype(member)>;
    T candidate = member;
    if (spec.reconfigure[0] == '\0' || !fromMessage(message, spec.name, &candidate) || candidate == member)
      return;
    const std::string why = errorOf(spec, candidate);
    if (why.empty())
    {
      member = candidate;
      return;
    }
    refused << (refused.tellp() > 0 ? "; " : "") << why << ", keeping " << show(member);
  });
  return refused.str();
}

}  // namespace se3_interpolation
