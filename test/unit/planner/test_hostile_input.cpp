// Hostile input, round 2: times beyond what ROS can carry, sampling that drops an
// end or repeats time_from_start, and unbounded or control-character frame ids. Each case is an
// InvalidInputError naming the field, or a result checked against values written here.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"

using namespace se3_interpolation;

namespace
{
Pose<double> pose(double x, double y, double z)
{
  return Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(x, y, z));
}

/// A straight line along x: 1 m per second with times {0, 1, 2}.
TrajectoryRequest line()
{
  TrajectoryRequest r;
  r.waypoints = { pose(0, 0, 0), pose(1, 0, 0), pose(2, 0, 0) };
  r.sample_count = 5;
  return r;
}

/// The message of the InvalidInputError `f` throws ("" if it throws nothing).
template <class F>
std::string errorOf(F f)
{
  try
  {
    f();
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}

bool startsWith(const std::string& s, const std::string& prefix)
{
  return s.compare(0, prefix.size(), prefix) == 0;
}
}  // namespace

// Row 14: durations and times beyond ros::Duration's signed 32-bit seconds name their field.
TEST(HostileTimes, DurationsBeyondRosRangeNameTheField)
{
  for (double d : { 3e9, 2147483648.0, 1e300 })
  {
    TrajectoryRequest r = line();
    r.duration = d;
    const std::string e = errorOf([&] { generate(r, PlannerLimits()); });
    EXPECT_TRUE(startsWith(e, "duration: ")) << d << ": " << e;
  }
  TrajectoryRequest at_limit = line();
  at_limit.duration = 2147483647.0;  // 2^31 - 1 s is the largest ros::Duration in whole seconds
  EXPECT_NEAR(generate(at_limit, PlannerLimits()).duration, 2147483647.0, 1e-6);

  TrajectoryRequest times = line();
  times.times = { 0.0, 1.0, 3e9 };
  EXPECT_TRUE(startsWith(errorOf([&] { generate(times, PlannerLimits()); }), "times[2]: "));
  TrajectoryRequest negative = line();
  negative.times = { -3e9, 1.0, 2.0 };
  EXPECT_TRUE(startsWith(errorOf([&] { generate(negative, PlannerLimits()); }), "times[0]: "));

  TrajectoryRequest knots = line();
  knots.curve = "bspline";
  knots.degree = 1;
  knots.knots = { 0.0, 0.0, 1.0, 1e300, 1e300 };
  EXPECT_TRUE(startsWith(errorOf([&] { generate(knots, PlannerLimits()); }), "knots[3]: "));

  TrajectoryRequest samples = line();
  samples.sample_times = { 0.0, 3e9 };
  EXPECT_TRUE(startsWith(errorOf([&] { generate(samples, PlannerLimits()); }), "sample_times[1]: "));
}

// Row 14: a tiny bound stretches time without limit; the error names the bound.
TEST(HostileTimes, TinyBoundsNameTheBound)
{
  const std::pair<double TrajectoryRequest::*, const char*> bounds[] = {
    { &TrajectoryRequest::max_linear_velocity, "max_linear_velocity: " },
    { &TrajectoryRequest::max_linear_acceleration, "max_linear_acceleration: " },
  };
  for (const auto& b : bounds)
    for (double tiny : { 1e-300, 1e-20 })
    {
      // p(t) = t + t^2 / 2 along x: peak speed 3 m/s, acceleration 1 m/s^2, so these
      // bounds stretch its 2 s beyond 2^31 s.
      TrajectoryRequest r = line();
      r.waypoints = { pose(0, 0, 0), pose(1, 0, 0), pose(4, 0, 0) };
      r.curve = "bezier";
      r.times = { 0.0, 1.0, 2.0 };
      r.*(b.first) = tiny;
      const std::string e = errorOf([&] { generate(r, PlannerLimits()); });
      EXPECT_TRUE(startsWith(e, b.second)) << tiny << ": " << e;
    }
  // A 1 m/s line bounded to 1e-6 m/s lasts 2e6 s: stretched, within range, accepted.
  TrajectoryRequest slow = line();
  slow.times = { 0.0, 1.0, 2.0 };
  slow.max_linear_velocity = 1e-6;
  EXPECT_NEAR(generate(slow, PlannerLimits()).duration, 2e6, 1e-3);
}

// Row 1: stamp + every time must be a ros::Time (unsigned 32-bit seconds, >= 0).
TEST(HostileTimes, StampedSpanWithinRosTime)
{
  EXPECT_EQ(errorOf([] { validateStampedSpan(1.7e9, 0.0, 10.0, "waypoints.header.stamp"); }), "");
  EXPECT_EQ(errorOf([] { validateStampedSpan(4294967285.0, 0.0, 10.0, "waypoints.header.stamp"); }), "");
  EXPECT_TRUE(startsWith(errorOf([] { validateStampedSpan(3.95e9, 0.0, 4e8, "waypoints.header.stamp"); }),
                         "waypoints.header.stamp: "));
  EXPECT_TRUE(startsWith(errorOf([] { validateStampedSpan(4294967290.0, 0.0, 10.0, "waypoints.header.stamp"); }),
                         "waypoints.header.stamp: "));
  EXPECT_TRUE(startsWith(errorOf([] { validateStampedSpan(5.0, -10.0, 1.0, "waypoints.header.stamp"); }),
                         "waypoints.header.stamp: "));
  EXPECT_TRUE(startsWith(errorOf([] { validateStampedSpan(5e9, 0.0, 1.0, "waypoints.header.stamp"); }),
                         "waypoints.header.stamp: "));
}

// Row 13: sample_period always includes both ends, whatever its size.
TEST(HostileSampling, SamplePeriodIncludesBothEnds)
{
  for (double period : { 2.0, 3.0, 1e9, 1e300 })
  {
    TrajectoryRequest r = line();
    r.times = { -5.0, -4.0, -3.0 };
    r.sample_period = period;
    const TrajectoryResult out = generate(r, PlannerLimits());
    ASSERT_EQ(out.samples.size(), 2u) << period;
    EXPECT_EQ(out.samples.front().time, -5.0) << period;
    EXPECT_EQ(out.samples.back().time, -3.0) << period;
    EXPECT_NEAR(out.samples.front().pose.p.x(), 0.0, 1e-15);
    EXPECT_NEAR(out.samples.back().pose.p.x(), 2.0, 1e-15);
  }
  TrajectoryRequest r = line();
  r.times = { 0.0, 1.0, 2.0 };
  r.sample_period = 0.75;
  const TrajectoryResult out = generate(r, PlannerLimits());
  const double expected[] = { 0.0, 0.75, 1.5, 2.0 };
  ASSERT_EQ(out.samples.size(), 4u);
  for (int i = 0; i < 4; ++i)
  {
    EXPECT_NEAR(out.samples[i].time, expected[i], 1e-15);
    EXPECT_NEAR(out.samples[i].pose.p.x(), expected[i], 1e-14);
  }
}

// Row 16: samples closer than 1 ns would repeat time_from_start; the field is named.
TEST(HostileSampling, SpacingBelowOneNanosecondIsRefused)
{
  TrajectoryRequest count = line();
  count.times = { 0.0, 0.5e-6, 1e-6 };
  count.sample_count = 10000;  // 1e-10 s apart
  EXPECT_TRUE(startsWith(errorOf([&] { generate(count, PlannerLimits()); }), "sample_count: "));

  TrajectoryRequest period = line();
  period.sample_period = 1e-10;
  period.sample_count = 0;
  EXPECT_TRUE(startsWith(errorOf([&] { generate(period, PlannerLimits()); }), "sample_period: "));

  TrajectoryRequest times = line();
  times.times = { 0.0, 1.0, 2.0 };
  times.sample_times = { 0.0, 0.5, 0.5 + 1e-10 };
  EXPECT_TRUE(startsWith(errorOf([&] { generate(times, PlannerLimits()); }), "sample_times[2]: "));

  // Far from 0, double precision is coarser than 1 ns: even spacing cannot be represented.
  TrajectoryRequest late = line();
  late.times = { 2e9, 2e9 + 1e-5, 2e9 + 2e-5 };
  late.sample_count = 1000;
  EXPECT_TRUE(startsWith(errorOf([&] { generate(late, PlannerLimits()); }), "sample_count: "));

  // Exactly 1 ns apart: accepted, and the rounded nanoseconds (time_from_start) all differ.
  TrajectoryRequest fine = line();
  fine.times = { 0.0, 0.5e-6, 1e-6 };
  fine.sample_count = 1001;
  const TrajectoryResult out = generate(fine, PlannerLimits());
  std::set<long long> nanoseconds;
  for (const TrajectorySample& s : out.samples)
    nanoseconds.insert(std::llround(s.time * 1e9));
  EXPECT_EQ(nanoseconds.size(), 1001u);
  // Repeated explicit sample times stay allowed (a dwell of the sampling, not of the curve).
  TrajectoryRequest repeated = line();
  repeated.times = { 0.0, 1.0, 2.0 };
  repeated.sample_times = { 0.5, 0.5, 1.0 };
  EXPECT_EQ(generate(repeated, PlannerLimits()).samples.size(), 3u);
}

// Rows 3, 5, 15, 17: frame ids are short and printable; messages quote a bounded prefix.
TEST(HostileFrameIds, LongAndControlCharacterIdsAreRefusedWithABoundedMessage)
{
  EXPECT_EQ(errorOf([] { validateFrameId(std::string(256, 'a'), "child_frame_id"); }), "");
  EXPECT_EQ(errorOf([] { validateFrameId("base_link", "child_frame_id"); }), "");
  const std::string huge(1000000, 'x');
  const std::string e = errorOf([&] { validateFrameId(huge, "child_frame_id"); });
  EXPECT_TRUE(startsWith(e, "child_frame_id: ")) << e.substr(0, 200);
  EXPECT_LT(e.size(), 200u);
  EXPECT_NE(e.find("1000000 characters"), std::string::npos) << e.substr(0, 200);
  EXPECT_TRUE(startsWith(errorOf([] { validateFrameId(std::string(257, 'a'), "f"); }), "f: "));

  for (const std::string& id : { std::string("a\0b", 3), std::string("bell\a"), std::string("esc\x1b[2J"),
                                std::string("del\x7f") })
  {
    const std::string m = errorOf([&] { validateFrameId(id, "waypoints.header.frame_id"); });
    EXPECT_TRUE(startsWith(m, "waypoints.header.frame_id: ")) << m;
    EXPECT_NE(m.find("control character"), std::string::npos) << m;
    for (char c : m)
      EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "unprintable byte " << static_cast<int>(c) << " in " << m;
  }
  EXPECT_NE(errorOf([] { validateFrameId("/map", "f"); }).find("leading slash"), std::string::npos);
  EXPECT_NE(errorOf([] { validateFrameId("a b", "f"); }).find("white space"), std::string::npos);
  EXPECT_EQ(quotedText("abc"), "'abc'");
  EXPECT_EQ(quotedText(std::string("\x01\xff", 2)), "'\\x01\\xFF'");
  EXPECT_EQ(quotedText(std::string(41, 'z')), "'" + std::string(40, 'z') + "'... (41 characters)");
}

// Found by fuzz_validate: a denormal sample_period gave an infinite work estimate; it is refused
// by validation, naming the field, before any estimate.
TEST(HostileSampling, DenormalSamplePeriodIsRefusedByValidation)
{
  TrajectoryRequest r = line();
  r.sample_period = 4.9406564584124654e-324;
  const std::string e = errorOf([&] { validateRequest(r, PlannerLimits()); });
  EXPECT_TRUE(startsWith(e, "sample_period: ")) << e;
  EXPECT_NE(e.find("1 ns resolution"), std::string::npos) << e;
}

// The node validates its string parameters with the same parsers as the request:
// every accepted name round-trips through toString, and a near miss is refused naming the
// field given (a parameter, not a request field) and listing the known names.
TEST(HostileNames, ParsersNameTheGivenFieldAndListTheKnownNames)
{
  for (const char* name : { "piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended" })
    EXPECT_STREQ(toString(parseName(name, "~curve", CurveType::kBezier)), name);
  for (const char* name : { "double_geodesic", "screw" })
    EXPECT_STREQ(toString(parseName(name, "~geometry", GeometryType::kScrew)), name);
  EXPECT_EQ(parseName("", "~curve", RequestDefaults::kCurve), CurveType::kInterpolating);
  EXPECT_EQ(parseName("", "~parameterization", RequestDefaults::kParameterization), Parameterization::kChord);
  EXPECT_EQ(parseName("uniform", "~parameterization", RequestDefaults::kParameterization), Parameterization::kUniform);
  EXPECT_EQ(parseName("centripetal", "~parameterization", RequestDefaults::kParameterization), Parameterization::kCentripetal);

  const std::string curve = errorOf([] { parseName("bspine", "~curve", RequestDefaults::kCurve); });
  EXPECT_EQ(curve.rfind("~curve: unknown value 'bspine'", 0), 0u) << curve;
  EXPECT_NE(curve.find("bspline"), std::string::npos) << curve;
  const std::string geometry = errorOf([] { parseName("Screw", "~geometry", RequestDefaults::kGeometry); });
  EXPECT_EQ(geometry.rfind("~geometry: unknown value 'Screw'", 0), 0u) << geometry;
  const std::string chord = errorOf([] { parseName("chordal", "~parameterization", RequestDefaults::kParameterization); });
  EXPECT_EQ(chord.rfind("~parameterization: unknown value 'chordal'", 0), 0u) << chord;
  // The request path still names the request's field.
  TrajectoryRequest r = line();
  r.curve = "bspine";
  const std::string request = errorOf([&] { generate(r, PlannerLimits()); });
  EXPECT_EQ(request.rfind("curve: unknown value 'bspine'", 0), 0u) << request;
}
