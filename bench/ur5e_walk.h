// The UR5e requests of the joint-space benchmarks (bench_joint_space, bench_toppra_joints): the arm
// of config/robots/ with its limits file, and waypoints that are its forward kinematics of a random
// walk in joint space from a working configuration (steps of ±0.05 rad per joint, a fixed seed), so
// that every pose is reachable on one branch. Bounds: 0.5 m/s, 1 rad/s, 2 m/s², 4 rad/s².
#pragma once

#include <memory>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "../test/unit/arm/arm_test_utils.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_bench
{
/// The UR5e (base_link → tool0) with the limits of config/robots/ur5e_joint_limits.yaml.
inline std::shared_ptr<const se3_interpolation::arm::ArmModel> ur5e()
{
  return se3_interpolation::test::loadArm("ur5e");
}

/// The walk's start, and the request's joint_seed.
inline const std::vector<double>& ur5eHome()
{
  static const std::vector<double> home = se3_interpolation::test::armHome("ur5e");
  return home;
}

/// An interpolating, time-optimal request through `n` poses of the walk, with the arm's joint_seed.
inline se3_interpolation::TrajectoryRequest ur5eWalk(const se3_interpolation::arm::ArmModel& model, std::size_t n)
{
  std::mt19937 rng(54);
  std::uniform_real_distribution<double> step(-0.05, 0.05);
  Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(ur5eHome().data(), 6);
  se3_interpolation::TrajectoryRequest r;
  r.joint_seed = ur5eHome();
  for (std::size_t i = 0; i < n; ++i)
  {
    r.waypoints.push_back(model.basePoseOfTip(q));
    for (Eigen::Index k = 0; k < 6; ++k)
      q[k] += step(rng);
  }
  r.curve = "interpolating";
  r.timing = "time_optimal";
  r.max_linear_velocity = 0.5;
  r.max_angular_velocity = 1.0;
  r.max_linear_acceleration = 2.0;
  r.max_angular_acceleration = 4.0;
  return r;
}
}  // namespace se3_bench
