// se3_interpolation/InterpolationNodelet: the node class under a nodelet manager.
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

#include "se3_interpolation/ros/interpolation_node.h"

namespace se3_interpolation
{
/// Owns one InterpolationNode on the nodelet's handles: its public namespace and its private
/// one (/<nodelet name>/...), so the service is /<nodelet name>/generate as for the node.
class InterpolationNodelet : public nodelet::Nodelet
{
private:
  void onInit() override { node_ = std::make_unique<InterpolationNode>(getNodeHandle(), getPrivateNodeHandle()); }

  std::unique_ptr<InterpolationNode> node_;
};
}  // namespace se3_interpolation

PLUGINLIB_EXPORT_CLASS(se3_interpolation::InterpolationNodelet, nodelet::Nodelet)
