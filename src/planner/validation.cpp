#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
using se3_interpolation::requireFinite;   // the scalar overload, beside the vector ones below
using se3_interpolation::requireBounded;  // the Vector3d overload, beside the others below

/// A vector of R^{m+1} (sphere points and tangents): components named [j].
void requireFinite(const Eigen::VectorXd& v, const std::string& field)
{
  for (Eigen::Index j = 0; j < v.size(); ++j)
    requireFinite(v[j], indexedField(field, static_cast<std::size_t>(j)));
}

/// A sphere tangent of bounded magnitude: components named [j].
void requireBounded(const Eigen::VectorXd& v, const std::string& field)
{
  for (Eigen::Index j = 0; j < v.size(); ++j)
    if (!(std::abs(v[j]) <= kMaxMagnitude))
      requireBounded(v[j], indexedField(field, static_cast<std::size_t>(j)));
}

/// A field only some families take (FamilyField) is refused, when `given`, for the others that
/// kExclusiveFields names.
void requireFamilyTakes(CurveType curve, FamilyField field, bool given, const char* name)
{
  if (given && (kExclusiveFields & field) != 0u && (familyFields(curve) & field) == 0u)
    throw InvalidInputError(std::string(name) + ": only used by curve " + familiesTaking(field) + " (curve is '" +
                            toString(curve) + "')");
}

/// The fields of curve fit (fitting/bspline_fit.h): refused for every other family; poses only.
template <class Space>
void validateFitFields(const BasicRequest<Space>& r, BasicValidatedRequest<Space>* v)
{
  requireFamilyTakes(v->curve, kFitField, r.control_period != 0.0, "control_period");
  requireFamilyTakes(v->curve, kFitField, r.smoothing != 0.0, "smoothing");
  requireFamilyTakes(v->curve, kFitField, !r.loss.empty(), "loss");
  requireFamilyTakes(v->curve, kFitField, r.loss_scale != 0.0, "loss_scale");
  if (v->curve != CurveType::kFit)
    return;
  if constexpr (std::is_same_v<Space, SphereSpace>)
    throw InvalidInputError("curve: 'fit' fits poses; it is not available on the sphere");
  requireFiniteNonNegative(r.control_period, "control_period");
  requireFiniteNonNegative(r.smoothing, "smoothing");
  requireFiniteNonNegative(r.loss_scale, "loss_scale");
  v->control_period = r.control_period > 0.0 ? r.control_period : kDefaultControlPeriod;
  v->smoothing = r.smoothing;
  v->loss = parseName(r.loss, "loss", FitLoss::kSquared);
  v->loss_scale = r.loss_scale;
  if (v->loss == FitLoss::kHuber && v->loss_scale == 0.0)
    throw InvalidInputError(
        "loss_scale: loss 'huber' needs loss_scale > 0 (m of chord distance: residuals beyond "
        "it count linearly, as outliers)");
  if (v->degree > kMaxFitDegree)
    throw InvalidInputError("degree: " + std::to_string(v->degree) + " for curve 'fit'; at most " +
                            std::to_string(kMaxFitDegree));
  // The knot count is bounded before anything is allocated (fitIntervals names control_period).
  fitIntervals(r.times.front(), r.times.back(), v->control_period, v->degree, r.waypoints.size());
}

/// A field without meaning in the space must stay 0.
void requireUnused(double x, const std::string& field, const std::string& instead)
{
  if (x != 0.0)
    throw InvalidInputError(field + ": not used on the sphere" + instead);
}

// --- The space-dependent rules: one overload per space ------------------------------------

std::vector<Pose<double>> validWaypoints(const std::vector<Pose<double>>& raw)
{
  std::vector<Pose<double>> out;
  out.reserve(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i)
    out.push_back(validatePose(raw[i], indexedField("waypoints", i)));
  return out;
}

/// Unit vectors of R^{m+1}, m >= 2, all of the dimension of waypoints[0].
std::vector<Eigen::VectorXd> validWaypoints(const std::vector<Eigen::VectorXd>& raw)
{
  const Eigen::Index dim = raw[0].size();
  if (dim < 3)
    throw InvalidInputError("waypoints[0]: has " + std::to_string(dim) +
                            " components; a point of the sphere S^m in R^{m+1}, m >= 2, needs at least 3");
  std::vector<Eigen::VectorXd> out;
  out.reserve(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i)
  {
    const std::string field = indexedField("waypoints", i);
    if (raw[i].size() != dim)
      throw InvalidInputError(field + ": has " + std::to_string(raw[i].size()) + " components; waypoints[0] has " +
                              std::to_string(dim) + " (all waypoints need the same dimension)");
    requireFinite(raw[i], field);
    const double n = raw[i].norm();
    requireUnitNorm(n, field, "", "vector");
    out.push_back(raw[i] / n);
  }
  return out;
}

/// A twist: finite, of bounded magnitude.
Twist validVelocity(const Twist& raw, const Pose<double>& /*at*/, const std::string& field)
{
  requireBounded(raw.linear, field + ".linear");
  requireBounded(raw.angular, field + ".angular");
  return raw;
}

/// A tangent vector at x (empty = zero), projected onto T_x S^m.
Eigen::VectorXd validVelocity(const Eigen::VectorXd& raw, const Eigen::VectorXd& x, const std::string& field)
{
  if (raw.size() == 0)
    return Eigen::VectorXd::Zero(x.size());
  if (raw.size() != x.size())
    throw InvalidInputError(field + ": has " + std::to_string(raw.size()) + " components; expected " +
                            std::to_string(x.size()) + " (a tangent vector of R^" + std::to_string(x.size()) + ")");
  requireBounded(raw, field);
  const double normal = raw.dot(x);
  if (std::abs(normal) > kMaxNormalFraction * raw.norm())
    throw InvalidInputError(field + ": is not tangent to the sphere at its waypoint (normal component " +
                            formatNumber(normal) + " of a vector of length " + formatNumber(raw.norm()) + ")");
  return raw - normal * x;
}

bool identical(const Pose<double>& a, const Pose<double>& b)
{
  return a.p == b.p && a.q.angularDistance(b.q) == 0.0;
}

bool identical(const Eigen::VectorXd& a, const Eigen::VectorXd& b)
{
  return a == b;
}

/// Consecutive poses whose relative rotation is exactly π: the geodesic is not unique.
void requireUniqueGeodesics(const std::vector<Pose<double>>& x)
{
  for (std::size_t i = 0; i + 1 < x.size(); ++i)
    if (std::abs(x[i].q.coeffs().dot(x[i + 1].q.coeffs())) <= kAntipodalTolerance)
      throw NonUniqueGeodesicError(indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1) +
                                   ": the relative rotation is exactly pi, so the geodesic between them is not unique");
}

/// Antipodal consecutive sphere points: NonUniqueGeodesicError naming both.
void requireUniqueGeodesics(const std::vector<Eigen::VectorXd>& x)
{
  polygonLogs<Sphere>(x, "waypoints");
}

/// The fields only poses have: geometry, rotation_scale, blend_radius.
void validateSpaceFields(const TrajectoryRequest& r, ValidatedRequest* v)
{
  v->geometry = parseName(r.geometry, "geometry", RequestDefaults::kGeometry);
  requireFiniteNonNegative(r.rotation_scale, "rotation_scale");
  v->rotation_scale = r.rotation_scale == 0.0 ? RequestDefaults::kRotationScale : r.rotation_scale;
  requireFiniteNonNegative(r.blend_radius, "blend_radius");
  requireFamilyTakes(v->curve, kBlendRadiusField, r.blend_radius > 0.0, "blend_radius");
  v->blend_radius = r.blend_radius;
}

/// On the sphere (one metric, angular motion) those fields and the linear bounds must be unset.
void validateSpaceFields(const SphereRequest& r, ValidatedSphereRequest* v)
{
  if (!r.geometry.empty())
    throw InvalidInputError("geometry: not used on the sphere (its metric is the round one); leave it empty");
  requireUnused(r.rotation_scale, "rotation_scale", " (chord spacing uses the great-circle angle)");
  requireUnused(r.max_linear_velocity, "max_linear_velocity", "; bound the speed with max_angular_velocity (rad/s)");
  requireUnused(r.max_linear_acceleration, "max_linear_acceleration",
                "; bound the acceleration with max_angular_acceleration (rad/s^2)");
  requireUnused(r.max_linear_jerk, "max_linear_jerk", "; bound the jerk with max_angular_jerk (rad/s^3)");
  requireUnused(r.blend_radius, "blend_radius", " (corner blends are for poses)");
  v->rotation_scale = 1.0;
}
/// timing constant_speed: a speed above 0, the ramps' acceleration bound, a pose request.
template <class Space>
void requireConstantSpeedFields(const BasicValidatedRequest<Space>& v)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
    throw InvalidInputError(
        "timing: 'constant_speed' is for poses (its chord speed is that of the position and "
        "the rotation); use 'stretch' or 'time_optimal' on the sphere");
  if (!(v.speed > 0.0))
    throw InvalidInputError("speed: " + formatNumber(v.speed) +
                            " (timing 'constant_speed' needs the chord speed to "
                            "hold, m/s, above 0)");
  if (!(v.max_linear_acceleration > 0.0))
    throw InvalidInputError(
        "max_linear_acceleration: timing 'constant_speed' needs it to bound its start and stop "
        "ramps (m/s^2, above 0)");
}

/// Distance (m, rad) below which waypoints[0] counts as the start pose itself: far above the
/// rounding of a pose evaluated on the old trajectory, far below any motion worth planning.
constexpr double kStartCoincidence = 1e-9;

/// Validates the start state and puts it in front of the waypoints (request.h, StartState).
void applyStartState(const StartState& raw, int raw_degree, ValidatedRequest* v)
{
  StartState s;
  s.pose = validatePose(raw.pose, "start_state.pose");
  s.velocity = validVelocity(raw.velocity, s.pose, "start_state.velocity");
  s.acceleration = validVelocity(raw.acceleration, s.pose, "start_state.acceleration");
  if (!v->knots.empty())
    throw InvalidInputError(
        "knots: cannot be combined with a start state (from_current): the start pose adds a "
        "control point; leave knots empty");
  const Pose<double>& first = v->waypoints.front();
  if (std::abs(first.q.coeffs().dot(s.pose.q.coeffs())) <= kAntipodalTolerance)
    throw NonUniqueGeodesicError(
        "waypoints[0]: its rotation from the start state (from_current) is exactly pi, "
        "so the geodesic between them is not unique");
  const bool same_pose =
      (first.p - s.pose.p).norm() <= kStartCoincidence && first.q.angularDistance(s.pose.q) <= kStartCoincidence;
  if (!v->times.empty())
  {
    if (v->times.front() < 0.0)
      throw InvalidInputError("times[0]: " + formatNumber(v->times.front()) +
                              " is before the start state (with from_current, times count from the switch time)");
    if (v->times.front() == 0.0 && !same_pose)
      throw InvalidInputError(
          "times[0]: 0 is the switch time, but waypoints[0] is not the start pose (with "
          "from_current, times count from the switch time: give waypoints[0] a later time)");
    if (v->times.front() > 0.0 && v->times.front() < kRosDurationResolution)
      throw InvalidInputError("times[0]: " + formatNumber(v->times.front()) +
                              " s after the start state, below the 1 ns resolution of time_from_start");
  }
  v->start_replaces_first = same_pose && (v->times.empty() || v->times.front() == 0.0);
  if (v->start_replaces_first)
  {
    v->waypoints.front() = s.pose;
    if (!v->velocities.empty())
      v->velocities.front() = s.velocity;
    if (v->waypoints.size() < 2)
      throw InvalidInputError(
          "waypoints: the only waypoint is the start pose (from_current): there is no motion "
          "to plan");
  }
  else
  {
    v->waypoints.insert(v->waypoints.begin(), s.pose);
    if (!v->times.empty())
      v->times.insert(v->times.begin(), 0.0);
    if (!v->velocities.empty())
      v->velocities.insert(v->velocities.begin(), s.velocity);
  }
  if (raw_degree == 0)
    v->degree = std::min(RequestDefaults::kDegree, static_cast<int>(v->waypoints.size()) - 1);
  if (continuesStartState(*v))
  {
    v->start_velocity = s.velocity;
    v->start_acceleration = s.acceleration;
  }
  v->start_state = s;
}

/// The sphere has no replanning (yet): a start state is refused.
void applyStartState(const StartState& /*raw*/, int /*raw_degree*/, ValidatedSphereRequest* /*v*/)
{
  throw InvalidInputError("start_state: starting from a given state is for poses only (not on the sphere)");
}
/// degree (default and range), knots and continuity, once the curve and waypoints are valid.
template <class Space>
void validateShapeFields(const BasicRequest<Space>& r, BasicValidatedRequest<Space>* v)
{
  const std::size_t n = r.waypoints.size();
  if (r.degree < 0)
    throw InvalidInputError("degree: " + std::to_string(r.degree) + " must be >= 1");
  const int max_degree = static_cast<int>(n) - 1;
  v->degree = r.degree == 0 ? std::min(RequestDefaults::kDegree, max_degree) : r.degree;
  if ((familyFields(v->curve) & kDegreeField) != 0u && v->degree > max_degree)
    throw InvalidInputError("degree: " + std::to_string(v->degree) + " is too high for " + std::to_string(n) +
                            " waypoints (at most " + std::to_string(max_degree) + ")");
  if (!r.knots.empty())
  {
    requireFamilyTakes(v->curve, kKnotsField, true, "knots");
    validateKnots(r.knots, n, v->degree);
    for (std::size_t i = 0; i < r.knots.size(); ++i)
      requireRosDuration(r.knots[i], indexedField("knots", i));
    v->knots = r.knots;
  }
  if (r.continuity < 0 || r.continuity > kMaxBlendingContinuity)
    throw InvalidInputError("continuity: " + std::to_string(r.continuity) + " is outside 1 ... " +
                            std::to_string(kMaxBlendingContinuity));
  v->continuity = r.continuity == 0 ? RequestDefaults::kContinuity : r.continuity;
}

/// duration, the bounds, timing and speed.
template <class Space>
void validateTimingFields(const BasicRequest<Space>& r, BasicValidatedRequest<Space>* v)
{
  requireFiniteNonNegative(r.duration, "duration");
  requireRosDuration(r.duration, "duration");
  v->duration = r.duration;
  requireFiniteNonNegative(r.max_linear_velocity, "max_linear_velocity");
  requireFiniteNonNegative(r.max_angular_velocity, "max_angular_velocity");
  requireFiniteNonNegative(r.max_linear_acceleration, "max_linear_acceleration");
  requireFiniteNonNegative(r.max_angular_acceleration, "max_angular_acceleration");
  v->max_linear_velocity = r.max_linear_velocity;
  v->max_angular_velocity = r.max_angular_velocity;
  v->max_linear_acceleration = r.max_linear_acceleration;
  v->max_angular_acceleration = r.max_angular_acceleration;
  requireFiniteNonNegative(r.max_linear_jerk, "max_linear_jerk");
  requireFiniteNonNegative(r.max_angular_jerk, "max_angular_jerk");
  v->max_linear_jerk = r.max_linear_jerk;
  v->max_angular_jerk = r.max_angular_jerk;
  v->timing = parseName(r.timing, "timing", RequestDefaults::kTiming);
  requireFiniteNonNegative(r.speed, "speed");
  v->speed = r.speed;
  if (v->timing == Timing::kConstantSpeed)
    requireConstantSpeedFields(*v);
}
}  // namespace

std::string withLimitPrefix(const std::string& message, const std::string& prefix)
{
  std::string out = message;
  for (const char* limit : { "(max_samples)", "(max_waypoints)", "(max_work_seconds)" })
  {
    const std::string name(limit);
    for (std::size_t at = out.find(name); at != std::string::npos;
         at = out.find(name, at + name.size() + prefix.size()))
      out.insert(at + 1, prefix);
  }
  return out;
}

template <class Space>
BasicValidatedRequest<Space> validateRequest(const BasicRequest<Space>& r, const PlannerLimits& limits)
{
  BasicValidatedRequest<Space> v;
  const std::size_t n = r.waypoints.size();
  // With a start state the start pose is the first point of the motion: one waypoint suffices.
  const std::size_t min_waypoints = r.start_state ? 1 : 2;
  if (n < min_waypoints)
    throw InvalidInputError("waypoints: " + std::to_string(n) + " given; at least " + std::to_string(min_waypoints) +
                            " are needed");
  if (n > limits.max_waypoints)
    throw LimitExceededError("waypoints: " + std::to_string(n) + " given; the limit (max_waypoints) is " +
                             std::to_string(limits.max_waypoints));
  v.waypoints = validWaypoints(r.waypoints);

  v.curve = parseName(r.curve, "curve", RequestDefaults::kCurve);
  v.end_condition = parseName(r.end_condition, "end_condition", RequestDefaults::kEndCondition);
  v.parameterization = parseName(r.parameterization, "parameterization", RequestDefaults::kParameterization);
  validateSpaceFields(r, &v);

  validateTimes(r.times, n);
  v.times = r.times;
  if (r.times.empty() && familyRequiresTimes(v.curve))
    throw InvalidInputError("times: curve '" + std::string(toString(v.curve)) +
                            "' needs the waypoints' times (one per waypoint: when each pose was recorded)");
  if (r.times.empty())
    for (std::size_t i = 0; i + 1 < n; ++i)
      if (identical(v.waypoints[i], v.waypoints[i + 1]))
        throw InvalidInputError(indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1) +
                                ": identical consecutive waypoints need explicit times (to dwell)");
  requireUniqueGeodesics(v.waypoints);

  validateShapeFields(r, &v);

  v.start_velocity = validVelocity(r.start_velocity, v.waypoints.front(), "start_velocity");
  v.end_velocity = validVelocity(r.end_velocity, v.waypoints.back(), "end_velocity");
  v.start_acceleration = validVelocity(r.start_acceleration, v.waypoints.front(), "start_acceleration");
  if (!r.velocities.empty() && r.velocities.size() != n)
    throw InvalidInputError("velocities: " + std::to_string(r.velocities.size()) + " given for " + std::to_string(n) +
                            " waypoints (give one per waypoint, or none)");
  for (std::size_t i = 0; i < r.velocities.size(); ++i)
  {
    if constexpr (std::is_same_v<typename Space::Velocity, Eigen::VectorXd>)
      if (r.velocities[i].size() == 0)
        throw InvalidInputError(indexedField("velocities", i) + ": is empty (expected a tangent vector)");
    v.velocities.push_back(validVelocity(r.velocities[i], v.waypoints[i], indexedField("velocities", i)));
  }

  validateTimingFields(r, &v);

  validateFitFields(r, &v);

  v.sampling = validateSampling(r.sample_times, r.sample_period, r.sample_count, limits);
  requireFiniteNonNegative(r.sample_tolerance, "sample_tolerance");
  if constexpr (std::is_same_v<Space, SphereSpace>)
    if (r.sample_tolerance > 0.0)
      throw InvalidInputError("sample_tolerance: " + formatNumber(r.sample_tolerance) +
                              " is for poses (the samples of a ~follow_trajectory goal); on the sphere give 0");
  v.sampling.sample_tolerance = r.sample_tolerance;
  if (r.start_state)
    applyStartState(*r.start_state, r.degree, &v);
  return v;
}

template ValidatedRequest validateRequest<PoseSpace>(const TrajectoryRequest&, const PlannerLimits&);
template ValidatedSphereRequest validateRequest<SphereSpace>(const SphereRequest&, const PlannerLimits&);

void requireFiniteNonNegative(double x, const std::string& field)
{
  requireFinite(x, field);
  if (x < 0.0)
    throw InvalidInputError(field + ": " + formatNumber(x) + " must be >= 0");
}

void validateTimes(const std::vector<double>& times, std::size_t num_waypoints)
{
  if (times.empty())
    return;
  requireIncreasingTimes(times, num_waypoints);
  for (std::size_t i = 0; i < times.size(); ++i)
  {
    requireRosDuration(times[i], indexedField("times", i));
    if (i > 0 && !(times[i] - times[i - 1] >= kRosDurationResolution))
      throw InvalidInputError(indexedField("times", i) + ": " + formatNumber(times[i]) + " is only " +
                              formatNumber(times[i] - times[i - 1]) + " s after times[" + std::to_string(i - 1) +
                              "], below the 1 ns resolution of time_from_start");
  }
}
}  // namespace se3_interpolation
