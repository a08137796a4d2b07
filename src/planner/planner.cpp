#include "se3_interpolation/planner/planner.h"

#include <cmath>
#include <memory>
#include <type_traits>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"
#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace
{
/// The uniform stretch k ≥ 1 that brings every peak rate within its bound (0 = unbounded):
/// speeds scale by 1/k and accelerations by 1/k². `cause` receives the binding bound's field.
template <class Space>
double stretchFactor(const BasicValidatedRequest<Space>& r, const CurveFigures& f, std::string* cause)
{
  double k = 1.0;
  auto bind = [&k, cause](double candidate, const char* field) {
    if (candidate > k)
    {
      k = candidate;
      *cause = field;
    }
  };
  auto speed = [&bind](double peak, double bound, const char* field) {
    if (bound > 0.0)
      bind(peak / bound, field);
  };
  auto accel = [&bind](double peak, double bound, const char* field) {
    if (bound > 0.0)
      bind(std::sqrt(peak / bound), field);
  };
  speed(f.max_linear_speed, r.max_linear_velocity, "max_linear_velocity");
  speed(f.max_angular_speed, r.max_angular_velocity, "max_angular_velocity");
  accel(f.max_linear_acceleration, r.max_linear_acceleration, "max_linear_acceleration");
  accel(f.max_angular_acceleration, r.max_angular_acceleration, "max_angular_acceleration");
  return k;
}

/// The chord distance between consecutive waypoints (SPEC, Timing).
double chordStep(const Pose<double>& a, const Pose<double>& b, double rotation_scale)
{
  const double dtheta = rotation_scale * rotationAngle(Quaternion<double>(a.q.conjugate() * b.q));
  return std::sqrt((b.p - a.p).squaredNorm() + dtheta * dtheta);
}

/// On the sphere: the great-circle angle.
double chordStep(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double /*rotation_scale*/)
{
  return Sphere::log<double>(a, b).norm();
}

/// One sample of a pose curve; quaternions sign-continuous with `previous` (the first w ≥ 0).
template <class G>
TrajectorySample sampleAt(const Curve<G>& curve, double t, const TrajectorySample* previous)
{
  const Kinematics k = kinematicsAt(curve, t);
  TrajectorySample s{ t, k.pose, k.velocity, k.acceleration };
  const Quaternion<double> before = previous ? previous->pose.q : Quaternion<double>(1.0, 0.0, 0.0, 0.0);
  if (s.pose.q.coeffs().dot(before.coeffs()) < 0.0)
    s.pose.q.coeffs() = -s.pose.q.coeffs();
  return s;
}

SphereSample sampleAt(const Curve<Sphere>& curve, double t, const SphereSample* /*previous*/)
{
  const SphereKinematics k = kinematicsAt(curve, t);
  return SphereSample{ t, k.point, k.velocity, k.acceleration };
}

bool allFinite(const TrajectorySample& s)
{
  return s.pose.p.allFinite() && s.pose.q.coeffs().allFinite() && s.velocity.linear.allFinite() &&
         s.velocity.angular.allFinite() && s.acceleration.linear.allFinite() && s.acceleration.angular.allFinite();
}

bool allFinite(const SphereSample& s)
{
  return s.point.allFinite() && s.velocity.allFinite() && s.acceleration.allFinite();
}

/// The bounds' field names for an error about the span they stretch the motion to.
template <class Space>
const char* boundFields()
{
  return std::is_same_v<Space, SphereSpace> ? "max_angular_velocity or max_angular_acceleration"
                                            : "max_linear_velocity, max_angular_velocity or their accelerations";
}

template <class Space, class G>
BasicResult<Space> run(const BasicValidatedRequest<Space>& r, const PlannerLimits& limits)
{
  const std::vector<double> times = waypointTimes(r);
  // Bounded work: refused from the fields alone, before the curve is built or measured.
  const WorkShape shape = workShape(r);
  requireWorkWithin(estimateWork(shape, expectedSamples(shape, times.back() - times.front())), shape, limits);
  std::shared_ptr<const Curve<G>> curve = makeCurve<G>(r, times);
  BasicResult<Space> out;
  if constexpr (std::is_same_v<Space, PoseSpace>)
    if (const auto blended = std::dynamic_pointer_cast<const CornerBlendedGeodesic<G>>(curve))
      out.blend_radii = blended->radii();
  CurveFigures fig = measureCurve(*curve, r.rotation_scale);

  out.waypoint_times = times;
  if (r.timing == Timing::kTimeOptimal)
  {
    timing::RateBounds bounds;
    bounds.velocity = { r.max_linear_velocity, r.max_angular_velocity };
    bounds.acceleration = { r.max_linear_acceleration, r.max_angular_acceleration };
    auto timed = timing::makeTimeOptimalCurve<G>(curve, bounds);
    out.time_scale = timed->profile().stretch;
    // Tiny bounds give a long motion: every time must still fit ros::Duration.
    validateTimeSpan(timed->startTime(), timed->endTime(), boundFields<Space>());
    for (double& t : out.waypoint_times)
      t = timed->profile().timeAt(t);
    curve = timed;
    // Length and rotation length are the path's; the rates and the energy are the timed motion's.
    const timing::TimingProfile& p = timed->profile();
    fig.max_linear_speed = p.max_speed[timing::kLinear];
    fig.max_angular_speed = p.max_speed[timing::kAngular];
    fig.max_linear_acceleration = p.max_acceleration[timing::kLinear];
    fig.max_angular_acceleration = p.max_acceleration[timing::kAngular];
    const double angular = p.acceleration_energy[timing::kAngular];
    // (ρ² · 0 must stay 0 for a huge ρ, as in measureCurve.)
    fig.energy = p.acceleration_energy[timing::kLinear] +
                 (angular > 0.0 ? r.rotation_scale * r.rotation_scale * angular : 0.0);
  }
  else
  {
    std::string cause = r.times.empty() ? "duration" : "times";
    out.time_scale = stretchFactor(r, fig, &cause);
    // Tiny bounds stretch time without limit: every time must still fit ros::Duration.
    validateTimeSpan(curve->startTime(),
                     curve->startTime() + (curve->endTime() - curve->startTime()) * out.time_scale, cause);
    for (double& t : out.waypoint_times)
      t = curve->startTime() + (t - curve->startTime()) * out.time_scale;
    if (out.time_scale > 1.0)
    {
      const double k = out.time_scale;
      curve = std::make_shared<TimeScaledCurve<G>>(curve, k);
      fig.max_linear_speed /= k;
      fig.max_angular_speed /= k;
      fig.max_linear_acceleration /= k * k;
      fig.max_angular_acceleration /= k * k;
      fig.energy /= k * k * k;
    }
  }
  out.start_time = curve->startTime();
  out.duration = curve->endTime() - curve->startTime();
  out.figures = fig;
  out.waypoints = r.waypoints;
  out.control_points = curve->controlPoints();
  out.point_at = [curve](double t) { return curve->value(t); };
  // Overflow (huge positions, times, rotation_scale or tiny max_* bounds) must not reach the
  // response as ∞ or NaN.
  const std::pair<const char*, double> figures[] = {
    { "time_scale", out.time_scale },
    { "duration", out.duration },
    { "length", fig.length },
    { "rotation_length", fig.rotation_length },
    { "max_linear_speed", fig.max_linear_speed },
    { "max_angular_speed", fig.max_angular_speed },
    { "max_linear_acceleration", fig.max_linear_acceleration },
    { "max_angular_acceleration", fig.max_angular_acceleration },
    { "energy", fig.energy },
  };
  for (const auto& f : figures)
    if (!std::isfinite(f.second))
      throw InterpolationError(std::string("the trajectory's ") + f.first + " is " + formatNumber(f.second) +
                               " (the input's magnitudes are too large: positions, times, rotation_scale or "
                               "max_* bounds)");
  for (std::size_t i = 0; i < out.waypoint_times.size(); ++i)
    if (!std::isfinite(out.waypoint_times[i]))
      throw InterpolationError(indexedField("waypoints", i) + ": its stretched time is " +
                               formatNumber(out.waypoint_times[i]) + " (the times or max_* bounds are too extreme)");

  const std::vector<double> ts = sampleTimes(r.sampling, curve->startTime(), curve->endTime(), limits);
  // Again with the final sample count (a stretch lengthens a sample_period's sampling).
  requireWorkWithin(estimateWork(shape, static_cast<double>(ts.size())), shape, limits);
  out.samples.reserve(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
  {
    out.samples.push_back(sampleAt(*curve, ts[i], i > 0 ? &out.samples.back() : nullptr));
    if (!allFinite(out.samples.back()))
      throw InterpolationError("the curve is not finite at t = " + formatNumber(ts[i]) +
                               " s (the input is too close to a singular configuration)");
  }
  return out;
}

TrajectoryResult dispatch(const ValidatedRequest& r, const PlannerLimits& limits)
{
  if (r.geometry == GeometryType::kScrew)
    return run<PoseSpace, ScrewSe3>(r, limits);
  return run<PoseSpace, DoubleGeodesicSe3>(r, limits);
}

SphereResult dispatch(const ValidatedSphereRequest& r, const PlannerLimits& limits)
{
  return run<SphereSpace, Sphere>(r, limits);
}
}  // namespace

template <class Space>
std::vector<double> waypointTimes(const BasicValidatedRequest<Space>& r)
{
  if (!r.times.empty())
    return r.times;
  const std::size_t n = r.waypoints.size();
  std::vector<double> cumulative(n, 0.0);
  for (std::size_t i = 1; i < n; ++i)
  {
    const double d = chordStep(r.waypoints[i - 1], r.waypoints[i], r.rotation_scale);
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

template <class Space>
BasicResult<Space> generate(const BasicRequest<Space>& request, const PlannerLimits& limits)
{
  return dispatch(validateRequest(request, limits), limits);
}

template std::vector<double> waypointTimes<PoseSpace>(const ValidatedRequest&);
template std::vector<double> waypointTimes<SphereSpace>(const ValidatedSphereRequest&);
template TrajectoryResult generate<PoseSpace>(const TrajectoryRequest&, const PlannerLimits&);
template SphereResult generate<SphereSpace>(const SphereRequest&, const PlannerLimits&);

}  // namespace se3_interpolation
