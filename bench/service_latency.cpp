// roscpp client measuring the latency of se3_interpolation_node's ~generate service for a large
// request: N waypoints, an `interpolating` double-geodesic curve, M samples.
// scripts/service_latency.sh starts a roscore on a free port and the node, then runs this client
// and the rospy one (scripts/service_latency.py) with the same request.
//
// Per repetition: the round trip of ros::service::call (request serialisation, the node's
// callback, response serialisation, transport, deserialisation into the client's response).
// After the calls, on the last response: its serialised size, and the time roscpp takes to
// serialise it and to deserialise it again (the two ends of the transport, measured apart).
//
// Usage: service_latency [--service NAME] [--waypoints N] [--samples M] [--repetitions R]
//                        [--outputs path,trajectory]   (empty: the service's default, both)
#include <ros/ros.h>
#include <ros/serialization.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"

namespace
{
using Clock = std::chrono::steady_clock;

double secondsSince(const Clock::time_point& start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Waypoint i of the benchmark's path: a deterministic helix-like walk with turning yaw and a
/// rocking roll, the same formula as scripts/service_latency.py.
geometry_msgs::Pose waypoint(int i)
{
  geometry_msgs::Pose p;
  p.position.x = 0.3 * i;
  p.position.y = std::sin(0.5 * i);
  p.position.z = 0.2 * std::cos(0.3 * i);
  const double yaw = 0.4 * i;
  const double roll = 0.3 * std::sin(0.7 * i);
  // q = q_z(yaw) q_x(roll)
  const double cy = std::cos(0.5 * yaw), sy = std::sin(0.5 * yaw);
  const double cr = std::cos(0.5 * roll), sr = std::sin(0.5 * roll);
  p.orientation.w = cy * cr;
  p.orientation.x = cy * sr;
  p.orientation.y = sy * sr;
  p.orientation.z = sy * cr;
  return p;
}
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "se3_service_latency", ros::init_options::AnonymousName);
  std::string service = "/se3_interpolation_node/generate";
  int waypoints = 1000;
  int samples = 100000;
  int repetitions = 5;
  std::string outputs;
  for (int a = 1; a + 1 < argc; a += 2)
  {
    const std::string key = argv[a];
    const char* value = argv[a + 1];
    if (key == "--service")
      service = value;
    else if (key == "--waypoints")
      waypoints = std::atoi(value);
    else if (key == "--samples")
      samples = std::atoi(value);
    else if (key == "--repetitions")
      repetitions = std::max(1, std::atoi(value));
    else if (key == "--outputs")
      outputs = value;
    else
    {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  ros::NodeHandle nh;
  if (!ros::service::waitForService(service, ros::Duration(30.0)))
  {
    std::fprintf(stderr, "service %s not available\n", service.c_str());
    return 1;
  }

  se3_interpolation::GenerateTrajectory srv;
  srv.request.waypoints.header.frame_id = "map";
  for (int i = 0; i < waypoints; ++i)
    srv.request.waypoints.poses.push_back(waypoint(i));
  srv.request.curve = "interpolating";
  srv.request.geometry = "double_geodesic";
  srv.request.sample_count = static_cast<std::uint32_t>(samples);
  std::stringstream names(outputs);
  for (std::string name; std::getline(names, name, ',');)
    srv.request.outputs.push_back(name);

  ros::ServiceClient client = nh.serviceClient<se3_interpolation::GenerateTrajectory>(service, true);
  std::vector<double> round_trips;
  for (int r = 0; r < repetitions; ++r)
  {
    const Clock::time_point start = Clock::now();
    if (!client.call(srv) || !srv.response.success)
    {
      std::fprintf(stderr, "call failed: %s\n", srv.response.message.c_str());
      return 1;
    }
    round_trips.push_back(secondsSince(start));
  }

  // The two ends of the transport for this response, measured on their own.
  const se3_interpolation::GenerateTrajectory::Response& res = srv.response;
  std::vector<double> serialise, deserialise;
  std::uint32_t bytes = 0;
  for (int r = 0; r < repetitions; ++r)
  {
    Clock::time_point start = Clock::now();
    const ros::SerializedMessage m = ros::serialization::serializeServiceResponse(true, res);
    serialise.push_back(secondsSince(start));
    bytes = static_cast<std::uint32_t>(m.num_bytes);
    se3_interpolation::GenerateTrajectory::Response back;
    start = Clock::now();
    // serializeServiceResponse prefixes the ok byte and the length (5 bytes).
    ros::serialization::IStream in(m.buf.get() + 5, static_cast<std::uint32_t>(m.num_bytes - 5));
    ros::serialization::deserialize(in, back);
    deserialise.push_back(secondsSince(start));
  }

  std::printf("roscpp client: %d waypoints, %d samples, outputs [%s]: path %zu poses, trajectory %zu points, "
              "response %.1f MB\n",
              waypoints, samples, outputs.c_str(), res.path.poses.size(), res.trajectory.points.size(),
              bytes / 1e6);
  std::printf("  round trip: median %.3f s, min %.3f s over %d calls\n", median(round_trips),
              *std::min_element(round_trips.begin(), round_trips.end()), repetitions);
  std::printf("  roscpp serialisation of the response: median %.3f s; deserialisation: median %.3f s\n",
              median(serialise), median(deserialise));
  return 0;
}
