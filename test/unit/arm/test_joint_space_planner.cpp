// The planner with an arm (planner/planner.h's generate() with an arm, docs/joint_space.md): the
// UR5e of config/robots/ follows interpolating motions through poses made by its own forward
// kinematics. Checked independently of the planner's joint code: forward kinematics of every joint
// sample against the pose sample, J·q̇ against the twist, every joint velocity and acceleration
// against the limits file at the samples (and the figures, from the dense check, against them),
// durations against the motion without the arm, and the refusals; the Panda's joint jerk limits
// against the differences of the samples' accelerations.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "arm_test_utils.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/planner/planner.h"

using namespace se3_interpolation;
using se3_interpolation::test::armLimits;

namespace
{
/// The UR5e with the limits of its file, velocities and accelerations scaled.
std::shared_ptr<const arm::ArmModel> ur5e(double velocity_scale = 1.0, double acceleration_scale = 1.0)
{
  return test::loadArm("ur5e", velocity_scale, acceleration_scale);
}

const std::vector<std::vector<double>> kConfigurations = {
  { 0.0, -1.2, 1.5, -1.9, -1.57, 0.0 },
  { 0.4, -1.0, 1.3, -1.8, -1.4, 0.3 },
  { 0.9, -1.3, 1.7, -2.0, -1.6, -0.2 },
  { 1.2, -0.9, 1.2, -1.7, -1.3, 0.5 },
};

/// Waypoints at the UR5e's forward kinematics of kConfigurations; joint_seed the first of them.
TrajectoryRequest request(const arm::ArmModel& arm, const std::string& timing)
{
  TrajectoryRequest r = test::requestThrough(arm, kConfigurations, 2001);
  r.timing = timing;
  return r;
}

/// Every sample's joints against its pose and twist, and against the arm's limits; returns the
/// largest ratio of a joint rate to its limit at the samples.
double checkSamples(const TrajectoryResult& out, const arm::ArmModel& arm)
{
  double worst = 0.0;
  for (const TrajectorySample& s : out.samples)
  {
    EXPECT_EQ(s.joint_position.size(), 6);
    const Pose<double> fk = arm.basePoseOfTip(s.joint_position);
    EXPECT_LT((fk.p - s.pose.p).norm(), 1e-9) << s.time;
    // The rotation between them: 2|vec(q_fk⁻¹ q)| ≈ its angle.
    EXPECT_LT(2.0 * (fk.q.conjugate() * s.pose.q).vec().norm(), 1e-9) << s.time;
    Eigen::Matrix<double, 6, 1> twist;
    twist << s.velocity.angular, s.velocity.linear;
    EXPECT_LT((arm.jacobian(s.joint_position) * s.joint_velocity - twist).norm(), 1e-8 * (1.0 + twist.norm()))
        << s.time;
    for (int k = 0; k < 6; ++k)
    {
      const arm::JointLimits& l = arm.joints()[static_cast<std::size_t>(k)].limits;
      worst = std::max({ worst, std::abs(s.joint_velocity[k]) / l.max_velocity,
                         std::abs(s.joint_acceleration[k]) / l.max_acceleration });
      EXPECT_GE(s.joint_position[k], l.min_position);
      EXPECT_LE(s.joint_position[k], l.max_position);
    }
  }
  for (std::size_t k = 0; k < 6; ++k)
  {
    const arm::JointLimits& l = arm.joints()[k].limits;
    EXPECT_LE(out.joint_figures.peaks[k].velocity, l.max_velocity * (1.0 + 1e-6)) << k;
    EXPECT_LE(out.joint_figures.peaks[k].acceleration, l.max_acceleration * (1.0 + 1e-6)) << k;
  }
  return worst;
}
}  // namespace

TEST(JointSpacePlanner, LooseJointLimitsLeaveTheTimeOptimalMotionAsItIs)
{
  const auto arm = ur5e(100.0, 100.0);
  TrajectoryRequest r = request(*arm, "time_optimal");
  const TrajectoryResult with = generate(r, armLimits(), arm);
  r.joint_seed.clear();
  const TrajectoryResult without = generate(r, armLimits());
  EXPECT_NEAR(with.duration, without.duration, 1e-6 * without.duration);
  EXPECT_LT(checkSamples(with, *arm), 0.1);
  EXPECT_EQ(with.joint_names.size(), 6u);
  EXPECT_TRUE(without.joint_names.empty());
}

TEST(JointSpacePlanner, BindingJointLimitsSlowEveryTimingAndHoldAtTheSamples)
{
  // Joint limits at 15 % of the file's velocities and accelerations: tighter than the Cartesian
  // bounds on this motion.
  const auto arm = ur5e(0.15, 0.15);
  for (const char* timing : { "time_optimal", "stretch" })
  {
    TrajectoryRequest r = request(*arm, timing);
    const TrajectoryResult with = generate(r, armLimits(), arm);
    r.joint_seed.clear();
    const TrajectoryResult without = generate(r, armLimits());
    EXPECT_GT(with.duration, 1.05 * without.duration) << timing;
    const double worst = checkSamples(with, *arm);
    EXPECT_LE(worst, 1.0 + 1e-6) << timing;
    // A binding limit is reached (within the samples' spacing).
    EXPECT_GT(worst, 0.97) << timing;
    EXPECT_NEAR(with.joint_figures.binding_ratio, 1.0, 1e-3) << timing;
  }
}

TEST(JointSpacePlanner, TheTimeOptimalMotionUnderJointLimitsIsFasterThanAStretch)
{
  const auto arm = ur5e(0.15, 0.15);
  const TrajectoryResult optimal = generate(request(*arm, "time_optimal"), armLimits(), arm);
  const TrajectoryResult stretched = generate(request(*arm, "stretch"), armLimits(), arm);
  EXPECT_LT(optimal.duration, stretched.duration);
}

TEST(JointSpacePlanner, RefusalsNameTheField)
{
  const auto arm = ur5e();
  TrajectoryRequest r = request(*arm, "time_optimal");
  const auto refused = [](const TrajectoryRequest& q, std::shared_ptr<const arm::ArmModel> a, const std::string& text) {
    try
    {
      generate(q, armLimits(), std::move(a));
      ADD_FAILURE() << "accepted; expected an error naming " << text;
    }
    catch (const InvalidInputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  refused(r, nullptr, "joint_seed");
  TrajectoryRequest no_seed = r;
  no_seed.joint_seed.clear();
  refused(no_seed, arm, "joint_seed");
  TrajectoryRequest short_seed = r;
  short_seed.joint_seed.pop_back();
  refused(short_seed, arm, "joint_seed");
  TrajectoryRequest nan_seed = r;
  nan_seed.joint_seed[2] = std::nan("");
  refused(nan_seed, arm, "joint_seed[2]");
  // A waypoint 3 m away: out of the UR5e's reach (0.85 m).
  TrajectoryRequest far = r;
  far.waypoints[2].p += Eigen::Vector3d(3.0, 0.0, 0.0);
  refused(far, arm, "t = ");
  refused(far, arm, "between waypoints[1] and waypoints[2]: ");
  // constant_speed keeps its speed: joints that cannot follow it are refused naming the joint.
  const auto slow = ur5e(0.05, 0.05);
  TrajectoryRequest constant = request(*slow, "constant_speed");
  constant.speed = 0.3;
  refused(constant, slow, "joint '");
  refused(constant, slow, "waypoints[");
}

TEST(JointSpacePlanner, AMovingStartIsTimedWithinTheJointLimits)
{
  // Replanning from a moving arm: the start state at the first pose, moving at 0.05 m/s; the
  // time-optimal timing holds the joint limits from there (without them in its passes, the
  // elbow would reach 13 rad/s² against its 5).
  const auto arm = ur5e();
  TrajectoryRequest r = request(*arm, "time_optimal");
  r.max_linear_velocity = 1.0;
  r.max_angular_velocity = 2.0;
  r.max_linear_acceleration = 4.0;
  r.max_angular_acceleration = 8.0;
  StartState start;
  start.pose = r.waypoints.front();
  start.velocity.linear = Eigen::Vector3d(0.05, 0.0, 0.0);
  r.start_state = start;
  const TrajectoryResult out = generate(r, armLimits(), arm);
  EXPECT_LE(checkSamples(out, *arm), 1.0 + 1e-6);
  // The first sample is the start state: its joint velocity is J⁻¹ of the start's twist.
  const TrajectorySample& first = out.samples.front();
  EXPECT_LT((first.velocity.linear - start.velocity.linear).norm(), 1e-9);
  EXPECT_GT(first.joint_velocity.norm(), 0.0);
}

namespace
{
/// Panda configurations around its ready pose (rad).
const std::vector<std::vector<double>> kPandaConfigurations = {
  { 0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8 },
  { 0.3, -0.1, 0.2, -2.0, 0.1, 1.9, 0.6 },
  { 0.6, -0.4, 0.1, -2.3, -0.1, 2.1, 1.0 },
};

/// An interpolating motion through the Panda's poses at kPandaConfigurations (the first the seed).
TrajectoryRequest pandaRequest(const arm::ArmModel& arm, const std::string& curve, const std::string& timing)
{
  TrajectoryRequest r = test::requestThrough(arm, kPandaConfigurations, 4001);
  r.curve = curve;
  r.timing = timing;
  r.max_linear_velocity = 1.0;
  r.max_angular_velocity = 2.0;
  r.max_linear_acceleration = 5.0;
  r.max_angular_acceleration = 10.0;
  return r;
}

/// The largest ratio to its jerk limit of a joint's mean jerk between neighbouring samples (a lower
/// bound of its peak between them), less the rounding of the accelerations.
double sampledJerkRatio(const TrajectoryResult& out, const arm::ArmModel& arm)
{
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < out.samples.size(); ++i)
  {
    const TrajectorySample& a = out.samples[i];
    const TrajectorySample& b = out.samples[i + 1];
    const double dt = b.time - a.time;
    if (!(dt > 0.0))
      continue;
    for (int k = 0; k < arm.dof(); ++k)
    {
      const double step = std::abs(b.joint_acceleration[k] - a.joint_acceleration[k]) - 1e-9;
      worst = std::max(worst, step / dt / arm.joints()[static_cast<std::size_t>(k)].limits.max_jerk);
    }
  }
  return worst;
}
}  // namespace

TEST(JointSpacePlanner, ThePandasJerkLimitsHoldUnderTheTimingsThatBoundJerk)
{
  // Jerk limits at 0.2 % of the datasheet's (15 rad/s³ on the first joints): they bind.
  const auto arm = test::loadArm("panda", 1.0, 1.0, 0.002);
  const auto unlimited = test::loadArm("panda", 1.0, 1.0, std::numeric_limits<double>::infinity());
  for (const char* timing : { "time_optimal", "stretch" })
  {
    // (Fast waypoint times: the stretch stretches them until the joints hold.)
    TrajectoryRequest r = pandaRequest(*arm, "interpolating", timing);
    r.times = { 0.0, 0.2, 0.4 };
    const TrajectoryResult out = generate(r, armLimits(), arm);
    ASSERT_TRUE(out.joint_figures.has_jerk) << timing;
    EXPECT_LE(sampledJerkRatio(out, *arm), 1.0 + 1e-6) << timing;
    for (std::size_t k = 0; k < 7; ++k)
    {
      const arm::JointLimits& l = arm->joints()[k].limits;
      EXPECT_LE(out.joint_figures.peaks[k].jerk, l.max_jerk * (1.0 + 1e-6)) << timing << " joint " << k;
      EXPECT_LE(out.joint_figures.peaks[k].acceleration, l.max_acceleration * (1.0 + 1e-6)) << timing;
    }
    // The binding limit is a jerk, reached.
    EXPECT_EQ(out.joint_figures.binding_quantity, "jerk") << timing;
    EXPECT_NEAR(out.joint_figures.binding_ratio, 1.0, 1e-3) << timing;
    // The same request with the jerk limits lifted is faster (the window and stretch act).
    const TrajectoryResult free = generate(r, armLimits(), unlimited);
    EXPECT_GT(out.duration, 1.05 * free.duration) << timing;
  }
}

TEST(JointSpacePlanner, LooseJerkLimitsCostLittleAndAnAccelerationStepIsRefusedUnderThem)
{
  // The datasheet's jerk limits (7500 rad/s³) on a slow motion: the jerk-limited timing within a
  // few per cent of the time-optimal motion without them.
  const auto arm = test::loadArm("panda");
  const auto unlimited = test::loadArm("panda", 1.0, 1.0, std::numeric_limits<double>::infinity());
  const TrajectoryResult with = generate(pandaRequest(*arm, "interpolating", "time_optimal"), armLimits(), arm);
  const TrajectoryResult without =
      generate(pandaRequest(*unlimited, "interpolating", "time_optimal"), armLimits(), unlimited);
  EXPECT_TRUE(with.joint_figures.has_jerk);
  EXPECT_FALSE(without.joint_figures.has_jerk);  // (the time-optimal motion's acceleration steps)
  EXPECT_LE(sampledJerkRatio(with, *arm), 1.0 + 1e-6);
  EXPECT_LT(with.duration, 1.05 * without.duration);
  EXPECT_GE(with.duration, without.duration * (1.0 - 1e-6));
  // A stretch of a C¹ curve steps its acceleration at the waypoints: no stretch bounds the jerk.
  try
  {
    generate(pandaRequest(*arm, "hermite", "stretch"), armLimits(), arm);
    ADD_FAILURE() << "a stretch of a hermite curve under jerk limits was served";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("the arm's joint jerk limits"), std::string::npos) << e.what();
  }
}
