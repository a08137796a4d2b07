// Integration: the node with an arm (node_arm.test, docs/joint_space.md). The UR5e's joint
// trajectory in the response is checked against the arm model read from the same URDF file here:
// forward kinematics of every joint point equals the pose of the response's trajectory, and every
// joint velocity and acceleration is within the limits file. Requests the arm cannot serve are
// refused naming the field, the node keeps serving, and a node whose arm cannot be loaded refuses
// every request naming the link.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/arm/joint_limits.h"

#include "node_test_utils.h"

using namespace node_test;
using se3_interpolation::GenerateTrajectory;
namespace arm = se3_interpolation::arm;

namespace
{
const char* const kService = "/se3_interpolation_node/generate";
const char* const kBrokenService = "/broken_arm/generate";

const std::vector<std::vector<double>> kConfigurations = {
  { 0.0, -1.2, 1.5, -1.9, -1.57, 0.0 },
  { 0.4, -1.0, 1.3, -1.8, -1.4, 0.3 },
  { 0.9, -1.3, 1.7, -2.0, -1.6, -0.2 },
};

std::shared_ptr<arm::ArmModel> ur5e()
{
  const std::string robots = std::string(SE3_SOURCE_DIR) + "/config/robots/";
  auto model = std::make_shared<arm::ArmModel>(arm::ArmModel::fromUrdfFile(robots + "ur5e.urdf", "base_link", "tool0"));
  model->applyLimits(arm::readJointLimitsFile(robots + "ur5e_joint_limits.yaml"));
  return model;
}

/// Waypoints at the UR5e's forward kinematics of kConfigurations, seeded by the first.
GenerateTrajectory request(const arm::ArmModel& model)
{
  GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "base_link";
  for (const std::vector<double>& q : kConfigurations)
  {
    const Eigen::Isometry3d t = model.base_T_tip(Eigen::Map<const Eigen::VectorXd>(q.data(), 6));
    srv.request.waypoints.poses.push_back(pose(t.translation(), Eigen::Quaterniond(t.linear())));
  }
  srv.request.joint_seed = kConfigurations.front();
  srv.request.timing = "time_optimal";
  srv.request.max_linear_velocity = 0.5;
  srv.request.max_angular_velocity = 1.0;
  srv.request.max_linear_acceleration = 2.0;
  srv.request.max_angular_acceleration = 4.0;
  srv.request.sample_count = 301;
  return srv;
}

void expectRefused(GenerateTrajectory srv, const std::string& service, const std::string& text)
{
  ASSERT_TRUE(callService(service, srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find(text), std::string::npos) << srv.response.message;
}
}  // namespace

TEST(NodeArm, TheJointTrajectoryFollowsThePosesWithinTheLimits)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  const auto model = ur5e();
  GenerateTrajectory srv = request(*model);
  ASSERT_TRUE(callService(kService, srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const auto& joints = srv.response.joint_trajectory;
  EXPECT_EQ(joints.joint_names, model->jointNames());
  ASSERT_EQ(joints.points.size(), srv.response.trajectory.points.size());
  ASSERT_EQ(joints.points.size(), 301u);
  for (std::size_t i = 0; i < joints.points.size(); ++i)
  {
    const auto& point = joints.points[i];
    ASSERT_EQ(point.positions.size(), 6u);
    EXPECT_EQ(point.time_from_start, srv.response.trajectory.points[i].time_from_start);
    const Eigen::Isometry3d fk = model->base_T_tip(Eigen::Map<const Eigen::VectorXd>(point.positions.data(), 6));
    const Eigen::Isometry3d pose = tf2::transformToEigen(srv.response.trajectory.points[i].transforms[0]);
    EXPECT_LT((fk.translation() - pose.translation()).norm(), 1e-9) << i;
    EXPECT_LT(Eigen::AngleAxisd(fk.linear().transpose() * pose.linear()).angle(), 1e-9) << i;
    for (std::size_t k = 0; k < 6; ++k)
    {
      const arm::JointLimits& l = model->joints()[k].limits;
      EXPECT_LE(std::abs(point.velocities[k]), l.max_velocity * (1.0 + 1e-6)) << i << " " << k;
      EXPECT_LE(std::abs(point.accelerations[k]), l.max_acceleration * (1.0 + 1e-6)) << i << " " << k;
    }
  }
  EXPECT_EQ(srv.response.joint_max_velocity.size(), 6u);
  EXPECT_FALSE(srv.response.joint_binding.empty());
  EXPECT_GT(srv.response.joint_binding_ratio, 0.0);
}

TEST(NodeArm, OnlyTheJointTrajectoryWhenAsked)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  GenerateTrajectory srv = request(*ur5e());
  srv.request.outputs = { "joint_trajectory" };
  ASSERT_TRUE(callService(kService, srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_TRUE(srv.response.trajectory.points.empty());
  EXPECT_TRUE(srv.response.path.poses.empty());
  EXPECT_EQ(srv.response.joint_trajectory.points.size(), 301u);
}

TEST(NodeArm, RequestsTheArmCannotServeAreRefusedAndTheNodeServesOn)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  const auto model = ur5e();
  GenerateTrajectory no_seed = request(*model);
  no_seed.request.joint_seed.clear();
  expectRefused(no_seed, kService, "joint_seed");
  GenerateTrajectory short_seed = request(*model);
  short_seed.request.joint_seed.pop_back();
  expectRefused(short_seed, kService, "joint_seed");
  GenerateTrajectory far = request(*model);
  far.request.waypoints.poses[1].position.x += 3.0;
  expectRefused(far, kService, "t = ");
  GenerateTrajectory again = request(*model);
  ASSERT_TRUE(callService(kService, again));
  EXPECT_TRUE(again.response.success) << again.response.message;
}

TEST(NodeArm, ANodeWhoseArmCannotBeLoadedRefusesEveryRequestNamingTheLink)
{
  ASSERT_TRUE(ros::service::waitForService(kBrokenService, ros::Duration(30.0)));
  const auto model = ur5e();
  expectRefused(request(*model), kBrokenService, "no_such_link");
  GenerateTrajectory without_seed = request(*model);
  without_seed.request.joint_seed.clear();
  expectRefused(without_seed, kBrokenService, "no_such_link");
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_arm");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
