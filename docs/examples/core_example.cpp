// A trajectory through three poses with the core library alone (no ROS).
#include <cmath>
#include <cstdio>

#include <se3_interpolation/exceptions.h>
#include <se3_interpolation/planner/planner.h>

using namespace se3_interpolation;

int main()
{
  const auto pose = [](double x, double y, double z, double yaw) {
    return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
                        Eigen::Vector3d(x, y, z));
  };
  TrajectoryRequest request;  // field names as in srv/GenerateTrajectory.srv
  request.waypoints = { pose(0, 0, 0, 0), pose(1, 0, 0.5, 1.0), pose(1, 1, 1, 2.0) };
  request.curve = "interpolating";
  request.geometry = "screw";
  request.max_linear_velocity = 0.5;  // m/s
  request.sample_count = 5;
  try
  {
    const TrajectoryResult result = generate(request, PlannerLimits{});
    std::printf("duration %.3f s, length %.3f m\n", result.duration, result.figures.length);
    for (const TrajectorySample& s : result.samples)
      std::printf("t %.3f  p %.3f %.3f %.3f  |v| %.3f m/s\n", s.time, s.pose.p.x(), s.pose.p.y(),
                  s.pose.p.z(), s.velocity.linear.norm());
  }
  catch (const InterpolationError& e)  // a bad request: the message names the field
  {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
