// Integration: replanning from the current motion through the real node (docs/timing.md).
// A second request with from_current starts at the switch time T_s (its response's stamp) in the
// state the first trajectory has there: compared with the first trajectory evaluated at T_s by the
// node itself (the same request again, sampled at T_s), and on /tf, where no step between two
// messages may exceed what the trajectories' peak speeds allow in the time between them.
#include <geometry_msgs/PoseArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <trajectory_msgs/MultiDOFJointTrajectory.h>

#include <Eigen/Geometry>
#include <functional>
#include <mutex>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const std::string kNode = "/se3_interpolation_node";
constexpr double kSwitchTolerance = 1e-9;  // the C2 switch tolerance of docs/timing.md
constexpr double kLead = 0.2;              // ~replan_lead in node_replan.test

/// The moving frame's messages on /tf.
struct TfRecord
{
  struct Entry
  {
    ros::Time stamp;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
  };
  explicit TfRecord(ros::NodeHandle& nh)
    : sub(nh.subscribe<tf2_msgs::TFMessage>("/tf", 1000, [this](const tf2_msgs::TFMessage::ConstPtr& m) {
      for (const auto& t : m->transforms)
        if (t.child_frame_id == "interpolated")
        {
          const Eigen::Isometry3d x = tf2::transformToEigen(t);
          entries.push_back({ t.header.stamp, x.translation(), Eigen::Quaterniond(x.rotation()) });
        }
    }))
  {
  }
  ros::Subscriber sub;
  std::vector<Entry> entries;
};

se3_interpolation::GenerateTrajectory firstMotion(const std::string& timing)
{
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.header.stamp = ros::Time::now();
  srv.request.waypoints.poses = { pose({ 0.0, 0.0, 0.0 }, Eigen::Quaterniond::Identity()),
                                  pose({ 1.0, 0.5, 0.0 }, Eigen::Quaterniond(Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()))),
                                  pose({ 2.0, 0.0, 0.5 }, Eigen::Quaterniond(Eigen::AngleAxisd(1.5, Eigen::Vector3d(1, 1, 0).normalized()))) };
  srv.request.times = { 0.0, 1.5, 3.0 };
  srv.request.timing = timing;
  if (timing == "time_optimal")
  {
    srv.request.times.clear();
    srv.request.max_linear_velocity = 1.0;
    srv.request.max_angular_velocity = 1.0;
    srv.request.max_linear_acceleration = 1.0;
    srv.request.max_angular_acceleration = 1.0;
  }
  srv.request.publish = true;
  return srv;
}

std::vector<geometry_msgs::Pose> newWaypoints()
{
  return { pose({ 1.5, 1.5, 0.2 }, Eigen::Quaterniond(Eigen::AngleAxisd(-0.5, Eigen::Vector3d::UnitY()))),
           pose({ 0.0, 2.0, 0.0 }, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))) };
}

void expectSameState(const trajectory_msgs::MultiDOFJointTrajectoryPoint& a,
                     const trajectory_msgs::MultiDOFJointTrajectoryPoint& b, double tolerance)
{
  const Eigen::Isometry3d xa = tf2::transformToEigen(a.transforms[0]), xb = tf2::transformToEigen(b.transforms[0]);
  EXPECT_LT((xa.translation() - xb.translation()).norm(), tolerance);
  EXPECT_LT(Eigen::Quaterniond(xa.rotation()).angularDistance(Eigen::Quaterniond(xb.rotation())), tolerance);
  auto v = [](const geometry_msgs::Vector3& m) { return Eigen::Vector3d(m.x, m.y, m.z); };
  EXPECT_LT((v(a.velocities[0].linear) - v(b.velocities[0].linear)).norm(), tolerance);
  EXPECT_LT((v(a.velocities[0].angular) - v(b.velocities[0].angular)).norm(), tolerance);
  EXPECT_LT((v(a.accelerations[0].linear) - v(b.accelerations[0].linear)).norm(), tolerance);
  EXPECT_LT((v(a.accelerations[0].angular) - v(b.accelerations[0].angular)).norm(), tolerance);
}

/// Replans `first` at `after` s with from_current and checks the switch (responses and /tf).
void replanMidMotion(se3_interpolation::GenerateTrajectory first, double after, const std::string& timing)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(30.0)));
  TfRecord tf(nh);
  spinFor(0.3);
  ASSERT_TRUE(node_test::callService(kNode + "/generate", first));
  ASSERT_TRUE(first.response.success) << first.response.message;
  // (The frame jumps to the first motion's start: that motion does not start from the current one.)
  spinFor(0.1);
  tf.entries.clear();
  spinFor(after - 0.1);

  se3_interpolation::GenerateTrajectory second;
  second.request.waypoints.header.frame_id = "map";
  second.request.waypoints.poses = newWaypoints();
  second.request.from_current = true;
  second.request.timing = timing;
  second.request.max_linear_velocity = first.request.max_linear_velocity;
  second.request.max_angular_velocity = first.request.max_angular_velocity;
  second.request.max_linear_acceleration = first.request.max_linear_acceleration;
  second.request.max_angular_acceleration = first.request.max_angular_acceleration;
  second.request.publish = true;
  const ros::Time called = ros::Time::now();
  ASSERT_TRUE(node_test::callService(kNode + "/generate", second));
  ASSERT_TRUE(second.response.success) << second.response.message;
  const ros::Time switch_time = second.response.trajectory.header.stamp;
  EXPECT_EQ(second.response.path.header.stamp, switch_time);
  EXPECT_GE((switch_time - called).toSec(), kLead);
  EXPECT_LT((switch_time - called).toSec(), kLead + 1.0);
  const double t_switch = (switch_time - first.request.waypoints.header.stamp).toSec();
  ASSERT_GT(t_switch, 0.0);
  ASSERT_LT(t_switch, first.response.duration) << "the switch must fall inside the first motion";

  // The first trajectory at T_s, evaluated by the node: the same request sampled there.
  se3_interpolation::GenerateTrajectory reference = first;
  reference.request.publish = false;
  reference.request.sample_times = { t_switch };
  reference.request.sample_count = 0;
  ASSERT_TRUE(node_test::callService(kNode + "/generate", reference));
  ASSERT_TRUE(reference.response.success) << reference.response.message;
  ASSERT_EQ(reference.response.trajectory.points.size(), 1u);
  const auto& start = second.response.trajectory.points.front();
  EXPECT_EQ(start.time_from_start.toSec(), 0.0);
  expectSameState(start, reference.response.trajectory.points.front(), kSwitchTolerance);
  // It moves at the switch (a mid-motion replan, not a start at rest).
  EXPECT_GT(std::hypot(start.velocities[0].linear.x, start.velocities[0].linear.y), 0.05);

  // /tf across the switch: no step larger than the peak speeds allow between two messages.
  spinFor(kLead + 1.0);
  const double v_max = std::max(first.response.max_linear_speed, second.response.max_linear_speed);
  const double w_max = std::max(first.response.max_angular_speed, second.response.max_angular_speed);
  int around_switch = 0;
  for (std::size_t i = 1; i < tf.entries.size(); ++i)
  {
    const auto& a = tf.entries[i - 1];
    const auto& b = tf.entries[i];
    const double dt = (b.stamp - a.stamp).toSec();
    EXPECT_LE((b.p - a.p).norm(), v_max * dt * 1.01 + 1e-9) << "TF step at " << (b.stamp - switch_time).toSec()
                                                            << " s from the switch";
    EXPECT_LE(a.q.angularDistance(b.q), w_max * dt * 1.01 + 1e-9);
    if (a.stamp < switch_time && b.stamp >= switch_time)
      ++around_switch;
  }
  EXPECT_EQ(around_switch, 1) << "the TF record must span the switch";
  // After the switch the frame follows the new trajectory: at the last message, its sampled pose.
}
}  // namespace

TEST(NodeReplan, MidMotionReplanIsC2AndHasNoTfJump)
{
  replanMidMotion(firstMotion("stretch"), 0.8, "stretch");
}

TEST(NodeReplan, MidMotionReplanWithTimeOptimal)
{
  replanMidMotion(firstMotion("time_optimal"), 0.9, "time_optimal");
}

TEST(NodeReplan, IdleReplanStartsAtRestFromTheHeldPose)
{
  ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(30.0)));
  se3_interpolation::GenerateTrajectory first = firstMotion("stretch");
  first.request.times = { 0.0, 0.2, 0.4 };
  ASSERT_TRUE(node_test::callService(kNode + "/generate", first));
  ASSERT_TRUE(first.response.success) << first.response.message;
  spinFor(0.8);  // ended: the frame holds the last pose (loop false)

  se3_interpolation::GenerateTrajectory second;
  second.request.waypoints.header.frame_id = "map";
  second.request.waypoints.poses = newWaypoints();
  second.request.from_current = true;
  second.request.publish = true;
  ASSERT_TRUE(node_test::callService(kNode + "/generate", second));
  ASSERT_TRUE(second.response.success) << second.response.message;
  trajectory_msgs::MultiDOFJointTrajectoryPoint held = first.response.trajectory.points.back();
  for (auto* twist : { &held.velocities[0], &held.accelerations[0] })
    *twist = geometry_msgs::Twist();
  expectSameState(second.response.trajectory.points.front(), held, kSwitchTolerance);
  // Then through the requested waypoints: the last sample is the last one.
  const Eigen::Isometry3d end = tf2::transformToEigen(second.response.trajectory.points.back().transforms[0]);
  EXPECT_LT((end.translation() - Eigen::Vector3d(0.0, 2.0, 0.0)).norm(), 1e-9);
}

TEST(NodeReplan, NothingPlayingOnTheFrameStartsAtTheFirstWaypoint)
{
  ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(30.0)));
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.poses = newWaypoints();
  srv.request.from_current = true;
  srv.request.child_frame_id = "never_played";
  ASSERT_TRUE(node_test::callService(kNode + "/generate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const Eigen::Isometry3d x = tf2::transformToEigen(srv.response.trajectory.points.front().transforms[0]);
  EXPECT_LT((x.translation() - Eigen::Vector3d(1.5, 1.5, 0.2)).norm(), 1e-12);
}

TEST(NodeReplan, FromCurrentInAnotherFrameIsRefusedNamingTheField)
{
  ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(30.0)));
  se3_interpolation::GenerateTrajectory first = firstMotion("stretch");
  ASSERT_TRUE(node_test::callService(kNode + "/generate", first));
  ASSERT_TRUE(first.response.success);
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "odom";
  srv.request.waypoints.poses = newWaypoints();
  srv.request.from_current = true;
  ASSERT_TRUE(node_test::callService(kNode + "/generate", srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_EQ(srv.response.message.rfind("from_current", 0), 0u) << srv.response.message;
}

// Auto-generation from ~waypoints replans from the current motion (~replan_from_current default).
TEST(NodeReplan, AutoGenerationStartsFromTheCurrentMotion)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(30.0)));
  std::vector<trajectory_msgs::MultiDOFJointTrajectory> published;
  ros::Subscriber sub = nh.subscribe<trajectory_msgs::MultiDOFJointTrajectory>(
      kNode + "/trajectory", 10,
      [&](const trajectory_msgs::MultiDOFJointTrajectory::ConstPtr& m) { published.push_back(*m); });
  ros::Publisher array_pub = nh.advertise<geometry_msgs::PoseArray>(kNode + "/waypoints", 1, true);
  se3_interpolation::GenerateTrajectory first = firstMotion("stretch");
  ASSERT_TRUE(node_test::callService(kNode + "/generate", first));
  ASSERT_TRUE(first.response.success);
  spinFor(0.7);
  const std::size_t before = published.size();
  geometry_msgs::PoseArray array;
  array.header.frame_id = "map";
  array.poses = newWaypoints();
  array_pub.publish(array);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (published.size() == before && ros::WallTime::now() < deadline)
    spinFor(0.01);
  ASSERT_GT(published.size(), before);
  const trajectory_msgs::MultiDOFJointTrajectory& replanned = published.back();
  const double t_switch = (replanned.header.stamp - first.request.waypoints.header.stamp).toSec();
  ASSERT_GT(t_switch, 0.0);
  ASSERT_LT(t_switch, first.response.duration);
  se3_interpolation::GenerateTrajectory reference = first;
  reference.request.publish = false;
  reference.request.sample_times = { t_switch };
  ASSERT_TRUE(node_test::callService(kNode + "/generate", reference));
  ASSERT_TRUE(reference.response.success) << reference.response.message;
  expectSameState(replanned.points.front(), reference.response.trajectory.points.front(), kSwitchTolerance);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_replan");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
