// The arm's promise over the request's dimensions (docs/joint_space.md): a seeded random sweep of
// arms (the UR5e, the Panda with a held joint), curve families, geometries, timings and joint
// limits, through poses made by each arm's own forward kinematics near a working configuration.
// Every served motion passes one invariant check, written here without the planner's joint code:
// forward kinematics of every joint sample equals the pose sample, J·q̇ equals the twist, held
// joints stay at the seed, every joint rate at the samples and every figure of the dense check are
// within the limits, and every Cartesian bound holds at the samples. A refusal must name a time or
// a joint (out of reach, singular, a position limit, a corner a stretch cannot bound).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "arm_test_utils.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/planner/planner.h"

using namespace se3_interpolation;
using se3_interpolation::test::armLimits;

namespace
{
struct Arm
{
  std::shared_ptr<arm::ArmModel> model;
  std::vector<double> home;  ///< a working configuration the sweep's waypoints are drawn around
};

Arm makeArm(const std::string& name, double limit_scale)
{
  return { test::loadArm(name, limit_scale, limit_scale), test::armHome(name) };
}

/// The invariants of a served motion; failures are reported with `label`.
void checkMotion(const TrajectoryResult& out, const TrajectoryRequest& r, const arm::ArmModel& model,
                 const std::string& label)
{
  const int n = model.dof();
  ASSERT_FALSE(out.samples.empty()) << label;
  // The largest distance of each joint from the seed: n − 6 joints (the held ones) never move.
  Eigen::VectorXd travel = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd seed = Eigen::Map<const Eigen::VectorXd>(r.joint_seed.data(), n);
  for (const TrajectorySample& s : out.samples)
  {
    ASSERT_EQ(s.joint_position.size(), n) << label;
    const Pose<double> fk = model.basePoseOfTip(s.joint_position);
    EXPECT_LT((fk.p - s.pose.p).norm(), 1e-9) << label << " t = " << s.time;
    EXPECT_LT(2.0 * (fk.q.conjugate() * s.pose.q).vec().norm(), 1e-9) << label << " t = " << s.time;
    Eigen::Matrix<double, 6, 1> twist;
    twist << s.velocity.angular, s.velocity.linear;
    EXPECT_LT((model.jacobian(s.joint_position) * s.joint_velocity - twist).norm(), 1e-7 * (1.0 + twist.norm()))
        << label << " t = " << s.time;
    for (int k = 0; k < n; ++k)
    {
      const arm::JointLimits& l = model.joints()[static_cast<std::size_t>(k)].limits;
      EXPECT_LE(std::abs(s.joint_velocity[k]), l.max_velocity * (1.0 + 1e-6)) << label << " joint " << k;
      EXPECT_LE(std::abs(s.joint_acceleration[k]), l.max_acceleration * (1.0 + 1e-6)) << label << " joint " << k;
      travel[k] = std::max(travel[k], std::abs(s.joint_position[k] - seed[k]));
    }
    if (r.max_linear_velocity > 0.0)
      EXPECT_LE(s.velocity.linear.norm(), r.max_linear_velocity * (1.0 + 1e-6)) << label << " t = " << s.time;
    if (r.max_angular_velocity > 0.0)
      EXPECT_LE(s.velocity.angular.norm(), r.max_angular_velocity * (1.0 + 1e-6)) << label << " t = " << s.time;
  }
  EXPECT_GE((travel.array() <= 1e-12).count(), n - 6) << label;
  for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k)
  {
    const arm::JointLimits& l = model.joints()[k].limits;
    EXPECT_LE(out.joint_figures.peaks[k].velocity, l.max_velocity * (1.0 + 1e-6)) << label << " joint " << k;
    EXPECT_LE(out.joint_figures.peaks[k].acceleration, l.max_acceleration * (1.0 + 1e-6)) << label << " joint " << k;
  }
}
}  // namespace

TEST(JointSpaceSweep, EveryServedMotionHoldsTheInvariantsAndEveryRefusalNamesWhere)
{
  const char* const curves[] = { "interpolating", "bspline", "bezier", "blended", "hermite", "piecewise_geodesic" };
  const char* const geometries[] = { "double_geodesic", "screw" };
  const char* const timings[] = { "time_optimal", "stretch" };
  std::mt19937 rng(50);
  std::uniform_real_distribution<double> offset(-0.35, 0.35);
  int served = 0, refused = 0;
  for (int i = 0; i < 48; ++i)
  {
    const std::string arm_name = i % 3 == 2 ? "panda" : "ur5e";
    const double scale = (i / 3) % 2 == 0 ? 1.0 : 0.2;
    const Arm a = makeArm(arm_name, scale);
    TrajectoryRequest r;
    const int count = 2 + i % 4;
    for (int w = 0; w < count; ++w)
    {
      Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(a.home.data(), static_cast<Eigen::Index>(a.home.size()));
      if (w > 0)
        for (Eigen::Index k = 0; k < q.size(); ++k)
          q[k] += offset(rng);
      if (w == 0)
        r.joint_seed.assign(q.data(), q.data() + q.size());
      r.waypoints.push_back(a.model->basePoseOfTip(q));
    }
    r.curve = curves[i % 6];
    r.geometry = geometries[(i / 6) % 2];
    r.timing = timings[(i / 12) % 2];
    if (r.curve == "piecewise_geodesic")
      r.blend_radius = 0.02;
    r.max_linear_velocity = 0.5;
    r.max_angular_velocity = 1.0;
    r.max_linear_acceleration = 2.0;
    r.max_angular_acceleration = 4.0;
    r.sample_count = 400;
    const std::string label = arm_name + " " + r.curve + " " + r.geometry + " " + r.timing + " scale " +
                              std::to_string(scale) + " #" + std::to_string(i);
    try
    {
      const TrajectoryResult out = generate(r, armLimits(), a.model);
      checkMotion(out, r, *a.model, label);
      ++served;
    }
    catch (const InvalidInputError& e)
    {
      const std::string message = e.what();
      EXPECT_TRUE(message.find("t = ") != std::string::npos || message.find("joint") != std::string::npos)
          << label << ": " << message;
      ++refused;
    }
  }
  // Poses within 0.35 rad per joint of a working configuration: most are served.
  EXPECT_GE(served, 40) << refused << " refused";
}
