// ros/master_watchdog.h: surviving a master restart. Every ~master_check_period s the watchdog
// asks the master whether it still knows the node's first service (and whether its /run_id
// changed). After a restart it does not: roscpp never registers again by itself, so the watchdog
// does, and the node keeps running: it writes the parameters in effect (the launch file's and
// later dynamic_reconfigure changes) back under the private namespace, registers every
// publication and subscription of its process (including tf2's, dynamic_reconfigure's and
// /rosout) and the given services again, and connects the subscriptions to the publishers the new
// master knows. Playback, the waypoint buffer, the frames and the latched messages are untouched.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace se3_interpolation
{
class MasterWatchdog
{
public:
  /// Checks every `period` s (> 0) on its own thread; `services` are the resolved names of the
  /// node's services (the first is the one asked about); `write_parameters` puts the parameters in
  /// effect back on the (new) parameter server.
  MasterWatchdog(ros::NodeHandle private_nh, double period, std::vector<std::string> services,
                 std::function<void()> write_parameters);
  ~MasterWatchdog();

private:
  void check(const ros::TimerEvent& event);
  /// Whether the reachable master has forgotten this node.
  bool masterForgotUs();
  /// Registers everything again (see the file comment); returns a summary.
  std::string registerAgain();

  ros::NodeHandle private_nh_;
  std::vector<std::string> services_;
  std::function<void()> write_parameters_;
  std::string run_id_;  ///< the master's /run_id at start-up ("" when it has none)
  ros::CallbackQueue queue_;
  ros::Timer timer_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
};

}  // namespace se3_interpolation
