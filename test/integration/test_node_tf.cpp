// Integration: TF output read through a real tf2 listener (the moving frame's pose at a known
// time, its rate and monotonic stamps, the static sample frames), the waypoint topics →
// buffer → auto-generated path flow (including a PoseStamped in another frame transformed
// through tf2, and one in an unknown frame rejected), and the demo launch running headless.
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <mutex>

#include "se3_interpolation/GenerateTrajectory.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const char* const kNode = "/se3_interpolation_node";
}  // namespace

TEST(NodeTf, MovingFrameFollowsTheTrajectoryThroughTf2)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(std::string(kNode) + "/generate", ros::Duration(30.0)));
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);

  // Two poses joined by a double geodesic over 2 s: constant-rate slerp + lerp, so tf2's own
  // interpolation between broadcast stamps is exact and any lookup time can be checked.
  const Eigen::Quaterniond qa(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond qb(Eigen::AngleAxisd(1.3, Eigen::Vector3d(1, 2, 2).normalized()));
  const Eigen::Vector3d pa(0.5, -1.0, 0.2), pb(1.5, 1.0, 3.2);
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.header.stamp = ros::Time::now();
  srv.request.waypoints.poses = { pose(pa, qa), pose(pb, qb) };
  srv.request.times = { 0.0, 2.0 };
  srv.request.curve = "piecewise_geodesic";
  srv.request.publish = true;
  ASSERT_TRUE(node_test::callService(std::string(kNode) + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const ros::Time stamp = srv.request.waypoints.header.stamp;

  // Count the moving frame's messages and check their stamps increase strictly.
  std::vector<ros::Time> stamps;
  ros::Subscriber tf_sub = nh.subscribe<tf2_msgs::TFMessage>("/tf", 100, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
    for (const auto& t : m->transforms)
      if (t.child_frame_id == "interpolated" && t.header.stamp > stamp)
        stamps.push_back(t.header.stamp);
  });
  ros::WallDuration(0.2).sleep();
  stamps.clear();
  spinUntil([] { return false; }, 2.0);
  ASSERT_GE(stamps.size(), 60U) << "moving frame rate too low";  // 50 Hz nominal over 2 s
  EXPECT_LE(stamps.size(), 140U);
  for (std::size_t i = 1; i < stamps.size(); ++i)
    EXPECT_GT(stamps[i], stamps[i - 1]) << "TF stamps must strictly increase";

  int checked = 0;
  for (int attempt = 0; attempt < 40 && checked < 5; ++attempt)
  {
    spinUntil([] { return false; }, 0.05);
    const ros::Time t = ros::Time::now() - ros::Duration(0.25);
    const double lambda = std::fmod((t - stamp).toSec(), 2.0) / 2.0;
    if (lambda < 0.05 || lambda > 0.95)
      continue;  // avoid the loop's wrap-around between two broadcasts
    geometry_msgs::TransformStamped tr;
    try
    {
      tr = buffer.lookupTransform("map", "interpolated", t, ros::Duration(1.0));
    }
    catch (const tf2::TransformException& e)
    {
      ADD_FAILURE() << e.what();
      continue;
    }
    const Eigen::Isometry3d got = tf2::transformToEigen(tr);
    const Eigen::Quaterniond q_expected = qa.slerp(lambda, qb);
    const Eigen::Vector3d p_expected = (1 - lambda) * pa + lambda * pb;
    EXPECT_LT((got.translation() - p_expected).norm(), 1e-6) << "lambda " << lambda;
    EXPECT_LT(Eigen::Quaterniond(got.rotation()).angularDistance(q_expected), 1e-6) << "lambda " << lambda;
    ++checked;
  }
  EXPECT_GE(checked, 5);

  // Static frames: the first and last of the 20 evenly spaced samples are the waypoints.
  const auto first = buffer.lookupTransform("map", "interpolated_0", ros::Time(0), ros::Duration(2.0));
  const auto last = buffer.lookupTransform("map", "interpolated_19", ros::Time(0), ros::Duration(2.0));
  const auto mid = buffer.lookupTransform("map", "interpolated_10", ros::Time(0), ros::Duration(2.0));
  EXPECT_LT((tf2::transformToEigen(first).translation() - pa).norm(), 1e-12);
  EXPECT_LT((tf2::transformToEigen(last).translation() - pb).norm(), 1e-12);
  EXPECT_LT((tf2::transformToEigen(mid).translation() - ((1 - 10.0 / 19) * pa + 10.0 / 19 * pb)).norm(), 1e-12);
  EXPECT_FALSE(buffer.canTransform("map", "interpolated_20", ros::Time(0)));
}

TEST(NodeTf, WaypointTopicsFeedTheBufferAndAutoGenerate)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(std::string(kNode) + "/clear_waypoints", ros::Duration(30.0)));
  tf2_ros::StaticTransformBroadcaster static_broadcaster;
  geometry_msgs::TransformStamped offset;
  offset.header.frame_id = "map";
  offset.header.stamp = ros::Time::now();
  offset.child_frame_id = "offset_frame";
  offset.transform.translation.x = 10.0;
  offset.transform.rotation.w = 1.0;
  static_broadcaster.sendTransform(offset);

  Latest<nav_msgs::Path> path(nh, std::string(kNode) + "/path");
  ros::Publisher array_pub = nh.advertise<geometry_msgs::PoseArray>(std::string(kNode) + "/waypoints", 1, true);
  ros::Publisher pose_pub = nh.advertise<geometry_msgs::PoseStamped>(std::string(kNode) + "/waypoint", 10);
  std_srvs::Trigger clear;
  ASSERT_TRUE(node_test::callService(std::string(kNode) + "/clear_waypoints", clear));
  ASSERT_TRUE(clear.response.success);

  geometry_msgs::PoseArray array;
  array.header.frame_id = "map";
  array.poses = { pose(Eigen::Vector3d(0, 0, 0), Eigen::Quaterniond::Identity()),
                  pose(Eigen::Vector3d(1, 0, 0), Eigen::Quaterniond::Identity()) };
  ASSERT_TRUE(spinUntil([&] { return array_pub.getNumSubscribers() > 0 && pose_pub.getNumSubscribers() > 0; }, 10.0));
  const int before = path.count();
  array_pub.publish(array);
  ASSERT_TRUE(spinUntil([&] {
    // To rounding: auto-generation starts from the current motion (~replan_from_current), so the
    // waypoint times are no longer the exact 0 and 1 s.
    return path.count() > before && !path.msg().poses.empty() &&
           std::abs(path.msg().poses.back().pose.position.x - 1.0) < 1e-12;
  }, 10.0));

  // A PoseStamped in offset_frame is transformed into map before buffering.
  geometry_msgs::PoseStamped p;
  p.header.frame_id = "offset_frame";
  p.pose = pose(Eigen::Vector3d(1, 2, 0), Eigen::Quaterniond::Identity());
  const int before_offset = path.count();
  pose_pub.publish(p);
  ASSERT_TRUE(spinUntil([&] { return path.count() > before_offset; }, 10.0));
  const auto& end = path.msg().poses.back().pose.position;
  EXPECT_NEAR(end.x, 11.0, 1e-12);
  EXPECT_NEAR(end.y, 2.0, 1e-12);
  EXPECT_EQ(path.msg().header.frame_id, "map");

  // One in an unknown frame is rejected: the buffer (and so the generated path) is unchanged.
  geometry_msgs::PoseStamped lost = p;
  lost.header.frame_id = "nowhere";
  pose_pub.publish(lost);
  // A non-finite one is rejected too.
  geometry_msgs::PoseStamped bad = p;
  bad.header.frame_id = "map";
  bad.pose.position.z = std::numeric_limits<double>::infinity();
  pose_pub.publish(bad);
  spinUntil([] { return false; }, 1.0);
  se3_interpolation::GenerateTrajectory srv;  // empty waypoints: use the buffer
  ASSERT_TRUE(node_test::callService(std::string(kNode) + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_NEAR(srv.response.path.poses.back().pose.position.x, 11.0, 1e-12);
  EXPECT_EQ(srv.response.path.header.frame_id, "map");
}

TEST(DemoHeadless, DemoPublishesItsTrajectory)
{
  ros::NodeHandle nh;
  Latest<nav_msgs::Path> path(nh, std::string(kNode) + "/path");
  ASSERT_TRUE(spinUntil([&] { return path.count() > 0; }, 60.0)) << "the demo published no path";
  EXPECT_EQ(path.msg().poses.size(), 200U);
  EXPECT_EQ(path.msg().header.frame_id, "map");
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  EXPECT_TRUE(buffer.canTransform("map", "interpolated", ros::Time(0), ros::Duration(5.0)));
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_tf");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
