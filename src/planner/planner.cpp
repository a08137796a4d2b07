#include "se3_interpolation/planner/planner.h"

#include <cmath>
#include <memory>
#include <type_traits>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/curves/start_join.h"
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

/// The request's timing (stretch or time_optimal) applied to a curve that starts at waypoints[0].
template <class Space, class G>
void applyTiming(const BasicValidatedRequest<Space>& r, std::shared_ptr<const Curve<G>>* curve_io, CurveFigures* fig_io,
                 BasicResult<Space>* out_io)
{
  std::shared_ptr<const Curve<G>>& curve = *curve_io;
  CurveFigures& fig = *fig_io;
  BasicResult<Space>& out = *out_io;
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
    return;
  }
  std::string cause = r.times.empty() ? "duration" : "times";
  out.time_scale = stretchFactor(r, fig, &cause);
  // Tiny bounds stretch time without limit: every time must still fit ros::Duration.
  validateTimeSpan(curve->startTime(), curve->startTime() + (curve->endTime() - curve->startTime()) * out.time_scale,
                   cause);
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

/// sqrt(|linear|^2 + rho^2 |angular|^2): the speed of a twist in the metric of the chord parameterisation.
double weightedNorm(const Twist& v, double rho)
{
  return std::sqrt(v.linear.squaredNorm() + rho * rho * v.angular.squaredNorm());
}

/// The timing of a pose request with a start state (request.h, StartState): the curve through the
/// start pose and the waypoints (times from 0), entered by the joining quintic (curves/start_join.h)
/// unless it takes the start data itself. Stretch: the curve is stretched and the joining segment
/// rebuilt over the stretched first segment, so the start state is kept exactly. time_optimal from
/// a moving state: the path after the first segment is timed from the current path speed, the
/// joining segment leads into it in 2 d / (speed at its start + speed at its end) (the time of a
/// constant acceleration over the chord d), at most the rest-to-rest time 2 sqrt(d / a) of the
/// linear acceleration bound. The joining segment's own rates are not bounded: it starts at the old
/// motion's state, which may itself exceed the bounds.
template <class G>
void applyTimingFromStart(const ValidatedRequest& r, const std::vector<double>& times,
                          std::shared_ptr<const Curve<G>>* curve_io, CurveFigures* fig_io, TrajectoryResult* out_io)
{
  std::shared_ptr<const Curve<G>>& curve = *curve_io;
  const std::shared_ptr<const Curve<G>> through = curve;  // starts at the start pose at 0
  TrajectoryResult& out = *out_io;
  const StartState& s = *r.start_state;
  const double rho = r.rotation_scale;
  const double t1 = times[1];
  auto join = [&s](std::shared_ptr<const Curve<G>> rest, double h, double from) {
    return std::make_shared<StartJoinedCurve<G>>(s.pose, poseJet(s.pose, s.velocity, s.acceleration), 0.0, h,
                                                 std::move(rest), from);
  };
  const double start_speed = weightedNorm(s.velocity, rho);
  if (r.timing == Timing::kTimeOptimal && !(start_speed > 0.0))
  {
    // At rest: the time-optimal motion along the curve from the start pose, like any other.
    applyTiming<PoseSpace, G>(r, curve_io, fig_io, out_io);
  }
  else if (r.timing == Timing::kTimeOptimal)
  {
    timing::RateBounds bounds;
    bounds.velocity = { r.max_linear_velocity, r.max_angular_velocity };
    bounds.acceleration = { r.max_linear_acceleration, r.max_angular_acceleration };
    const double path_speed = weightedNorm(kinematicsAt(*through, t1).velocity, rho);
    timing::TimeOptimalOptions options;
    options.start_speed = path_speed > 0.0 ? start_speed / path_speed : 0.0;
    auto timed = timing::makeTimeOptimalCurve<G>(std::make_shared<CurveTail<G>>(through, t1), bounds, options);
    out.time_scale = timed->profile().stretch;
    const Kinematics entry = kinematicsAt(*timed, t1);
    const double chord = std::sqrt((entry.pose.p - s.pose.p).squaredNorm() +
                                   std::pow(rho * entry.pose.q.angularDistance(s.pose.q), 2));
    double h = 2.0 * chord / (start_speed + weightedNorm(entry.velocity, rho));
    if (r.max_linear_acceleration > 0.0)
      h = std::min(h, 2.0 * std::sqrt(chord / r.max_linear_acceleration));
    validateTimeSpan(0.0, h + timed->endTime() - t1, boundFields<PoseSpace>());
    curve = join(timed, h, t1);
    for (std::size_t i = 1; i < times.size(); ++i)
      out.waypoint_times[i] = h + timed->profile().timeAt(times[i]) - t1;
    *fig_io = measureCurve(*curve, rho);
  }
  else
  {
    const bool native = r.curve == CurveType::kInterpolating && r.end_condition == EndCondition::kStart;
    if (!native)
      curve = join(through, t1, t1);
    *fig_io = measureCurve(*curve, rho);
    std::string cause = r.times.empty() ? "duration" : "times";
    const double k = stretchFactor(r, *fig_io, &cause);
    validateTimeSpan(0.0, curve->endTime() * k, cause);
    if (k > 1.0)
    {
      curve = join(std::make_shared<TimeScaledCurve<G>>(through, k), k * t1, k * t1);
      *fig_io = measureCurve(*curve, rho);
      for (double& t : out.waypoint_times)
        t *= k;
    }
    out.time_scale = k;
  }
  // The response lists the requested waypoints' times and radii, not the start pose's.
  if (!r.start_replaces_first)
  {
    out.waypoint_times.erase(out.waypoint_times.begin());
    if (!out.blend_radii.empty())
      out.blend_radii.erase(out.blend_radii.begin());
  }
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
  bool timed = false;
  if constexpr (std::is_same_v<Space, PoseSpace>)
    if (r.start_state)
    {
      applyTimingFromStart<G>(r, times, &curve, &fig, &out);
      timed = true;
    }
  if (!timed)
    applyTiming<Space, G>(r, &curve, &fig, &out);
  out.start_time = curve->startTime();
  out.duration = curve->endTime() - curve->startTime();
  out.figures = fig;
  out.waypoints = r.waypoints;
  out.control_points = curve->controlPoints();
  out.point_at = [curve](double t) { return curve->value(t); };
  out.state_at = [curve](double t) { return sampleAt(*curve, t, nullptr); };
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
  // Spaced by at least what time_from_start resolves (a denormal duration would divide by ~0).
  for (std::size_t i = 1; i < n; ++i)
    if (!(times[i] - times[i - 1] >= kRosDurationResolution))
      throw InvalidInputError(indexedField("waypoints", i - 1) + " and " + indexedField("waypoints", i) +
                              ": too close to be spaced apart in time (" + formatNumber(times[i] - times[i - 1]) +
                              " s, below the 1 ns resolution of time_from_start); give a longer duration or "
                              "explicit times");
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
