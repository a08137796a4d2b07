// The motion of a pose request with a start state (request.h, StartState; docs/timing.md "Start
// states and replanning"). Two candidates:
//  - joined: the curve through the start pose and the waypoints, entered by the joining quintic
//    (curves/start_join.h) unless the curve takes the start data itself (`interpolating` with
//    end_condition `start`), timed from the start state (applyTimingFromStart);
//  - braked: the start's own motion brought to rest within the bounds (curves/braked_start.h's
//    B1, B2 without jerk bounds; curves/jerk_brake.h with them), then the request's motion from
//    rest at the stopping pose.
// Under time_optimal and constant_speed, a moving start is served the joined motion, which does not
// stop, when neither its duration nor its path length (|p| length + ρ · rotation length) exceeds
// the braked one's by more than kJoinedPreference (10 %), else the braked one; the braked one also serves where the joined
// one is refused, and alone where the start exceeds a velocity bound without jerk bounds (braking is
// the fastest recovery the acceleration bounds allow). Under jerk bounds a start beyond a bound has
// the joined motion only (the jerk-limited timing's recovery). A start at rest, and `stretch`
// (whose times are the request's own), have the joined motion only.
#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "joint_space.h"
#include "planned_motion.h"
#include "start_brakes.h"
#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/braked_start.h"
#include "se3_interpolation/curves/jerk_brake.h"
#include "se3_interpolation/curves/start_join.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/constant_speed.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "timing_figures.h"

namespace se3_interpolation
{
namespace planner_detail
{
namespace
{
/// sqrt(|linear|² + ρ²|angular|²): the speed of a twist in the metric of the chord parameterisation.
double weightedNorm(const Twist& v, double rho)
{
  return std::sqrt(v.linear.squaredNorm() + rho * rho * v.angular.squaredNorm());
}

bool isZero(const Twist& v)
{
  return v.linear.isZero(0.0) && v.angular.isZero(0.0);
}

/// The durations of the joining segment tried (chooseJoin): h0 · 2^k for k from kJoinShortest to
/// kJoinLongest. A start faster than the bounds needs a long joining segment: its acceleration at
/// its own timing falls as v/h, and it is within the bounds only once h is a few times v / a
/// (about 2^6 h0 for a start at three times the velocity bound).
constexpr int kJoinShortest = -2;
constexpr int kJoinLongest = 12;
/// The most the curve's clock after the joint is scaled by (either way) to enter it at the start
/// state's speed.
constexpr double kMaxEntryScale = 1e3;
/// The curve after the joint is entered with at most 1 / kEntryHeadroom of its acceleration bounds
/// when the clock that matches the start's speed would enter it faster (chooseJoin): room for the
/// joining segment's own bend.
constexpr double kEntryHeadroom = 2.0;
/// Samples of the joining segment at which its acceleration is compared with the bounds.
constexpr int kJoinSamples = 32;
/// The joined motion, which continues without stopping, is served when its duration and path length
/// are at most the braked one's times 1 + this; a longer one is a detour, and the braked one is served.
constexpr double kJoinedPreference = 0.1;

/// The largest ratio of the acceleration of `curve` on [0, h] (at its own timing) to its bound, over
/// both channels and kJoinSamples + 1 evenly spaced times; 0 without acceleration bounds.
template <class G>
double accelerationExcess(const ValidatedRequest& r, const Curve<G>& curve, double h)
{
  double excess = 0.0;
  for (int k = 0; k <= kJoinSamples; ++k)
  {
    const Kinematics j = kinematicsAt(curve, h * k / kJoinSamples, k == kJoinSamples ? Side::kLeft : Side::kRight);
    if (r.max_linear_acceleration > 0.0)
      excess = std::max(excess, j.acceleration.linear.norm() / r.max_linear_acceleration);
    if (r.max_angular_acceleration > 0.0)
      excess = std::max(excess, j.acceleration.angular.norm() / r.max_angular_acceleration);
  }
  return excess;
}

/// The path of a moving start: the joining segment of duration h into the curve after the joint,
/// whose clock is scaled by `scale`. Its own clock has the start state at t = 0 (path speed 1).
template <class G>
struct JoinedPath
{
  std::shared_ptr<const Curve<G>> path;
  double h = 0.0;
  double scale = 1.0;
};

template <class G>
std::shared_ptr<const Curve<G>> joinStart(const StartState& s, std::shared_ptr<const Curve<G>> rest, double h,
                                          double from)
{
  return std::make_shared<StartJoinedCurve<G>>(s.pose, poseJet(s.pose, s.velocity, s.acceleration), 0.0, h,
                                               std::move(rest), from);
}

/// The joining segment of a moving start into `through` (which starts at the start pose and reaches
/// waypoints[1] at t1). The curve after the joint is entered at the start's speed: its clock is
/// scaled so, so that the joining segment blends the two directions instead of hooking into a much
/// faster or slower curve. The scale also scales the entry acceleration (by 1 / scale²), which the
/// joining segment ends with, so a second scale is tried: the smallest at which the entry
/// acceleration is at most 1 / kEntryHeadroom of its bounds. Of durations h0 · 2^k, the shortest
/// whose own timing is within the acceleration bounds, else the one that comes closest: too short,
/// the segment bends sharply out of the start velocity; too long, the start velocity and
/// acceleration carry it far away.
template <class G>
JoinedPath<G> chooseJoin(const ValidatedRequest& r, const std::shared_ptr<const Curve<G>>& through, double t1)
{
  const StartState& s = *r.start_state;
  const double rho = r.rotation_scale;
  const Kinematics entry = kinematicsAt(*through, t1);
  const double chord =
      std::sqrt((entry.pose.p - s.pose.p).squaredNorm() + std::pow(rho * entry.pose.q.angularDistance(s.pose.q), 2));
  const double start_speed = weightedNorm(s.velocity, rho);
  const double entry_speed = weightedNorm(entry.velocity, rho);
  double matching = 1.0;
  if (start_speed > 0.0 && entry_speed > 0.0)
    matching = std::min(kMaxEntryScale, std::max(1.0 / kMaxEntryScale, entry_speed / start_speed));
  double entry_ratio = 0.0;  // of the entry acceleration to its bound, the larger channel's
  if (r.max_linear_acceleration > 0.0)
    entry_ratio = std::max(entry_ratio, entry.acceleration.linear.norm() / r.max_linear_acceleration);
  if (r.max_angular_acceleration > 0.0)
    entry_ratio = std::max(entry_ratio, entry.acceleration.angular.norm() / r.max_angular_acceleration);
  const double calm = std::min(kMaxEntryScale, std::max(matching, std::sqrt(kEntryHeadroom * entry_ratio)));
  JoinedPath<G> best{ through, t1, 1.0 };
  double best_excess = std::numeric_limits<double>::infinity();
  const double scales[] = { matching, calm };
  for (int attempt = 0; attempt < 2 && best_excess > 1.0; ++attempt)
  {
    const double scale = scales[attempt];
    if (attempt > 0 && scale == matching)
      break;
    const std::shared_ptr<const Curve<G>> scaled = std::make_shared<TimeScaledCurve<G>>(through, scale);
    const double guess = 2.0 * chord / (start_speed + entry_speed / scale);
    const double h0 = guess > 0.0 && std::isfinite(guess) ? guess : t1;
    for (int k = kJoinShortest; k <= kJoinLongest && best_excess > 1.0; ++k)
    {
      const double h = std::ldexp(h0, k);
      auto joined = joinStart<G>(s, scaled, h, scale * t1);
      const double excess = std::max(1.0, accelerationExcess(r, *joined, h));
      if (excess < best_excess)
      {
        best_excess = excess;
        best = JoinedPath<G>{ joined, h, scale };
      }
    }
  }
  return best;
}

/// The time-optimal timing from path speed 1 (the start state's own) along a joined path; a start
/// that cannot brake within the acceleration bounds where the path bends is refused.
template <class G>
std::shared_ptr<const timing::TimeOptimalCurve<G>> timeOptimalFromStart(const ValidatedRequest& r,
                                                                        std::shared_ptr<const Curve<G>> path,
                                                                        bool native)
{
  timing::TimeOptimalOptions options;
  options.start_speed = 1.0;
  options.hold_start = true;
  options.boxes = jointBoxesOf(r, path, {});  // (the joined path: its refusals name no waypoint)
  auto timed = timing::makeTimeOptimalCurve<G>(path, rateBounds(r), options);
  const double excess = timed->profile().recovery_excess;
  if (excess > 1.0 + timing::kRecoveryExcessTolerance)
  {
    if (native)
      throw InvalidInputError(
          "end_condition: 'start' continues the start state's motion on a spline that bends too "
          "sharply to brake from it within the acceleration bounds (braking would take " +
          formatNumber(excess) +
          " times a bound or an arm joint's acceleration limit); use end_condition 'natural' or 'clamped', "
          "whose joining segment is chosen for the bounds");
    throw InvalidInputError(
        "start_state: the motion starts too fast for the curve it joins: braking along it would "
        "take " +
        formatNumber(excess) +
        " times an acceleration bound or an arm joint's acceleration limit; start more slowly or "
        "farther from the first waypoint, or raise the acceleration bounds");
  }
  return timed;
}

/// The timing of a moving start along its path (time-optimal, jerk-limited or constant-speed, from
/// the start state: path speed 1 at t = 0), into `m`. `map_time` takes a time of the request's
/// curve to the path's own clock.
template <class G, class MapTime>
void timeAlongPath(const ValidatedRequest& r, const std::vector<double>& times, bool measured,
                   std::shared_ptr<const Curve<G>> path, const MapTime& map_time, bool native,
                   PlannedMotion<PoseSpace, G>* m)
{
  TrajectoryResult& out = m->out;
  // The timed motion replaces the curve: its span, the waypoints' times through its s⁻¹, and the
  // path's lengths (the curve's are measured already; a joined path is measured here).
  const auto adopt = [&](const auto& timed) {
    validateTimeSpan(timed->startTime(), timed->endTime(), boundFields<PoseSpace>());
    for (std::size_t i = 1; i < times.size(); ++i)
      out.waypoint_times[i] = timed->profile().timeAt(map_time(times[i]));
    out.waypoint_times.back() = timed->endTime();  // (the sum above may round off the path's end)
    const std::pair<double, double> lengths =
        measured ? std::make_pair(m->figures.length, m->figures.rotation_length) : measureLengths(*path);
    m->figures = CurveFigures();
    std::tie(m->figures.length, m->figures.rotation_length) = lengths;
    m->curve = timed;
  };
  if (r.timing == Timing::kConstantSpeed)
  {
    // The ramp rises from the path's chord speed and acceleration at its start (the start state's).
    timing::ConstantSpeedOptions options;
    options.speed = r.speed;
    options.metric = { 1.0, r.rotation_scale * r.rotation_scale };
    options.continue_start = true;
    auto timed = timing::makeConstantSpeedCurve<G>(path, rateBounds(r), options);
    adopt(timed);
    out.constant_speed_start = timed->profile().windowStart();
    out.constant_speed_end = timed->profile().windowEnd();
    setConstantSpeedFigures(*timed, &m->figures);
  }
  else if (hasJerkBound(r) || jointJerkWindow(r) > 0.0)
  {
    timing::JerkLimitedOptions options;
    options.start_speed = 1.0;
    options.window = jointJerkWindow(r);
    auto timed = explainingArmJerk(r, [&] { return timing::makeJerkLimitedCurve<G>(path, rateBounds(r), options); });
    out.time_scale = timed->profile().stretch;
    adopt(timed);
    setJerkLimitedFigures(r, *timed, &m->figures);
  }
  else
  {
    auto timed = timeOptimalFromStart<G>(r, path, native);
    out.recovery_time = timed->profile().recovery_end - timed->startTime();
    out.time_scale = timed->profile().stretch;
    adopt(timed);
    setTimedFigures(r, timed->profile(), &m->figures);
  }
}

/// A moving start under `stretch`: the start velocity fixes the time scale, so a curve that exceeds
/// a bound (k > 1) is refused naming `timing`.
template <class G>
void stretchFromStart(const ValidatedRequest& r, bool at_rest, PlannedMotion<PoseSpace, G>* m)
{
  std::shared_ptr<const Curve<G>>& curve = m->curve;
  CurveFigures& fig = m->figures;
  fig = measureCurve(*curve, r.rotation_scale);
  measureJerk(r, *curve, &fig);
  std::string cause = r.times.empty() ? "duration" : "times";
  const double k = stretchFactor(r, fig, &cause);
  validateTimeSpan(0.0, curve->endTime() * k, cause);
  if (k > 1.0 && !at_rest)
    throw InvalidInputError("timing: 'stretch' would slow the motion down " + formatNumber(k) + " times for " + cause +
                            ", which would change the start state's velocity and acceleration; use timing "
                            "'time_optimal', which keeps the start state and brings the motion within the bounds");
  if (k > 1.0)
  {
    curve = std::make_shared<TimeScaledCurve<G>>(curve, k);
    const CurveFigures unscaled = fig;
    fig = measureCurve(*curve, r.rotation_scale);
    fig.max_linear_jerk = unscaled.max_linear_jerk / (k * k * k);
    fig.max_angular_jerk = unscaled.max_angular_jerk / (k * k * k);
    for (double& t : m->out.waypoint_times)
      t *= k;
  }
  m->out.time_scale = k;
}

/// The joined motion of a request with a start state (file comment): the curve through the start
/// pose and the waypoints (times from 0), timed so that its state at t = 0 is the start state:
///  - a start at rest: the joined curve under the request's timing, like any other;
///  - a moving start under `stretch`: stretchFromStart;
///  - a moving start under `time_optimal` or `constant_speed`: the timing from the start state
///    along the joined path (chooseJoin; a start beyond the bounds recovers by braking along it,
///    and the result reports when, recovery_time).
template <class G>
PlannedMotion<PoseSpace, G> joinedMotion(const ValidatedRequest& r, const std::vector<double>& times)
{
  PlannedMotion<PoseSpace, G> m = buildCurve<PoseSpace, G>(r, times);
  const StartState& s = *r.start_state;
  const bool native = continuesStartState(r);
  const bool at_rest = isZero(s.velocity) && isZero(s.acceleration);
  const std::shared_ptr<const Curve<G>> through = m.curve;  // starts at the start pose at 0
  const double t1 = times[1];
  if (r.timing != Timing::kStretch && at_rest)
  {
    // A fit approximates the start pose (its first fitted point) instead of passing it: the joining
    // segment leads from the start pose to it first, as under stretch.
    if (r.curve == CurveType::kFit)
      m.curve = joinStart<G>(s, through, t1, t1);
    applyTiming<PoseSpace, G>(r, &m.curve, &m.figures, &m.out);
  }
  else if (r.timing != Timing::kStretch)
  {
    const JoinedPath<G> join = native ? JoinedPath<G>{ through, t1, 1.0 } : chooseJoin<G>(r, through, t1);
    const auto map_time = [&](double t) { return native ? t : join.h + join.scale * (t - t1); };
    timeAlongPath<G>(r, times, native, join.path, map_time, native, &m);
  }
  else
  {
    if (!native)
      m.curve = joinStart<G>(s, through, t1, t1);
    stretchFromStart<G>(r, at_rest, &m);
  }
  // The response lists the requested waypoints' times and radii, not the start pose's.
  if (!r.start_replaces_first)
  {
    m.out.waypoint_times.erase(m.out.waypoint_times.begin());
    if (!m.out.blend_radii.empty())
      m.out.blend_radii.erase(m.out.blend_radii.begin());
  }
  return m;
}

/// The braked motion (file comment): `brake` on [0, T], then the request's motion from rest at the
/// stopping pose, with the whole motion's figures (the brake's with the motion's from rest).
template <class G, class Brake>
PlannedMotion<PoseSpace, G> brakedMotion(const ValidatedRequest& r, const Brake& brake, const BrakeFigures& bf)
{
  const Pose<double> stop_pose = brake.stopPose();
  ValidatedRequest from_rest = r;
  from_rest.start_state = StartState{ stop_pose, Twist{}, Twist{} };
  from_rest.waypoints.front() = stop_pose;
  if (!from_rest.velocities.empty())
    from_rest.velocities.front() = Twist{};
  if (continuesStartState(from_rest))
  {
    from_rest.start_velocity = Twist{};
    from_rest.start_acceleration = Twist{};
  }
  PlannedMotion<PoseSpace, G> m = planMotion<PoseSpace, G>(from_rest, waypointTimes(from_rest));
  auto braked = std::make_shared<BrakedStartCurve<G, Brake>>(brake, m.curve);
  const double stop = braked->stopTime();
  m.curve = braked;
  for (double& t : m.out.waypoint_times)
    t += stop;
  if (r.timing == Timing::kConstantSpeed)
  {
    m.out.constant_speed_start += stop;
    m.out.constant_speed_end += stop;
  }
  m.out.recovery_time = bf.recovery;
  m.out.stop_time = stop;
  CurveFigures& f = m.figures;
  f.length += bf.length;
  f.rotation_length += bf.rotation_length;
  f.max_linear_speed = std::max(f.max_linear_speed, bf.max_speed[0]);
  f.max_angular_speed = std::max(f.max_angular_speed, bf.max_speed[1]);
  f.max_linear_acceleration = std::max(f.max_linear_acceleration, bf.max_acceleration[0]);
  f.max_angular_acceleration = std::max(f.max_angular_acceleration, bf.max_acceleration[1]);
  f.max_linear_jerk = std::max(f.max_linear_jerk, bf.max_jerk[0]);
  f.max_angular_jerk = std::max(f.max_angular_jerk, bf.max_jerk[1]);
  f.energy += bf.energy;
  return m;
}

/// A planned motion, or the refusal that took its place (a refusal by the work limit is not a
/// candidate's: it propagates).
template <class G>
struct Candidate
{
  std::optional<PlannedMotion<PoseSpace, G>> motion;
  std::exception_ptr refusal;
};

template <class G, class Plan>
Candidate<G> attempt(const Plan& plan)
{
  Candidate<G> c;
  try
  {
    c.motion = plan();
  }
  catch (const LimitExceededError&)
  {
    throw;
  }
  catch (const InterpolationError&)
  {
    c.refusal = std::current_exception();
  }
  return c;
}

/// |p| length + ρ · rotation length of a motion's path.
double pathLength(const ValidatedRequest& r, const CurveFigures& f)
{
  return f.length + (f.rotation_length > 0.0 ? r.rotation_scale * f.rotation_length : 0.0);
}

/// Whether `a` is no longer than `b` times 1 + `tolerance` in duration and path length.
template <class G>
bool noLonger(const ValidatedRequest& r, const PlannedMotion<PoseSpace, G>& a, const PlannedMotion<PoseSpace, G>& b,
              double tolerance)
{
  const double da = a.curve->endTime() - a.curve->startTime();
  const double db = b.curve->endTime() - b.curve->startTime();
  return da <= db * (1.0 + tolerance) &&
         pathLength(r, a.figures) <= pathLength(r, b.figures) * (1.0 + tolerance) + 1e-12;
}

/// The braked candidate of a moving start (std::nullopt where no brake exists), and whether it is to
/// be served alone: a start beyond a velocity bound without jerk bounds, whose recovery by the brake
/// is the fastest the acceleration bounds allow. Under jerk bounds a start beyond a bound has none.
template <class G>
std::optional<Candidate<G>> brakedCandidate(const ValidatedRequest& r, bool* alone)
{
  const StartState& s = *r.start_state;
  const bool over_velocity = (r.max_linear_velocity > 0.0 && s.velocity.linear.norm() > r.max_linear_velocity) ||
                             (r.max_angular_velocity > 0.0 && s.velocity.angular.norm() > r.max_angular_velocity);
  *alone = over_velocity;
  if (hasJerkBound(r))
  {
    // A start above a bound recovers along the joined path under the jerk-limited timing (its
    // corrections), not by the jerk brake, whose exceeded rates could grow while its acceleration
    // ramps down.
    const auto above = [](double rate, double bound) { return bound > 0.0 && rate > bound * (1.0 + kRateTolerance); };
    const bool over = above(s.velocity.linear.norm(), r.max_linear_velocity) ||
                      above(s.velocity.angular.norm(), r.max_angular_velocity) ||
                      above(s.acceleration.linear.norm(), r.max_linear_acceleration) ||
                      above(s.acceleration.angular.norm(), r.max_angular_acceleration);
    *alone = false;
    if (over)
      return std::nullopt;
    std::optional<Candidate<G>> shortest;
    for (const auto& brake : jerkBrakes(r))
    {
      Candidate<G> c = attempt<G>([&] { return brakedMotion<G>(r, brake.first, brake.second); });
      if (!shortest || (c.motion && (!shortest->motion || noLonger(r, *c.motion, *shortest->motion, 0.0))))
        shortest = std::move(c);
    }
    return shortest;
  }
  const std::optional<BrakeToRest> brake = brakeToRest(r);
  if (!brake)
    return std::nullopt;
  return attempt<G>([&] { return brakedMotion<G>(r, *brake, brakeFigures(r, *brake)); });
}
}  // namespace

template <class G>
PlannedMotion<PoseSpace, G> planWithStartState(const ValidatedRequest& r, const std::vector<double>& times)
{
  const StartState& s = *r.start_state;
  const bool moving = !(isZero(s.velocity) && isZero(s.acceleration));
  if (!moving || r.timing == Timing::kStretch)
    return joinedMotion<G>(r, times);
  bool alone = false;
  std::optional<Candidate<G>> braked = brakedCandidate<G>(r, &alone);
  if (braked && braked->motion && alone)
    return std::move(*braked->motion);
  Candidate<G> joined = attempt<G>([&] { return joinedMotion<G>(r, times); });
  if (!braked || !braked->motion)
  {
    if (!joined.motion)
      std::rethrow_exception(joined.refusal);
    return std::move(*joined.motion);
  }
  if (joined.motion && noLonger(r, *joined.motion, *braked->motion, kJoinedPreference))
    return std::move(*joined.motion);
  return std::move(*braked->motion);
}

template PlannedMotion<PoseSpace, DoubleGeodesicSe3> planWithStartState<DoubleGeodesicSe3>(const ValidatedRequest&,
                                                                                           const std::vector<double>&);
template PlannedMotion<PoseSpace, ScrewSe3> planWithStartState<ScrewSe3>(const ValidatedRequest&,
                                                                         const std::vector<double>&);
}  // namespace planner_detail
}  // namespace se3_interpolation
