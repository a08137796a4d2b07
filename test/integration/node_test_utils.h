// Helpers shared by the rostest clients of test/integration/: waypoint poses, spinning or
// waiting until a condition holds (wall-clock deadlines: the tests' own time limits), and the
// latest message of a (latched) topic.
#pragma once

#include <geometry_msgs/Pose.h>
#include <ros/ros.h>
#include <tf2_eigen/tf2_eigen.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <string>

namespace node_test
{
/// A pose at (x, y, z) m turned by `yaw` rad about z.
inline geometry_msgs::Pose pose(double x, double y, double z, double yaw)
{
  geometry_msgs::Pose p;
  p.position.x = x;
  p.position.y = y;
  p.position.z = z;
  p.orientation.z = std::sin(yaw / 2);
  p.orientation.w = std::cos(yaw / 2);
  return p;
}

/// The pose world_T_body = (q, p).
inline geometry_msgs::Pose pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q)
{
  geometry_msgs::Pose msg;
  msg.position = tf2::toMsg(p);
  msg.orientation = tf2::toMsg(q);
  return msg;
}

/// Calls the service `name` with `srv`, as `ros::service::call` does, on a connection this client
/// closes: a persistent client, dropped after its one call. With roscpp's non-persistent call the
/// server closes the connection right after its response, and on a loaded machine the client's
/// poll thread can take the hang-up before it has read the response and report the call failed
/// (https://github.com/ros/ros_comm/issues/1976: the POLLRDHUP branch of
/// TransportTCP::socketUpdate; in this suite's CI, one light request of about 80 made while the
/// node was loaded).
template <class Service>
bool callService(const std::string& name, Service& srv)
{
  ros::ServiceClient client = ros::NodeHandle().serviceClient<Service>(name, true);
  return client.call(srv);
}

/// Spins this thread's callbacks until `done` or `seconds` of wall time; returns done().
inline bool spinUntil(const std::function<bool()>& done, double seconds)
{
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < deadline)
  {
    ros::spinOnce();
    if (done())
      return true;
    ros::WallDuration(0.002).sleep();
  }
  return done();
}

/// Spins this thread's callbacks for `seconds` of wall time.
inline void spinFor(double seconds)
{
  spinUntil([] { return false; }, seconds);
}

/// Waits (without spinning: for tests whose spinner threads run the callbacks) until `done` or
/// `seconds` of wall time; returns done().
inline bool waitFor(const std::function<bool()>& done, double seconds)
{
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < deadline)
  {
    if (done())
      return true;
    ros::WallDuration(0.01).sleep();
  }
  return done();
}

/// Latest message on a (latched) topic, and how many arrived.
template <class M>
class Latest
{
public:
  Latest(ros::NodeHandle& nh, const std::string& topic)
    : sub_(nh.subscribe<M>(topic, 10, [this](const typename M::ConstPtr& m) {
      msg_ = *m;
      ++count_;
    }))
  {
  }
  const M& msg() const { return msg_; }
  int count() const { return count_; }

private:
  ros::Subscriber sub_;
  M msg_;
  int count_ = 0;
};
}  // namespace node_test
