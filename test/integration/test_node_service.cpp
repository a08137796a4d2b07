// Integration: a real roscore and se3_interpolation_node; service calls for every curve and
// geometry, bad requests answered with success=false while the node keeps serving, the request's
// `outputs` choosing the response's sample arrays, and the latched ~path reaching a late subscriber.
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <ros/serialization.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/GenerationStatus.h"

#include "node_test_utils.h"

using namespace node_test;

namespace
{
const char* const kService = "/se3_interpolation_node/generate";

se3_interpolation::GenerateTrajectory goodRequest()
{
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  srv.request.waypoints.poses = { pose(0, 0, 0, 0), pose(1, 0, 0, 0.5), pose(1, 1, 0.5, 1.5), pose(0, 2, 1, 2.5) };
  srv.request.sample_count = 50;
  return srv;
}

/// goodRequest() as an interpolating spline timed time_optimal under 0.5 m/s, 0.8 rad/s, 1 m/s²,
/// 2 rad/s².
se3_interpolation::GenerateTrajectory timeOptimalRequest()
{
  auto srv = goodRequest();
  srv.request.curve = "interpolating";
  srv.request.timing = "time_optimal";
  srv.request.max_linear_velocity = 0.5;
  srv.request.max_angular_velocity = 0.8;
  srv.request.max_linear_acceleration = 1.0;
  srv.request.max_angular_acceleration = 2.0;
  return srv;
}

bool call(se3_interpolation::GenerateTrajectory& srv)
{
  return node_test::callService(kService, srv);
}
}  // namespace

TEST(NodeService, EveryCurveAndGeometry)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  for (const char* curve : { "piecewise_geodesic", "bezier", "bspline" })
    for (const char* geometry : { "double_geodesic", "screw" })
    {
      auto srv = goodRequest();
      srv.request.curve = curve;
      srv.request.geometry = geometry;
      srv.request.duration = 4.0;
      ASSERT_TRUE(call(srv));
      ASSERT_TRUE(srv.response.success) << curve << "/" << geometry << ": " << srv.response.message;
      ASSERT_EQ(srv.response.path.poses.size(), 50U);
      ASSERT_EQ(srv.response.trajectory.points.size(), 50U);
      EXPECT_EQ(srv.response.path.header.frame_id, "map");
      EXPECT_EQ(srv.response.trajectory.joint_names.at(0), "interpolated");
      EXPECT_NEAR(srv.response.duration, 4.0, 1e-12);
      // Starts at the first waypoint and ends at the last.
      const auto& first = srv.response.path.poses.front().pose.position;
      const auto& last = srv.response.path.poses.back().pose.position;
      EXPECT_NEAR(first.x, 0.0, 1e-12);
      EXPECT_NEAR(last.y, 2.0, 1e-12);
      EXPECT_NEAR(last.z, 1.0, 1e-12);
      EXPECT_NEAR(srv.response.trajectory.points.back().time_from_start.toSec(), 4.0, 1e-6);
      EXPECT_GT(srv.response.length, 2.0);
      EXPECT_GT(srv.response.max_linear_speed, 0.0);
      EXPECT_EQ(srv.response.trajectory.points[10].velocities.size(), 1U);
      EXPECT_EQ(srv.response.trajectory.points[10].accelerations.size(), 1U);
    }
}

TEST(NodeService, TimeOptimalTimingWithinTheBounds)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto srv = timeOptimalRequest();
  srv.request.sample_count = 500;
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const auto& points = srv.response.trajectory.points;
  ASSERT_EQ(points.size(), 500U);
  EXPECT_NEAR(points.back().time_from_start.toSec() - points.front().time_from_start.toSec(), srv.response.duration,
              1e-6);
  EXPECT_LE(srv.response.max_linear_speed, 0.5 * (1 + 1e-9));
  EXPECT_LE(srv.response.max_angular_speed, 0.8 * (1 + 1e-9));
  for (const auto& p : points)
  {
    const auto& v = p.velocities.at(0);
    const auto& a = p.accelerations.at(0);
    EXPECT_LE(std::hypot(v.linear.x, v.linear.y, v.linear.z), 0.5 * (1 + 1e-9));
    EXPECT_LE(std::hypot(a.linear.x, a.linear.y, a.linear.z), 1.0 * (1 + 1e-9));
    EXPECT_LE(std::hypot(a.angular.x, a.angular.y, a.angular.z), 2.0 * (1 + 1e-9));
  }
  const auto& v0 = points.front().velocities.at(0).linear;
  EXPECT_EQ(std::hypot(v0.x, v0.y, v0.z), 0.0);
  // Faster than the uniform stretch of the same path under the same bounds.
  auto stretched = srv;
  stretched.request.timing = "stretch";
  ASSERT_TRUE(call(stretched));
  ASSERT_TRUE(stretched.response.success) << stretched.response.message;
  EXPECT_LT(srv.response.duration, stretched.response.duration);
  // A pure rotation with linear bounds only: an error naming the missing bound.
  auto bad = goodRequest();
  bad.request.waypoints.poses = { pose(0, 0, 0, 0), pose(0, 0, 0, 1) };
  bad.request.timing = "time_optimal";
  bad.request.max_linear_velocity = 1.0;
  bad.request.max_linear_acceleration = 1.0;
  ASSERT_TRUE(call(bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_EQ(bad.response.message.find("max_angular_velocity"), 0U) << bad.response.message;
}

// Jerk bounds through the service: the response's peaks are the motion's (differences of the
// trajectory's accelerations stay within the bound and reach near it), ~status carries them, and a
// negative jerk bound is an error naming the field while the node keeps serving.
TEST(NodeService, JerkBoundsAndTheirPeaks)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto srv = timeOptimalRequest();
  srv.request.max_linear_jerk = 4.0;
  srv.request.max_angular_jerk = 8.0;
  srv.request.sample_count = 0;
  srv.request.sample_period = 0.002;
  srv.request.publish = true;
  ros::NodeHandle nh;
  se3_interpolation::GenerationStatus::ConstPtr status;
  ros::Subscriber sub = nh.subscribe<se3_interpolation::GenerationStatus>(
      "/se3_interpolation_node/status", 10, [&status](const se3_interpolation::GenerationStatus::ConstPtr& m) {
        if (m->peak_linear_jerk > 0.0)
          status = m;
      });
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const auto& points = srv.response.trajectory.points;
  ASSERT_GT(points.size(), 1000U);
  double jerk = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i)
  {
    const auto& a = points[i].accelerations.at(0).linear;
    const auto& b = points[i - 1].accelerations.at(0).linear;
    const double dt = (points[i].time_from_start - points[i - 1].time_from_start).toSec();
    jerk = std::max(jerk, std::hypot(a.x - b.x, a.y - b.y, a.z - b.z) / dt);
  }
  EXPECT_LE(jerk, 4.0 * (1 + 1e-6));
  EXPECT_LE(srv.response.peak_linear_jerk, 4.0 * (1 + 1e-6));
  EXPECT_GE(srv.response.peak_linear_jerk, jerk * (1 - 1e-6));
  EXPECT_LE(srv.response.peak_angular_jerk, 8.0 * (1 + 1e-6));
  EXPECT_LE(srv.response.peak_linear_acceleration, 1.0 * (1 + 1e-6));
  EXPECT_GT(srv.response.peak_linear_acceleration, 0.0);
  EXPECT_TRUE(spinUntil([&status] { return status != nullptr; }, 10.0));
  if (status)
  {
    EXPECT_EQ(status->peak_linear_jerk, srv.response.peak_linear_jerk);
    EXPECT_EQ(status->peak_angular_acceleration, srv.response.peak_angular_acceleration);
  }
  auto bad = goodRequest();
  bad.request.max_angular_jerk = -1.0;
  ASSERT_TRUE(call(bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_EQ(bad.response.message.rfind("max_angular_jerk: ", 0), 0U) << bad.response.message;
  auto good = goodRequest();
  ASSERT_TRUE(call(good));
  EXPECT_TRUE(good.response.success) << good.response.message;
}

// timing constant_speed through the service: the trajectory's chord speed √(|v|² + |ω|²) is
// `speed` at every point of the response's window [constant_speed_start, constant_speed_end], the
// window is on ~status, and a request without the ramps' bound is an error naming it while the
// node keeps serving.
TEST(NodeService, ConstantSpeedAndItsWindow)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto srv = goodRequest();
  srv.request.curve = "interpolating";
  srv.request.timing = "constant_speed";
  srv.request.speed = 0.2;
  srv.request.max_linear_acceleration = 1.0;
  srv.request.sample_count = 0;
  srv.request.sample_period = 0.01;
  srv.request.publish = true;
  ros::NodeHandle nh;
  se3_interpolation::GenerationStatus::ConstPtr status;
  ros::Subscriber sub = nh.subscribe<se3_interpolation::GenerationStatus>(
      "/se3_interpolation_node/status", 10, [&status](const se3_interpolation::GenerationStatus::ConstPtr& m) {
        if (m->constant_speed_end > 0.0)
          status = m;
      });
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const double a = srv.response.constant_speed_start, b = srv.response.constant_speed_end;
  EXPECT_GT(a, 0.0);
  EXPECT_GT(b, a + 5.0);
  EXPECT_LT(b, srv.response.duration);
  std::size_t inside = 0;
  for (const auto& p : srv.response.trajectory.points)
  {
    const double t = p.time_from_start.toSec();
    if (t <= a || t >= b)
      continue;
    ++inside;
    const auto& v = p.velocities.at(0);
    EXPECT_NEAR(std::hypot(std::hypot(v.linear.x, v.linear.y, v.linear.z), std::hypot(v.angular.x, v.angular.y, v.angular.z)),
                0.2, 1e-6) << t;
  }
  EXPECT_GT(inside, 500U);
  EXPECT_TRUE(spinUntil([&status] { return status != nullptr; }, 10.0));
  if (status)
  {
    EXPECT_EQ(status->constant_speed_start, a);
    EXPECT_EQ(status->constant_speed_end, b);
  }
  auto bad = srv;
  bad.request.max_linear_acceleration = 0.0;
  bad.request.publish = false;
  ASSERT_TRUE(call(bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_EQ(bad.response.message.rfind("max_linear_acceleration: ", 0), 0U) << bad.response.message;
  auto good = goodRequest();
  ASSERT_TRUE(call(good));
  EXPECT_TRUE(good.response.success) << good.response.message;
}

TEST(NodeServiceDefaults, TimingAndBoundsFromTheNodeParameters)
{
  // Run by node_service_defaults.test (node with ~timing: time_optimal, ~max_linear_velocity 0.5,
  // ~max_linear_acceleration 2); skipped in node_service.test.
  if (!ros::NodeHandle("~").param("node_defaults", false))
    GTEST_SKIP() << "needs the node parameters of node_service_defaults.test";
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto srv = goodRequest();
  srv.request.waypoints.poses = { pose(0, 0, 0, 0), pose(3, 0, 0, 0) };
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  // The closed-form trapezoid 3/0.5 + 0.5/2 s, at 0.5 m/s.
  EXPECT_NEAR(srv.response.duration, 6.25, 0.005 * 6.25);
  EXPECT_NEAR(srv.response.max_linear_speed, 0.5, 1e-6);
  // A request's own fields win.
  srv.request.timing = "stretch";
  srv.request.max_linear_velocity = 1.5;
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_NEAR(srv.response.max_linear_speed, 1.5, 1e-9);

  // An error caused by a field the node filled from its parameter names that parameter: 15000
  // waypoints of a screw hermite timed time_optimal are refused by the work estimate (about 2.6 s),
  // naming timing. (The node's default curve is refused by the deadline instead since the timing
  // got faster, in whichever phase the deadline falls: not a fixed message.)
  auto heavy = goodRequest();
  heavy.request.waypoints.poses.clear();
  for (int i = 0; i < 15000; ++i)
    heavy.request.waypoints.poses.push_back(pose(0.1 * i, 0.05 * (i % 7), 0, 0.01 * (i % 5)));
  heavy.request.curve = "hermite";
  heavy.request.geometry = "screw";
  heavy.request.timing = "time_optimal";
  ASSERT_TRUE(call(heavy));
  ASSERT_FALSE(heavy.response.success);
  const std::string explicit_message = heavy.response.message;
  ASSERT_EQ(explicit_message.rfind("timing: 'time_optimal'", 0), 0u) << explicit_message;
  heavy.request.timing.clear();
  ASSERT_TRUE(call(heavy));
  ASSERT_FALSE(heavy.response.success);
  EXPECT_EQ(heavy.response.message,
            "~" + explicit_message + " (the node's parameter, used for the request's empty timing)");
}

TEST(NodeService, BadRequestsFailCleanlyAndTheNodeKeepsServing)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  struct Case
  {
    const char* name;
    std::function<void(se3_interpolation::GenerateTrajectory&)> spoil;
    const char* expected;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Case cases[] = {
    { "NaN position", [nan](auto& s) { s.request.waypoints.poses[2].position.y = nan; }, "waypoints[2].position.y" },
    { "Inf time", [](auto& s) { s.request.times = { 0, 1, std::numeric_limits<double>::infinity(), 3 }; },
      "times[2]" },
    { "zero quaternion", [](auto& s) { s.request.waypoints.poses[1].orientation = geometry_msgs::Quaternion(); },
      "waypoints[1].orientation" },
    { "one waypoint", [](auto& s) { s.request.waypoints.poses.resize(1); }, "waypoints" },
    // No poses means "use the buffer"; nothing was sent to ~waypoint(s) here, so it is empty.
    { "no waypoints, empty buffer", [](auto& s) { s.request.waypoints.poses.clear(); },
      "waypoints: 0 given and the ~waypoint buffer is empty; at least 2 are needed" },
    { "unknown curve", [](auto& s) { s.request.curve = "catmull_rom"; }, "curve" },
    { "unknown geometry", [](auto& s) { s.request.geometry = "euler"; }, "geometry" },
    { "bad knots", [](auto& s) { s.request.curve = "bspline"; s.request.knots = { 0, 1 }; }, "knots" },
    // Refused up front by ~max_work_seconds instead of computing for seconds.
    { "heavy bezier",
      [](auto& s) {
        s.request.curve = "bezier";
        s.request.waypoints.poses.clear();
        for (int i = 0; i < 250; ++i)
          s.request.waypoints.poses.push_back(pose(std::cos(0.1 * i), std::sin(0.1 * i), 0.01 * i, 0.02 * i));
      },
      "waypoints: 250 waypoints make a bezier of degree 249" },
    // outputs: only the names of the response's sample arrays, each once.
    { "unknown output", [](auto& s) { s.request.outputs = { "trajectory", "markers" }; },
      "outputs[1]: unknown value 'markers' (expected one of: path, trajectory, joint_trajectory)" },
    { "repeated output", [](auto& s) { s.request.outputs = { "path", "path" }; }, "outputs[1]: 'path' is named twice" },
    { "empty output name", [](auto& s) { s.request.outputs = { "" }; }, "outputs[0]: empty name" },
  };
  for (const auto& c : cases)
  {
    auto bad = goodRequest();
    c.spoil(bad);
    bad.request.publish = true;
    ASSERT_TRUE(call(bad)) << c.name;  // the call itself succeeds: the error is in the response
    EXPECT_FALSE(bad.response.success) << c.name;
    EXPECT_NE(bad.response.message.find(c.expected), std::string::npos) << c.name << ": " << bad.response.message;
    EXPECT_TRUE(bad.response.path.poses.empty()) << c.name;

    auto good = goodRequest();
    ASSERT_TRUE(call(good)) << "after " << c.name;
    EXPECT_TRUE(good.response.success) << "after " << c.name << ": " << good.response.message;
  }
}

TEST(NodeService, BlendRadiusFromTheRequestOrTheNodeDefault)
{
  // goodRequest's polyline: legs of 1, sqrt(1.25) and 1.5 m. Blends cut every interior corner.
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  const double polyline_length = 1.0 + std::sqrt(1.25) + 1.5;
  auto srv = goodRequest();
  srv.request.curve = "piecewise_geodesic";
  srv.request.blend_radius = 0.3;
  srv.request.publish = true;
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_LT(srv.response.length, polyline_length - 1e-3);
  const auto& last = srv.response.path.poses.back().pose.position;
  EXPECT_NEAR(last.y, 2.0, 1e-12);  // the last waypoint is still reached

  // The markers show a translucent sphere of radius r_i = 0.3 m at each blended corner.
  ros::NodeHandle nh;
  visualization_msgs::MarkerArray markers;
  bool got = false;
  ros::Subscriber sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/se3_interpolation_node/markers", 1, [&](const visualization_msgs::MarkerArray::ConstPtr& msg) {
        markers = *msg;
        got = true;
      });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!got && ros::WallTime::now() < deadline)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_TRUE(got);
  int zones = 0;
  for (const auto& m : markers.markers)
    if (m.ns == "blend_zones")
    {
      ++zones;
      EXPECT_EQ(m.type, visualization_msgs::Marker::SPHERE);
      EXPECT_NEAR(m.scale.x, 0.6, 1e-12);
      EXPECT_LT(m.color.a, 1.0F);
    }
  EXPECT_EQ(zones, 2);

  // Without a blend_radius the node's ~blend_radius (0.1 m in node_service.test) applies, to
  // piecewise_geodesic only: other curves are not refused because of the node's default.
  auto by_default = goodRequest();
  by_default.request.curve = "piecewise_geodesic";
  ASSERT_TRUE(call(by_default));
  ASSERT_TRUE(by_default.response.success) << by_default.response.message;
  EXPECT_LT(by_default.response.length, polyline_length - 1e-4);
  EXPECT_GT(by_default.response.length, srv.response.length);
  auto bezier = goodRequest();
  bezier.request.curve = "bezier";
  ASSERT_TRUE(call(bezier));
  EXPECT_TRUE(bezier.response.success) << bezier.response.message;

  for (double bad_radius : { -0.1, std::numeric_limits<double>::quiet_NaN() })
  {
    auto bad = goodRequest();
    bad.request.blend_radius = bad_radius;
    ASSERT_TRUE(call(bad));
    EXPECT_FALSE(bad.response.success);
    EXPECT_EQ(bad.response.message.rfind("blend_radius", 0), 0U) << bad.response.message;
  }
  auto other = goodRequest();
  other.request.curve = "interpolating";
  other.request.blend_radius = 0.2;
  ASSERT_TRUE(call(other));
  EXPECT_FALSE(other.response.success);
  EXPECT_EQ(other.response.message.rfind("blend_radius", 0), 0U) << other.response.message;
}

/// The serialised bytes of a message: equal bytes, equal messages (every field, every sample).
template <class M>
std::vector<std::uint8_t> bytes(const M& msg)
{
  const ros::SerializedMessage m = ros::serialization::serializeMessage(msg);
  return std::vector<std::uint8_t>(m.buf.get(), m.buf.get() + m.num_bytes);
}

TEST(NodeService, OutputsChooseTheSampleArraysOfTheResponse)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  // A fixed stamp: the responses' headers and sample stamps are then the same call to call.
  auto reference = goodRequest();
  reference.request.waypoints.header.stamp = ros::Time(100.0);
  reference.request.curve = "interpolating";
  ASSERT_TRUE(call(reference));
  ASSERT_TRUE(reference.response.success) << reference.response.message;
  ASSERT_EQ(reference.response.path.poses.size(), 50U);
  ASSERT_EQ(reference.response.trajectory.points.size(), 50U);

  auto trajectory_only = reference;
  trajectory_only.response = se3_interpolation::GenerateTrajectory::Response();
  trajectory_only.request.outputs = { "trajectory" };
  ASSERT_TRUE(call(trajectory_only));
  ASSERT_TRUE(trajectory_only.response.success) << trajectory_only.response.message;
  EXPECT_TRUE(trajectory_only.response.path.poses.empty());
  EXPECT_TRUE(trajectory_only.response.path.header.frame_id.empty());
  EXPECT_EQ(bytes(trajectory_only.response.trajectory), bytes(reference.response.trajectory));
  EXPECT_EQ(trajectory_only.response.duration, reference.response.duration);
  EXPECT_EQ(trajectory_only.response.energy, reference.response.energy);

  auto path_only = reference;
  path_only.response = se3_interpolation::GenerateTrajectory::Response();
  path_only.request.outputs = { "path" };
  ASSERT_TRUE(call(path_only));
  ASSERT_TRUE(path_only.response.success) << path_only.response.message;
  EXPECT_TRUE(path_only.response.trajectory.points.empty());
  EXPECT_TRUE(path_only.response.trajectory.joint_names.empty());
  EXPECT_EQ(bytes(path_only.response.path), bytes(reference.response.path));
  EXPECT_EQ(path_only.response.max_linear_speed, reference.response.max_linear_speed);

  auto both = reference;
  both.response = se3_interpolation::GenerateTrajectory::Response();
  both.request.outputs = { "trajectory", "path" };
  ASSERT_TRUE(call(both));
  ASSERT_TRUE(both.response.success) << both.response.message;
  EXPECT_EQ(bytes(both.response), bytes(reference.response));

  // Publishing is not affected: ~path carries every sample although the response omits it.
  auto published = reference;
  published.request.outputs = { "trajectory" };
  published.request.sample_count = 37;
  published.request.publish = true;
  ASSERT_TRUE(call(published));
  ASSERT_TRUE(published.response.success) << published.response.message;
  EXPECT_TRUE(published.response.path.poses.empty());
  ros::NodeHandle nh;
  nav_msgs::Path received;
  bool got = false;
  ros::Subscriber sub = nh.subscribe<nav_msgs::Path>("/se3_interpolation_node/path", 1,
                                                     [&](const nav_msgs::Path::ConstPtr& msg) {
                                                       received = *msg;
                                                       got = received.poses.size() == 37U;
                                                     });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!got && ros::WallTime::now() < deadline)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_TRUE(got) << "the latched ~path has " << received.poses.size() << " poses, not 37";
  EXPECT_EQ(received.header.frame_id, "map");
}

TEST(NodeService, LatchedPathReachesALateSubscriber)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  auto srv = goodRequest();
  srv.request.curve = "bezier";
  srv.request.sample_count = 33;
  srv.request.publish = true;
  ASSERT_TRUE(call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;

  ros::NodeHandle nh;
  nav_msgs::Path received;
  bool got = false;
  ros::Subscriber sub = nh.subscribe<nav_msgs::Path>("/se3_interpolation_node/path", 1,
                                                     [&](const nav_msgs::Path::ConstPtr& msg) {
                                                       received = *msg;
                                                       got = true;
                                                     });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!got && ros::WallTime::now() < deadline)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_TRUE(got);
  EXPECT_EQ(received.poses.size(), 33U);
  EXPECT_EQ(received.header.frame_id, "map");
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_service");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
