#include "se3_interpolation/ros/run_time_parameters.h"

#include <ros/console.h>

namespace se3_interpolation
{
namespace
{
InterpolationNodeConfig toConfig(const NodeParameters& p)
{
  InterpolationNodeConfig config = InterpolationNodeConfig::__getDefault__();
  dynamic_reconfigure::Config message = toReconfigureMessage(p);
  config.__fromMessage__(message);
  return config;
}
}  // namespace

RunTimeParameters::RunTimeParameters(const ros::NodeHandle& private_nh, const NodeParameters& initial,
                                     ChangeHandler on_change)
  : params_(initial), on_change_(std::move(on_change))
{
  server_ = std::make_unique<dynamic_reconfigure::Server<InterpolationNodeConfig>>(server_mutex_, private_nh);
  // The description's ranges are the table's, for rqt_reconfigure's sliders; the generated ones are
  // unbounded, so that the server's clamp leaves every requested value to reconfigure()'s check.
  InterpolationNodeConfig min = InterpolationNodeConfig::__getMin__();
  InterpolationNodeConfig max = InterpolationNodeConfig::__getMax__();
  dynamic_reconfigure::Config lower = reconfigureRange(false);
  dynamic_reconfigure::Config upper = reconfigureRange(true);
  min.__fromMessage__(lower);
  max.__fromMessage__(upper);
  server_->setConfigMin(min);
  server_->setConfigMax(max);
  server_->updateConfig(toConfig(initial));
  server_->setCallback([this](InterpolationNodeConfig& config, std::uint32_t /*level*/) { reconfigure(config); });
}

RunTimeParameters::~RunTimeParameters()
{
  server_.reset();
}

NodeParameters RunTimeParameters::get() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return params_;
}

void RunTimeParameters::reconfigure(InterpolationNodeConfig& config)
{
  dynamic_reconfigure::Config requested;
  config.__toMessage__(requested);
  const NodeParameters before = get();
  NodeParameters after = before;
  const std::string refused = applyReconfigureMessage(requested, &after);
  if (!refused.empty())
    ROS_WARN_STREAM("dynamic_reconfigure: " << refused);
  // The server answers the caller with `config`: the values taken, the old ones where refused.
  config = toConfig(after);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    params_ = after;
  }
  if (on_change_)
    on_change_(before, after);
}

}  // namespace se3_interpolation
