// The chain of arm/arm_model.h from a URDF: the walk from the tip up to the base, the fixed joints
// folded into the movable joints' transforms, the URDF's limits checked; applyLimits.
#include "se3_interpolation/arm/arm_model.h"
#include "source_name.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <urdf_parser/urdf_parser.h>

namespace se3_interpolation
{
namespace arm
{
namespace
{
std::string readTextFile(const std::string& path, const char* what)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ArmModelError(std::string(what) + " " + quotedSource(path) + ": cannot be read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool finite(const urdf::Vector3& v)
{
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The joint's <origin> as an isometry; refuses a non-finite one.
Eigen::Isometry3d originOf(const urdf::Joint& joint, const std::string& prefix)
{
  const urdf::Pose& o = joint.parent_to_joint_origin_transform;
  const urdf::Rotation& r = o.rotation;
  if (!finite(o.position) || !std::isfinite(r.w) || !std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z))
    throw ArmModelError(prefix + "<origin> is not finite");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(o.position.x, o.position.y, o.position.z);
  return t;
}

/// The URDF's <limit> of a movable joint into `joint.limits`, checked.
void readUrdfLimits(const urdf::Joint& urdf_joint, const std::string& prefix, ArmJoint* joint)
{
  if (!urdf_joint.limits)
    return;  // only a continuous joint may omit <limit> (urdfdom refuses the others)
  const urdf::JointLimits& l = *urdf_joint.limits;
  if (joint->type != JointType::kContinuous)
  {
    if (!std::isfinite(l.lower) || !std::isfinite(l.upper))
      throw ArmModelError(prefix + "<limit> lower/upper are not finite");
    if (l.lower > l.upper)
      throw ArmModelError(prefix + "<limit> lower " + formatNumber(l.lower) + " > upper " + formatNumber(l.upper));
    joint->limits.min_position = l.lower;
    joint->limits.max_position = l.upper;
  }
  if (!std::isfinite(l.velocity) || l.velocity <= 0.0)
    throw ArmModelError(prefix + "<limit> velocity " + formatNumber(l.velocity) + " must be positive and finite");
  joint->limits.max_velocity = l.velocity;
}

/// The movable joint `urdf_joint` of the chain, with prev_T_joint = `before` · its origin.
ArmJoint movableJoint(const urdf::Joint& urdf_joint, const Eigen::Isometry3d& before, const std::string& prefix)
{
  ArmJoint joint;
  joint.name = urdf_joint.name;
  joint.type = urdf_joint.type == urdf::Joint::PRISMATIC  ? JointType::kPrismatic :
               urdf_joint.type == urdf::Joint::CONTINUOUS ? JointType::kContinuous :
                                                            JointType::kRevolute;
  if (urdf_joint.mimic)
    throw ArmModelError(prefix + "mimic joints are not supported in the chain");
  const Eigen::Vector3d axis(urdf_joint.axis.x, urdf_joint.axis.y, urdf_joint.axis.z);
  if (!axis.allFinite() || axis.norm() < 1e-12)
    throw ArmModelError(prefix + "<axis> must be finite and non-zero");
  joint.axis = axis.normalized();
  joint.prev_T_joint = before * originOf(urdf_joint, prefix);
  readUrdfLimits(urdf_joint, prefix, &joint);
  return joint;
}
}  // namespace

ArmModel::ArmModel(const std::string& urdf_text, const std::string& base_link, const std::string& tip_link,
                   const std::string& source)
  : source_(source), base_link_(base_link), tip_link_(tip_link)
{
  const std::string where = quotedSource(source) + ": ";
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_text);
  if (!model)
    throw ArmModelError(where + "not a valid URDF (urdfdom could not parse it)");
  for (const auto& [name, joint] : model->joints_)
    urdf_joint_names_.push_back(name);
  for (const std::string* link : { &base_link, &tip_link })
    if (!model->getLink(*link))
      throw ArmModelError(where + "link " + quotedText(*link) + " is not in the URDF (robot " +
                          quotedText(model->getName()) + ")");
  if (base_link == tip_link)
    throw ArmModelError(where + "base and tip are the same link " + quotedText(base_link));

  // From the tip up to the base: the joints in reverse chain order.
  std::vector<urdf::JointConstSharedPtr> path;
  for (urdf::LinkConstSharedPtr link = model->getLink(tip_link); link->name != base_link;)
  {
    const urdf::JointConstSharedPtr joint = link->parent_joint;
    if (!joint)
      throw ArmModelError(where + "tip link " + quotedText(tip_link) + " is not a descendant of base link " +
                          quotedText(base_link) + " (its root is " + quotedText(link->name) + ")");
    path.push_back(joint);
    link = model->getLink(joint->parent_link_name);
  }
  std::reverse(path.begin(), path.end());

  Eigen::Isometry3d fixed = Eigen::Isometry3d::Identity();  // since the last movable joint's child
  for (const urdf::JointConstSharedPtr& joint : path)
  {
    const std::string prefix = where + "joint " + quotedText(joint->name) + ": ";
    switch (joint->type)
    {
      case urdf::Joint::FIXED:
        fixed = fixed * originOf(*joint, prefix);
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
      case urdf::Joint::PRISMATIC:
        joints_.push_back(movableJoint(*joint, fixed, prefix));
        fixed = Eigen::Isometry3d::Identity();
        break;
      default:
        throw ArmModelError(prefix + "floating, planar and unknown joints cannot be on an arm's chain");
    }
  }
  last_T_tip_ = fixed;
  if (joints_.empty())
    throw ArmModelError(where + "no movable joint between " + quotedText(base_link) + " and " + quotedText(tip_link));
  if (joints_.size() > static_cast<std::size_t>(kMaxArmJoints))
    throw ArmModelError(where + "the chain has " + std::to_string(joints_.size()) + " movable joints, at most " +
                        std::to_string(kMaxArmJoints) + " are supported");
}

ArmModel ArmModel::fromUrdfFile(const std::string& path, const std::string& base_link, const std::string& tip_link)
{
  return ArmModel(readTextFile(path, "URDF file"), base_link, tip_link, path);
}

void ArmModel::applyLimits(const JointLimitsFile& limits)
{
  const std::string where = quotedSource(limits.source) + ": ";
  for (const auto& named_entry : limits.joints)
  {
    const std::string& name = named_entry.first;
    const JointLimitsEntry& entry = named_entry.second;
    const std::string prefix = where + "joint " + quotedText(name) + ": ";
    if (std::find(urdf_joint_names_.begin(), urdf_joint_names_.end(), name) == urdf_joint_names_.end())
      throw ArmModelError(where + "joint " + quotedText(name) + " is not in the URDF " + quotedSource(source_));
    const auto joint = std::find_if(joints_.begin(), joints_.end(), [&](const ArmJoint& j) { return j.name == name; });
    if (joint == joints_.end())
      continue;
    JointLimits l = joint->limits;
    if (entry.min_position || entry.max_position)
    {
      if (joint->type == JointType::kContinuous)
        throw ArmModelError(prefix + "a continuous joint has no position limits");
      l.min_position = entry.min_position.value_or(l.min_position);
      l.max_position = entry.max_position.value_or(l.max_position);
    }
    l.max_velocity = entry.max_velocity.value_or(l.max_velocity);
    l.max_acceleration = entry.max_acceleration.value_or(l.max_acceleration);
    l.max_jerk = entry.max_jerk.value_or(l.max_jerk);
    joint->limits = l;
  }
}

}  // namespace arm
}  // namespace se3_interpolation
