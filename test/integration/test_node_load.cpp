// Load: 50 concurrent heavy service requests while the moving TF frame is watched. Every
// response must be correct, and the TF timer (own callback queue and thread) must keep its
// rate: generation never starves the broadcast. Bounded work: a request the up-front estimate
// accepts but whose work is several times ~max_work_seconds is stopped by the deadline inside the
// computation, while another client keeps being served.
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

#include "node_test_utils.h"
#include "se3_interpolation/GenerateTrajectory.h"

namespace
{
const std::string kService = "/se3_interpolation_node/generate";

se3_interpolation::GenerateTrajectory heavyRequest(int k)
{
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  const int n = 400;
  for (int i = 0; i < n; ++i)
  {
    geometry_msgs::Pose p;
    p.position.x = std::cos(0.05 * i) * (1 + 0.01 * k);
    p.position.y = std::sin(0.05 * i);
    p.position.z = 0.01 * i;
    p.orientation.z = std::sin(0.02 * i);
    p.orientation.w = std::cos(0.02 * i);
    srv.request.waypoints.poses.push_back(p);
  }
  srv.request.curve = k % 2 == 0 ? "bspline" : "piecewise_geodesic";
  srv.request.geometry = k % 3 == 0 ? "screw" : "double_geodesic";
  srv.request.duration = 20.0;
  srv.request.sample_count = 20000;
  return srv;
}

const std::string kLimitParam = "/se3_interpolation_node/max_work_seconds";

/// A request the work estimate (planner/work_estimate.h) under-predicts about fivefold, so that
/// it passes the up-front check and only the deadline inside the computation (deadline.h) stops it:
/// time_optimal timing of a corner-blended (blend_radius) screw polyline whose legs alternate
/// between a rotation with a translation of ~0.5 m and the same kind of rotation with a
/// translation of ~1e-8 m. 15000 waypoints: accepted by the estimate under the default limit of
/// 1 s, measured 3.4 s through the CLI without a limit (3.0 s of it generate(): 3 times the
/// limit), refused with "ran past its work limit" under the limit after 1.5 s. Sized again
/// whenever the timing gets faster: 1000 waypoints with 1e-6 m legs took 3.3 s when this test was
/// written, 1.5 s after the time-optimal timing's speed-ups, and then finished within the deadline
/// of a CI run; 2000 took 4.1 s, and 2.2 s once the timings measured only the path's lengths; 3000
/// took 3.4 s, and 0.65 s once a corner blend became one exp per point.
se3_interpolation::GenerateTrajectory overLimitRequest(int n = 15000)
{
  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  // world_T_body composed leg by leg: p += R(q) step, q = q * dq (quaternions as x, y, z, w).
  double q[4] = { 0.0, 0.0, 0.0, 1.0 };
  double p[3] = { 0.0, 0.0, 0.0 };
  auto push = [&] {
    geometry_msgs::Pose w;
    w.position.x = p[0];
    w.position.y = p[1];
    w.position.z = p[2];
    w.orientation.x = q[0];
    w.orientation.y = q[1];
    w.orientation.z = q[2];
    w.orientation.w = q[3];
    srv.request.waypoints.poses.push_back(w);
  };
  push();
  for (int i = 1; i < n; ++i)
  {
    const double k = i;
    double axis[3] = { std::sin(1.7 * k) + 0.1, std::cos(2.3 * k), std::sin(0.9 * k + 1.0) };
    const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    const double angle = 0.2 + 0.4 * (1.0 + std::sin(3.1 * k));
    const double s = std::sin(0.5 * angle) / norm;
    const double d[4] = { s * axis[0], s * axis[1], s * axis[2], std::cos(0.5 * angle) };
    const double f = 1e-8;
    const double step[3] = { i % 2 ? f * std::cos(k) : 0.5 * std::cos(1.3 * k),
                             i % 2 ? f * std::sin(k) : 0.5 * std::sin(0.7 * k),
                             i % 2 ? 0.5 * f : 0.5 * std::cos(2.9 * k) };
    // R(q) step = step + 2 w (v x step) + 2 v x (v x step), v = (x, y, z).
    const double* v = q;
    const double c1[3] = { v[1] * step[2] - v[2] * step[1], v[2] * step[0] - v[0] * step[2],
                           v[0] * step[1] - v[1] * step[0] };
    const double c2[3] = { v[1] * c1[2] - v[2] * c1[1], v[2] * c1[0] - v[0] * c1[2], v[0] * c1[1] - v[1] * c1[0] };
    for (int j = 0; j < 3; ++j)
      p[j] += step[j] + 2.0 * q[3] * c1[j] + 2.0 * c2[j];
    const double r[4] = { q[3] * d[0] + q[0] * d[3] + q[1] * d[2] - q[2] * d[1],
                          q[3] * d[1] - q[0] * d[2] + q[1] * d[3] + q[2] * d[0],
                          q[3] * d[2] + q[0] * d[1] - q[1] * d[0] + q[2] * d[3],
                          q[3] * d[3] - q[0] * d[0] - q[1] * d[1] - q[2] * d[2] };
    const double rn = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    for (int j = 0; j < 4; ++j)
      q[j] = r[j] / rn;
    push();
  }
  srv.request.curve = "piecewise_geodesic";
  srv.request.geometry = "screw";
  srv.request.blend_radius = 0.3;
  srv.request.timing = "time_optimal";
  srv.request.max_linear_velocity = 0.5;
  srv.request.max_angular_velocity = 0.5;
  srv.request.max_linear_acceleration = 1.0;
  srv.request.max_angular_acceleration = 1.0;
  return srv;
}

se3_interpolation::GenerateTrajectory lightRequest()
{
  se3_interpolation::GenerateTrajectory srv = heavyRequest(1);
  srv.request.waypoints.poses.resize(4);
  srv.request.sample_count = 10;
  return srv;
}
}  // namespace

TEST(NodeLoad, ConcurrentHeavyRequestsDoNotStarveTf)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));

  // Start the moving frame with a light trajectory.
  auto light = heavyRequest(0);
  light.request.sample_count = 10;
  light.request.publish = true;
  ASSERT_TRUE(node_test::callService(kService, light));
  ASSERT_TRUE(light.response.success) << light.response.message;

  // Watch /tf on a dedicated queue and thread so the clients below cannot delay us.
  ros::CallbackQueue queue;
  ros::NodeHandle watch_nh;
  watch_nh.setCallbackQueue(&queue);
  std::mutex mutex;
  std::vector<ros::Time> stamps;
  std::vector<ros::WallTime> arrivals;
  ros::Subscriber sub = watch_nh.subscribe<tf2_msgs::TFMessage>("/tf", 1000, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
    for (const auto& t : m->transforms)
      if (t.child_frame_id == "interpolated")
      {
        std::lock_guard<std::mutex> lock(mutex);
        stamps.push_back(t.header.stamp);
        arrivals.push_back(ros::WallTime::now());
      }
  });
  ros::AsyncSpinner spinner(1, &queue);
  spinner.start();
  ros::WallDuration(1.0).sleep();

  const ros::WallTime start = ros::WallTime::now();
  std::atomic<int> ok{ 0 };
  std::vector<std::string> errors(50);
  std::vector<std::thread> clients;
  for (int k = 0; k < 50; ++k)
    clients.emplace_back([k, &ok, &errors] {
      auto srv = heavyRequest(k);
      if (!node_test::callService(kService, srv))
      {
        errors[k] = "call failed";
        return;
      }
      const auto& r = srv.response;
      const auto& last = r.path.poses.empty() ? geometry_msgs::PoseStamped() : r.path.poses.back();
      const auto& end = srv.request.waypoints.poses.back().position;
      if (!r.success)
        errors[k] = r.message;
      else if (r.path.poses.size() != 20000 || r.trajectory.points.size() != 20000)
        errors[k] = "wrong sample count";
      else if (std::abs(last.pose.position.x - end.x) > 1e-9 || std::abs(last.pose.position.z - end.z) > 1e-9)
        errors[k] = "does not end at the last waypoint";
      else if (std::abs(r.duration - 20.0) > 1e-9)
        errors[k] = "wrong duration";
      else
        ++ok;
    });
  for (auto& c : clients)
    c.join();
  const double elapsed = (ros::WallTime::now() - start).toSec();
  spinner.stop();
  for (int k = 0; k < 50; ++k)
    EXPECT_TRUE(errors[k].empty()) << "request " << k << ": " << errors[k];
  EXPECT_EQ(ok.load(), 50);

  std::lock_guard<std::mutex> lock(mutex);
  std::size_t during = 0;
  double worst_gap = 0.0;          // between the stamps the node gave (when it published)
  double worst_arrival_gap = 0.0;  // between their arrivals here
  for (std::size_t i = 0; i < arrivals.size(); ++i)
  {
    if (arrivals[i] < start)
      continue;
    ++during;
    if (i > 0)
    {
      EXPECT_GT(stamps[i], stamps[i - 1]);
      worst_gap = std::max(worst_gap, (stamps[i] - stamps[i - 1]).toSec());
      worst_arrival_gap = std::max(worst_arrival_gap, (arrivals[i] - arrivals[i - 1]).toSec());
    }
  }
  const double rate = during / elapsed;
  std::cout << "[load] 50 requests in " << elapsed << " s; moving frame " << rate << " Hz, worst gap " << worst_gap
            << " s between stamps, " << worst_arrival_gap << " s between arrivals" << std::endl;
  EXPECT_GT(elapsed, 0.5) << "the load was too light to mean anything";
  // Nominal 50 Hz. A frame starved by the requests would stop for the whole load (2.4-3.6 s here):
  // the node stamps each transform when it publishes it, so a gap between stamps is the node's, and
  // a gap between arrivals may be this process's or the connection's too. On this 2-core machine
  // under CI's parallel sanitizer build the arrivals' worst gap measured 0.09-0.88 s in 12 runs and
  // 1.54 s once, with the rate at 47 Hz: the transforms had been published on time and arrived in a
  // burst. So the stamps are held to 1.5 s (3x over the arrivals' usual worst) and the arrivals,
  // which must not stall for the whole load either, to 3 s.
  EXPECT_GT(rate, 15.0);
  EXPECT_LT(worst_gap, 1.5);
  EXPECT_LT(worst_arrival_gap, 3.0);
}

// A request sized to about 4x max_work_seconds, accepted by the estimate, ends within 2x the
// limit (the deadline, kDeadlineFactor = 1.5 of it, and the few milliseconds between checks) with
// a refusal naming the work limit, while a second client's light requests are answered throughout;
// afterwards the node still serves. The functional deadline is asserted with a margin for a loaded
// machine (6x the limit: the request's own work is ~4x); no other timing is asserted.
TEST(NodeLoad, RequestPastTheWorkLimitIsStoppedWhileAnotherClientIsServed)
{
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));
  double limit = 0.0;
  ASSERT_TRUE(ros::param::get(kLimitParam, limit)) << kLimitParam << " is not set (node_load.test sets it)";
  ASSERT_GT(limit, 0.0);
  ASSERT_LE(limit, 2.0) << "overLimitRequest is sized for the default limit of 1 s";

  std::atomic<bool> heavy_done{ false };
  std::atomic<int> light_answered{ 0 }, light_during_heavy{ 0 };
  std::vector<std::string> light_errors;
  std::thread light_client([&] {
    while (!heavy_done)
    {
      auto light = lightRequest();
      const bool called = node_test::callService(kService, light);
      const bool during = !heavy_done;
      if (!called || !light.response.success)
        light_errors.push_back(called ? light.response.message : "call failed");
      else
      {
        ++light_answered;
        if (during)
          ++light_during_heavy;
      }
      ros::WallDuration(0.02).sleep();
    }
  });

  auto heavy = overLimitRequest();
  ASSERT_EQ(heavy.request.waypoints.poses.size(), 15000u);
  const ros::WallTime start = ros::WallTime::now();
  const bool called = node_test::callService(kService, heavy);
  const double elapsed = (ros::WallTime::now() - start).toSec();
  heavy_done = true;
  light_client.join();

  ASSERT_TRUE(called);
  const std::string& m = heavy.response.message;
  std::cout << "[bounded work] limit " << limit << " s; refused after " << elapsed << " s: " << m << std::endl;
  EXPECT_FALSE(heavy.response.success) << m;
  // Refused by the deadline inside the computation, not by the estimate up front ("would take
  // about"): if the estimate learns to see this request's cost, pick another one it under-predicts.
  EXPECT_NE(m.find("ran past its work limit"), std::string::npos) << m;
  EXPECT_NE(m.find("max_work_seconds"), std::string::npos) << m;
  EXPECT_EQ(m.find("would take about"), std::string::npos) << m;
  EXPECT_TRUE(heavy.response.path.poses.empty());
  EXPECT_TRUE(heavy.response.trajectory.points.empty());
  // A long loop without checkDeadlineEvery lets the request run on until a later phase checks (the
  // message names that phase). When this test was written, time_optimal's final checks and figures
  // did not check: the 1000-waypoint version of this request ended in "sampling" after ~3.4 s of CPU
  // instead of at 1.5 s.
  EXPECT_LT(elapsed, 6.0 * limit) << "the request ran far past its work limit of " << limit
                                  << " s: a long loop without a deadline check before the phase named in: " << m;

  for (const auto& e : light_errors)
    ADD_FAILURE() << "a light request failed while the heavy one ran: " << e;
  EXPECT_GE(light_during_heavy.load(), 2) << "the light client was not served while the heavy request ran";

  // Afterwards the node still serves.
  auto after = lightRequest();
  ASSERT_TRUE(node_test::callService(kService, after));
  EXPECT_TRUE(after.response.success) << after.response.message;
  EXPECT_EQ(after.response.path.poses.size(), 10u);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_load");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
