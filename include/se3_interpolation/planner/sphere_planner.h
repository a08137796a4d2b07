// The trajectory planner on the sphere S^m (the CLI's `--space sphere`, SPEC "Command line").
//
// The same request fields, curves, timing and sampling as the pose planner (planner.h), with
//  - waypoints: unit vectors x_i ∈ R^{m+1}, m ≥ 2, all of one dimension; a vector whose norm is
//    not finite or outside [0.99, 1.01] is rejected, others are normalised;
//  - start_velocity, end_velocity, start_acceleration, velocities: vectors of R^{m+1} tangent to
//    the sphere at their waypoint (empty = zero). They are projected onto the tangent space; a
//    normal component above 1 % of the vector's length is an error (the vector probably belongs
//    to another point). start_acceleration is the covariant acceleration D²x/dt² (Crouch Case 2);
//  - curves (sphere.h): piecewise_geodesic, bezier, bspline (great-circle de Casteljau / de Boor),
//    interpolating (natural / clamped: the C² cubic B-spline through the waypoints; start: Crouch
//    Case 2 forward), hermite (Crouch Case 1 on each segment; velocities given, else estimated as
//    in hermite.h), blended (Pobegailo's C^n circle splines, blending.h);
//  - timing: `chord` spacing uses the great-circle angle between consecutive waypoints (rad),
//    `centripetal` its square root; `duration` as for poses (default 1 s per segment);
//  - bounds: max_angular_velocity bounds the speed |ẋ| (rad/s on the unit sphere) and
//    max_angular_acceleration the covariant acceleration |D²x/dt²| (rad/s²); the time axis is
//    stretched uniformly, never shrunk; with `timing` "time_optimal" the same two bounds shape the
//    fastest rest-to-rest traversal of the great-circle path instead (timing/time_optimal.h,
//    max_angular_acceleration required). `geometry`, `rotation_scale` and the max_linear_* bounds
//    have no meaning on the sphere and are rejected when set;
//  - antipodal consecutive waypoints are an error naming both.
// Errors are InterpolationError subclasses whose messages name the field and index.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
/// A request on S^m; field names as in GenerateTrajectory.srv (see the file comment).
struct SphereRequest
{
  std::vector<Eigen::VectorXd> waypoints;
  std::vector<double> times;
  std::string curve;
  std::string geometry;  ///< must be empty (the sphere has one metric)
  int degree = 0;
  std::vector<double> knots;
  int continuity = 0;
  std::string end_condition;
  Eigen::VectorXd start_velocity;  ///< empty = zero
  Eigen::VectorXd end_velocity;
  Eigen::VectorXd start_acceleration;
  std::vector<Eigen::VectorXd> velocities;
  std::string parameterization;
  double rotation_scale = 0.0;  ///< must be 0 (unused)
  double duration = 0.0;
  double max_linear_velocity = 0.0;  ///< must be 0 (unused)
  double max_angular_velocity = 0.0;
  double max_linear_acceleration = 0.0;  ///< must be 0 (unused)
  double max_angular_acceleration = 0.0;
  std::string timing;  ///< "stretch" (default) or "time_optimal"
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = 0;
};

struct SphereSample
{
  double time = 0.0;
  Eigen::VectorXd point;         ///< unit vector
  Eigen::VectorXd velocity;      ///< ẋ, tangent at point
  Eigen::VectorXd acceleration;  ///< D²x/dt², tangent at point
};

struct SphereResult
{
  std::vector<SphereSample> samples;
  std::vector<double> waypoint_times;       ///< final times (after any stretch)
  std::vector<Eigen::VectorXd> waypoints;   ///< normalised
  double start_time = 0.0;
  double duration = 0.0;
  double time_scale = 1.0;  ///< the stretch, or the time-optimal profile's final correction
  double length = 0.0;            ///< ∫ |ẋ| dt, rad
  double max_speed = 0.0;         ///< rad/s
  double max_acceleration = 0.0;  ///< covariant, rad/s²
  double energy = 0.0;            ///< Crouch et al. eq. 32
  std::function<Eigen::VectorXd(double)> point_at;
};

/// Validates, builds the curve, applies the bounds and samples it. Throws InterpolationError.
SphereResult generateSphereTrajectory(const SphereRequest& request, const PlannerLimits& limits);

}  // namespace se3_interpolation
