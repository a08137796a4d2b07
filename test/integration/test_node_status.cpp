// Integration: the latched ~status topic (GenerationStatus) of se3_interpolation_node reports
// every generation: a successful and a failing service call, and a failed auto-generation
// (which the node otherwise only logs), each with its source, curve, geometry and figures.
#include <geometry_msgs/PoseArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <mutex>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/GenerationStatus.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const char* const kService = "/se3_interpolation_node/generate";
const char* const kStatus = "/se3_interpolation_node/status";

/// Collects ~status messages.
class StatusLog
{
public:
  explicit StatusLog(ros::NodeHandle& nh) : sub_(nh.subscribe(kStatus, 10, &StatusLog::callback, this)) {}

  /// The first message after `skip` received ones, waiting up to 10 s.
  bool next(std::size_t skip, se3_interpolation::GenerationStatus* out)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
    while (ros::WallTime::now() < end)
    {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (log_.size() > skip)
        {
          *out = log_[skip];
          return true;
        }
      }
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }
  std::size_t size()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return log_.size();
  }
  std::size_t publishers() const { return sub_.getNumPublishers(); }

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

bool waitForPublisher(const StatusLog& log)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
  while (log.publishers() == 0 && ros::WallTime::now() < end)
    ros::WallDuration(0.05).sleep();
  return log.publishers() > 0;
}
}  // namespace

TEST(NodeStatus, ServiceCallsAreReportedWithTheirOutcome)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  StatusLog log(nh);
  ASSERT_TRUE(waitForPublisher(log));
  ros::WallDuration(0.5).sleep();  // a latched message from an earlier generation, if any
  std::size_t seen = log.size();

  // Success, with the node's default curve (interpolating) and geometry (double_geodesic).
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.poses = { pose(0, 0, 0, 0), pose(1, 0, 0, 0.5), pose(1, 1, 0.5, 1.5), pose(0, 2, 1, 2.5) };
  srv.request.sample_count = 50;
  srv.request.duration = 4.0;
  ASSERT_TRUE(node_test::callService(kService, srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  se3_interpolation::GenerationStatus s;
  ASSERT_TRUE(log.next(seen++, &s));
  EXPECT_TRUE(s.success);
  EXPECT_EQ(s.source, "service");
  EXPECT_EQ(s.curve, "interpolating");
  EXPECT_EQ(s.geometry, "double_geodesic");
  EXPECT_EQ(s.header.frame_id, "map");
  EXPECT_EQ(s.waypoint_count, 4U);
  EXPECT_EQ(s.message, srv.response.message);
  EXPECT_NEAR(s.duration, 4.0, 1e-12);
  EXPECT_EQ(s.length, srv.response.length);
  EXPECT_EQ(s.max_angular_speed, srv.response.max_angular_speed);
  EXPECT_GT(s.length, 2.0);
  EXPECT_FALSE(s.header.stamp.isZero());

  // Failure: the error message travels on ~status too, with the request's own curve.
  srv.request.curve = "bspline";
  srv.request.geometry = "screw";
  srv.request.times = { 0.0, 1.0 };  // 2 times for 4 waypoints
  ASSERT_TRUE(node_test::callService(kService, srv));
  ASSERT_FALSE(srv.response.success);
  ASSERT_TRUE(log.next(seen++, &s));
  EXPECT_FALSE(s.success);
  EXPECT_EQ(s.source, "service");
  EXPECT_EQ(s.curve, "bspline");
  EXPECT_EQ(s.geometry, "screw");
  EXPECT_EQ(s.message, srv.response.message);
  EXPECT_NE(s.message.find("times"), std::string::npos) << s.message;
  EXPECT_EQ(s.duration, 0.0);
}

TEST(NodeStatus, AFailedAutoGenerationIsReportedAndLatched)
{
  ros::NodeHandle nh;
  ros::Publisher waypoints = nh.advertise<geometry_msgs::PoseArray>("/se3_interpolation_node/waypoints", 1, true);
  StatusLog log(nh);
  ASSERT_TRUE(waitForPublisher(log));
  ros::WallDuration(0.5).sleep();
  std::size_t seen = log.size();

  // A buffer whose two poses are half a turn apart: no unique geodesic, so generation fails.
  geometry_msgs::PoseArray a;
  a.header.frame_id = "map";
  a.poses = { pose(0, 0, 0, 0), pose(1, 0, 0, M_PI) };
  waypoints.publish(a);
  se3_interpolation::GenerationStatus s;
  ASSERT_TRUE(log.next(seen++, &s));
  EXPECT_FALSE(s.success);
  EXPECT_EQ(s.source, "auto_generation");
  EXPECT_EQ(s.curve, "interpolating");
  EXPECT_EQ(s.waypoint_count, 2U);
  EXPECT_NE(s.message.find("pi"), std::string::npos) << s.message;

  // A late subscriber still gets it (latched).
  StatusLog late(nh);
  se3_interpolation::GenerationStatus l;
  ASSERT_TRUE(late.next(0, &l));
  EXPECT_EQ(l.source, "auto_generation");
  EXPECT_FALSE(l.success);

  // Then a good buffer: the auto-generation succeeds and says so.
  a.poses = { pose(0, 0, 0, 0), pose(1, 0, 0, 1.0), pose(2, 1, 0, 2.0) };
  waypoints.publish(a);
  ASSERT_TRUE(log.next(seen++, &s));
  EXPECT_TRUE(s.success) << s.message;
  EXPECT_EQ(s.source, "auto_generation");
  EXPECT_EQ(s.waypoint_count, 3U);
  EXPECT_GT(s.duration, 0.0);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_status");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
