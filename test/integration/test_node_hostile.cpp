// Integration, hostile input and faults: a far-future stamp does not kill the TF
// timer, frame ids are bounded, /tf_static holds only the latest trajectory's frames, dropped
// ~waypoint messages are warned, ~waypoint's tf2 waits and a heavy request do not delay a light
// request, and the node killed with SIGKILL is respawned and serves again.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <tf2_msgs/TFMessage.h>
#include <xmlrpcpp/XmlRpc.h>

#include <signal.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>
#include <thread>

#include "se3_interpolation/GenerateTrajectory.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const char* const kNode = "/se3_interpolation_node";
const char* const kService = "/se3_interpolation_node/generate";

se3_interpolation::GenerateTrajectory lightRequest()
{
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.poses = { pose(0, 0, 0, 0), pose(1, 0, 0, 0.5), pose(1, 1, 0.5, 1.5) };
  srv.request.sample_count = 10;
  return srv;
}

/// The node's messages on /rosout (the test's spinner threads fill it).
class RosoutLog
{
public:
  explicit RosoutLog(ros::NodeHandle& nh)
    : sub_(nh.subscribe<rosgraph_msgs::Log>("/rosout", 10000, [this](const rosgraph_msgs::Log::ConstPtr& m) {
      if (m->name != kNode)
        return;
      std::lock_guard<std::mutex> lock(mutex_);
      lines_.push_back(m->msg);
    }))
  {
  }
  int count(const std::string& part) const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    int n = 0;
    for (const auto& l : lines_)
      n += l.find(part) != std::string::npos ? 1 : 0;
    return n;
  }
  std::size_t longest() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t n = 0;
    for (const auto& l : lines_)
      n = std::max(n, l.size());
    return n;
  }

private:
  mutable std::mutex mutex_;
  std::vector<std::string> lines_;
  /// Last: constructed after and destroyed before what its callback uses (the spinner thread may
  /// run the callback as soon as it subscribes: at once for a latched message).
  ros::Subscriber sub_;
};

/// The node's process id, asked over its XML-RPC slave API (0 if it cannot be reached).
int nodePid()
{
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = kNode;
  if (!ros::master::execute("lookupNode", args, result, payload, false))
    return 0;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port))
    return 0;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue request, response;
  request[0] = ros::this_node::getName();
  if (!client.execute("getPid", request, response) || response.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      response.size() != 3 || static_cast<int>(response[0]) != 1)
    return 0;
  return static_cast<int>(response[2]);
}
}  // namespace

// Row 1: a legal stamp 2^31 s ahead used to make the TF timer throw out of roscpp.
TEST(NodeHostile, FarFutureStampDoesNotKillTheNode)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  const int pid = nodePid();
  ASSERT_GT(pid, 0);
  auto far = lightRequest();
  far.request.waypoints.header.stamp = ros::Time(3950000000u);
  far.request.publish = true;
  ASSERT_TRUE(node_test::callService(kService, far));
  EXPECT_TRUE(far.response.success) << far.response.message;

  // The TF timer replays it (tf_rate 50 Hz) for a while; the node must still be the same process.
  ros::WallDuration(1.0).sleep();
  auto light = lightRequest();
  ASSERT_TRUE(node_test::callService(kService, light));
  EXPECT_TRUE(light.response.success) << light.response.message;
  EXPECT_EQ(nodePid(), pid);

  // A stamp whose trajectory would end after the last ros::Time: refused, naming the field.
  auto late = lightRequest();
  late.request.waypoints.header.stamp = ros::Time(4294967290u);
  late.request.duration = 100.0;
  ASSERT_TRUE(node_test::callService(kService, late));
  EXPECT_FALSE(late.response.success);
  EXPECT_EQ(late.response.message.rfind("waypoints.header.stamp: ", 0), 0u) << late.response.message;
  // Row 14: a duration ROS cannot carry names the field.
  auto huge = lightRequest();
  huge.request.duration = 3e9;
  ASSERT_TRUE(node_test::callService(kService, huge));
  EXPECT_FALSE(huge.response.success);
  EXPECT_EQ(huge.response.message.rfind("duration: ", 0), 0u) << huge.response.message;
}

// Rows 3, 5, 15, 17: long or control-character frame ids are refused with a bounded message,
// and a rejected ~waypoints message with a 1 MB frame id is not echoed into the log.
TEST(NodeHostile, FrameIdsAreBounded)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  ros::NodeHandle nh;
  RosoutLog log(nh);
  const std::string mb(1000000, 'f');
  const std::pair<std::function<void(se3_interpolation::GenerateTrajectory&)>, const char*> cases[] = {
    { [&mb](auto& s) { s.request.waypoints.header.frame_id = mb; }, "waypoints.header.frame_id: " },
    { [&mb](auto& s) { s.request.child_frame_id = mb; }, "child_frame_id: " },
    { [](auto& s) { s.request.child_frame_id = std::string(257, 'c'); }, "child_frame_id: " },
    { [](auto& s) { s.request.child_frame_id = std::string("a\0b", 3); }, "child_frame_id: " },
    { [](auto& s) { s.request.child_frame_id = "bell\a"; }, "child_frame_id: " },
    { [](auto& s) { s.request.waypoints.header.frame_id = "esc\x1b[2J"; }, "waypoints.header.frame_id: " },
  };
  for (const auto& c : cases)
  {
    auto srv = lightRequest();
    c.first(srv);
    srv.request.publish = true;
    ASSERT_TRUE(node_test::callService(kService, srv)) << c.second;
    EXPECT_FALSE(srv.response.success) << c.second;
    EXPECT_EQ(srv.response.message.rfind(c.second, 0), 0u) << srv.response.message.substr(0, 200);
    EXPECT_LT(srv.response.message.size(), 300u) << c.second;
    EXPECT_TRUE(srv.response.path.poses.empty());
  }
  auto ok = lightRequest();
  ok.request.child_frame_id = std::string(256, 'k');
  ASSERT_TRUE(node_test::callService(kService, ok));
  EXPECT_TRUE(ok.response.success) << ok.response.message;

  ros::Publisher waypoints = nh.advertise<geometry_msgs::PoseArray>(std::string(kNode) + "/waypoints", 10);
  ASSERT_TRUE(waitFor([&] { return waypoints.getNumSubscribers() > 0; }, 10.0));
  geometry_msgs::PoseArray bad;
  bad.header.frame_id = mb;
  bad.poses = { pose(0, 0, 0, 0), pose(1, 0, 0, 0) };
  // The /rosout subscription connects in the background: one message is sent until its
  // rejection is seen (the log is then connected), then five more must each be rejected.
  const char* rejected = "~waypoints rejected: waypoints.header.frame_id";
  ASSERT_TRUE(waitFor(
      [&] {
        waypoints.publish(bad);
        return waitFor([&] { return log.count(rejected) >= 1; }, 1.0);
      },
      30.0));
  const int before = log.count(rejected);
  for (int i = 0; i < 5; ++i)
    waypoints.publish(bad);
  ASSERT_TRUE(waitFor([&] { return log.count(rejected) >= before + 5; }, 20.0));
  EXPECT_LT(log.longest(), 2000u);
}

// Row 4: /tf_static carries the latest trajectory's frames only, whatever the child was before.
TEST(NodeHostile, TfStaticHoldsOnlyTheLatestTrajectory)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  for (const char* child : { "first", "second", "third" })
  {
    auto srv = lightRequest();
    srv.request.child_frame_id = child;
    srv.request.publish = true;
    ASSERT_TRUE(node_test::callService(kService, srv));
    ASSERT_TRUE(srv.response.success) << srv.response.message;
  }
  // A late subscriber receives the latched message(s) of every /tf_static publisher; the
  // node's one must hold exactly max_tf_samples = 7 frames, all of "third".
  ros::NodeHandle nh;
  std::mutex mutex;
  std::vector<tf2_msgs::TFMessage> from_node;
  // (A boost::function of the event: a lambda would bind to the ConstPtr overload and lose the
  // publisher's name.)
  const boost::function<void(const ros::MessageEvent<const tf2_msgs::TFMessage>&)> record =
      [&](const ros::MessageEvent<const tf2_msgs::TFMessage>& e) {
        if (e.getPublisherName() != kNode)
          return;
        std::lock_guard<std::mutex> lock(mutex);
        from_node.push_back(*e.getMessage());
      };
  ros::Subscriber sub = nh.subscribe<tf2_msgs::TFMessage>("/tf_static", 10, record);
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return !from_node.empty();
      },
      10.0));
  ros::WallDuration(0.5).sleep();
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(from_node.size(), 1u);
  ASSERT_EQ(from_node[0].transforms.size(), 7u);
  for (std::size_t k = 0; k < 7; ++k)
    EXPECT_EQ(from_node[0].transforms[k].child_frame_id, "third_" + std::to_string(k));
}

// Row 9 and deliverable 3: ~waypoint messages in frames tf2 cannot resolve each wait
// ~tf_timeout = 1 s; a service call made meanwhile is answered before they are all rejected.
TEST(NodeHostile, WaypointTfWaitsDoNotDelayTheService)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  ros::NodeHandle nh;
  RosoutLog log(nh);
  ros::Publisher waypoint = nh.advertise<geometry_msgs::PoseStamped>(std::string(kNode) + "/waypoint", 100);
  ASSERT_TRUE(waitFor([&] { return waypoint.getNumSubscribers() > 0; }, 10.0));
  for (int i = 0; i < 8; ++i)
  {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "nowhere_" + std::to_string(i);
    p.pose = pose(i, 0, 0, 0);
    waypoint.publish(p);
  }
  ASSERT_TRUE(waitFor([&] { return log.count("~waypoint rejected") >= 1; }, 20.0));
  auto light = lightRequest();
  ASSERT_TRUE(node_test::callService(kService, light));
  EXPECT_TRUE(light.response.success) << light.response.message;
  // Served on its own threads: at most a couple of the 1 s waits were over when it returned.
  EXPECT_LT(log.count("~waypoint rejected"), 5);
  ASSERT_TRUE(waitFor([&] { return log.count("~waypoint rejected") >= 5; }, 30.0));
}

// Row 8: messages dropped by the ~waypoint backlog (~waypoint_queue_size = 5) are counted and
// warned (test_node_flood checks the count).
TEST(NodeHostile, DroppedWaypointsAreWarned)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  ros::NodeHandle nh;
  RosoutLog log(nh);
  ros::Publisher waypoint = nh.advertise<geometry_msgs::PoseStamped>(std::string(kNode) + "/waypoint", 100000);
  ASSERT_TRUE(waitFor([&] { return waypoint.getNumSubscribers() > 0; }, 10.0));
  for (std::uint32_t i = 1; i <= 3000; ++i)
  {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "map";
    p.pose = pose(0.001 * i, std::sin(0.01 * i), 0, 0.001 * i);
    waypoint.publish(p);
  }
  ASSERT_TRUE(waitFor([&] { return log.count("dropped waypoint messages: ~waypoint ") >= 1; }, 60.0));
}

// Deliverable 3: a heavy request in flight does not delay a light one.
TEST(NodeHostile, HeavyRequestDoesNotDelayALightOne)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  se3_interpolation::GenerateTrajectory heavy;
  heavy.request.waypoints.header.frame_id = "map";
  for (int i = 0; i < 200; ++i)
    heavy.request.waypoints.poses.push_back(pose(std::cos(0.1 * i), std::sin(0.1 * i), 0.01 * i, 0.05 * i));
  heavy.request.curve = "bezier";
  heavy.request.sample_count = 1000;
  std::atomic<bool> heavy_started{ false }, heavy_done{ false };
  std::thread worker([&] {
    heavy_started = true;
    node_test::callService(kService, heavy);
    heavy_done = true;
  });
  ASSERT_TRUE(waitFor([&] { return heavy_started.load(); }, 10.0));
  ros::WallDuration(0.3).sleep();  // let the heavy request reach the node first
  bool light_done_first = false;
  for (int i = 0; i < 3; ++i)
  {
    auto light = lightRequest();
    ASSERT_TRUE(node_test::callService(kService, light));
    EXPECT_TRUE(light.response.success) << light.response.message;
    light_done_first = !heavy_done;
  }
  EXPECT_TRUE(light_done_first) << "the light requests waited for the heavy one";
  worker.join();
  EXPECT_TRUE(heavy.response.success) << heavy.response.message;
}

// Deliverable 4: killed with SIGKILL mid-playback, the node is respawned and serves again.
TEST(NodeHostile, RespawnedAfterSigkill)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto playing = lightRequest();
  playing.request.duration = 30.0;
  playing.request.publish = true;
  ASSERT_TRUE(node_test::callService(kService, playing));
  ASSERT_TRUE(playing.response.success) << playing.response.message;
  const int pid = nodePid();
  ASSERT_GT(pid, 0);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  ASSERT_TRUE(waitFor(
      [&] {
        const int now = nodePid();
        return now > 0 && now != pid;
      },
      60.0));
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto light = lightRequest();
  light.request.publish = true;
  ASSERT_TRUE(node_test::callService(kService, light));
  EXPECT_TRUE(light.response.success) << light.response.message;
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_hostile");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
