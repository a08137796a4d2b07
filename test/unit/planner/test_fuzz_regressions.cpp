// Regression tests for what the fuzzer (test/fuzz/fuzz_generate.cpp) found: each request here
// once produced a non-finite output or an unexpected failure. A request must give either a
// finite result or an InterpolationError that names the field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/planner.h"
#include "test_utils.h"

using namespace se3_interpolation;

namespace
{
Pose<double> pose(double x, double y, double z, const Quaternion<double>& q = Quaternion<double>::Identity())
{
  return Pose<double>(q, Eigen::Vector3d(x, y, z));
}

void expectFinite(const TrajectoryResult& out)
{
  for (double x : { out.duration, out.figures.length, out.figures.rotation_length, out.figures.max_linear_speed, out.figures.max_angular_speed,
                    out.figures.max_linear_acceleration, out.figures.max_angular_acceleration, out.figures.energy })
    EXPECT_TRUE(std::isfinite(x)) << x;
  for (const TrajectorySample& s : out.samples)
  {
    EXPECT_TRUE(s.pose.p.allFinite());
    EXPECT_NEAR(s.pose.q.norm(), 1.0, 1e-9);
    EXPECT_TRUE(s.velocity.linear.allFinite() && s.velocity.angular.allFinite());
    EXPECT_TRUE(s.acceleration.linear.allFinite() && s.acceleration.angular.allFinite());
  }
}
}  // namespace

// Found by fuzz_generate: energy = ∫ |p̈|² + ρ²|ω̇|² dt was computed as ρ² · |ω̇|², which is
// ∞ · 0 = NaN for a huge rotation_scale ρ on a motion without rotation. It is (ρ ω̇)², 0 here.
TEST(FuzzRegressions, HugeRotationScaleWithoutRotationGivesTheTranslationEnergy)
{
  TrajectoryRequest r;
  r.waypoints = { pose(-8.0, -7.75, 1e-15), pose(-8.0, -4.375, -7.75) };
  r.times = { 0.0, 6.5 };
  r.curve = "interpolating";
  r.sample_period = 6.5;
  const TrajectoryResult reference = generate(r, PlannerLimits());
  r.rotation_scale = 1e300;
  const TrajectoryResult out = generate(r, PlannerLimits());
  expectFinite(out);
  EXPECT_EQ(out.figures.energy, reference.figures.energy);
  EXPECT_EQ(out.samples.size(), 2u);
}

// The same overflow with a rotating motion cannot be represented: an InterpolationError
// naming the figure, not ∞ in the response.
TEST(FuzzRegressions, OverflowingEnergyIsAnError)
{
  TrajectoryRequest r;
  r.waypoints = { pose(0.0, 0.0, 0.0), pose(1.0, 0.0, 0.0, so3Exp<double>(Eigen::Vector3d(0.0, 0.0, 1.0))),
                  pose(2.0, 1.0, 0.0, so3Exp<double>(Eigen::Vector3d(1.0, 0.5, 0.0))) };
  r.times = { 0.0, 1.0, 2.0 };
  r.curve = "interpolating";
  r.rotation_scale = 1e300;
  try
  {
    generate(r, PlannerLimits());
    FAIL() << "expected an InterpolationError";
  }
  catch (const InterpolationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("energy"), std::string::npos) << e.what();
  }
}
