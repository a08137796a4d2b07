// The trajectory planner: request → validation → timing → curve → stretch → samples.
//
// This is the ROS-free heart of the `~generate` service and the `se3_interpolate` CLI:
// both translate their input into a TrajectoryRequest (same field names as
// srv/GenerateTrajectory.srv) and call generateTrajectory(). Every bad input is
// rejected by validateRequest() before anything is computed, with an
// InterpolationError whose message names the field and index.
//
// Frames and units: waypoints are world_T_body poses in one frame ("the waypoints'
// frame"): positions in m, quaternions (x, y, z, w). Times in s after the request stamp.
// Velocities are (linear, angular) = (dp/dt, ω) with dR/dt = [ω]× R, both expressed in
// the waypoints' frame (m/s, rad/s); accelerations are (d²p/dt², dω/dt) in the same frame.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
/// A twist or its time derivative: linear (m/s or m/s²) and angular (rad/s or rad/s²)
/// parts, both in the waypoints' frame.
struct Twist
{
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

enum class CurveType
{
  kPiecewiseGeodesic,
  kBezier,
  kBspline,
  kInterpolating,
  kHermite,
  kBlended
};
enum class GeometryType
{
  kDoubleGeodesic,
  kScrew
};
enum class EndCondition
{
  kNatural,
  kClamped,
  kStart
};
enum class Parameterization
{
  kChord,
  kUniform,
  kCentripetal
};
/// How the max_* bounds shape the timing (field `timing`).
enum class Timing
{
  kStretch,     ///< "stretch": the curve's time axis stretched uniformly until every peak fits
  kTimeOptimal  ///< "time_optimal": the fastest rest-to-rest traversal of the path (timing/time_optimal.h)
};

/// The request, field for field as in GenerateTrajectory.srv. Empty strings and zeros
/// select the defaults documented in the README.
struct TrajectoryRequest
{
  /// Raw input poses; orientations are validated (finite, norm in [0.99, 1.01]) and normalised.
  std::vector<Pose<double>> waypoints;
  std::vector<double> times;
  std::string curve;
  std::string geometry;
  int degree = 0;
  std::vector<double> knots;
  int continuity = 0;
  std::string end_condition;
  Twist start_velocity;
  Twist end_velocity;
  Twist start_acceleration;
  std::vector<Twist> velocities;
  std::string parameterization;
  double rotation_scale = 0.0;
  double duration = 0.0;
  double max_linear_velocity = 0.0;
  double max_angular_velocity = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  std::string timing;
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = 0;
  /// m (chord distance, see corner_blend.h); 0 = sharp corners. Only for piecewise_geodesic.
  double blend_radius = 0.0;
};

/// Resource bounds per request (node parameters ~max_samples, ~max_waypoints, ~max_work).
struct PlannerLimits
{
  std::size_t max_samples = 200000;
  std::size_t max_waypoints = 20000;
  /// Estimated work units per request (work_estimate.h): about 1 s on one core.
  double max_work = 1.25e6;
};

/// A request after validation, with defaults resolved and orientations normalised.
struct ValidatedRequest
{
  std::vector<Pose<double>> waypoints;
  std::vector<double> times;  ///< explicit times, or empty
  CurveType curve = CurveType::kInterpolating;
  GeometryType geometry = GeometryType::kDoubleGeodesic;
  int degree = 3;
  std::vector<double> knots;  ///< explicit knots, or empty
  int continuity = 2;
  EndCondition end_condition = EndCondition::kNatural;
  Twist start_velocity;
  Twist end_velocity;
  Twist start_acceleration;
  std::vector<Twist> velocities;
  Parameterization parameterization = Parameterization::kChord;
  double rotation_scale = 1.0;
  double duration = 0.0;
  double max_linear_velocity = 0.0;
  double max_angular_velocity = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  Timing timing = Timing::kStretch;
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = 100;
  double blend_radius = 0.0;
};

struct TrajectorySample
{
  double time = 0.0;  ///< s after the request stamp
  Pose<double> pose;  ///< world_T_body, quaternion sign-continuous along the samples
  Twist velocity;
  Twist acceleration;
};

struct TrajectoryResult
{
  std::vector<TrajectorySample> samples;
  std::vector<double> waypoint_times;  ///< final times of the waypoints (after any stretch)
  std::vector<Pose<double>> waypoints;  ///< the validated (normalised) input waypoints
  std::vector<Pose<double>> control_points;
  /// Per waypoint, the radius r_i of its corner blend (m, chord distance; 0 = not blended).
  /// Empty unless the request has a blend_radius.
  std::vector<double> blend_radii;
  double start_time = 0.0;
  double duration = 0.0;         ///< s
  /// Uniform stretch applied to meet the max_* bounds (≥ 1); with timing time_optimal the final
  /// correction of the optimal profile (TimingProfile::stretch, within a few 1e-3 of 1).
  double time_scale = 1.0;
  double length = 0.0;           ///< ∫ |ṗ| dt, m
  double rotation_length = 0.0;  ///< ∫ |ω| dt, rad
  double max_linear_speed = 0.0;
  double max_angular_speed = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  double energy = 0.0;  ///< ∫ |p̈|² + ρ²|ω̇|² dt (Crouch et al. eq. 32 with the product metric)
  /// The final curve's pose at any time in [start_time, start_time + duration] (for TF).
  std::function<Pose<double>(double)> pose_at;
};

/// Checks every field; throws InvalidInputError / NonUniqueGeodesicError / LimitExceededError
/// naming the field and index. Nothing is computed for a rejected request.
ValidatedRequest validateRequest(const TrajectoryRequest& request, const PlannerLimits& limits);

/// A validated, normalised pose; throws InvalidInputError naming `field` (e.g. "waypoints[2]").
Pose<double> validatePose(const Pose<double>& raw, const std::string& field);

/// Waypoint times: the explicit ones, else spaced by the parameterisation (SPEC, Timing).
std::vector<double> waypointTimes(const ValidatedRequest& request);

/// Validates, builds the curve, applies the bounds and samples it.
TrajectoryResult generateTrajectory(const TrajectoryRequest& request, const PlannerLimits& limits);

/// The names accepted in the request's string fields.
const char* toString(CurveType c);
const char* toString(GeometryType g);
const char* toString(Timing t);

/// The `timing` field: "" → stretch; unknown names throw InvalidInputError naming `timing`.
Timing parseTiming(const std::string& name);

}  // namespace se3_interpolation
