// Load: 50 concurrent heavy service requests while the moving TF frame is watched. Every
// response must be correct, and the TF timer (own callback queue and thread) must keep its
// rate: generation never starves the broadcast.
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

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
}  // namespace

TEST(NodeLoad, ConcurrentHeavyRequestsDoNotStarveTf)
{
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(30.0)));

  // Start the moving frame with a light trajectory.
  auto light = heavyRequest(0);
  light.request.sample_count = 10;
  light.request.publish = true;
  ASSERT_TRUE(ros::service::call(kService, light));
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
      if (!ros::service::call(kService, srv))
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
  double worst_gap = 0.0;
  for (std::size_t i = 0; i < arrivals.size(); ++i)
  {
    if (arrivals[i] < start)
      continue;
    ++during;
    if (i > 0)
    {
      EXPECT_GT(stamps[i], stamps[i - 1]);
      worst_gap = std::max(worst_gap, (arrivals[i] - arrivals[i - 1]).toSec());
    }
  }
  const double rate = during / elapsed;
  std::cout << "[load] 50 requests in " << elapsed << " s; moving frame " << rate << " Hz, worst gap " << worst_gap
            << " s" << std::endl;
  EXPECT_GT(elapsed, 0.5) << "the load was too light to mean anything";
  EXPECT_GT(rate, 40.0);       // nominal 50 Hz
  EXPECT_LT(worst_gap, 0.25);  // never starved for more than a few periods
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_load");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
