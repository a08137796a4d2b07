// Validation (planner/validation.h, planner/names.h): one rule per function, one message style,
// the same rules for poses and spheres. Each case states the expected field and value here,
// independently of the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"

using namespace se3_interpolation;

namespace
{
Pose<double> pose(double x)
{
  return Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(x, 0.0, 0.0));
}

TrajectoryRequest poseRequest()
{
  TrajectoryRequest r;
  r.waypoints = { pose(0.0), pose(1.0), pose(3.0) };
  return r;
}

SphereRequest sphereRequest()
{
  SphereRequest r;
  r.waypoints = { Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1) };
  return r;
}

/// The message of the InterpolationError `f` throws ("" if it throws nothing).
template <class F>
std::string errorOf(F f)
{
  try
  {
    f();
  }
  catch (const InterpolationError& e)
  {
    return e.what();
  }
  return "";
}

template <class Request>
std::string validationError(const Request& r)
{
  return errorOf([&] { validateRequest(r, PlannerLimits()); });
}

bool startsWith(const std::string& s, const std::string& prefix)
{
  return s.compare(0, prefix.size(), prefix) == 0;
}
}  // namespace

TEST(Validation, DefaultsComeFromRequestDefaults)
{
  const ValidatedRequest v = validateRequest(poseRequest(), PlannerLimits());
  EXPECT_EQ(v.curve, CurveType::kInterpolating);
  EXPECT_EQ(v.geometry, GeometryType::kDoubleGeodesic);
  EXPECT_EQ(v.end_condition, EndCondition::kNatural);
  EXPECT_EQ(v.parameterization, Parameterization::kChord);
  EXPECT_EQ(v.timing, Timing::kStretch);
  EXPECT_EQ(v.degree, 2);  // min(3, N - 1) for N = 3
  EXPECT_EQ(v.continuity, 2);
  EXPECT_EQ(v.sampling.sample_count, 100u);
  EXPECT_EQ(v.rotation_scale, 1.0);
  TrajectoryRequest four = poseRequest();
  four.waypoints.push_back(pose(4.0));
  EXPECT_EQ(validateRequest(four, PlannerLimits()).degree, 3);
  TrajectoryRequest two = poseRequest();
  two.waypoints.pop_back();
  EXPECT_EQ(validateRequest(two, PlannerLimits()).degree, 1);
  // The sphere reads the same defaults.
  const ValidatedSphereRequest s = validateRequest(sphereRequest(), PlannerLimits());
  EXPECT_EQ(s.curve, CurveType::kInterpolating);
  EXPECT_EQ(s.sampling.sample_count, 100u);
}

TEST(Validation, SameRuleSameMessageInBothSpaces)
{
  TrajectoryRequest p = poseRequest();
  SphereRequest s = sphereRequest();
  p.curve = s.curve = "splines";
  EXPECT_EQ(validationError(p), validationError(s));
  EXPECT_TRUE(startsWith(validationError(p), "curve: unknown value 'splines'"));

  p = poseRequest();
  s = sphereRequest();
  p.times = s.times = { 0.0, 2.0, 2.0 };
  EXPECT_EQ(validationError(p), "times[2]: 2 is not after times[1] = 2 (times must be strictly increasing)");
  EXPECT_EQ(validationError(p), validationError(s));

  p.times = s.times = { 0.0, 1.0 };
  EXPECT_EQ(validationError(p), "times: 2 given for 3 waypoints (give one time per waypoint, or none)");
  EXPECT_EQ(validationError(p), validationError(s));

  p.times = s.times = {};
  p.continuity = s.continuity = 9;
  EXPECT_EQ(validationError(p), "continuity: 9 is outside 1 ... 8");
  EXPECT_EQ(validationError(p), validationError(s));

  p.continuity = s.continuity = 0;
  p.sample_count = s.sample_count = 1;
  EXPECT_EQ(validationError(p), "sample_count: 1 is too few (at least 2: both ends)");
  EXPECT_EQ(validationError(p), validationError(s));

  p.sample_count = s.sample_count = 0;
  p.waypoints.resize(1);
  s.waypoints.resize(1);
  EXPECT_EQ(validationError(p), "waypoints: 1 given; at least 2 are needed");
  EXPECT_EQ(validationError(p), validationError(s));
}

TEST(Validation, UnitNormBoundsAreInclusiveAndNormalise)
{
  // 0.99 and 1.01 are accepted (and normalised), just outside is refused, for both spaces.
  for (double norm : { 0.99, 1.01 })
  {
    TrajectoryRequest p = poseRequest();
    p.waypoints[1].q = Quaternion<double>(norm, 0.0, 0.0, 0.0);
    const ValidatedRequest v = validateRequest(p, PlannerLimits());
    EXPECT_NEAR(v.waypoints[1].q.norm(), 1.0, 1e-15);
    SphereRequest s = sphereRequest();
    s.waypoints[1] *= norm;
    EXPECT_NEAR(validateRequest(s, PlannerLimits()).waypoints[1].norm(), 1.0, 1e-15);
  }
  TrajectoryRequest p = poseRequest();
  p.waypoints[2].q = Quaternion<double>(1.0101, 0.0, 0.0, 0.0);
  EXPECT_EQ(validationError(p), "waypoints[2].orientation: quaternion norm 1.0101 is outside [0.99, 1.01] "
                                "(expected a unit quaternion x, y, z, w)");
  SphereRequest s = sphereRequest();
  s.waypoints[2] *= 0.9899;
  EXPECT_TRUE(startsWith(validationError(s), "waypoints[2]: norm 0.9899")) << validationError(s);
}

TEST(Validation, NonFiniteComponentsNameTheirAxis)
{
  TrajectoryRequest p = poseRequest();
  p.waypoints[1].p.y() = NAN;
  EXPECT_EQ(validationError(p), "waypoints[1].position.y: nan is not a finite number");
  p = poseRequest();
  p.start_velocity.angular.z() = INFINITY;
  EXPECT_EQ(validationError(p), "start_velocity.angular.z: inf is not a finite number");
  SphereRequest s = sphereRequest();
  s.waypoints[0][2] = NAN;
  EXPECT_EQ(validationError(s), "waypoints[0][2]: nan is not a finite number");
}

TEST(Validation, FieldsWithoutMeaningOnTheSphereAreRefused)
{
  for (const char* field : { "geometry", "rotation_scale", "max_linear_velocity", "max_linear_acceleration",
                             "blend_radius" })
  {
    SphereRequest s = sphereRequest();
    const std::string f = field;
    if (f == "geometry")
      s.geometry = "screw";
    else if (f == "rotation_scale")
      s.rotation_scale = 2.0;
    else if (f == "max_linear_velocity")
      s.max_linear_velocity = 1.0;
    else if (f == "max_linear_acceleration")
      s.max_linear_acceleration = 1.0;
    else
      s.blend_radius = 0.1;
    EXPECT_TRUE(startsWith(validationError(s), f + ": not used on the sphere")) << validationError(s);
  }
}

TEST(Validation, SphereTangentsAreProjectedWithinOnePercent)
{
  SphereRequest s = sphereRequest();
  // At (1, 0, 0): a normal component of 0.5 % of the length is projected away, 2 % is refused.
  s.start_velocity = Eigen::Vector3d(0.005, 1.0, 0.0);
  const ValidatedSphereRequest v = validateRequest(s, PlannerLimits());
  EXPECT_NEAR(v.start_velocity[0], 0.0, 1e-17);
  EXPECT_EQ(v.start_velocity[1], 1.0);
  s.start_velocity = Eigen::Vector3d(0.02, 1.0, 0.0);
  EXPECT_TRUE(startsWith(validationError(s), "start_velocity: is not tangent to the sphere"));
}

TEST(Validation, IdenticalNeighboursNeedTimesAndAntipodesAreRefused)
{
  TrajectoryRequest p = poseRequest();
  p.waypoints[2] = p.waypoints[1];
  EXPECT_EQ(validationError(p), "waypoints[1] and waypoints[2]: identical consecutive waypoints need explicit times "
                                "(to dwell)");
  p.times = { 0.0, 1.0, 2.0 };
  EXPECT_EQ(validationError(p), "");

  p = poseRequest();
  p.waypoints[1].q = Quaternion<double>(0.0, 1.0, 0.0, 0.0);  // a half turn about x from the identity
  EXPECT_TRUE(startsWith(validationError(p), "waypoints[0] and waypoints[1]:"));
  SphereRequest s = sphereRequest();
  s.waypoints[1] = -s.waypoints[0];
  EXPECT_TRUE(startsWith(validationError(s), "waypoints[0] and waypoints[1]:"));
}

TEST(Validation, SampleTimesIncludeBothEnds)
{
  Sampling count;
  count.sample_count = 3;
  const std::vector<double> ts = sampleTimes(count, 1.0, 2.0, PlannerLimits());
  ASSERT_EQ(ts.size(), 3u);
  EXPECT_EQ(ts[0], 1.0);
  EXPECT_EQ(ts[1], 1.5);
  EXPECT_EQ(ts[2], 2.0);
  Sampling period;
  period.sample_period = 0.4;
  const std::vector<double> tp = sampleTimes(period, 0.0, 1.0, PlannerLimits());
  ASSERT_EQ(tp.size(), 4u);
  EXPECT_EQ(tp[2], 0.8);
  EXPECT_EQ(tp[3], 1.0);
}

TEST(Validation, MessageHelpers)
{
  EXPECT_EQ(indexedField("times", 12), "times[12]");
  EXPECT_EQ(formatNumber(0.1), "0.10000000000000001");
  EXPECT_EQ(quotedText(std::string("a\x01z")), "'a\\x01z'");
  EXPECT_EQ(quotedText(std::string(50, 'x')), "'" + std::string(kMaxQuotedLength, 'x') + "'... (50 characters)");
}

// Fuzz finding fuzz_curves-denormal-duration (test/fuzz/findings): a denormal duration spaced two
// waypoints 4.9e-324 s apart and the curve divided by it (NaN). Waypoint times closer than the
// 1 ns that time_from_start resolves are refused, explicit or spaced by the duration.
TEST(Validation, WaypointTimesCloserThanOneNanosecondAreRefused)
{
  TrajectoryRequest p = poseRequest();
  p.waypoints.pop_back();
  p.duration = 4.9e-324;
  const std::string e = errorOf([&] { generate(p, PlannerLimits()); });
  EXPECT_TRUE(startsWith(e, "waypoints[0] and waypoints[1]: too close to be spaced apart in time")) << e;
  SphereRequest s = sphereRequest();
  s.duration = 1e-12;
  EXPECT_TRUE(startsWith(errorOf([&] { generate(s, PlannerLimits()); }), "waypoints[0] and waypoints[1]: too close"));

  p = poseRequest();
  p.times = { 0.0, 5e-10, 1.0 };
  EXPECT_EQ(validationError(p), "times[1]: 5.0000000000000003e-10 is only 5.0000000000000003e-10 s after times[0], "
                                "below the 1 ns resolution of time_from_start");
  p.times = { 0.0, 1e-9, 1.0 };
  EXPECT_EQ(validationError(p), "");
}

TEST(Validation, ResponseOutputsAreNamedOnceEachFromTheirTable)
{
  // Empty: both arrays (the behaviour before the field existed).
  const ResponseOutputs all = parseResponseOutputs({});
  EXPECT_TRUE(all.path);
  EXPECT_TRUE(all.trajectory);
  const ResponseOutputs trajectory = parseResponseOutputs({ "trajectory" });
  EXPECT_FALSE(trajectory.path);
  EXPECT_TRUE(trajectory.trajectory);
  const ResponseOutputs path = parseResponseOutputs({ "path" });
  EXPECT_TRUE(path.path);
  EXPECT_FALSE(path.trajectory);
  const ResponseOutputs both = parseResponseOutputs({ "trajectory", "path" });
  EXPECT_TRUE(both.path);
  EXPECT_TRUE(both.trajectory);

  const std::pair<std::vector<std::string>, std::string> bad[] = {
    { { "path", "markers" }, "outputs[1]: unknown value 'markers' (expected one of: path, trajectory, joint_trajectory)" },
    { { "Path" }, "outputs[0]: unknown value 'Path'" },
    { { "trajectory", "trajectory" }, "outputs[1]: 'trajectory' is named twice" },
    { { "path", "" }, "outputs[1]: empty name (expected one of: path, trajectory, joint_trajectory)" },
  };
  for (const auto& b : bad)
  {
    try
    {
      parseResponseOutputs(b.first);
      ADD_FAILURE() << "accepted: " << b.second;
    }
    catch (const InvalidInputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(b.second), std::string::npos) << e.what();
    }
  }
}

// Fuzz finding fuzz_curves-infinite-acceleration (now a seed of test/fuzz/corpus): a hermite
// request with a finite end velocity of 1.8e308 m/s passed validation and the curve's linear
// acceleration, (-6 L + 2 h v0 + 4 h v1)/h^2 at the end, overflowed to infinity. Positions and
// the components of every velocity and acceleration are limited to kMaxMagnitude (1e100).
TEST(Validation, MagnitudesBeyondTheLimitAreRefused)
{
  TrajectoryRequest p = poseRequest();
  p.waypoints.pop_back();
  p.curve = "hermite";
  p.velocities.resize(2);
  p.velocities[1].linear.y() = 1.7976931348623157e308;
  EXPECT_EQ(validationError(p), "velocities[1].linear.y: 1.7976931348623157e+308 is beyond the magnitude limit 1e+100 "
                                "(larger values can overflow the curve's acceleration)");
  p.velocities[1].linear.y() = 0.0;
  p.velocities[0].angular.x() = std::nextafter(-1e100, -INFINITY);
  EXPECT_TRUE(startsWith(validationError(p), "velocities[0].angular.x: ")) << validationError(p);
  EXPECT_NE(validationError(p).find("is beyond the magnitude limit 1e+100"), std::string::npos);
  p.velocities[0].angular.x() = 0.0;
  p.start_acceleration.linear.z() = 2e100;
  EXPECT_TRUE(startsWith(validationError(p), "start_acceleration.linear.z: 2e+100 is beyond")) << validationError(p);
  p.start_acceleration.linear.z() = 0.0;
  p.waypoints[1].p.x() = -2e100;
  EXPECT_TRUE(startsWith(validationError(p), "waypoints[1].position.x: -2e+100 is beyond")) << validationError(p);
  SphereRequest s = sphereRequest();
  s.curve = "hermite";
  s.velocities = { Eigen::Vector3d(0, 2e100, 0), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero() };
  EXPECT_TRUE(startsWith(validationError(s), "velocities[0][1]: 2e+100 is beyond")) << validationError(s);

  // At the limit (inclusive) and the shortest step, 1 ns, the curve stays finite: a pure
  // translation, where the hermite cubic is the classical one, ends with the acceleration
  // (-6 L + 4 h v1)/h^2 = (-6 + 4e-9 * 1e100)/1e-18 = 4e109 m/s^2.
  p.waypoints[1].p.x() = 1.0;
  p.times = { 0.0, 1e-9 };
  p.velocities[1].linear.x() = 1e100;
  p.sample_count = 2;
  const TrajectoryResult out = generate(p, PlannerLimits());
  ASSERT_EQ(out.samples.size(), 2u);
  const Eigen::Vector3d a = out.samples.back().acceleration.linear;
  EXPECT_NEAR(a.x() / 4e109, 1.0, 1e-9) << a.transpose();
  EXPECT_TRUE(std::isfinite(out.figures.energy));
}
