// The node's arm (ros/node_arm.h).
#include "se3_interpolation/ros/node_arm.h"

#include <ros/console.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cstdio>
#include <sstream>

#include "se3_interpolation/arm/joint_limits.h"
#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace
{
/// A parameter's value as JSON text (which YAML reads): the limits' one parser reads it.
void writeJson(XmlRpc::XmlRpcValue& v, std::ostringstream* out)
{
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeStruct:
    {
      *out << "{";
      bool first = true;
      for (auto& member : v)
      {
        *out << (first ? "" : ", ") << "\"" << member.first << "\": ";
        writeJson(member.second, out);
        first = false;
      }
      *out << "}";
      break;
    }
    case XmlRpc::XmlRpcValue::TypeArray:
      *out << "[";
      for (int i = 0; i < v.size(); ++i)
      {
        *out << (i ? ", " : "");
        writeJson(v[i], out);
      }
      *out << "]";
      break;
    case XmlRpc::XmlRpcValue::TypeBoolean:
      *out << (static_cast<bool>(v) ? "true" : "false");
      break;
    case XmlRpc::XmlRpcValue::TypeInt:
      *out << static_cast<int>(v);
      break;
    case XmlRpc::XmlRpcValue::TypeDouble:
    {
      char text[32];
      std::snprintf(text, sizeof text, "%.17g", static_cast<double>(v));
      *out << text;
      break;
    }
    default:
      *out << "\"" << v.toXml() << "\"";
  }
}

/// The chain of the URDF that p.robot_description names, with ~joint_limits' limits.
std::shared_ptr<const arm::ArmModel> loadArm(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                                             const NodeParameters& p)
{
  if (p.base_link.empty())
    throw InvalidInputError("~base_link: empty, but ~tip_link is " + quotedText(p.tip_link) +
                            " (an arm is the chain from ~base_link to ~tip_link)");
  std::string key;
  std::string urdf;
  if (!nh.searchParam(p.robot_description, key) || !nh.getParam(key, urdf))
    throw InvalidInputError("~robot_description: no parameter " + quotedText(p.robot_description) +
                            " holds the arm's URDF (load it as robot_state_publisher reads it)");
  auto model = std::make_shared<arm::ArmModel>(urdf, p.base_link, p.tip_link, key);
  XmlRpc::XmlRpcValue limits;
  if (private_nh.getParam(kJointLimitsParameter, limits))
  {
    std::ostringstream text;
    text << "{\"joint_limits\": ";
    writeJson(limits, &text);
    text << "}";
    model->applyLimits(arm::parseJointLimits(text.str(), "~joint_limits"));
  }
  return model;
}
}  // namespace

NodeArm::NodeArm(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeParameters& p)
{
  if (p.tip_link.empty())
    return;
  try
  {
    model_ = loadArm(nh, private_nh, p);
  }
  catch (const std::exception& e)
  {
    error_ = e.what();
    ROS_ERROR_STREAM("se3_interpolation_node: the arm (~tip_link " << p.tip_link << ") is not available: " << error_
                                                                   << "; requests are refused until it is fixed");
  }
}

std::shared_ptr<const arm::ArmModel> NodeArm::forRequest() const
{
  if (!error_.empty())
    throw InvalidInputError("the node's arm (~tip_link) could not be loaded: " + error_);
  return model_;
}

std::string NodeArm::summary() const
{
  if (!error_.empty())
    return "arm not loaded";
  if (!model_)
    return "no arm";
  return "arm " + model_->baseLink() + " -> " + model_->tipLink() + " (" + std::to_string(model_->dof()) + " joints)";
}
}  // namespace se3_interpolation
