// Integration: curve fit through se3_interpolation_node. Auto-generation with ~curve fit fits the
// poses streamed on ~waypoint at their stamps (a recording, replayed at its pace); the
// service returns the fitted B-spline (control_poses, knots) and residuals, which replayed as a
// bspline request give the same motion; a fit without times is refused naming `times` and the node
// keeps serving.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <trajectory_msgs/MultiDOFJointTrajectory.h>

#include <cmath>
#include <mutex>
#include <random>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/GenerationStatus.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const char* const kService = "/se3_interpolation_node/generate";

/// 3 s of a slow arc at 20 Hz, 1 mm of noise per axis.
std::vector<geometry_msgs::Pose> noisyArc(std::size_t count, std::vector<double>* times)
{
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::vector<geometry_msgs::Pose> poses;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double t = 0.05 * static_cast<double>(i);
    poses.push_back(pose(std::cos(0.3 * t) + noise(rng), std::sin(0.3 * t) + noise(rng), 0.2 + noise(rng), 0.3 * t));
    times->push_back(t);
  }
  return poses;
}

class StatusLog
{
public:
  explicit StatusLog(ros::NodeHandle& nh)
    : sub_(nh.subscribe("/se3_interpolation_node/status", 100, &StatusLog::callback, this))
  {
  }
  /// The first status with `count` waypoints that succeeded, waiting up to 20 s.
  bool successWith(std::uint32_t count, se3_interpolation::GenerationStatus* out)
  {
    return waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& s : log_)
            if (s.success && s.waypoint_count == count && s.source == "auto_generation")
            {
              *out = s;
              return true;
            }
          return false;
        },
        20.0);
  }

private:
  void callback(const se3_interpolation::GenerationStatus& m)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    log_.push_back(m);
  }
  std::mutex mutex_;
  std::vector<se3_interpolation::GenerationStatus> log_;
  /// Last: constructed after and destroyed before what its callback uses (the spinner thread may
  /// run the callback as soon as it subscribes: at once for a latched message).
  ros::Subscriber sub_;
};

trajectory_msgs::MultiDOFJointTrajectory g_trajectory;
std::mutex g_trajectory_mutex;
void onTrajectory(const trajectory_msgs::MultiDOFJointTrajectory& m)
{
  std::lock_guard<std::mutex> lock(g_trajectory_mutex);
  g_trajectory = m;
}
}  // namespace

TEST(NodeFit, AutoGenerationFitsTheStampedStream)
{
  ros::NodeHandle nh;
  StatusLog log(nh);
  ros::Subscriber traj = nh.subscribe("/se3_interpolation_node/trajectory", 1, onTrajectory);
  ros::Publisher waypoint = nh.advertise<geometry_msgs::PoseStamped>("/se3_interpolation_node/waypoint", 100);
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  ASSERT_TRUE(waitFor([&] { return waypoint.getNumSubscribers() > 0; }, 30.0));
  std::vector<double> times;
  const std::vector<geometry_msgs::Pose> poses = noisyArc(61, &times);
  const ros::Time start(1000.0);
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "map";
    p.header.stamp = start + ros::Duration(times[i]);
    p.header.seq = static_cast<std::uint32_t>(i);
    p.pose = poses[i];
    waypoint.publish(p);
    ros::WallDuration(0.005).sleep();
  }
  se3_interpolation::GenerationStatus s;
  ASSERT_TRUE(log.successWith(61, &s));
  EXPECT_EQ(s.curve, "fit");
  EXPECT_GT(s.residual_linear, 0.0005);  // the noise (1 mm per axis: about 1.7 mm RMS)
  EXPECT_LT(s.residual_linear, 0.004);
  EXPECT_NEAR(s.duration, 3.0, 1e-9);    // the recording's span
  // The recording is replayed at its own pace from its first pose (~replan_from_current, on by
  // default, does not apply to a recording): the trajectory spans the stamps' 3 s.
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(g_trajectory_mutex);
        return g_trajectory.points.size() > 1 && g_trajectory.points.front().time_from_start.toSec() == 0.0 &&
               std::abs(g_trajectory.points.back().time_from_start.toSec() - 3.0) < 1e-6;
      },
      10.0));
}

TEST(NodeFit, TheServiceReturnsTheFittedBSplineWhichReplaysIt)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  se3_interpolation::GenerateTrajectory fit;
  fit.request.waypoints.header.frame_id = "map";
  fit.request.waypoints.header.stamp = ros::Time(50.0);
  fit.request.waypoints.poses = noisyArc(41, &fit.request.times);
  fit.request.curve = "fit";
  fit.request.control_period = 0.4;
  fit.request.smoothing = 1e-6;
  fit.request.sample_count = 31;
  ASSERT_TRUE(node_test::callService(kService, fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  EXPECT_NE(fit.response.message.find("fitted 8 control poses to 41 waypoints"), std::string::npos)
      << fit.response.message;
  ASSERT_EQ(fit.response.knots.size(), 8u + 3u + 1u);  // ⌈2 / 0.4⌉ = 5 intervals, degree 3
  ASSERT_EQ(fit.response.control_poses.poses.size(), 8u);
  EXPECT_EQ(fit.response.control_poses.header.frame_id, "map");
  EXPECT_EQ(fit.response.control_poses.header.stamp, ros::Time(50.0));
  EXPECT_GT(fit.response.residual_angular, 0.0);

  se3_interpolation::GenerateTrajectory replay;
  replay.request.waypoints = fit.response.control_poses;
  replay.request.curve = "bspline";
  replay.request.degree = 3;
  replay.request.knots = fit.response.knots;
  replay.request.sample_count = 31;
  ASSERT_TRUE(node_test::callService(kService, replay));
  ASSERT_TRUE(replay.response.success) << replay.response.message;
  ASSERT_EQ(replay.response.trajectory.points.size(), fit.response.trajectory.points.size());
  for (std::size_t i = 0; i < fit.response.trajectory.points.size(); ++i)
  {
    const auto& a = fit.response.trajectory.points[i].transforms[0];
    const auto& b = replay.response.trajectory.points[i].transforms[0];
    EXPECT_NEAR(a.translation.x, b.translation.x, 1e-12) << i;
    EXPECT_NEAR(a.translation.y, b.translation.y, 1e-12) << i;
    EXPECT_NEAR(std::abs(a.rotation.w * b.rotation.w + a.rotation.x * b.rotation.x + a.rotation.y * b.rotation.y +
                         a.rotation.z * b.rotation.z),
                1.0, 1e-12)
        << i;
  }
  EXPECT_TRUE(replay.response.knots.empty());  // a bspline request is no fit
}

TEST(NodeFit, BadFitsAreRefusedNamingTheFieldAndTheNodeKeepsServing)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  std::vector<double> times;
  srv.request.waypoints.poses = noisyArc(21, &times);
  srv.request.curve = "fit";
  ASSERT_TRUE(node_test::callService(kService, srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_EQ(srv.response.message.rfind("times: curve 'fit' needs the waypoints' times", 0), 0u) << srv.response.message;
  srv.request.times = times;
  srv.request.loss = "cauchy";
  ASSERT_TRUE(node_test::callService(kService, srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_EQ(srv.response.message.rfind("loss: unknown value 'cauchy'", 0), 0u) << srv.response.message;
  srv.request.loss = "";
  srv.request.control_period = 0.001;  // more control poses than waypoints
  ASSERT_TRUE(node_test::callService(kService, srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_EQ(srv.response.message.rfind("control_period:", 0), 0u) << srv.response.message;
  // For another curve the fit's fields are refused, not ignored.
  srv.request.curve = "interpolating";
  srv.request.control_period = 0.0;
  srv.request.smoothing = 1.0;
  ASSERT_TRUE(node_test::callService(kService, srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_EQ(srv.response.message.rfind("smoothing: only used by curve 'fit'", 0), 0u) << srv.response.message;
  srv.request.smoothing = 0.0;
  ASSERT_TRUE(node_test::callService(kService, srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_fit");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
