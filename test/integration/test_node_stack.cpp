// Integration: the node inside a robot stack, through a real roscore and tf2 listener.
// node_stack.test: two instances side by side through launch/se3_interpolation.launch (/arm1
// holding its last pose, /arm2 looping), a third (/slow) with a long tf2 wait, and two taught
// frames from tf2_ros static_transform_publisher. node_nodelet.test: the nodelet under a manager.
// Expected poses are written here: a double-geodesic segment between two poses is the lerp of the
// positions and the slerp of the rotations at the time fraction, which tf2 interpolates exactly.
#include <dynamic_reconfigure/ConfigDescription.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <signal.h>
#include <std_srvs/Trigger.h>
#include <sys/wait.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_listener.h>
#include <unistd.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <future>
#include <sstream>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/GenerationStatus.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const std::string kArm1 = "/arm1/se3_interpolation_node";
const std::string kArm2 = "/arm2/se3_interpolation_node";
const std::string kSlow = "/slow/se3_interpolation_node";
const std::string kNodelet = "/arm3/se3_interpolation_node";

const Eigen::Quaterniond kQa(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
const Eigen::Quaterniond kQb(Eigen::AngleAxisd(1.3, Eigen::Vector3d(1, 2, 2).normalized()));
const Eigen::Vector3d kPa(0.5, -1.0, 0.2), kPb(1.5, 1.0, 3.2);

/// pa -> pb over `duration` s as a double geodesic, published, stamped `stamp`.
se3_interpolation::GenerateTrajectory segment(double duration, const ros::Time& stamp)
{
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.header.stamp = stamp;
  srv.request.waypoints.poses = { pose(kPa, kQa), pose(kPb, kQb) };
  srv.request.times = { 0.0, duration };
  srv.request.curve = "piecewise_geodesic";
  srv.request.publish = true;
  return srv;
}

/// The segment's pose at time fraction `s`.
Eigen::Isometry3d segmentAt(double s)
{
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = kQa.slerp(s, kQb).toRotationMatrix();
  x.translation() = (1 - s) * kPa + s * kPb;
  return x;
}

double distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
  return (a.translation() - b.translation()).norm() +
         Eigen::Quaterniond(a.rotation()).angularDistance(Eigen::Quaterniond(b.rotation()));
}

Eigen::Isometry3d lookUp(tf2_ros::Buffer& buffer, const std::string& child, const ros::Time& t)
{
  return tf2::transformToEigen(buffer.lookupTransform("map", child, t, ros::Duration(3.0)));
}

/// Sends a dynamic_reconfigure change (strings, ints, bools) to `node`; returns the config
/// the server keeps.
dynamic_reconfigure::Config reconfigure(const std::string& node, const std::vector<std::pair<std::string, std::string>>& strs,
                                        const std::vector<std::pair<std::string, int>>& ints,
                                        const std::vector<std::pair<std::string, bool>>& bools)
{
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& i : ints)
  {
    dynamic_reconfigure::IntParameter p;
    p.name = i.first;
    p.value = i.second;
    srv.request.config.ints.push_back(p);
  }
  for (const auto& s : strs)
  {
    dynamic_reconfigure::StrParameter p;
    p.name = s.first;
    p.value = s.second;
    srv.request.config.strs.push_back(p);
  }
  for (const auto& b : bools)
  {
    dynamic_reconfigure::BoolParameter p;
    p.name = b.first;
    p.value = b.second;
    srv.request.config.bools.push_back(p);
  }
  EXPECT_TRUE(node_test::callService(node + "/set_parameters", srv)) << node;
  return srv.response.config;
}

/// Sends a dynamic_reconfigure change of numbers to `node`; returns the config the server keeps.
dynamic_reconfigure::Config reconfigureNumbers(const std::string& node,
                                               const std::vector<std::pair<std::string, double>>& doubles,
                                               const std::vector<std::pair<std::string, int>>& ints)
{
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& d : doubles)
  {
    dynamic_reconfigure::DoubleParameter p;
    p.name = d.first;
    p.value = d.second;
    srv.request.config.doubles.push_back(p);
  }
  for (const auto& i : ints)
  {
    dynamic_reconfigure::IntParameter p;
    p.name = i.first;
    p.value = i.second;
    srv.request.config.ints.push_back(p);
  }
  EXPECT_TRUE(node_test::callService(node + "/set_parameters", srv)) << node;
  return srv.response.config;
}

double doubleOf(const dynamic_reconfigure::Config& c, const std::string& name)
{
  for (const auto& d : c.doubles)
    if (d.name == name)
      return d.value;
  ADD_FAILURE() << name << " absent";
  return NAN;
}

int intOf(const dynamic_reconfigure::Config& c, const std::string& name)
{
  for (const auto& i : c.ints)
    if (i.name == name)
      return i.value;
  ADD_FAILURE() << name << " absent";
  return -1;
}

std::string strOf(const dynamic_reconfigure::Config& c, const std::string& name)
{
  for (const auto& s : c.strs)
    if (s.name == name)
      return s.value;
  return "<absent>";
}

bool boolOf(const dynamic_reconfigure::Config& c, const std::string& name)
{
  for (const auto& b : c.bools)
    if (b.name == name)
      return b.value;
  ADD_FAILURE() << name << " absent";
  return false;
}

/// /rosout: WARN messages of one node.
class Warnings
{
public:
  explicit Warnings(ros::NodeHandle& nh)
    : sub_(nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000, [this](const rosgraph_msgs::Log::ConstPtr& m) {
      if (m->level == rosgraph_msgs::Log::WARN)
        log_.push_back(*m);
    }))
  {
  }
  /// Does a warning of `node` contain every one of `parts`?
  bool has(const std::string& node, const std::vector<std::string>& parts) const
  {
    for (const auto& m : log_)
    {
      if (m.name != node)
        continue;
      bool all = true;
      for (const auto& p : parts)
        all = all && m.msg.find(p) != std::string::npos;
      if (all)
        return true;
    }
    return false;
  }
  const ros::Subscriber& subscriber() const { return sub_; }

private:
  std::vector<rosgraph_msgs::Log> log_;
  /// Last: constructed after and destroyed before what its callback uses (the spinner thread may
  /// run the callback as soon as it subscribes: at once for a latched message).
  ros::Subscriber sub_;
};

void waitForNodes()
{
  for (const auto& n : { kArm1, kArm2, kSlow })
    ASSERT_TRUE(ros::service::waitForService(n + "/generate", ros::Duration(30.0))) << n;
}
}  // namespace

// ~loop false (arm1, the default) holds the last pose; ~loop true (arm2) replays the same request.
TEST(NodeStack, HoldsTheLastPoseUnlessLooping)
{
  waitForNodes();
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  const ros::Time stamp = ros::Time::now();
  auto held = segment(1.0, stamp);
  auto looped = segment(1.0, stamp);
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", held));
  ASSERT_TRUE(held.response.success) << held.response.message;
  ASSERT_TRUE(node_test::callService(kArm2 + "/generate", looped));
  ASSERT_TRUE(looped.response.success) << looped.response.message;

  // 1.25 s: a quarter into the second cycle when looping, past the end when holding.
  const ros::Time t = stamp + ros::Duration(1.25);
  ASSERT_TRUE(spinUntil([&] { return ros::Time::now() > t + ros::Duration(0.3); }, 10.0));
  EXPECT_LT(distance(lookUp(buffer, "arm1_tool", t), segmentAt(1.0)), 1e-6);
  EXPECT_LT(distance(lookUp(buffer, "arm2_tool", t), segmentAt(0.25)), 1e-6);
  // Still there later: the held frame keeps being broadcast at the last pose.
  spinFor(0.5);
  const ros::Time later = ros::Time::now() - ros::Duration(0.1);
  EXPECT_LT(distance(lookUp(buffer, "arm1_tool", later), segmentAt(1.0)), 1e-6);
}

// ~clear_waypoints stops playback along the path, empties ~path and deletes the markers.
TEST(NodeStack, ClearStopsPlaybackAndClearsPathAndMarkers)
{
  waitForNodes();
  ros::NodeHandle nh;
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  Latest<nav_msgs::Path> path(nh, kArm2 + "/path");
  Latest<visualization_msgs::MarkerArray> markers(nh, kArm2 + "/markers");
  auto srv = segment(4.0, ros::Time::now());
  ASSERT_TRUE(node_test::callService(kArm2 + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  ASSERT_TRUE(spinUntil([&] { return !path.msg().poses.empty() && !markers.msg().markers.empty(); }, 10.0));
  spinFor(0.5);

  const int paths_before = path.count();
  const int markers_before = markers.count();
  std_srvs::Trigger clear;
  ASSERT_TRUE(node_test::callService(kArm2 + "/clear_waypoints", clear));
  EXPECT_TRUE(clear.response.success);
  ASSERT_TRUE(spinUntil([&] { return path.count() > paths_before && markers.count() > markers_before; }, 10.0));
  EXPECT_TRUE(path.msg().poses.empty());
  EXPECT_EQ(path.msg().header.frame_id, "map");
  ASSERT_EQ(markers.msg().markers.size(), 1U);
  EXPECT_EQ(markers.msg().markers[0].action, visualization_msgs::Marker::DELETEALL);

  // Stopped along the path (no bounds here: the smooth ramp of ~stop_time, 0.5 s, from 50 ms after
  // the clear), then held: two broadcasts 0.5 s apart are the same pose, one on the segment
  // strictly inside it (the 4 s motion was stopped after about 0.5 s).
  spinFor(1.0);
  const Eigen::Isometry3d first = lookUp(buffer, "arm2_tool", ros::Time::now() - ros::Duration(0.1));
  spinFor(0.5);
  const Eigen::Isometry3d second = lookUp(buffer, "arm2_tool", ros::Time::now() - ros::Duration(0.1));
  EXPECT_LT(distance(first, second), 1e-12);
  const double s = (first.translation() - kPa).dot(kPb - kPa) / (kPb - kPa).squaredNorm();
  EXPECT_GT(s, 0.0);
  EXPECT_LT(s, 1.0);
  EXPECT_LT(distance(first, segmentAt(s)), 1e-9) << "s " << s;
}

// dynamic_reconfigure: a refused name keeps the old value, an accepted one takes effect.
TEST(NodeStack, ReconfigureChangesTheDefaultsWithValidation)
{
  waitForNodes();
  ros::NodeHandle nh;
  Warnings warnings(nh);
  ASSERT_TRUE(spinUntil([&] { return warnings.subscriber().getNumPublishers() >= 3; }, 10.0));
  spinFor(0.5);
  dynamic_reconfigure::Config kept = reconfigure(kArm1, { { "curve", "bspine" } }, {}, {});
  EXPECT_EQ(strOf(kept, "curve"), "interpolating");
  ASSERT_TRUE(spinUntil([&] { return warnings.has(kArm1, { "~curve: unknown value 'bspine'", "keeping" }); }, 10.0));
  std::string curve;
  ASSERT_TRUE(nh.getParam(kArm1 + "/curve", curve));
  EXPECT_EQ(curve, "interpolating");

  dynamic_reconfigure::Config changed =
      reconfigure(kArm1, { { "curve", "piecewise_geodesic" } }, { { "sample_count", 3 } }, { { "loop", true } });
  EXPECT_EQ(strOf(changed, "curve"), "piecewise_geodesic");
  EXPECT_TRUE(boolOf(changed, "loop"));

  // A request without curve now gets the piecewise geodesic: at half time its pose is the
  // segment's midpoint (an interpolating spline through 3 poses would bulge away from it).
  se3_interpolation::GenerateTrajectory srv = segment(1.0, ros::Time::now());
  srv.request.curve.clear();
  srv.request.waypoints.poses.push_back(pose(Eigen::Vector3d(3, -2, 0), kQa));
  srv.request.times = { 0.0, 1.0, 2.0 };
  srv.request.publish = false;
  Latest<se3_interpolation::GenerationStatus> status(nh, kArm1 + "/status");
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  ASSERT_EQ(srv.response.path.poses.size(), 3U);  // the reconfigured sample_count
  Eigen::Isometry3d mid;
  tf2::fromMsg(srv.response.path.poses[1].pose, mid);
  EXPECT_LT(distance(mid, segmentAt(1.0)), 1e-9);
  ASSERT_TRUE(spinUntil([&] { return status.count() > 0 && status.msg().curve == "piecewise_geodesic"; }, 10.0));

  // The loop setting is the playback's: arm1 now replays.
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  const ros::Time stamp = ros::Time::now();
  auto looped = segment(1.0, stamp);
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", looped));
  ASSERT_TRUE(looped.response.success) << looped.response.message;
  const ros::Time t = stamp + ros::Duration(1.25);
  ASSERT_TRUE(spinUntil([&] { return ros::Time::now() > t + ros::Duration(0.3); }, 10.0));
  EXPECT_LT(distance(lookUp(buffer, "arm1_tool", t), segmentAt(0.25)), 1e-6);

  dynamic_reconfigure::Config restored =
      reconfigure(kArm1, { { "curve", "interpolating" } }, { { "sample_count", 100 } }, { { "loop", false } });
  EXPECT_FALSE(boolOf(restored, "loop"));
}

// A number its row refuses (negative, not finite, beyond the range) is refused, never clamped:
// `dynparam set ... max_linear_velocity -1` keeps the bound in force instead of making it 0
// ("unbounded"); the answer carries the value kept, a warning names the value refused, and the
// description carries the table's ranges for rqt_reconfigure.
TEST(NodeStack, ReconfigureRefusesNegativeAndNonFiniteNumbers)
{
  waitForNodes();
  ros::NodeHandle nh;
  Warnings warnings(nh);
  ASSERT_TRUE(spinUntil([&] { return warnings.subscriber().getNumPublishers() >= 3; }, 10.0));
  spinFor(0.5);
  Latest<dynamic_reconfigure::ConfigDescription> description(nh, kSlow + "/parameter_descriptions");
  EXPECT_EQ(doubleOf(reconfigureNumbers(kSlow, { { "max_linear_velocity", 0.5 } }, {}), "max_linear_velocity"), 0.5);
  const struct
  {
    const char* name;
    double value;
    double kept;
  } refusals[] = { { "max_linear_velocity", -1.0, 0.5 },       { "max_linear_velocity", NAN, 0.5 },
                   { "max_linear_velocity", INFINITY, 0.5 },   { "path_tolerance_linear", -1.0, 0.0 },
                   { "max_linear_acceleration", -INFINITY, 0.0 }, { "tf_rate", 2000.0, 50.0 } };
  for (const auto& c : refusals)
  {
    EXPECT_EQ(doubleOf(reconfigureNumbers(kSlow, { { c.name, c.value } }, {}), c.name), c.kept) << c.name << " " << c.value;
    std::ostringstream refused;
    refused << "~" << c.name << ": refused " << c.value;
    EXPECT_TRUE(spinUntil([&] { return warnings.has(kSlow, { refused.str(), "keeping" }); }, 10.0)) << refused.str();
  }
  EXPECT_EQ(intOf(reconfigureNumbers(kSlow, {}, { { "sample_count", -5 } }), "sample_count"), 100);
  EXPECT_TRUE(spinUntil([&] { return warnings.has(kSlow, { "~sample_count: refused -5", "keeping 100" }); }, 10.0));
  double kept = 0.0;
  EXPECT_TRUE(nh.getParam(kSlow + "/max_linear_velocity", kept));
  EXPECT_EQ(kept, 0.5);

  // The bound is in force: the 3.7 m segment in 1 s is stretched to 0.5 m/s.
  auto srv = segment(1.0, ros::Time::now());
  srv.request.publish = false;
  ASSERT_TRUE(node_test::callService(kSlow + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_LE(srv.response.max_linear_speed, 0.5 * (1.0 + 1e-9));
  EXPECT_GT(srv.response.duration, 7.0);

  ASSERT_TRUE(spinUntil([&] { return description.count() > 0; }, 10.0));
  EXPECT_EQ(doubleOf(description.msg().min, "max_linear_velocity"), 0.0);
  EXPECT_EQ(doubleOf(description.msg().max, "tf_rate"), 1000.0);
  EXPECT_EQ(intOf(description.msg().min, "sample_count"), 2);
  EXPECT_EQ(doubleOf(reconfigureNumbers(kSlow, { { "max_linear_velocity", 0.0 } }, {}), "max_linear_velocity"), 0.0);
}

// Every start-up parameter is validated: unknown values and wrong types are refused by name, and
// a misspelled parameter is named with the closest known one.
TEST(NodeStack, RefusedParametersKeepTheDefaults)
{
  const std::string log = testing::TempDir() + "refused_parameters.log";
  const pid_t pid = fork();
  if (pid == 0)
  {
    std::freopen(log.c_str(), "w", stdout);
    dup2(fileno(stdout), fileno(stderr));
    execl(SE3_NODE_BIN, SE3_NODE_BIN, "__name:=refused_node", "_curve:=bspine", "_geometry:=screwy",
          "_parameterization:=chordal", "_timing:=fastest", "_tf_rate:=-5.0", "_loop:=maybe", "_sample_count:=1",
          "_child_frame_id:=bad frame", "_master_check_period:=0.0", "_max_velocity:=0.5", "_max_samples:=1e12",
          "_max_waypoints:=3e4",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(pid, 0);
  const bool up = ros::service::waitForService("/refused_node/generate", ros::Duration(30.0));
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  const std::string out = text.str();
  for (const char* expected :
       { "~curve: unknown value 'bspine' (expected one of: piecewise_geodesic, bezier, bspline", "keeping 'interpolating'",
         "~geometry: unknown value 'screwy'", "~parameterization: unknown value 'chordal'",
         "~timing: unknown value 'fastest'", "~tf_rate: refused -5 (must be in (0, 1000] Hz); keeping 50",
         "~loop: refused (not of the expected type); keeping 0", "~sample_count: refused 1 (must be >= 2)",
         "~child_frame_id: ",
         "~max_velocity: unknown parameter, ignored (did you mean ~max_linear_velocity?)",
         "~max_samples: refused 1e+12 (must be a whole number from -2147483648 to 2147483647, >= 2); keeping 200000" })
    EXPECT_NE(out.find(expected), std::string::npos) << expected << "\n" << out;
  EXPECT_EQ(out.find("request"), std::string::npos) << "a parameter error named as the request's\n" << out;
  EXPECT_EQ(out.find("max_waypoints"), std::string::npos) << "3e4 is the int 30000\n" << out;

  if (up)
  {
    // The defaults are in force: a request leaving curve empty succeeds with interpolating.
    ros::NodeHandle nh;
    Latest<se3_interpolation::GenerationStatus> status(nh, "/refused_node/status");
    auto srv = segment(1.0, ros::Time::now());
    srv.request.curve.clear();
    ASSERT_TRUE(node_test::callService("/refused_node/generate", srv));
    EXPECT_TRUE(srv.response.success) << srv.response.message;
    EXPECT_EQ(srv.response.path.poses.size(), 100U);
    EXPECT_EQ(srv.response.trajectory.joint_names.at(0), "interpolated");
    EXPECT_TRUE(spinUntil([&] { return status.count() > 0; }, 10.0));
    EXPECT_EQ(status.msg().curve, "interpolating");
    EXPECT_EQ(status.msg().geometry, "double_geodesic");
    EXPECT_EQ(status.msg().timing, "stretch");
    // dynamic_reconfigure wrote the kept values back to the parameter server.
    std::string curve;
    EXPECT_TRUE(nh.getParam("/refused_node/curve", curve));
    EXPECT_EQ(curve, "interpolating");
  }
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(up) << out;
}

// waypoint_frames: taught frames from static_transform_publisher, after waypoints.poses.
TEST(NodeStack, WaypointFramesAreLookedUpWithTf2)
{
  waitForNodes();
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.poses = { pose(Eigen::Vector3d(0, 0, 0), Eigen::Quaterniond::Identity()) };
  srv.request.waypoint_frames = { "taught_1", "taught_2" };
  srv.request.curve = "piecewise_geodesic";
  srv.request.times = { 0.0, 1.0, 2.0 };
  srv.request.sample_times = { 0.0, 1.0, 2.0 };
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  ASSERT_EQ(srv.response.path.poses.size(), 3U);
  // static_transform_publisher args of node_stack.test.
  Eigen::Isometry3d taught_1, taught_2;
  tf2::fromMsg(srv.response.path.poses[1].pose, taught_1);
  tf2::fromMsg(srv.response.path.poses[2].pose, taught_2);
  EXPECT_LT((taught_1.translation() - Eigen::Vector3d(1.0, 0.0, 0.5)).norm(), 1e-12);
  EXPECT_LT(Eigen::Quaterniond(taught_1.rotation()).angularDistance(Eigen::Quaterniond::Identity()), 1e-9);
  EXPECT_LT((taught_2.translation() - Eigen::Vector3d(2.0, 1.0, 0.0)).norm(), 1e-12);
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  EXPECT_LT(Eigen::Quaterniond(taught_2.rotation()).angularDistance(q2), 1e-6);

  // Frames alone are enough (the buffer is not used).
  se3_interpolation::GenerateTrajectory frames_only;
  frames_only.request.waypoint_frames = { "taught_2", "taught_1" };
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", frames_only));
  ASSERT_TRUE(frames_only.response.success) << frames_only.response.message;
  EXPECT_NEAR(frames_only.response.path.poses.front().pose.position.x, 2.0, 1e-12);
  EXPECT_NEAR(frames_only.response.path.poses.back().pose.position.x, 1.0, 1e-12);

  // An unknown frame is named; an unbounded one is refused without being echoed.
  se3_interpolation::GenerateTrajectory unknown;
  unknown.request.waypoint_frames = { "taught_1", "nowhere" };
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", unknown));
  EXPECT_FALSE(unknown.response.success);
  EXPECT_EQ(unknown.response.message.rfind("waypoint_frames[1]: no transform from 'nowhere' to 'map'", 0), 0U)
      << unknown.response.message;
  se3_interpolation::GenerateTrajectory huge;
  huge.request.waypoint_frames = { "taught_1", std::string(100000, 'f') };
  ASSERT_TRUE(node_test::callService(kArm1 + "/generate", huge));
  EXPECT_FALSE(huge.response.success);
  EXPECT_EQ(huge.response.message.rfind("waypoint_frames[1]: ", 0), 0U) << huge.response.message.substr(0, 200);
  EXPECT_LT(huge.response.message.size(), 400U);
}

// A lookup waiting for a frame (/slow waits up to 3 s) blocks neither another request nor the
// moving frame's broadcasts: both happen while the waiting call is still outstanding.
TEST(NodeStack, WaitingLookupBlocksNeitherRequestsNorTf)
{
  waitForNodes();
  ros::NodeHandle nh;
  auto first = segment(10.0, ros::Time::now());
  ASSERT_TRUE(node_test::callService(kSlow + "/generate", first));
  ASSERT_TRUE(first.response.success) << first.response.message;
  int broadcasts = 0;
  ros::Subscriber tf_sub = nh.subscribe<tf2_msgs::TFMessage>("/tf", 100, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
    for (const auto& t : m->transforms)
      broadcasts += t.child_frame_id == "slow_tool";
  });
  ASSERT_TRUE(spinUntil([&] { return broadcasts > 0; }, 10.0));

  std::future<se3_interpolation::GenerateTrajectory> waiting = std::async(std::launch::async, [] {
    se3_interpolation::GenerateTrajectory w;
    w.request.waypoint_frames = { "taught_1", "appears_never" };
    node_test::callService(kSlow + "/generate", w);
    return w;
  });
  spinFor(0.3);  // the waiting call is inside its tf2 wait now
  auto other = segment(1.0, ros::Time::now());
  other.request.publish = false;
  ASSERT_TRUE(node_test::callService(kSlow + "/generate", other));
  EXPECT_TRUE(other.response.success) << other.response.message;
  const int before = broadcasts;
  spinFor(0.5);
  EXPECT_GT(broadcasts, before);
  EXPECT_EQ(waiting.wait_for(std::chrono::seconds(0)), std::future_status::timeout)
      << "the lookup did not wait (tf_timeout 3 s)";
  const se3_interpolation::GenerateTrajectory w = waiting.get();
  EXPECT_FALSE(w.response.success);
  EXPECT_NE(w.response.message.find("'appears_never'"), std::string::npos) << w.response.message;
}

// Two namespaced instances do not collide on /tf; a third publisher of arm1's frame is warned,
// naming it (connection header callerid), and only by arm1. Last: it disturbs arm1_tool.
TEST(NodeStack, TfCollisionIsWarnedNamingThePublisher)
{
  waitForNodes();
  ros::NodeHandle nh;
  Warnings warnings(nh);
  ASSERT_TRUE(spinUntil([&] { return warnings.subscriber().getNumPublishers() >= 3; }, 10.0));
  for (const auto& n : { kArm1, kArm2 })
  {
    auto srv = segment(5.0, ros::Time::now());
    ASSERT_TRUE(node_test::callService(n + "/generate", srv));
  }
  spinFor(1.0);
  EXPECT_FALSE(warnings.has(kArm1, { "TF collision" }));
  EXPECT_FALSE(warnings.has(kArm2, { "TF collision" }));

  ros::Publisher tf_pub = nh.advertise<tf2_msgs::TFMessage>("/tf", 10);
  tf2_msgs::TFMessage m;
  geometry_msgs::TransformStamped t;
  t.header.frame_id = "map";
  t.child_frame_id = "arm1_tool";
  t.transform.rotation.w = 1.0;
  m.transforms.push_back(t);
  const std::string me = "'" + ros::this_node::getName() + "'";
  const bool warned = spinUntil(
      [&] {
        m.transforms[0].header.stamp = ros::Time::now();
        tf_pub.publish(m);
        return warnings.has(kArm1, { "TF collision", me, "'arm1_tool'" });
      },
      20.0);
  EXPECT_TRUE(warned);
  EXPECT_FALSE(warnings.has(kArm2, { "TF collision" }));
}

// The nodelet: the same class under a nodelet manager answers the service, broadcasts its frame
// and serves dynamic_reconfigure.
TEST(NodeletStack, AnswersTheServiceBroadcastsAndReconfigures)
{
  ASSERT_TRUE(ros::service::waitForService(kNodelet + "/generate", ros::Duration(30.0)));
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  auto srv = segment(0.5, ros::Time::now());
  ASSERT_TRUE(node_test::callService(kNodelet + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_EQ(srv.response.trajectory.joint_names.at(0), "arm3_tool");
  ASSERT_TRUE(spinUntil([&] { return ros::Time::now() > srv.request.waypoints.header.stamp + ros::Duration(1.0); }, 10.0));
  EXPECT_LT(distance(lookUp(buffer, "arm3_tool", ros::Time::now() - ros::Duration(0.1)), segmentAt(1.0)), 1e-6);
  dynamic_reconfigure::Config c = reconfigure(kNodelet, { { "timing", "time_optimal" } }, {}, {});
  EXPECT_EQ(strOf(c, "timing"), "time_optimal");
  std_srvs::Trigger clear;
  ASSERT_TRUE(node_test::callService(kNodelet + "/clear_waypoints", clear));
  EXPECT_TRUE(clear.response.success);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_stack");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
