#include "se3_interpolation/planner/planner.h"

#include <cmath>
#include <memory>
#include <sstream>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"

namespace se3_interpolation
{
namespace
{
/// The uniform stretch k ≥ 1 that brings every peak rate within its bound (0 = unbounded):
/// speeds scale by 1/k and accelerations by 1/k². `cause` receives the binding bound's field.
double stretchFactor(const ValidatedRequest& r, const CurveFigures& f, std::string* cause)
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

template <class G>
TrajectoryResult run(const ValidatedRequest& r, const PlannerLimits& limits)
{
  const std::vector<double> times = waypointTimes(r);
  // Bounded work: refused from the fields alone, before the curve is built or measured.
  requireWorkWithin(estimateWork(r, expectedSamples(r, times.back() - times.front())), r, limits);
  std::shared_ptr<const Curve<G>> curve = makeCurve<G>(r, times);
  TrajectoryResult out;
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
    validateTimeSpan(timed->startTime(), timed->endTime(),
                     "max_linear_velocity, max_angular_velocity or their accelerations");
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
  }
  if (r.timing == Timing::kStretch && out.time_scale > 1.0)
  {
    const double k = out.time_scale;
    curve = std::make_shared<TimeScaledCurve<G>>(curve, k);
    fig.max_linear_speed /= k;
    fig.max_angular_speed /= k;
    fig.max_linear_acceleration /= k * k;
    fig.max_angular_acceleration /= k * k;
    fig.energy /= k * k * k;
  }
  out.start_time = curve->startTime();
  out.duration = curve->endTime() - curve->startTime();
  out.length = fig.length;
  out.rotation_length = fig.rotation_length;
  out.max_linear_speed = fig.max_linear_speed;
  out.max_angular_speed = fig.max_angular_speed;
  out.max_linear_acceleration = fig.max_linear_acceleration;
  out.max_angular_acceleration = fig.max_angular_acceleration;
  out.energy = fig.energy;
  out.waypoints = r.waypoints;
  out.control_points = curve->controlPoints();
  out.pose_at = [curve](double t) { return curve->value(t); };
  // Overflow (huge positions, times, rotation_scale or tiny max_* bounds) must not reach the
  // response as ∞ or NaN.
  const std::pair<const char*, double> figures[] = {
    { "time_scale", out.time_scale },
    { "duration", out.duration },
    { "length", out.length },
    { "rotation_length", out.rotation_length },
    { "max_linear_speed", out.max_linear_speed },
    { "max_angular_speed", out.max_angular_speed },
    { "max_linear_acceleration", out.max_linear_acceleration },
    { "max_angular_acceleration", out.max_angular_acceleration },
    { "energy", out.energy },
  };
  for (const auto& f : figures)
    if (!std::isfinite(f.second))
      throw InterpolationError(std::string("the trajectory's ") + f.first + " is " + formatNumber(f.second) +
                               " (the input's magnitudes are too large: positions, times, rotation_scale or "
                               "max_* bounds)");
  for (std::size_t i = 0; i < out.waypoint_times.size(); ++i)
    if (!std::isfinite(out.waypoint_times[i]))
      throw InterpolationError("waypoints[" + std::to_string(i) + "]: its stretched time is " +
                               formatNumber(out.waypoint_times[i]) + " (the times or max_* bounds are too extreme)");

  const std::vector<double> ts =
      sampleTimes(Sampling{ r.sample_times, r.sample_period, r.sample_count }, curve->startTime(), curve->endTime(), limits);
  // Again with the final sample count (a stretch lengthens a sample_period's sampling).
  requireWorkWithin(estimateWork(r, static_cast<double>(ts.size())), r, limits);
  out.samples.resize(ts.size());
  Quaternion<double> previous(1.0, 0.0, 0.0, 0.0);
  for (std::size_t i = 0; i < ts.size(); ++i)
  {
    const Kinematics k = kinematicsAt(*curve, ts[i]);
    TrajectorySample& s = out.samples[i];
    s.time = ts[i];
    s.pose = k.pose;
    // Sign-continuous quaternions, the first with w ≥ 0.
    if (s.pose.q.coeffs().dot(previous.coeffs()) < 0.0)
      s.pose.q.coeffs() = -s.pose.q.coeffs();
    previous = s.pose.q;
    s.velocity = k.velocity;
    s.acceleration = k.acceleration;
    for (double x : { s.pose.p.x(), s.pose.p.y(), s.pose.p.z(), s.pose.q.w(), s.velocity.linear.norm(),
                      s.velocity.angular.norm(), s.acceleration.linear.norm(), s.acceleration.angular.norm() })
      if (!std::isfinite(x))
        throw InterpolationError("the curve is not finite at t = " + formatNumber(ts[i]) +
                                 " s (the input is too close to a singular configuration)");
  }
  return out;
}
}  // namespace

std::vector<double> waypointTimes(const ValidatedRequest& r)
{
  if (!r.times.empty())
    return r.times;
  const std::size_t n = r.waypoints.size();
  std::vector<double> cumulative(n, 0.0);
  for (std::size_t i = 1; i < n; ++i)
  {
    const Pose<double>& a = r.waypoints[i - 1];
    const Pose<double>& b = r.waypoints[i];
    const double dtheta = r.rotation_scale * rotationAngle(Quaternion<double>(a.q.conjugate() * b.q));
    const double d = std::sqrt((b.p - a.p).squaredNorm() + dtheta * dtheta);
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
      throw InvalidInputError("waypoints[" + std::to_string(i - 1) + "] and waypoints[" + std::to_string(i) +
                              "]: too close to be spaced apart in time; give explicit times");
  return times;
}

TrajectoryResult generateTrajectory(const TrajectoryRequest& request, const PlannerLimits& limits)
{
  const ValidatedRequest r = validateRequest(request, limits);
  if (r.geometry == GeometryType::kScrew)
    return run<ScrewSe3>(r, limits);
  return run<DoubleGeodesicSe3>(r, limits);
}

}  // namespace se3_interpolation
