#include "se3_interpolation/planner/planner.h"

#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/execution/sample_refinement.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"
#include "se3_interpolation/timing/constant_speed.h"
#include "se3_interpolation/timing/geodesic_timing.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "joint_space.h"
#include "planned_motion.h"
#include "timing_figures.h"

namespace se3_interpolation
{
namespace
{
using planner_detail::boundFields;
using planner_detail::buildCurve;
using planner_detail::curveFigures;
using planner_detail::fillJoints;
using planner_detail::followWithArm;
using planner_detail::jointBoxesOf;
using planner_detail::jointSpaceOf;
using planner_detail::hasJerkBound;
using planner_detail::measureJerk;
using planner_detail::pathLengths;
using planner_detail::PlannedMotion;
using planner_detail::planMotion;
using planner_detail::planWithStartState;
using planner_detail::rateBounds;
using planner_detail::setConstantSpeedFigures;
using planner_detail::setGeodesicFigures;
using planner_detail::setJerkLimitedFigures;
using planner_detail::setTimedFigures;
using planner_detail::stretchFactor;

/// The chord distance between consecutive waypoints (docs/timing.md).
double chordStep(const Pose<double>& a, const Pose<double>& b, double rotation_scale)
{
  return chordDistance(a, b, rotation_scale);
}

/// On the sphere: the great-circle angle.
double chordStep(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double /*rotation_scale*/)
{
  return Sphere::log<double>(a, b).norm();
}

/// Flips s's quaternion to the sign of `previous`'s (without one: w ≥ 0).
void alignSign(TrajectorySample* s, const TrajectorySample* previous)
{
  const Quaternion<double> before = previous ? previous->pose.q : Quaternion<double>(1.0, 0.0, 0.0, 0.0);
  if (s->pose.q.coeffs().dot(before.coeffs()) < 0.0)
    s->pose.q.coeffs() = -s->pose.q.coeffs();
}

/// One sample of a pose curve; quaternions sign-continuous with `previous` (the first w ≥ 0).
template <class G>
TrajectorySample sampleAt(const Curve<G>& curve, double t, const TrajectorySample* previous, Side side = Side::kRight)
{
  const Kinematics k = kinematicsAt(curve, t, side);
  TrajectorySample s;
  s.time = t;
  s.pose = k.pose;
  s.velocity = k.velocity;
  s.acceleration = k.acceleration;
  alignSign(&s, previous);
  return s;
}

SphereSample sampleAt(const Curve<Sphere>& curve, double t, const SphereSample* /*previous*/, Side side = Side::kRight)
{
  const SphereKinematics k = kinematicsAt(curve, t, side);
  return SphereSample{ t, k.point, k.velocity, k.acceleration };
}

/// The refinement of the samples that sample_tolerance asks for (execution/sample_refinement.h), on
/// the request's geometry and bounds; none without it, and none on the sphere (refused by validation).
template <class Space, class G>
std::optional<SampleRefiner> refinerFor(const BasicValidatedRequest<Space>& r,
                                        const std::shared_ptr<const Curve<G>>& curve, std::size_t budget)
{
  if constexpr (std::is_same_v<Space, PoseSpace>)
  {
    if (!(r.sampling.sample_tolerance > 0.0))
      return std::nullopt;
    SampleRefinement settings;
    settings.tolerance = r.sampling.sample_tolerance;
    settings.rotation_scale = r.rotation_scale;
    settings.geometry = r.geometry;
    settings.limits = motionLimitsOf(r);
    return SampleRefiner(
        settings, [curve](double t) { return sampleAt(*curve, t, nullptr); }, budget);
  }
  else
    return std::nullopt;
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

/// Samples taken between two checks of the request's deadline (deadline.h).
constexpr std::size_t kSamplesPerDeadlineCheck = 1024;

/// Hands `block` to `sink` outside the request's deadline (the caller's work is not the request's).
template <class Sample>
void handOn(const std::function<void(const Sample*, std::size_t)>& sink, const std::vector<Sample>& block)
{
  const ScopedDeadlinePause pause;
  sink(block.data(), block.size());
}
}  // namespace

namespace planner_detail
{
/// The request's timing (stretch, time_optimal or constant_speed) applied to a curve that starts at waypoints[0].
template <class Space, class G>
void applyTiming(const BasicValidatedRequest<Space>& r, std::shared_ptr<const Curve<G>>* curve_io, CurveFigures* fig_io,
                 BasicResult<Space>* out_io)
{
  std::shared_ptr<const Curve<G>>& curve = *curve_io;
  CurveFigures& fig = *fig_io;
  BasicResult<Space>& out = *out_io;
  // A retimed motion replaces the curve: its span (tiny bounds give a long motion: every time must
  // still fit ros::Duration; `cause` is named otherwise) and the waypoints' times through its s⁻¹,
  // the last pinned to the end where s⁻¹ is exact only to rounding.
  const auto adopt = [&](const auto& timed, const std::string& cause, bool pin_end) {
    validateTimeSpan(timed->startTime(), timed->endTime(), cause);
    for (double& t : out.waypoint_times)
      t = timed->profile().timeAt(t);
    if (pin_end && !out.waypoint_times.empty())
      out.waypoint_times.back() = timed->endTime();
    curve = timed;
  };
  if constexpr (std::is_same_v<Space, PoseSpace>)
    if (r.timing == Timing::kConstantSpeed)
    {
      timing::ConstantSpeedOptions options;
      options.speed = r.speed;
      options.metric = { 1.0, r.rotation_scale * r.rotation_scale };
      auto timed = timing::makeConstantSpeedCurve<G>(curve, rateBounds(r), options);
      adopt(timed, "speed", true);
      out.constant_speed_start = timed->profile().windowStart();
      out.constant_speed_end = timed->profile().windowEnd();
      setConstantSpeedFigures(*timed, &fig);
      return;
    }
  // A chain of geodesic segments at proportional rates: the exact time-optimal motion in closed
  // form (timing/geodesic_timing.h); any other path, bounds it does not serve, or an arm's joint
  // limits, the general timings.
  if constexpr (std::is_same_v<Space, PoseSpace>)
    if (r.timing == Timing::kTimeOptimal && !r.joint_space)
      if (auto timed = timing::makeGeodesicTimedCurve<G>(curve, rateBounds(r)))
      {
        adopt(timed, boundFields<Space>(), true);
        setGeodesicFigures(r, timed->profile(), &fig);
        return;
      }
  if (r.timing == Timing::kTimeOptimal && (hasJerkBound(r) || planner_detail::jointJerkWindow(r) > 0.0))
  {
    timing::JerkLimitedOptions options;
    options.grid.boxes = jointBoxesOf(r, curve, out.waypoint_times);
    options.window = planner_detail::jointJerkWindow(r);
    auto timed = explainingArmJerk(r, [&] { return timing::makeJerkLimitedCurve<G>(curve, rateBounds(r), options); });
    out.time_scale = timed->profile().stretch;
    adopt(timed, boundFields<Space>(), true);
    setJerkLimitedFigures(r, *timed, &fig);
    return;
  }
  if (r.timing == Timing::kTimeOptimal)
  {
    timing::TimeOptimalOptions options;
    options.boxes = jointBoxesOf(r, curve, out.waypoint_times);
    auto timed = timing::makeTimeOptimalCurve<G>(curve, rateBounds(r), options);
    out.time_scale = timed->profile().stretch;
    adopt(timed, boundFields<Space>(), false);  // (grid points map exactly: the end is the end)
    setTimedFigures(r, timed->profile(), &fig);
    return;
  }
  measureJerk(r, *curve, &fig);
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
    planner_detail::stretchFigures(k, &fig);
  }
}

/// `end_condition: start` solves the spline forward from the start data, which amplifies them
/// (each segment's end acceleration feeds the next): a curve more than kMaxStartLengthRatio times
/// as long as its waypoint polygon (chord lengths, rotation_scale ρ) is refused rather than returned.
constexpr double kMaxStartLengthRatio = 10.0;

template <class Space>
void requireStableStartSolve(const BasicValidatedRequest<Space>& r, const CurveFigures& fig)
{
  if (!continuesStartState(r))
    return;
  double polygon = 0.0;
  for (std::size_t i = 1; i < r.waypoints.size(); ++i)
    polygon += chordStep(r.waypoints[i - 1], r.waypoints[i], r.rotation_scale);
  // The curve's chord length: poses ∫|ṗ| + ρ∫|ω| (ρ · 0 stays 0 for a huge ρ), the sphere ∫|ẋ|.
  double length = fig.rotation_length;
  if constexpr (std::is_same_v<Space, PoseSpace>)
    length = fig.length + (fig.rotation_length > 0.0 ? r.rotation_scale * fig.rotation_length : 0.0);
  if (length > kMaxStartLengthRatio * polygon + 1e-12)
    throw InvalidInputError("end_condition: 'start' makes a curve " + formatNumber(length) +
                            " long through waypoints whose polygon is " + formatNumber(polygon) + " long (more than " +
                            formatNumber(kMaxStartLengthRatio) +
                            " times: solving forward from the start data amplifies them); use end_condition "
                            "'natural' or 'clamped', or waypoints and times that the start velocity leads into");
}

template <class Space, class G>
PlannedMotion<Space, G> buildCurve(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
{
  FamilyCurve<G> built = makeFamilyCurve<G>(r, times);
  PlannedMotion<Space, G> m;
  m.curve = std::move(built.curve);
  BasicResult<Space>& out = m.out;
  out.blend_radii = std::move(built.blend_radii);
  if (built.fit)
  {
    m.fit_control = m.curve->controlPoints();
    out.residual_linear = built.fit->residual_linear;
    out.residual_angular = built.fit->residual_angular;
    out.knots = std::move(built.fit->knots);
  }
  // A timing other than the stretch measures the rates and the energy of its own motion: the
  // curve's lengths are all it needs of the curve's figures (as the start's stability check does).
  if (r.timing == Timing::kStretch)
    m.figures = curveFigures(*m.curve, r.rotation_scale);
  else
    std::tie(m.figures.length, m.figures.rotation_length) = pathLengths(*m.curve);
  requireStableStartSolve(r, m.figures);
  out.waypoint_times = times;
  return m;
}

template <class Space, class G>
PlannedMotion<Space, G> planMotion(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
{
  if constexpr (std::is_same_v<Space, PoseSpace>)
    if (r.start_state)
      return planWithStartState<G>(r, times);
  PlannedMotion<Space, G> m = buildCurve<Space, G>(r, times);
  applyTiming<Space, G>(r, &m.curve, &m.figures, &m.out);
  return m;
}

template void applyTiming<PoseSpace, DoubleGeodesicSe3>(const ValidatedRequest&,
                                                        std::shared_ptr<const Curve<DoubleGeodesicSe3>>*, CurveFigures*,
                                                        TrajectoryResult*);
template void applyTiming<PoseSpace, ScrewSe3>(const ValidatedRequest&, std::shared_ptr<const Curve<ScrewSe3>>*,
                                               CurveFigures*, TrajectoryResult*);
template PlannedMotion<PoseSpace, DoubleGeodesicSe3> buildCurve<PoseSpace, DoubleGeodesicSe3>(
    const ValidatedRequest&, const std::vector<double>&);
template PlannedMotion<PoseSpace, ScrewSe3> buildCurve<PoseSpace, ScrewSe3>(const ValidatedRequest&,
                                                                            const std::vector<double>&);
template PlannedMotion<PoseSpace, DoubleGeodesicSe3> planMotion<PoseSpace, DoubleGeodesicSe3>(
    const ValidatedRequest&, const std::vector<double>&);
template PlannedMotion<PoseSpace, ScrewSe3> planMotion<PoseSpace, ScrewSe3>(const ValidatedRequest&,
                                                                            const std::vector<double>&);
}  // namespace planner_detail

namespace
{
/// Overflow (huge positions, times, rotation_scale or tiny max_* bounds) must not reach the
/// response as ∞ or NaN: throws InterpolationError naming the first figure or waypoint time that
/// is not finite.
template <class Space>
void requireFiniteFigures(const BasicResult<Space>& out, const CurveFigures& fig)
{
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
}

template <class Space, class G>
BasicResult<Space> run(const BasicValidatedRequest<Space>& r, const PlannerLimits& limits,
                       const SampleSink<Space>* sink)
{
  const std::vector<double> times = waypointTimes(r);
  // Bounded work: refused from the fields alone, before the curve is built or measured.
  const WorkShape shape = workShape(r);
  requireWorkWithin(estimateWork(shape, expectedSamples(shape, times.back() - times.front())), shape, limits);
  PlannedMotion<Space, G> planned = planMotion<Space, G>(r, times);
  const std::shared_ptr<const arm::JointMotion> joints = followWithArm(r, &planned);
  const std::shared_ptr<const Curve<G>> curve = std::move(planned.curve);
  const CurveFigures& fig = planned.figures;
  BasicResult<Space> out = std::move(planned.out);
  std::optional<std::vector<typename Space::Waypoint>>& fit_control = planned.fit_control;
  out.start_time = curve->startTime();
  out.duration = curve->endTime() - curve->startTime();
  out.figures = fig;
  out.waypoints = r.waypoints;
  // A fit's control points are the fitted B-spline's (with its knots they replay it), not those of
  // the motion that a start state's joining segment prepends the start pose to.
  out.control_points = fit_control ? std::move(*fit_control) : curve->controlPoints();
  out.point_at = [curve](double t) { return curve->value(t); };
  // At the start time from the left, as the first sample: the state the motion starts from.
  const double t0 = curve->startTime();
  out.state_at = [curve, t0](double t) { return sampleAt(*curve, t, nullptr, t == t0 ? Side::kLeft : Side::kRight); };
  requireFiniteFigures(out, fig);

  const std::vector<double> ts = sampleTimes(r.sampling, curve->startTime(), curve->endTime(), limits);
  // Again with the final sample count (a stretch lengthens a sample_period's sampling).
  requireWorkWithin(estimateWork(shape, static_cast<double>(ts.size())), shape, limits);
  // Without a sink every sample is kept in out.samples; with one they go to it a block at a time.
  std::vector<typename Space::Sample> block;
  block.reserve(sink ? std::min(ts.size(), kSamplesPerBlock) : ts.size());
  std::optional<typename Space::Sample> handed_on;  // the last sample of the blocks handed on
  auto last = [&]() -> const typename Space::Sample* {
    return !block.empty() ? &block.back() : handed_on ? &*handed_on : nullptr;
  };
  auto push = [&](typename Space::Sample s) {
    if (sink && block.size() == kSamplesPerBlock)
    {
      handed_on = block.back();
      handOn(*sink, block);
      block.clear();
    }
    if (!allFinite(s))
      throw InterpolationError("the curve is not finite at t = " + formatNumber(s.time) +
                               " s (the input is too close to a singular configuration)");
    if constexpr (std::is_same_v<Space, PoseSpace>)
      if (joints)
        fillJoints(*joints, &s, s.time == t0 ? Side::kLeft : Side::kRight);
    block.push_back(std::move(s));
  };
  // With sample_tolerance, the samples it inserts before each one (up to ~max_samples in all).
  std::optional<SampleRefiner> refiner =
      refinerFor(r, curve, limits.max_samples - std::min(limits.max_samples, ts.size()));
  for (std::size_t i = 0; i < ts.size(); ++i)
  {
    checkDeadlineEvery(i, kSamplesPerDeadlineCheck, "sampling");
    // The first sample from the left: the state the motion starts from (a time-optimal motion
    // from rest starts its acceleration there; timing/time_optimal.h, pathParameter).
    typename Space::Sample s =
        sampleAt(*curve, ts[i], last(), i == 0 && ts[0] == curve->startTime() ? Side::kLeft : Side::kRight);
    if constexpr (std::is_same_v<Space, PoseSpace>)
      if (refiner && i > 0)
      {
        // Inserted samples, and the one after them, sign-continuous with the last one pushed.
        const typename Space::Sample previous = *last();
        refiner->between(previous, s, [&](TrajectorySample m) {
          alignSign(&m, last());
          push(std::move(m));
        });
        alignSign(&s, last());
      }
    push(std::move(s));
  }
  if (!sink)
    out.samples = std::move(block);
  else if (!block.empty())
    handOn(*sink, block);
  return out;
}

TrajectoryResult dispatch(const ValidatedRequest& r, const PlannerLimits& limits, const SampleSink<PoseSpace>* sink)
{
  if (r.geometry == GeometryType::kScrew)
    return run<PoseSpace, ScrewSe3>(r, limits, sink);
  return run<PoseSpace, DoubleGeodesicSe3>(r, limits, sink);
}

SphereResult dispatch(const ValidatedSphereRequest& r, const PlannerLimits& limits, const SampleSink<SphereSpace>* sink)
{
  return run<SphereSpace, Sphere>(r, limits, sink);
}

template <class Space>
BasicResult<Space> generateWith(const BasicRequest<Space>& request, const PlannerLimits& limits,
                                const SampleSink<Space>* sink, std::shared_ptr<const arm::ArmModel> arm = nullptr)
{
  Deadline deadline(std::max(kDeadlineFactor * limits.max_work_seconds, kMinDeadlineSeconds), limits.max_work_seconds);
  const ScopedDeadline scope(deadline);
  BasicValidatedRequest<Space> r = validateRequest(request, limits);
  r.joint_space = jointSpaceOf(request, std::move(arm));
  return dispatch(r, limits, sink);
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
  return generateWith<Space>(request, limits, nullptr);
}

template <class Space>
BasicResult<Space> generate(const BasicRequest<Space>& request, const PlannerLimits& limits,
                            const SampleSink<Space>& sink)
{
  return generateWith<Space>(request, limits, &sink);
}

TrajectoryResult generate(const TrajectoryRequest& request, const PlannerLimits& limits,
                          std::shared_ptr<const arm::ArmModel> arm)
{
  return generateWith<PoseSpace>(request, limits, nullptr, std::move(arm));
}

TrajectoryResult generate(const TrajectoryRequest& request, const PlannerLimits& limits,
                          std::shared_ptr<const arm::ArmModel> arm, const SampleSink<PoseSpace>& sink)
{
  return generateWith<PoseSpace>(request, limits, &sink, std::move(arm));
}

template std::vector<double> waypointTimes<PoseSpace>(const ValidatedRequest&);
template std::vector<double> waypointTimes<SphereSpace>(const ValidatedSphereRequest&);
template TrajectoryResult generate<PoseSpace>(const TrajectoryRequest&, const PlannerLimits&);
template SphereResult generate<SphereSpace>(const SphereRequest&, const PlannerLimits&);
template TrajectoryResult generate<PoseSpace>(const TrajectoryRequest&, const PlannerLimits&,
                                              const SampleSink<PoseSpace>&);
template SphereResult generate<SphereSpace>(const SphereRequest&, const PlannerLimits&, const SampleSink<SphereSpace>&);

}  // namespace se3_interpolation
