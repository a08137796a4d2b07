// ros/run_time_parameters.h: the node's parameters in effect, and the dynamic_reconfigure server
// that changes the run-time ones (the rows of cfg/node_parameters.yaml with a reconfigure group).
// A change is validated by the same table as at start-up; a refused value is not taken: the
// server answers the caller with the value kept (dynparam and rqt_reconfigure show it) and the
// node logs one warning naming each refused parameter.
#pragma once

#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/server.h>
#include <ros/node_handle.h>

#include <functional>
#include <memory>
#include <mutex>

#include "se3_interpolation/InterpolationNodeConfig.h"
#include "se3_interpolation/ros/node_parameters.h"

namespace se3_interpolation
{
class RunTimeParameters
{
public:
  /// Called after every accepted reconfiguration with the values before and after it.
  using ChangeHandler = std::function<void(const NodeParameters& before, const NodeParameters& after)>;

  /// Serves dynamic_reconfigure on `private_nh`, starting from `initial` (the validated start-up
  /// values, so that a refused ~curve is not read back from the parameter server).
  RunTimeParameters(const ros::NodeHandle& private_nh, const NodeParameters& initial, ChangeHandler on_change);
  ~RunTimeParameters();

  /// The parameters in effect now (a copy).
  NodeParameters get() const;

private:
  void reconfigure(InterpolationNodeConfig& config);

  mutable std::mutex mutex_;
  NodeParameters params_;
  ChangeHandler on_change_;
  boost::recursive_mutex server_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<InterpolationNodeConfig>> server_;
};

}  // namespace se3_interpolation
