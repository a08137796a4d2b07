// Fault: the ROS master killed (SIGKILL) and restarted on the same port. roscpp never registers
// again with a new master by itself; the node's watchdog notices that the new master does not
// know it and registers everything again, and the node keeps running: same process, its
// services on the new master, its parameters in effect (launch values and a dynamic_reconfigure
// change) written back, its own TF frames, the playing motion without a jump, the waypoint buffer
// and the latched ~path kept. Two namespaced node instances and one nodelet (standalone manager)
// with their own parameters. This test runs its own master on a free port (never 11311) and the
// instances as child processes, without rostest.
#include <dynamic_reconfigure/Reconfigure.h>
#include <geometry_msgs/PoseArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <netinet/in.h>
#include <ros/ros.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>
#include <xmlrpcpp/XmlRpc.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "node_test_utils.h"
#include "se3_interpolation/GenerateTrajectory.h"
namespace
{
int freePort()
{
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof(a);
  if (s < 0 || bind(s, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 ||
      getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0)
    return 0;
  const int port = ntohs(a.sin_port);
  close(s);
  return port;
}

/// Starts `argv` with its output in `log`; returns the child's pid.
pid_t spawn(const std::vector<std::string>& argv, const std::string& log)
{
  const pid_t pid = fork();
  if (pid == 0)
  {
    std::freopen(log.c_str(), "w", stdout);
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> args;
    for (const auto& a : argv)
      args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

/// Does the master at `port` know `service` (lookupService)?
bool masterHasService(int port, const std::string& service)
{
  XmlRpc::XmlRpcClient client("127.0.0.1", port, "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = "/test_master_restart";
  args[1] = service;
  return client.execute("lookupService", args, result) && result.getType() == XmlRpc::XmlRpcValue::TypeArray &&
         static_cast<int>(result[0]) == 1;
}

bool masterUp(int port)
{
  XmlRpc::XmlRpcClient client("127.0.0.1", port, "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = "/test_master_restart";
  return client.execute("getUri", args, result) && result.getType() == XmlRpc::XmlRpcValue::TypeArray &&
         static_cast<int>(result[0]) == 1;
}

template <class F>
bool waitFor(F done, double seconds)
{
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline)
  {
    if (done())
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

std::string slurp(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// One planner instance: /<ns>/planner, its own moving frame and a constant-speed motion along x
/// (speed m/s) that plays from `start` over 60 s.
struct Instance
{
  std::string ns;
  std::string child_frame_id;
  int sample_count;  ///< in effect: the launch value, or the reconfigured one
  double speed;
  std::vector<geometry_msgs::Pose> buffer;  ///< published on ~waypoints before the restart
  pid_t pid = -1;
  std::string log;
  ros::Time start;
  std::string node() const { return ns + "/planner"; }
};

geometry_msgs::Pose poseAt(double x, double y)
{
  geometry_msgs::Pose p;
  p.position.x = x;
  p.position.y = y;
  p.orientation.w = 1.0;
  return p;
}

/// ~generate from the ~waypoints buffer (empty waypoints), not published.
bool generateFromBuffer(const Instance& instance, se3_interpolation::GenerateTrajectory* srv)
{
  srv->request = se3_interpolation::GenerateTrajectory::Request();
  srv->request.publish = false;
  return node_test::callService(instance.node() + "/generate", *srv) && srv->response.success;
}

/// The buffer is used: the path runs from its first waypoint to its last, with the sample count
/// in effect.
void expectBufferUsed(const Instance& instance, const se3_interpolation::GenerateTrajectory& srv)
{
  const auto& poses = srv.response.path.poses;
  ASSERT_EQ(static_cast<int>(poses.size()), instance.sample_count) << instance.node() << ": " << srv.response.message;
  EXPECT_NEAR(poses.front().pose.position.x, instance.buffer.front().position.x, 1e-9) << instance.node();
  EXPECT_NEAR(poses.front().pose.position.y, instance.buffer.front().position.y, 1e-9) << instance.node();
  EXPECT_NEAR(poses.back().pose.position.x, instance.buffer.back().position.x, 1e-9) << instance.node();
  EXPECT_NEAR(poses.back().pose.position.y, instance.buffer.back().position.y, 1e-9) << instance.node();
}

/// /tf transforms of the instances' moving frames for `seconds` (a subscriber made now, so it
/// registers with the master running now); per child frame, (publisher, transform).
std::map<std::string, std::vector<std::pair<std::string, geometry_msgs::TransformStamped>>> watchTf(double seconds)
{
  std::mutex mutex;
  std::map<std::string, std::vector<std::pair<std::string, geometry_msgs::TransformStamped>>> seen;
  ros::NodeHandle nh;
  // (A boost::function of the event: a lambda would bind to the ConstPtr overload and lose the
  // publisher's name.)
  const boost::function<void(const ros::MessageEvent<const tf2_msgs::TFMessage>&)> record =
      [&](const ros::MessageEvent<const tf2_msgs::TFMessage>& e) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& t : e.getMessage()->transforms)
          seen[t.child_frame_id].emplace_back(e.getPublisherName(), t);
      };
  ros::Subscriber sub = nh.subscribe<tf2_msgs::TFMessage>("/tf", 1000, record);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  sub.shutdown();
  std::lock_guard<std::mutex> lock(mutex);
  return seen;
}

/// Each instance's frame is broadcast by that instance only, at the pose of continuous playback.
void expectContinuousPlayback(const std::vector<Instance>& instances, double seconds)
{
  auto seen = watchTf(seconds);
  for (const Instance& instance : instances)
  {
    const auto& transforms = seen[instance.child_frame_id];
    ASSERT_GE(transforms.size(), 3u) << instance.child_frame_id << " not broadcast:\n" << slurp(instance.log);
    for (const auto& entry : transforms)
    {
      EXPECT_EQ(entry.first, instance.node()) << instance.child_frame_id;
      const geometry_msgs::TransformStamped& t = entry.second;
      EXPECT_EQ(t.header.frame_id, "map");
      const double elapsed = (t.header.stamp - instance.start).toSec();
      EXPECT_GT(elapsed, 0.0);
      EXPECT_NEAR(t.transform.translation.x, instance.speed * elapsed, 1e-6) << instance.child_frame_id;
      EXPECT_NEAR(t.transform.translation.y, 0.0, 1e-9) << instance.child_frame_id;
    }
  }
}

bool alive(pid_t pid)
{
  int status = 0;
  return waitpid(pid, &status, WNOHANG) == 0;
}
}  // namespace

TEST(MasterRestart, InstancesKeepRunningAndRegisterAgainWithTheirParametersAndMotion)
{
  const int port = freePort();
  ASSERT_GT(port, 0);
  const std::string uri = "http://127.0.0.1:" + std::to_string(port) + "/";
  setenv("ROS_MASTER_URI", uri.c_str(), 1);
  setenv("ROS_IP", "127.0.0.1", 1);
  const std::string dir = testing::TempDir();
  const std::vector<std::string> master = { "rosmaster", "--core", "-p", std::to_string(port) };
  pid_t master_pid = spawn(master, dir + "master_restart_master1.log");
  ASSERT_TRUE(waitFor([&] { return masterUp(port); }, 30.0));

  std::vector<Instance> instances = {
    { "/robot_a", "tool_a", 20, 0.1, { poseAt(1, 0), poseAt(2, 1), poseAt(3, 0) } },
    { "/robot_b", "tool_b", 30, 0.2, { poseAt(-1, 0), poseAt(-2, -1), poseAt(-3, 0), poseAt(-4, 1) } },
    { "/robot_c", "tool_c", 40, 0.3, { poseAt(5, 5), poseAt(6, 5) } },
  };
  for (std::size_t i = 0; i < instances.size(); ++i)
  {
    Instance& instance = instances[i];
    instance.log = dir + "master_restart_" + instance.child_frame_id + ".log";
    const std::vector<std::string> params = { "__ns:=" + instance.ns, "__name:=planner",
                                              "_child_frame_id:=" + instance.child_frame_id, "_frame_id:=map",
                                              "_auto_generate:=false", "_master_check_period:=0.2", "_tf_rate:=20",
                                              "_sample_count:=" + std::to_string(instance.sample_count) };
    std::vector<std::string> argv;
    if (i + 1 < instances.size())
      argv = { SE3_NODE_BIN };
    else  // the nodelet, in a standalone manager
      argv = { "rosrun", "nodelet", "nodelet", "standalone", "se3_interpolation/InterpolationNodelet" };
    argv.insert(argv.end(), params.begin(), params.end());
    instance.pid = spawn(argv, instance.log);
  }
  std::map<std::string, std::string> remappings = { { "__master", uri } };
  ros::init(remappings, "test_master_restart", ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::NodeHandle nh;
  for (const Instance& instance : instances)
    ASSERT_TRUE(ros::service::waitForService(instance.node() + "/generate", ros::Duration(30.0)))
        << slurp(instance.log);

  // A run-time change on the first instance: its ~sample_count becomes 25.
  {
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::IntParameter p;
    p.name = "sample_count";
    p.value = 25;
    srv.request.config.ints.push_back(p);
    ASSERT_TRUE(node_test::callService(instances[0].node() + "/set_parameters", srv));
    instances[0].sample_count = 25;
  }

  // The waypoint buffers, and a motion playing on each moving frame.
  std::vector<ros::Publisher> buffer_pubs;
  for (Instance& instance : instances)
  {
    buffer_pubs.push_back(nh.advertise<geometry_msgs::PoseArray>(instance.node() + "/waypoints", 1, true));
    geometry_msgs::PoseArray buffer;
    buffer.header.frame_id = "map";
    buffer.poses = instance.buffer;
    buffer_pubs.back().publish(buffer);
  }
  for (Instance& instance : instances)
  {
    se3_interpolation::GenerateTrajectory srv;
    ASSERT_TRUE(waitFor([&] { return generateFromBuffer(instance, &srv); }, 30.0)) << srv.response.message;
    expectBufferUsed(instance, srv);

    se3_interpolation::GenerateTrajectory motion;
    motion.request.waypoints.header.frame_id = "map";
    instance.start = ros::Time::now();
    motion.request.waypoints.header.stamp = instance.start;
    motion.request.waypoints.poses = { poseAt(0, 0), poseAt(60 * instance.speed, 0) };
    motion.request.times = { 0.0, 60.0 };
    motion.request.curve = "piecewise_geodesic";
    motion.request.sample_count = 10;
    motion.request.publish = true;
    ASSERT_TRUE(node_test::callService(instance.node() + "/generate", motion));
    ASSERT_TRUE(motion.response.success) << motion.response.message;
  }
  expectContinuousPlayback(instances, 1.0);

  // Killed, away for a while (the instances wait), restarted on the same port.
  kill(master_pid, SIGKILL);
  waitpid(master_pid, nullptr, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  for (const Instance& instance : instances)
    EXPECT_TRUE(alive(instance.pid)) << instance.node() << " exited while the master was down:\n" << slurp(instance.log);
  master_pid = spawn(master, dir + "master_restart_master2.log");
  ASSERT_TRUE(waitFor([&] { return masterUp(port); }, 30.0));

  // Checked every 0.2 s: registered again well within 30 s.
  for (const Instance& instance : instances)
  {
    EXPECT_TRUE(waitFor([&] { return masterHasService(port, instance.node() + "/generate"); }, 30.0))
        << slurp(instance.log);
    EXPECT_TRUE(waitFor([&] { return masterHasService(port, instance.node() + "/clear_waypoints"); }, 30.0));
    EXPECT_TRUE(waitFor([&] { return masterHasService(port, instance.node() + "/set_parameters"); }, 30.0));
  }
  // The same processes (children of this test: a respawned one would not be).
  for (const Instance& instance : instances)
    EXPECT_TRUE(alive(instance.pid)) << instance.node() << " exited:\n" << slurp(instance.log);

  // The parameters in effect, on the new parameter server.
  for (const Instance& instance : instances)
  {
    std::string child, frame;
    int samples = 0;
    double tf_rate = 0.0;
    bool auto_generate = true;
    EXPECT_TRUE(waitFor([&] { return ros::param::get(instance.node() + "/child_frame_id", child); }, 30.0));
    EXPECT_EQ(child, instance.child_frame_id);
    EXPECT_TRUE(ros::param::get(instance.node() + "/frame_id", frame));
    EXPECT_EQ(frame, "map");
    EXPECT_TRUE(ros::param::get(instance.node() + "/sample_count", samples));
    EXPECT_EQ(samples, instance.sample_count) << instance.node();
    EXPECT_TRUE(ros::param::get(instance.node() + "/tf_rate", tf_rate));
    EXPECT_EQ(tf_rate, 20.0);
    EXPECT_TRUE(ros::param::get(instance.node() + "/auto_generate", auto_generate));
    EXPECT_FALSE(auto_generate);
  }

  // The services answer on the new master, from the kept buffer with the parameters in effect.
  for (const Instance& instance : instances)
  {
    se3_interpolation::GenerateTrajectory srv;
    ASSERT_TRUE(generateFromBuffer(instance, &srv)) << instance.node() << ": " << srv.response.message;
    expectBufferUsed(instance, srv);
  }
  // The motion played on: the frames broadcast after the restart are those of continuous playback.
  expectContinuousPlayback(instances, 1.5);
  // The latched ~path of the motion, to a subscriber of the new master.
  for (const Instance& instance : instances)
  {
    std::mutex mutex;
    std::size_t poses = 0;
    ros::Subscriber sub = nh.subscribe<nav_msgs::Path>(instance.node() + "/path", 1, [&](const nav_msgs::Path::ConstPtr& m) {
      std::lock_guard<std::mutex> lock(mutex);
      poses = m->poses.size();
    });
    EXPECT_TRUE(waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(mutex);
          return poses == 10;
        },
        30.0))
        << instance.node();
  }
  for (const Instance& instance : instances)
    EXPECT_NE(slurp(instance.log).find("registered again with the new master"), std::string::npos)
        << slurp(instance.log);

  spinner.stop();
  for (const Instance& instance : instances)
  {
    kill(instance.pid, SIGINT);
    if (!waitFor([&] { return !alive(instance.pid); }, 20.0))
    {
      kill(instance.pid, SIGKILL);
      waitpid(instance.pid, nullptr, 0);
    }
  }
  kill(master_pid, SIGKILL);
  waitpid(master_pid, nullptr, 0);
}
