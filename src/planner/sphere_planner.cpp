#include "se3_interpolation/planner/sphere_planner.h"

#include <cmath>
#include <memory>
#include <sstream>

#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/geometry/sphere.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"

namespace se3_interpolation
{
namespace
{
/// A SphereRequest after validation: defaults resolved, points normalised, tangents projected.
struct ValidSphereRequest
{
  std::vector<Eigen::VectorXd> waypoints;
  std::vector<double> times;
  CurveType curve = CurveType::kInterpolating;
  int degree = 3;
  std::vector<double> knots;
  int continuity = 2;
  EndCondition end_condition = EndCondition::kNatural;
  Eigen::VectorXd start_velocity;
  Eigen::VectorXd end_velocity;
  Eigen::VectorXd start_acceleration;
  std::vector<Eigen::VectorXd> velocities;
  Parameterization parameterization = Parameterization::kChord;
  double duration = 0.0;
  double max_speed = 0.0;
  double max_acceleration = 0.0;
  Timing timing = Timing::kStretch;
  Sampling sampling;
};

void requireUnused(double x, const std::string& field, const std::string& instead)
{
  if (x != 0.0)
    throw InvalidInputError(field + ": not used on the sphere" + instead);
}

template <class E>
E parseName(const std::string& value, const std::string& field, const std::vector<std::pair<std::string, E>>& names,
            E default_value)
{
  if (value.empty())
    return default_value;
  std::string known;
  for (const auto& n : names)
  {
    if (value == n.first)
      return n.second;
    known += (known.empty() ? "" : ", ") + n.first;
  }
  throw InvalidInputError(field + ": unknown value '" + value + "' (expected one of: " + known + ")");
}

/// The unit vector of a raw waypoint; `dim` is the dimension of waypoints[0].
Eigen::VectorXd validPoint(const Eigen::VectorXd& raw, Eigen::Index dim, const std::string& field)
{
  if (raw.size() != dim)
    throw InvalidInputError(field + ": has " + std::to_string(raw.size()) + " components; waypoints[0] has " +
                            std::to_string(dim) + " (all waypoints need the same dimension)");
  for (Eigen::Index j = 0; j < raw.size(); ++j)
    requireFinite(raw[j], indexedField(field, static_cast<std::size_t>(j)));
  const double n = raw.norm();
  if (!(n >= 0.99 && n <= 1.01))
    throw InvalidInputError(field + ": norm " + formatNumber(n) + " is outside [0.99, 1.01] (expected a unit vector)");
  return raw / n;
}

/// A tangent vector at x (empty = zero), projected onto T_x S^m.
Eigen::VectorXd validTangent(const Eigen::VectorXd& raw, const Eigen::VectorXd& x, const std::string& field)
{
  if (raw.size() == 0)
    return Eigen::VectorXd::Zero(x.size());
  if (raw.size() != x.size())
    throw InvalidInputError(field + ": has " + std::to_string(raw.size()) + " components; expected " +
                            std::to_string(x.size()) + " (a tangent vector of R^" + std::to_string(x.size()) + ")");
  for (Eigen::Index j = 0; j < raw.size(); ++j)
    requireFinite(raw[j], indexedField(field, static_cast<std::size_t>(j)));
  const double normal = raw.dot(x);
  if (std::abs(normal) > 0.01 * raw.norm())
    throw InvalidInputError(field + ": is not tangent to the sphere at its waypoint (normal component " +
                            formatNumber(normal) + " of a vector of length " + formatNumber(raw.norm()) + ")");
  return raw - normal * x;
}

ValidSphereRequest validate(const SphereRequest& r, const PlannerLimits& limits)
{
  ValidSphereRequest v;
  const std::size_t n = r.waypoints.size();
  if (n < 2)
    throw InvalidInputError("waypoints: " + std::to_string(n) + " given; at least 2 are needed");
  if (n > limits.max_waypoints)
    throw LimitExceededError("waypoints: " + std::to_string(n) + " given; the limit (~max_waypoints) is " +
                             std::to_string(limits.max_waypoints));
  const Eigen::Index dim = r.waypoints[0].size();
  if (dim < 3)
    throw InvalidInputError("waypoints[0]: has " + std::to_string(dim) +
                            " components; a point of the sphere S^m in R^{m+1}, m >= 2, needs at least 3");
  for (std::size_t i = 0; i < n; ++i)
    v.waypoints.push_back(validPoint(r.waypoints[i], dim, indexedField("waypoints", i)));

  if (!r.geometry.empty())
    throw InvalidInputError("geometry: not used on the sphere (its metric is the round one); leave it empty");
  std::vector<std::pair<std::string, CurveType>> curves;
  for (CurveType c : { CurveType::kPiecewiseGeodesic, CurveType::kBezier, CurveType::kBspline,
                       CurveType::kInterpolating, CurveType::kHermite, CurveType::kBlended })
    curves.emplace_back(toString(c), c);
  v.curve = parseName(r.curve, "curve", curves, CurveType::kInterpolating);
  v.end_condition = parseName<EndCondition>(
      r.end_condition, "end_condition",
      { { "natural", EndCondition::kNatural }, { "clamped", EndCondition::kClamped }, { "start", EndCondition::kStart } },
      EndCondition::kNatural);
  v.parameterization = parseName<Parameterization>(r.parameterization, "parameterization",
                                                   { { "chord", Parameterization::kChord },
                                                     { "uniform", Parameterization::kUniform },
                                                     { "centripetal", Parameterization::kCentripetal } },
                                                   Parameterization::kChord);

  validateTimes(r.times, n);
  if (!r.times.empty())
  {
    v.times = r.times;
  }
  else
  {
    for (std::size_t i = 0; i + 1 < n; ++i)
      if (v.waypoints[i] == v.waypoints[i + 1])
        throw InvalidInputError(indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1) +
                                ": identical consecutive waypoints need explicit times (to dwell)");
  }
  // Antipodal neighbours: NonUniqueGeodesicError naming both.
  polygonLogs<Sphere>(v.waypoints, "waypoints");

  if (r.degree < 0)
    throw InvalidInputError("degree: " + std::to_string(r.degree) + " must be >= 1");
  const int max_degree = static_cast<int>(n) - 1;
  v.degree = r.degree == 0 ? std::min(3, max_degree) : r.degree;
  if (v.curve == CurveType::kBspline && v.degree > max_degree)
    throw InvalidInputError("degree: " + std::to_string(v.degree) + " is too high for " + std::to_string(n) +
                            " waypoints (at most " + std::to_string(max_degree) + ")");
  if (!r.knots.empty())
  {
    if (v.curve != CurveType::kBspline)
      throw InvalidInputError("knots: only used by curve 'bspline' (curve is '" + std::string(toString(v.curve)) +
                              "')");
    validateKnots(r.knots, n, v.degree);
    v.knots = r.knots;
  }
  if (r.continuity < 0 || r.continuity > 8)
    throw InvalidInputError("continuity: " + std::to_string(r.continuity) + " is outside 1 ... 8");
  v.continuity = r.continuity == 0 ? 2 : r.continuity;

  v.start_velocity = validTangent(r.start_velocity, v.waypoints.front(), "start_velocity");
  v.end_velocity = validTangent(r.end_velocity, v.waypoints.back(), "end_velocity");
  v.start_acceleration = validTangent(r.start_acceleration, v.waypoints.front(), "start_acceleration");
  if (!r.velocities.empty() && r.velocities.size() != n)
    throw InvalidInputError("velocities: " + std::to_string(r.velocities.size()) + " given for " + std::to_string(n) +
                            " waypoints (give one per waypoint, or none)");
  for (std::size_t i = 0; i < r.velocities.size(); ++i)
  {
    if (r.velocities[i].size() == 0)
      throw InvalidInputError(indexedField("velocities", i) + ": is empty (expected a tangent vector)");
    v.velocities.push_back(validTangent(r.velocities[i], v.waypoints[i], indexedField("velocities", i)));
  }

  requireUnused(r.rotation_scale, "rotation_scale", " (chord spacing uses the great-circle angle)");
  requireFiniteNonNegative(r.duration, "duration");
  requireRosDuration(r.duration, "duration");
  v.duration = r.duration;
  requireUnused(r.max_linear_velocity, "max_linear_velocity", "; bound the speed with max_angular_velocity (rad/s)");
  requireUnused(r.max_linear_acceleration, "max_linear_acceleration",
                "; bound the acceleration with max_angular_acceleration (rad/s^2)");
  requireFiniteNonNegative(r.max_angular_velocity, "max_angular_velocity");
  requireFiniteNonNegative(r.max_angular_acceleration, "max_angular_acceleration");
  v.max_speed = r.max_angular_velocity;
  v.max_acceleration = r.max_angular_acceleration;
  v.timing = parseTiming(r.timing);

  v.sampling = validateSampling(r.sample_times, r.sample_period, r.sample_count, limits);
  return v;
}

/// Waypoint times: explicit, else spaced by the great-circle angles (SPEC, Timing).
std::vector<double> sphereWaypointTimes(const ValidSphereRequest& r)
{
  if (!r.times.empty())
    return r.times;
  const std::size_t n = r.waypoints.size();
  std::vector<double> cumulative(n, 0.0);
  for (std::size_t i = 1; i < n; ++i)
  {
    const double d = Sphere::log<double>(r.waypoints[i - 1], r.waypoints[i]).norm();
    double step = 1.0;
    if (r.parameterization == Parameterization::kChord)
      step = d;
    else if (r.parameterization == Parameterization::kCentripetal)
      step = std::sqrt(d);
    cumulative[i] = cumulative[i - 1] + step;
  }
  const double total = r.duration > 0.0 ? r.duration : static_cast<double>(n - 1);
  std::vector<double> times(n);
  for (std::size_t i = 0; i < n; ++i)
    times[i] = total * cumulative[i] / cumulative[n - 1];
  times.back() = total;
  for (std::size_t i = 1; i < n; ++i)
    if (!(times[i] > times[i - 1]))
      throw InvalidInputError(indexedField("waypoints", i - 1) + " and " + indexedField("waypoints", i) +
                              ": too close to be spaced apart in time; give explicit times");
  return times;
}

std::shared_ptr<const Curve<Sphere>> makeSphereCurve(const ValidSphereRequest& r, const std::vector<double>& times)
{
  const auto& x = r.waypoints;
  switch (r.curve)
  {
    case CurveType::kPiecewiseGeodesic:
      return std::make_shared<PiecewiseGeodesic<Sphere>>(x, times);
    case CurveType::kBezier:
      return std::make_shared<BezierCurve<Sphere>>(x, times.front(), times.back());
    case CurveType::kBspline:
      return std::make_shared<BSplineCurve<Sphere>>(
          x, r.degree, r.knots.empty() ? clampedUniformKnots(x.size(), r.degree, times.front(), times.back()) : r.knots);
    case CurveType::kInterpolating:
      return makeInterpolatingSpline<Sphere>(x, times, r.end_condition, r.start_velocity, r.end_velocity,
                                             r.start_acceleration);
    case CurveType::kHermite:
      return std::make_shared<HermiteSpline<Sphere>>(
          x, times, r.velocities.empty() ? estimateTangents<Sphere>(x, times) : r.velocities);
    case CurveType::kBlended:
      return std::make_shared<BlendedSpline<Sphere>>(x, times, r.continuity);
  }
  throw InvalidInputError(std::string("curve: '") + toString(r.curve) + "' is not available on the sphere");
}

}  // namespace

SphereResult generateSphereTrajectory(const SphereRequest& request, const PlannerLimits& limits)
{
  const ValidSphereRequest r = validate(request, limits);
  const std::vector<double> times = sphereWaypointTimes(r);
  // Bounded work, as for poses (work_estimate.h): refused before the curve is built.
  WorkShape shape;
  shape.curve = r.curve;
  shape.waypoints = r.waypoints.size();
  shape.degree = r.degree;
  shape.sample_times = r.sampling.sample_times;
  shape.sample_period = r.sampling.sample_period;
  shape.sample_count = r.sampling.sample_count;
  requireWorkWithin(estimateWork(shape, expectedSamples(shape, times.back() - times.front())), shape, limits);
  std::shared_ptr<const Curve<Sphere>> curve = makeSphereCurve(r, times);
  SphereCurveFigures fig = measureSphereCurve(*curve);

  SphereResult out;
  out.waypoint_times = times;
  double k = 1.0;
  if (r.timing == Timing::kTimeOptimal)
  {
    timing::RateBounds bounds;
    bounds.velocity[timing::kAngular] = r.max_speed;
    bounds.acceleration[timing::kAngular] = r.max_acceleration;
    auto timed = timing::makeTimeOptimalCurve<Sphere>(curve, bounds);
    out.time_scale = timed->profile().stretch;
    validateTimeSpan(timed->startTime(), timed->endTime(), "max_angular_velocity or max_angular_acceleration");
    for (double& t : out.waypoint_times)
      t = timed->profile().timeAt(t);
    curve = timed;
    // The length is the path's; the rates and the energy are the timed motion's.
    fig.max_speed = timed->profile().max_speed[timing::kAngular];
    fig.max_acceleration = timed->profile().max_acceleration[timing::kAngular];
    fig.energy = timed->profile().acceleration_energy[timing::kAngular];
  }
  else
  {
    std::string cause = r.times.empty() ? "duration" : "times";
    if (r.max_speed > 0.0 && fig.max_speed / r.max_speed > k)
    {
      k = fig.max_speed / r.max_speed;
      cause = "max_angular_velocity";
    }
    if (r.max_acceleration > 0.0 && std::sqrt(fig.max_acceleration / r.max_acceleration) > k)
    {
      k = std::sqrt(fig.max_acceleration / r.max_acceleration);
      cause = "max_angular_acceleration";
    }
    validateTimeSpan(curve->startTime(), curve->startTime() + (curve->endTime() - curve->startTime()) * k, cause);
    out.time_scale = k;
    for (double& t : out.waypoint_times)
      t = curve->startTime() + (t - curve->startTime()) * k;
  }
  if (k > 1.0)
  {
    curve = std::make_shared<TimeScaledCurve<Sphere>>(curve, k);
    fig.max_speed /= k;
    fig.max_acceleration /= k * k;
    fig.energy /= k * k * k;
  }
  out.start_time = curve->startTime();
  out.duration = curve->endTime() - curve->startTime();
  out.length = fig.length;
  out.max_speed = fig.max_speed;
  out.max_acceleration = fig.max_acceleration;
  out.energy = fig.energy;
  out.waypoints = r.waypoints;
  out.point_at = [curve](double t) { return curve->value(t); };

  const std::vector<double> ts = sampleTimes(r.sampling, curve->startTime(), curve->endTime(), limits);
  requireWorkWithin(estimateWork(shape, static_cast<double>(ts.size())), shape, limits);
  out.samples.resize(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
  {
    const SphereKinematics kin = sphereKinematicsAt(*curve, ts[i]);
    SphereSample& s = out.samples[i];
    s.time = ts[i];
    s.point = kin.point;
    s.velocity = kin.velocity;
    s.acceleration = kin.acceleration;
    if (!s.point.allFinite() || !s.velocity.allFinite() || !s.acceleration.allFinite())
      throw InterpolationError("the curve is not finite at t = " + formatNumber(ts[i]) +
                               " s (the input is too close to a singular configuration)");
  }
  return out;
}

}  // namespace se3_interpolation
