#include "se3_interpolation/ros/master_watchdog.h"

#include <ros/connection_manager.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/this_node.h>
#include <ros/xmlrpc_manager.h>

#include <stdexcept>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
MasterWatchdog::MasterWatchdog(ros::NodeHandle private_nh, double period, std::vector<std::string> services,
                               std::function<void()> write_parameters)
  : private_nh_(std::move(private_nh)), services_(std::move(services)), write_parameters_(std::move(write_parameters))
{
  ros::param::get("/run_id", run_id_);
  ros::NodeHandle watchdog_nh(private_nh_);
  watchdog_nh.setCallbackQueue(&queue_);
  timer_ = watchdog_nh.createTimer(ros::Duration(period), &MasterWatchdog::check, this);
  spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
  spinner_->start();
}

MasterWatchdog::~MasterWatchdog()
{
  spinner_->stop();
}

void MasterWatchdog::check(const ros::TimerEvent& /*event*/)
{
  try
  {
    if (!ros::master::check())
      return;  // the master is away: wait for it to come back
    if (!masterForgotUs())
      return;
    ROS_WARN_STREAM("the ROS master at " << ros::master::getURI() << " no longer knows " << ros::this_node::getName()
                                         << " (it restarted); registering again");
    ROS_WARN_STREAM("registered again with the new master: " << registerAgain());
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_STREAM_THROTTLE(10.0, "master watchdog: " << boundedMessage(e.what()));
  }
}

bool MasterWatchdog::masterForgotUs()
{
  // A failed call (the master gone again meanwhile) counts as forgotten: registering again is
  // harmless (the master's registrations are idempotent) and is retried at the next check.
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = services_.front();
  if (!ros::master::execute("lookupService", args, result, payload, false))
    return true;
  if (run_id_.empty())
    return false;
  XmlRpc::XmlRpcValue param_args, param_result, run_id;
  param_args[0] = ros::this_node::getName();
  param_args[1] = "/run_id";
  if (!ros::master::execute("getParam", param_args, param_result, run_id, false) ||
      run_id.getType() != XmlRpc::XmlRpcValue::TypeString)
    return true;
  if (static_cast<std::string>(run_id) == run_id_)
    return false;
  run_id_ = static_cast<std::string>(run_id);
  return true;
}

namespace
{
/// Calls `method` of this process's own slave API (its XML-RPC server) and returns the value of
/// its [code, message, value] answer; throws when it fails.
XmlRpc::XmlRpcValue callOwnSlaveApi(const std::string& method, XmlRpc::XmlRpcValue& args)
{
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(ros::XMLRPCManager::instance()->getServerURI(), host, port))
    throw std::runtime_error("cannot parse this node's XML-RPC URI");
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue result;
  if (!client.execute(method.c_str(), args, result) || result.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      result.size() != 3 || static_cast<int>(result[0]) != 1)
    throw std::runtime_error("this node's XML-RPC " + method + " failed");
  return result[2];
}
}  // namespace

std::string MasterWatchdog::registerAgain()
{
  const std::string caller = ros::this_node::getName();
  const std::string caller_api = ros::XMLRPCManager::instance()->getServerURI();
  write_parameters_();
  std::size_t failed = 0;
  auto registerOne = [&](const char* method, const std::string& name, const std::string& api) {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = caller;
    args[1] = name;
    args[2] = api;
    args[3] = caller_api;
    if (!ros::master::execute(method, args, result, payload, false))
    {
      ++failed;
      ROS_WARN_STREAM("master " << method << " " << name << " failed; retried at the next check");
    }
    return payload;
  };
  // Publications first, so that the subscriptions below find this process's own publishers too.
  XmlRpc::XmlRpcValue own_args;
  own_args[0] = caller;
  XmlRpc::XmlRpcValue publications = callOwnSlaveApi("getPublications", own_args);
  for (int i = 0; i < publications.size(); ++i)
    registerOne("registerPublisher", publications[i][0], publications[i][1]);
  XmlRpc::XmlRpcValue subscriptions = callOwnSlaveApi("getSubscriptions", own_args);
  for (int i = 0; i < subscriptions.size(); ++i)
  {
    const std::string topic = subscriptions[i][0];
    XmlRpc::XmlRpcValue publishers = registerOne("registerSubscriber", topic, subscriptions[i][1]);
    if (publishers.getType() != XmlRpc::XmlRpcValue::TypeArray)
      continue;
    // What the master would send a subscriber: connects to the publishers it knows.
    XmlRpc::XmlRpcValue update;
    update[0] = std::string("/master");
    update[1] = topic;
    update[2] = publishers;
    callOwnSlaveApi("publisherUpdate", update);
  }
  const std::string service_api =
      "rosrpc://" + ros::network::getHost() + ":" + std::to_string(ros::ConnectionManager::instance()->getTCPPort());
  for (const std::string& service : services_)
    registerOne("registerService", service, service_api);
  std::ostringstream summary;
  summary << publications.size() << " publications, " << subscriptions.size() << " subscriptions, " << services_.size()
          << " services and the parameters under " << private_nh_.getNamespace();
  if (failed > 0)
    summary << " (" << failed << " registrations failed)";
  return summary.str();
}

}  // namespace se3_interpolation
