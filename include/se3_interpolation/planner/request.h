// The planner's input and output types, written once over the space the motion lives in.
//
// A space is the set of points a trajectory moves through, with the request types that name
// them: PoseSpace (world_T_body poses, either SE(3) geometry of geometry/) and SphereSpace (unit
// vectors of R^{m+1}, the sphere S^m of geometry/sphere.h). The request, its validated form and
// the result are one template each over the space, so the service, the CLI and the tests read
// the same field names (those of srv/GenerateTrajectory.srv) whatever the space.
//
// Frames and units (poses): waypoints are world_T_body poses in one frame ("the waypoints'
// frame"): positions in m, quaternions (x, y, z, w). Times in s after the request stamp.
// Velocities are (linear, angular) = (dp/dt, ω) with dR/dt = [ω]× R, both expressed in the
// waypoints' frame (m/s, rad/s); accelerations are (d²p/dt², dω/dt) in the same frame.
// On the sphere: points are unit vectors, velocities ẋ and covariant accelerations D²x/dt²
// tangent at their point; the motion is angular (rad on the unit sphere), so its rates are the
// angular channel of the figures and of the max_angular_* bounds, and the linear channel is 0.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/arm/joint_timing.h"
#include "se3_interpolation/curves/end_condition.h"
#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/geometry/trajectory_sample.h"

namespace se3_interpolation
{
/// The curve families (request field `curve`), in the order of their registry, CurveFamilies
/// (planner/curve_families.h), whose descriptors say what each takes and builds.
enum class CurveType
{
  kPiecewiseGeodesic,
  kBezier,
  kBspline,
  kInterpolating,
  kHermite,
  kBlended,
  kFit
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
  kStretch,      ///< "stretch": the curve's time axis stretched uniformly until every peak fits
  kTimeOptimal,  ///< "time_optimal": the fastest rest-to-rest traversal of the path (timing/time_optimal.h)
  /// "constant_speed": the chord speed `speed` between a start and a stop ramp (timing/constant_speed.h)
  kConstantSpeed
};

/// The sample arrays a response of the ~generate service can carry (its request's `outputs`;
/// the CLI checks the names too and writes its CSV whatever they are).
enum class ResponseOutput
{
  kPath,            ///< "path": nav_msgs/Path of the sampled poses
  kTrajectory,      ///< "trajectory": MultiDOFJointTrajectory of poses, velocities and accelerations
  kJointTrajectory  ///< "joint_trajectory": JointTrajectory of an arm's joints (empty without an arm)
};

/// Which of the response's sample arrays to fill (default: all, the behaviour before `outputs`).
struct ResponseOutputs
{
  bool path = true;
  bool trajectory = true;
  bool joint_trajectory = true;
};

/// The defaults of the request's empty or zero fields: the one place the planner, the node's
/// parameters and the CLI read them from (docs/curves.md, docs/timing.md).
struct RequestDefaults
{
  static constexpr CurveType kCurve = CurveType::kInterpolating;
  static constexpr GeometryType kGeometry = GeometryType::kDoubleGeodesic;
  static constexpr EndCondition kEndCondition = EndCondition::kNatural;
  static constexpr Parameterization kParameterization = Parameterization::kChord;
  static constexpr Timing kTiming = Timing::kStretch;
  /// Degree of `bspline` (and of nothing else), lowered to N − 1 for fewer waypoints.
  static constexpr int kDegree = 3;
  /// Continuity C^n of `blended`.
  static constexpr int kContinuity = 2;
  /// Samples over the trajectory when neither sample_times nor sample_period is given.
  static constexpr std::uint32_t kSampleCount = 100;
  /// rotation_scale ρ (m per rad) of the chord spacing and the energy.
  static constexpr double kRotationScale = 1.0;
};

/// Resource bounds per request (node parameters ~max_samples, ~max_waypoints, ~max_work_seconds).
struct PlannerLimits
{
  std::size_t max_samples = 200000;
  std::size_t max_waypoints = 20000;
  /// The time one request may take on one core (s): a request whose estimated cost
  /// (work_estimate.h) exceeds it is refused before anything is computed, and one that runs past
  /// kDeadlineFactor times it is stopped (deadline.h).
  double max_work_seconds = 1.0;
};

/// The deadline of a request, as a multiple of PlannerLimits::max_work_seconds: room for the
/// estimate's error (within 2× of measured) before a request that was accepted is stopped, and
/// below 2× so that none runs past twice its limit (the loops check every few milliseconds).
constexpr double kDeadlineFactor = 1.5;
/// The shortest deadline: a limit below a few tens of milliseconds is enforced by the estimate
/// alone (a deadline that short would stop requests the estimate accepted on a loaded machine or
/// under the sanitizers).
constexpr double kMinDeadlineSeconds = 0.05;

/// The sampling fields after validation (sample_count defaulted).
struct Sampling
{
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = RequestDefaults::kSampleCount;
  /// m of chord distance; > 0: samples inserted until a goal made of them executes the motion
  /// (execution/sample_refinement.h). Poses only.
  double sample_tolerance = 0.0;
};

struct SphereSample
{
  double time = 0.0;
  Eigen::VectorXd point;         ///< unit vector
  Eigen::VectorXd velocity;      ///< ẋ, tangent at point
  Eigen::VectorXd acceleration;  ///< D²x/dt², tangent at point
};

/// The state a new trajectory starts from when it replaces a moving one (replanning,
/// docs/timing.md "Start states and replanning"): the pose, velocity and acceleration of the old motion at the switch time, which
/// is time 0 of the new request (its `times` count from it). The trajectory then starts exactly in
/// this state (C² switch) and goes through the requested waypoints: `interpolating` with
/// end_condition `start` takes it as its start data (the start pose becomes its first point);
/// every other curve, and every stretched one, is entered by the joining quintic of
/// curves/start_join.h, which replaces the curve's first segment (from the start pose to the first
/// requested waypoint). A waypoints[0] equal to the start pose (1e-9) is not visited twice.
/// Poses only: a sphere request with a start state is refused.
struct StartState
{
  Pose<double> pose;
  Twist velocity;
  Twist acceleration;
};

/// The arm that follows a pose motion (arm/joint_path.h): its model, whose base frame is the
/// waypoints' frame and whose tip is the moving body, and the joint positions it has at the
/// motion's start (the request's joint_seed; the first waypoint is reached on their branch).
struct JointSpace
{
  std::shared_ptr<const arm::ArmModel> arm;
  Eigen::VectorXd seed;
};

/// Poses: waypoints world_T_body, velocities spatial twists; geometry chosen by the request.
struct PoseSpace
{
  using Waypoint = Pose<double>;
  using Velocity = Twist;
  using Sample = TrajectorySample;
};

/// The sphere S^m: waypoints unit vectors of R^{m+1}, velocities tangent vectors (empty = zero).
struct SphereSpace
{
  using Waypoint = Eigen::VectorXd;
  using Velocity = Eigen::VectorXd;
  using Sample = SphereSample;
};

/// The request, field for field as in GenerateTrajectory.srv. Empty strings and zeros select
/// the defaults (RequestDefaults). Fields without meaning in a space (on the sphere: geometry,
/// rotation_scale, max_linear_*, blend_radius) must stay empty or zero there.
template <class Space>
struct BasicRequest
{
  using Waypoint = typename Space::Waypoint;
  using Velocity = typename Space::Velocity;

  /// Raw input points: poses' orientations (or sphere points) finite with norm in
  /// [kMinUnitNorm, kMaxUnitNorm], normalised by validation.
  std::vector<Waypoint> waypoints;
  std::vector<double> times;
  std::string curve;
  std::string geometry;
  int degree = 0;
  std::vector<double> knots;
  int continuity = 0;
  std::string end_condition;
  Velocity start_velocity{};
  Velocity end_velocity{};
  Velocity start_acceleration{};
  std::vector<Velocity> velocities;
  std::string parameterization;
  double rotation_scale = 0.0;
  double duration = 0.0;
  double max_linear_velocity = 0.0;
  double max_angular_velocity = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  /// m/s³, bound on |d³p/dt³| (0 = unbounded; timing/jerk_limited.h)
  double max_linear_jerk = 0.0;
  /// rad/s³, bound on |ω̈| (0 = unbounded)
  double max_angular_jerk = 0.0;
  std::string timing;
  /// m/s, the chord speed √(|ṗ|² + ρ²|ω|²) of timing constant_speed (read by no other timing)
  double speed = 0.0;
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = 0;
  /// m of chord distance √(|Δp|² + ρ²θ²) (0 = only the samples asked for): samples are inserted
  /// between those until a ~follow_trajectory goal made of them stays within this distance of the
  /// motion and within its bounds (execution/sample_refinement.h). Poses only.
  double sample_tolerance = 0.0;
  /// m (chord distance, see corner_blend.h); 0 = sharp corners. Only for piecewise_geodesic.
  double blend_radius = 0.0;
  /// curve fit (fitting/bspline_fit.h): s between knots (0 = kDefaultControlPeriod), the jerk
  /// penalty λ ≥ 0, the loss ("" = squared, "squared", "huber") and Huber's δ (m of chord distance).
  double control_period = 0.0;
  double smoothing = 0.0;
  std::string loss;
  double loss_scale = 0.0;
  /// Start from this state instead of at waypoints[0] (the service's `from_current`, filled by the
  /// node from the trajectory it is playing; the CLI's `start_state`). With it one waypoint suffices.
  std::optional<StartState> start_state;
  /// rad or m per movable joint of the arm in chain order: its joint positions at the motion's
  /// start. Required with an arm (generate()'s `arm`), refused without one. Poses only.
  std::vector<double> joint_seed;
};

/// A request after validation: names parsed, defaults resolved, points normalised, sphere
/// tangents projected onto their tangent space.
template <class Space>
struct BasicValidatedRequest
{
  using Waypoint = typename Space::Waypoint;
  using Velocity = typename Space::Velocity;

  std::vector<Waypoint> waypoints;
  std::vector<double> times;  ///< explicit times, or empty
  CurveType curve = RequestDefaults::kCurve;
  GeometryType geometry = RequestDefaults::kGeometry;
  int degree = RequestDefaults::kDegree;
  std::vector<double> knots;  ///< explicit knots, or empty
  int continuity = RequestDefaults::kContinuity;
  EndCondition end_condition = RequestDefaults::kEndCondition;
  Velocity start_velocity{};
  Velocity end_velocity{};
  Velocity start_acceleration{};
  std::vector<Velocity> velocities;
  Parameterization parameterization = RequestDefaults::kParameterization;
  double rotation_scale = RequestDefaults::kRotationScale;
  double duration = 0.0;
  double max_linear_velocity = 0.0;
  double max_angular_velocity = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  double max_linear_jerk = 0.0;   ///< m/s³ (0 = unbounded)
  double max_angular_jerk = 0.0;  ///< rad/s³ (0 = unbounded)
  Timing timing = RequestDefaults::kTiming;
  double speed = 0.0;  ///< m/s (timing constant_speed; > 0 there, else unread)
  Sampling sampling;
  double blend_radius = 0.0;
  /// curve fit: control_period (s, > 0: the default resolved), smoothing, loss, loss_scale.
  double control_period = 0.0;
  double smoothing = 0.0;
  FitLoss loss = FitLoss::kSquared;
  double loss_scale = 0.0;
  /// The validated start state. When set, `waypoints`, `times` and `velocities` begin with it: the
  /// start pose at time 0 (in place of waypoints[0] when that is the start pose, see
  /// `start_replaces_first`, else inserted before it).
  std::optional<StartState> start_state;
  bool start_replaces_first = false;
  /// With an arm: the arm and the validated joint_seed.
  std::optional<JointSpace> joint_space;
};

template <class Space>
struct BasicResult
{
  using Waypoint = typename Space::Waypoint;

  std::vector<typename Space::Sample> samples;
  std::vector<double> waypoint_times;  ///< final times of the waypoints (after any stretch)
  std::vector<Waypoint> waypoints;     ///< the validated (normalised) input waypoints
  std::vector<Waypoint> control_points;
  /// Per waypoint, the radius r_i of its corner blend (m, chord distance; 0 = not blended).
  /// Empty unless the request has a blend_radius.
  std::vector<double> blend_radii;
  double start_time = 0.0;
  double duration = 0.0;  ///< s
  /// Uniform stretch applied to meet the max_* bounds (≥ 1); with timing time_optimal the final
  /// correction of the optimal profile (TimingProfile::stretch, within a few 1e-3 of 1).
  double time_scale = 1.0;
  /// With a start state that the bounds cannot hold (faster than they allow, or too fast to brake
  /// for what lies ahead; timing time_optimal): the time after the start at which its recovery
  /// ends, from which every bound holds (s). 0 otherwise.
  double recovery_time = 0.0;
  /// With a start state that cannot continue along the curve within the bounds under time_optimal
  /// timing (one beyond a velocity bound, or one whose timing along the joining segment is refused):
  /// how long its motion brakes to rest along its own directions before the motion from rest
  /// begins (s; curves/braked_start.h). 0 when the motion continues the start state.
  double stop_time = 0.0;
  /// With timing constant_speed: the window in which the chord speed is `speed` (s, on the same
  /// clock as start_time), where a process tool is switched on. Both 0 otherwise.
  double constant_speed_start = 0.0;
  double constant_speed_end = 0.0;
  /// With curve fit: the RMS distances of the fitted curve from the waypoints at their times
  /// (m and rad) and the fitted B-spline's knots (its control poses are control_points). Else 0
  /// and empty.
  double residual_linear = 0.0;
  double residual_angular = 0.0;
  std::vector<double> knots;
  /// Length, rotation length, peak rates and energy of the final (timed) motion.
  CurveFigures figures;
  /// With an arm: its movable joints' names in chain order (the samples' joint vectors follow it)
  /// and the joint rates of the final motion against the arm's limits (per joint peak |q̇|, |q̈|,
  /// the binding joint and its ratio to its limit). Empty without an arm.
  std::vector<std::string> joint_names;
  arm::JointRatesCheck joint_figures;
  /// The final curve's point at any time in [start_time, start_time + duration] (for TF).
  std::function<Waypoint(double)> point_at;
  /// Point, velocity and acceleration (exact jets, one-sided from the right) at any such time: what
  /// a replanning request starts from (StartState).
  std::function<typename Space::Sample(double)> state_at;
};

using TrajectoryRequest = BasicRequest<PoseSpace>;
using ValidatedRequest = BasicValidatedRequest<PoseSpace>;
using TrajectoryResult = BasicResult<PoseSpace>;
using SphereRequest = BasicRequest<SphereSpace>;
using ValidatedSphereRequest = BasicValidatedRequest<SphereSpace>;
using SphereResult = BasicResult<SphereSpace>;

}  // namespace se3_interpolation
