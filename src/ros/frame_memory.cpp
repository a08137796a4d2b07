#include "se3_interpolation/ros/frame_memory.h"

#include <cmath>

namespace se3_interpolation
{
namespace
{
constexpr int kPoseValues = 7;  // x, y, z, qx, qy, qz, qw

double numberOf(XmlRpc::XmlRpcValue& v)
{
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    return static_cast<int>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    return static_cast<double>(v);
  return NAN;
}
}  // namespace

void rememberFrame(const ros::NodeHandle& private_nh, const RememberedFrame& frame)
{
  XmlRpc::XmlRpcValue v;
  v["frame_id"] = frame.frame_id;
  const double values[kPoseValues] = { frame.pose.p.x(), frame.pose.p.y(), frame.pose.p.z(), frame.pose.q.x(),
                                       frame.pose.q.y(), frame.pose.q.z(), frame.pose.q.w() };
  XmlRpc::XmlRpcValue pose;
  pose.setSize(kPoseValues);
  for (int i = 0; i < kPoseValues; ++i)
    pose[i] = values[i];
  v["pose"] = pose;
  v["at_rest"] = frame.at_rest;
  private_nh.setParam(kFrameMemoryParameter, v);
}

std::optional<RememberedFrame> recallFrame(const ros::NodeHandle& private_nh)
{
  XmlRpc::XmlRpcValue v;
  if (!private_nh.getParam(kFrameMemoryParameter, v))
    return std::nullopt;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeStruct && v.hasMember("frame_id") && v.hasMember("pose") &&
      v.hasMember("at_rest") && v["frame_id"].getType() == XmlRpc::XmlRpcValue::TypeString &&
      v["at_rest"].getType() == XmlRpc::XmlRpcValue::TypeBoolean &&
      v["pose"].getType() == XmlRpc::XmlRpcValue::TypeArray && v["pose"].size() == kPoseValues)
  {
    double x[kPoseValues];
    bool finite = true;
    for (int i = 0; i < kPoseValues; ++i)
      finite = std::isfinite(x[i] = numberOf(v["pose"][i])) && finite;
    const double norm = std::sqrt(x[3] * x[3] + x[4] * x[4] + x[5] * x[5] + x[6] * x[6]);
    if (finite && norm > 0.5)
    {
      RememberedFrame frame;
      frame.frame_id = static_cast<std::string>(v["frame_id"]);
      frame.pose.p = Eigen::Vector3d(x[0], x[1], x[2]);
      frame.pose.q = Quaternion<double>(x[6] / norm, x[3] / norm, x[4] / norm, x[5] / norm);
      frame.at_rest = static_cast<bool>(v["at_rest"]);
      return frame;
    }
  }
  ROS_WARN_STREAM("~" << kFrameMemoryParameter
                      << " is not what this node writes (frame_id, pose [x, y, z, qx, qy, qz, qw], at_rest): ignored");
  return std::nullopt;
}

}  // namespace se3_interpolation
