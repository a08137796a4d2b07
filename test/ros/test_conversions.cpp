// ROS conversions (ros/conversions.h), without a roscore: round trips, the quaternion's (x, y, z, w)
// order, the twist's (linear, angular) order, stamps and time_from_start of the samples, each
// against values written here.
#include <gtest/gtest.h>

#include <cmath>

#include "se3_interpolation/ros/conversions.h"

using namespace se3_interpolation;

namespace
{
Pose<double> samplePose()
{
  // A rotation of 0.3 rad about (1, 2, 2)/3 at (1, -2, 0.5).
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
  return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.3, axis)), Eigen::Vector3d(1.0, -2.0, 0.5));
}
}  // namespace

TEST(Conversions, PoseFieldsAndRoundTrip)
{
  const Pose<double> x = samplePose();
  const geometry_msgs::Pose msg = toMsg(x);
  EXPECT_EQ(msg.position.x, 1.0);
  EXPECT_EQ(msg.position.y, -2.0);
  EXPECT_EQ(msg.position.z, 0.5);
  // (x, y, z, w) = (sin(θ/2) axis, cos(θ/2)).
  EXPECT_NEAR(msg.orientation.w, std::cos(0.15), 1e-15);
  EXPECT_NEAR(msg.orientation.x, std::sin(0.15) / 3.0, 1e-15);
  EXPECT_NEAR(msg.orientation.y, 2.0 * std::sin(0.15) / 3.0, 1e-15);
  EXPECT_NEAR(msg.orientation.z, 2.0 * std::sin(0.15) / 3.0, 1e-15);
  const Pose<double> back = fromMsg(msg);
  EXPECT_EQ(back.p, x.p);
  EXPECT_EQ(back.q.coeffs(), x.q.coeffs());

  geometry_msgs::Transform t;
  toMsg(x, t);
  EXPECT_EQ(t.translation.y, -2.0);
  EXPECT_EQ(t.rotation.w, msg.orientation.w);
  EXPECT_EQ(t.rotation.z, msg.orientation.z);
}

TEST(Conversions, TwistOrderIsLinearThenAngular)
{
  Twist v;
  v.linear = Eigen::Vector3d(1.0, 2.0, 3.0);
  v.angular = Eigen::Vector3d(-4.0, -5.0, -6.0);
  const geometry_msgs::Twist msg = toMsg(v);
  EXPECT_EQ(msg.linear.x, 1.0);
  EXPECT_EQ(msg.linear.z, 3.0);
  EXPECT_EQ(msg.angular.x, -4.0);
  EXPECT_EQ(msg.angular.z, -6.0);
  const Twist back = fromMsg(msg);
  EXPECT_EQ(back.linear, v.linear);
  EXPECT_EQ(back.angular, v.angular);
}

TEST(Conversions, RequestFieldsAreCopied)
{
  GenerateTrajectory::Request msg;
  msg.curve = "bspline";
  msg.geometry = "screw";
  msg.degree = 4;
  msg.times = { 0.0, 1.5 };
  msg.start_velocity.angular.z = 0.25;
  msg.velocities.resize(2);
  msg.velocities[1].linear.x = 2.0;
  msg.sample_count = 7;
  msg.blend_radius = 0.1;
  const std::vector<geometry_msgs::Pose> poses = { toMsg(samplePose()), toMsg(samplePose()) };
  const TrajectoryRequest r = fromMsg(msg, poses);
  ASSERT_EQ(r.waypoints.size(), 2u);
  EXPECT_EQ(r.waypoints[1].p, samplePose().p);
  EXPECT_EQ(r.curve, "bspline");
  EXPECT_EQ(r.geometry, "screw");
  EXPECT_EQ(r.degree, 4);
  EXPECT_EQ(r.times, msg.times);
  EXPECT_EQ(r.start_velocity.angular.z(), 0.25);
  ASSERT_EQ(r.velocities.size(), 2u);
  EXPECT_EQ(r.velocities[1].linear.x(), 2.0);
  EXPECT_EQ(r.sample_count, 7u);
  EXPECT_EQ(r.blend_radius, 0.1);
}

TEST(Conversions, SamplesAreStampedAndTimedFromTheHeader)
{
  TrajectoryResult result;
  for (double t : { 0.0, 0.25, 2.0 })
  {
    TrajectorySample s;
    s.time = t;
    s.pose = samplePose();
    s.pose.p.x() += t;
    s.velocity.linear.x() = 1.0;
    s.acceleration.angular.y() = t;
    result.samples.push_back(s);
  }
  std_msgs::Header header;
  header.frame_id = "map";
  header.stamp = ros::Time(100, 500000000);

  nav_msgs::Path path;
  toMsg(result, header, path);
  ASSERT_EQ(path.poses.size(), 3u);
  EXPECT_EQ(path.header.frame_id, "map");
  EXPECT_EQ(path.poses[1].header.stamp, ros::Time(100, 750000000));
  EXPECT_EQ(path.poses[2].header.stamp, ros::Time(102, 500000000));
  EXPECT_EQ(path.poses[2].pose.position.x, 3.0);

  trajectory_msgs::MultiDOFJointTrajectory traj;
  toMsg(result, header, "body", traj);
  ASSERT_EQ(traj.points.size(), 3u);
  ASSERT_EQ(traj.joint_names.size(), 1u);
  EXPECT_EQ(traj.joint_names[0], "body");
  EXPECT_EQ(traj.points[1].time_from_start, ros::Duration(0, 250000000));
  ASSERT_EQ(traj.points[2].transforms.size(), 1u);
  EXPECT_EQ(traj.points[2].transforms[0].translation.x, 3.0);
  EXPECT_EQ(traj.points[2].velocities[0].linear.x, 1.0);
  EXPECT_EQ(traj.points[2].accelerations[0].angular.y, 2.0);
  // Converting into a used message replaces its content.
  toMsg(result, header, "body", traj);
  EXPECT_EQ(traj.points.size(), 3u);
  EXPECT_EQ(traj.points[0].transforms.size(), 1u);
}
