// The joint invariants of the request-space checker (test/unit/planner/joint_invariants.h) can fail:
// a served UR5e motion passes them all, and each mutation of it (a joint position, velocity or
// acceleration of one sample, a motion between the samples that is not theirs, a joint jump between
// two samples, a held joint that moves, limits below what the motion reaches at the samples or only
// between them, a jerk figure below its peak, jerk limits below the motion's or across an
// acceleration step) is reported by its own check.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "arm_test_utils.h"
#include "planner/joint_invariants.h"
#include "se3_interpolation/planner/planner.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

namespace
{
/// Through configurations around the UR5e's home.
TrajectoryRequest ur5eRequest(const arm::ArmModel& model, std::uint32_t samples)
{
  return requestThrough(model,
                        { { 0.0, -1.2, 1.5, -1.9, -1.57, 0.0 },
                          { 0.4, -1.0, 1.3, -1.8, -1.4, 0.3 },
                          { 0.9, -1.3, 1.7, -2.0, -1.6, -0.2 } },
                        samples);
}

/// The joint invariants `result` breaks for `model`.
std::vector<Violation> violationsOf(const TrajectoryResult& result, const arm::ArmModel& model)
{
  std::vector<Violation> v;
  CheckOptions options;
  options.dense_points = 600;
  checkJointInvariants(result, model, options, v);
  return v;
}

/// Their kinds.
std::set<std::string> brokenKinds(const TrajectoryResult& result, const arm::ArmModel& model)
{
  std::set<std::string> kinds;
  for (const Violation& x : violationsOf(result, model))
    kinds.insert(x.kind);
  return kinds;
}

/// Their kinds and details, a line each.
std::string described(const std::vector<Violation>& v)
{
  std::string text;
  for (const Violation& x : v)
    text += x.kind + ": " + x.detail + "\n";
  return text;
}

/// The UR5e with limits `edit` changes (a limits file entry per joint, from the file's values).
template <class Edit>
std::shared_ptr<arm::ArmModel> ur5eWith(Edit edit)
{
  auto model = loadArm("ur5e");
  arm::JointLimitsFile file;
  file.source = "mutated limits";
  for (const arm::ArmJoint& j : model->joints())
  {
    arm::JointLimitsEntry e;
    e.max_velocity = j.limits.max_velocity;
    e.max_acceleration = j.limits.max_acceleration;
    e.min_position = j.limits.min_position;
    e.max_position = j.limits.max_position;
    if (j.limits.hasJerkLimit())
      e.max_jerk = j.limits.max_jerk;
    edit(j.name, &e);
    file.joints[j.name] = e;
  }
  model->applyLimits(file);
  return model;
}
}  // namespace

TEST(JointInvariants, AServedMotionPassesAndEachMutationBreaksItsCheck)
{
  const auto model = loadArm("ur5e");
  const TrajectoryResult served = generate(ur5eRequest(*model, 64), armLimits(), model);
  ASSERT_EQ(described(violationsOf(served, *model)), "");

  auto mutated = [&](auto mutate) {
    TrajectoryResult r = served;
    mutate(&r);
    return brokenKinds(r, *model);
  };
  // One sample's q off by 1e-7 rad: its FK misses the pose.
  EXPECT_EQ(mutated([](TrajectoryResult* r) { r->samples[10].joint_position[2] += 1e-7; }).count("joint FK position"),
            1u);
  EXPECT_EQ(mutated([](TrajectoryResult* r) { r->samples[10].joint_position[5] += 1e-7; }).count("joint FK rotation"),
            1u);
  // q̇ and q̈ off by a part in 1e6 of one joint's.
  EXPECT_EQ(mutated([](TrajectoryResult* r) {
              r->samples[10].joint_velocity[1] *= 1.0 + 1e-6;
            }).count("joint J q' vs twist"),
            1u);
  EXPECT_EQ(mutated([](TrajectoryResult* r) {
              r->samples[10].joint_acceleration[1] += 1e-6;
            }).count("joint J q'' + J' q' vs acceleration"),
            1u);
  // The motion between the samples 1e-6 m off theirs from sample 40 on: the joints carried from
  // sample 39 arrive off sample 40's.
  const std::set<std::string> off = mutated([](TrajectoryResult* r) {
    const double from = r->samples[40].time;
    const auto motion = r->state_at;
    r->state_at = [motion, from](double t) {
      TrajectorySample s = motion(t);
      if (t >= from)
        s.pose.p.x() += 1e-6;
      return s;
    };
  });
  EXPECT_EQ(off.count("joint continuity"), 1u);
  EXPECT_EQ(off.count("joint FK position"), 0u);
  // A jump of one joint between two samples, faster than its velocity limit allows.
  EXPECT_EQ(mutated([](TrajectoryResult* r) {
              for (std::size_t i = 40; i < r->samples.size(); ++i)
                r->samples[i].joint_position[0] += 0.5;
            }).count("joint step"),
            1u);

  // A figure 1e-3 below the peak of its joint (ten times the figures' tolerance).
  EXPECT_EQ(mutated([](TrajectoryResult* r) {
              r->joint_figures.peaks[2].velocity *= 1.0 - 1e-3;
            }).count("joint figure velocity"),
            1u);
  EXPECT_EQ(mutated([](TrajectoryResult* r) {
              r->joint_figures.peaks[2].acceleration *= 1.0 - 1e-3;
            }).count("joint figure acceleration"),
            1u);

  // Limits below the peaks: the figures, the samples and between them.
  const auto slow = ur5eWith([&](const std::string& name, arm::JointLimitsEntry* e) {
    if (name == "elbow_joint")
    {
      *e->max_velocity = 0.5 * served.joint_figures.peaks[2].velocity;
      *e->max_acceleration = 0.5 * served.joint_figures.peaks[2].acceleration;
    }
  });
  const std::set<std::string> over = brokenKinds(served, *slow);
  for (const char* kind :
       { "joint velocity limit", "joint acceleration limit", "joint step", "joint velocity limit between samples",
         "joint acceleration limit between samples", "joint figures above the limits" })
    EXPECT_EQ(over.count(kind), 1u) << kind;
  const auto narrow = ur5eWith([&](const std::string& name, arm::JointLimitsEntry* e) {
    if (name == "shoulder_pan_joint")
      *e->max_position = served.samples.back().joint_position[0] - 1e-3;
  });
  const std::set<std::string> beyond = brokenKinds(served, *narrow);
  EXPECT_EQ(beyond.count("joint position limit"), 1u);
  EXPECT_EQ(beyond.count("joint position limit between samples"), 1u);
}

TEST(JointInvariants, TheRatesBetweenSamplesAreCheckedWhereTheSamplesHoldTheLimits)
{
  // Eight samples: each joint's largest rate lies between two of them. Limits just above what
  // the samples reach, below the peaks: only the checks between the samples see them.
  const auto model = loadArm("ur5e");
  const TrajectoryResult served = generate(ur5eRequest(*model, 8), armLimits(), model);
  Eigen::VectorXd at_samples = Eigen::VectorXd::Zero(6);
  for (const TrajectorySample& s : served.samples)
    at_samples = at_samples.cwiseMax(s.joint_velocity.cwiseAbs());
  const auto tight = ur5eWith([&](const std::string& name, arm::JointLimitsEntry* e) {
    const auto names = model->jointNames();
    const auto k = std::find(names.begin(), names.end(), name) - names.begin();
    *e->max_velocity = at_samples[k] * (1.0 + 1e-5);
  });
  const std::set<std::string> kinds = brokenKinds(served, *tight);
  EXPECT_EQ(kinds.count("joint velocity limit"), 0u);
  EXPECT_EQ(kinds.count("joint velocity limit between samples"), 1u);
}

TEST(JointInvariants, ARedundantArmHoldsItsJoints)
{
  const auto model = loadArm("panda");
  std::vector<std::vector<double>> configurations{ armHome("panda") };
  for (int w = 1; w < 3; ++w)
  {
    configurations.push_back(configurations.back());
    for (double& q : configurations.back())
      q += 0.15;
  }
  const TrajectoryRequest r = requestThrough(*model, configurations, 64);
  const TrajectoryResult served = generate(r, armLimits(), model);
  ASSERT_EQ(described(violationsOf(served, *model)), "");
  const std::vector<int> held = heldJoints(served, 7);
  ASSERT_EQ(held.size(), 1u);
  TrajectoryResult moved = served;
  moved.samples[20].joint_position[held[0]] += 1e-7;
  EXPECT_EQ(brokenKinds(moved, *model).count("joint held"), 1u);
  // The Panda's jerk limits: the served motion reports its joints' jerk; a jerk figure 1e-3 below
  // its peak, and jerk limits at half the largest ratio, break their checks.
  ASSERT_TRUE(served.joint_figures.has_jerk);
  double ratio = 0.0;
  for (std::size_t k = 0; k < 7; ++k)
    ratio = std::max(ratio, served.joint_figures.peaks[k].jerk / model->joints()[k].limits.max_jerk);
  ASSERT_GT(ratio, 0.0);
  TrajectoryResult low = served;
  for (arm::JointPeak& p : low.joint_figures.peaks)
    p.jerk *= 1.0 - 1e-3;
  EXPECT_EQ(brokenKinds(low, *model).count("joint figure jerk"), 1u);
  const std::set<std::string> over = brokenKinds(served, *loadArm("panda", 1.0, 1.0, 0.5 * ratio));
  EXPECT_EQ(over.count("joint jerk limit between samples"), 1u);
  EXPECT_EQ(over.count("joint figures above the limits"), 1u);
}

TEST(JointInvariants, AnAccelerationStepBreaksAJerkLimit)
{
  // The UR5e's time-optimal motion (no jerk limit in its file) steps its joints' accelerations:
  // against any jerk limit the mean jerk across a step is above it.
  const auto model = loadArm("ur5e");
  const TrajectoryResult served = generate(ur5eRequest(*model, 64), armLimits(), model);
  ASSERT_FALSE(served.joint_figures.has_jerk);
  const auto limited = ur5eWith([](const std::string&, arm::JointLimitsEntry* e) { e->max_jerk = 1e3; });
  EXPECT_EQ(brokenKinds(served, *limited).count("joint jerk limit between samples"), 1u);
}
