// MoveIt's joint_limits.yaml (arm/joint_limits.h): read with yaml-cpp, every value checked.
#include "se3_interpolation/arm/joint_limits.h"
#include "source_name.h"

#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace se3_interpolation
{
namespace arm
{
namespace
{
/// The keys of a joint's entry: the has_* flag, the value it enables, and whether the value is a
/// rate (positive) or a position (any finite number).
struct LimitKey
{
  const char* flag;
  const char* value;
  std::optional<double> JointLimitsEntry::*field;  ///< null: read and checked, not kept (effort)
  bool rate;
};

const LimitKey kLimitKeys[] = {
  { "has_position_limits", "min_position", &JointLimitsEntry::min_position, false },
  { "has_position_limits", "max_position", &JointLimitsEntry::max_position, false },
  { "has_velocity_limits", "max_velocity", &JointLimitsEntry::max_velocity, true },
  { "has_acceleration_limits", "max_acceleration", &JointLimitsEntry::max_acceleration, true },
  { "has_jerk_limits", "max_jerk", &JointLimitsEntry::max_jerk, true },
  { "has_effort_limits", "max_effort", nullptr, true },
};

bool knownKey(const std::string& key)
{
  for (const LimitKey& k : kLimitKeys)
    if (key == k.flag || key == k.value)
      return true;
  return false;
}

template <class T>
T scalar(const YAML::Node& node, const std::string& field, const char* kind)
{
  try
  {
    if (node.IsScalar())
      return node.as<T>();
  }
  catch (const YAML::Exception&)
  {
  }
  throw ArmModelError(field + ": not " + kind);
}

/// One joint's entry; `where` is "<source>: joint_limits.<joint>".
JointLimitsEntry readEntry(const YAML::Node& node, const std::string& where)
{
  if (!node.IsMap())
    throw ArmModelError(where + ": not a map of limits");
  for (const auto& kv : node)
  {
    const std::string key = kv.first.Scalar();
    if (!knownKey(key))
      throw ArmModelError(where + "." + quotedText(key) + ": unknown key (known: has_<kind>_limits and min_position, " +
                          "max_position, max_velocity, max_acceleration, max_jerk, max_effort)");
  }
  JointLimitsEntry entry;
  for (const LimitKey& k : kLimitKeys)
  {
    if (!node[k.flag] || !scalar<bool>(node[k.flag], where + "." + k.flag, "a bool"))
      continue;
    const std::string field = where + "." + k.value;
    if (!node[k.value])
      throw ArmModelError(field + ": missing (" + k.flag + " is true)");
    const double v = scalar<double>(node[k.value], field, "a number");
    if (!std::isfinite(v))
      throw ArmModelError(field + ": " + formatNumber(v) + " is not finite");
    if (k.rate && v <= 0.0)
      throw ArmModelError(field + ": " + formatNumber(v) + " must be positive");
    if (k.field)
      entry.*(k.field) = v;
  }
  if (entry.min_position && entry.max_position && *entry.min_position > *entry.max_position)
    throw ArmModelError(where + ": min_position " + formatNumber(*entry.min_position) + " > max_position " +
                        formatNumber(*entry.max_position));
  return entry;
}
}  // namespace

JointLimitsFile parseJointLimits(const std::string& yaml_text, const std::string& source)
{
  const std::string where = quotedSource(source) + ": ";
  YAML::Node root;
  try
  {
    root = YAML::Load(yaml_text);
  }
  catch (const YAML::Exception& e)
  {
    throw ArmModelError(where + "not valid YAML (line " + std::to_string(e.mark.line + 1) + ": " + e.msg + ")");
  }
  if (!root.IsMap() || !root["joint_limits"])
    throw ArmModelError(where + "joint_limits: missing (the file must be a map with the key joint_limits)");
  const YAML::Node table = root["joint_limits"];
  if (!table.IsMap())
    throw ArmModelError(where + "joint_limits: not a map from joint names to limits");
  JointLimitsFile file;
  file.source = source;
  for (const auto& kv : table)
  {
    const std::string name = kv.first.Scalar();
    file.joints[name] = readEntry(kv.second, where + "joint_limits." + quotedText(name));
  }
  return file;
}

JointLimitsFile readJointLimitsFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ArmModelError("joint limits file " + quotedSource(path) + ": cannot be read");
  std::ostringstream s;
  s << in.rdbuf();
  return parseJointLimits(s.str(), path);
}

}  // namespace arm
}  // namespace se3_interpolation
