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
#include "se3_interpolation/curves/braked_start.h"
#include "se3_interpolation/curves/start_join.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/execution/sample_refinement.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"
#include "se3_interpolation/timing/constant_speed.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "timing_figures.h"

namespace se3_interpolation
{
namespace
{
using planner_detail::hasJerkBound;
using planner_detail::measureJerk;
using planner_detail::rateBounds;
using planner_detail::setConstantSpeedFigures;
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
  TrajectorySample s{ t, k.pose, k.velocity, k.acceleration };
  alignSign(&s, previous);
  return s;
}

SphereSample sampleAt(const Curve<Sphere>& curve, double t, const SphereSample* /*previous*/,
                      Side side = Side::kRight)
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
    return SampleRefiner(settings, [curve](double t) { return sampleAt(*curve, t, nullptr); }, budget);
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

/// The bounds' field names for an error about the span they stretch the motion to.
template <class Space>
const char* boundFields()
{
  return std::is_same_v<Space, SphereSpace> ? "max_angular_velocity or max_angular_acceleration"
                                            : "max_linear_velocity, max_angular_velocity or their accelerations";
}

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
  if (r.timing == Timing::kTimeOptimal && hasJerkBound(r))
  {
    auto timed = timing::makeJerkLimitedCurve<G>(curve, rateBounds(r));
    out.time_scale = timed->profile().stretch;
    adopt(timed, boundFields<Space>(), true);
    setJerkLimitedFigures(r, *timed, &fig);
    return;
  }
  if (r.timing == Timing::kTimeOptimal)
  {
    auto timed = timing::makeTimeOptimalCurve<G>(curve, rateBounds(r));
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
    fig.max_linear_speed /= k;
    fig.max_angular_speed /= k;
    fig.max_linear_acceleration /= k * k;
    fig.max_angular_acceleration /= k * k;
    fig.max_linear_jerk /= k * k * k;
    fig.max_angular_jerk /= k * k * k;
    fig.energy /= k * k * k;
  }
}

/// sqrt(|linear|^2 + rho^2 |angular|^2): the speed of a twist in the metric of the chord parameterisation.
double weightedNorm(const Twist& v, double rho)
{
  return std::sqrt(v.linear.squaredNorm() + rho * rho * v.angular.squaredNorm());
}

bool isZero(const Twist& v)
{
  return v.linear.isZero(0.0) && v.angular.isZero(0.0);
}

/// The durations of the joining segment tried under time_optimal (applyTimingFromStart): h0 · 2^k
/// for k from kJoinShortest to kJoinLongest. A start faster than the bounds needs a long joining
/// segment: its acceleration at its own timing falls as v/h, and it is within the bounds only
/// once h is a few times v / a (about 2^6 h0 for a start at three times the velocity bound).
constexpr int kJoinShortest = -2;
constexpr int kJoinLongest = 12;
/// The most the curve's clock after the joint is scaled by (either way) to enter it at the start
/// state's speed.
constexpr double kMaxEntryScale = 1e3;
/// The relative excess over a bound that breaks it: every bound holds to 1e-6 relative on the
/// motion's dense evaluation (docs/timing.md, the request-space test's invariant check).
constexpr double kBoundTolerance = 1e-6;
/// The curve after the joint is entered with at most 1 / kEntryHeadroom of its acceleration
/// bounds when the clock that matches the start's speed would enter it faster
/// (applyTimingFromStart): room for the joining segment's own bend.
constexpr double kEntryHeadroom = 2.0;
/// Samples of the joining segment at which its acceleration is compared with the bounds.
constexpr int kJoinSamples = 32;
/// When the jerk-limited timing along the joined curve fails to converge (a start whose
/// corrections leave an excess, a profile that stalls), the joining segment is lengthened,
/// doubling its duration at most this many times, as long as its own timing stays within the
/// acceleration bounds (or no farther from them than the chosen one): another joining segment is
/// another path, and replanning from a moving state should not be refused for the shape of one
/// of them. Measured on replans from every 30 ms of a jerk-limited motion (test_start_join): 27 of
/// 58 refused without it, 19, 16, 15 and 15 after one, two, three and five doublings.
constexpr int kJoinRetries = 3;

/// The largest ratio of the acceleration of `curve` on [0, h] (at its own timing) to its bound,
/// over both channels and kJoinSamples + 1 evenly spaced times; 0 without acceleration bounds.
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

/// The timing of a pose request with a start state (request.h, StartState): the curve through the
/// start pose and the waypoints (times from 0), entered by the joining quintic (curves/start_join.h)
/// unless it takes the start data itself (`interpolating` with end_condition `start`). The motion's
/// state at t = 0 is the start state exactly, whatever the timing:
///  - a start at rest (zero velocity and acceleration): the joined curve stretched uniformly, or
///    the time-optimal or constant-speed motion from rest along it;
///  - a moving (or accelerating) start under `stretch`: the start velocity fixes the time scale,
///    so a curve that exceeds a bound (k > 1) is refused naming `timing`;
///  - a moving start under `time_optimal`: the time-optimal motion along the joined curve (whose
///    joining segment lasts about 2 d / (speed at its start + the curve's speed at its end), the
///    duration whose own timing comes closest to the acceleration bounds) starting at its own path
///    speed with its own acceleration (TimeOptimalOptions::start_speed = 1, hold_start): a start
///    beyond the bounds recovers by braking, and the result reports when (recovery_time);
///  - a moving start under `constant_speed`: along the same joined curve, the ramp rises from the
///    start state's chord speed and acceleration (ConstantSpeedOptions::continue_start); a start
///    beyond the bounds is refused naming `start_state` (no recovery).
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
  const bool native = continuesStartState(r);
  const bool at_rest = isZero(s.velocity) && isZero(s.acceleration);
  auto join = [&s](std::shared_ptr<const Curve<G>> rest, double h, double from) {
    return std::make_shared<StartJoinedCurve<G>>(s.pose, poseJet(s.pose, s.velocity, s.acceleration), 0.0, h,
                                                 std::move(rest), from);
  };
  if (r.timing != Timing::kStretch && at_rest)
  {
    // At rest: the time-optimal or constant-speed motion along the curve from the start pose, like
    // any other. A fit approximates the start pose (its first fitted point) instead of passing it:
    // the joining segment leads from the start pose to it first, as under stretch.
    if (r.curve == CurveType::kFit)
      curve = join(through, t1, t1);
    applyTiming<PoseSpace, G>(r, curve_io, fig_io, out_io);
  }
  else if (r.timing != Timing::kStretch)
  {
    const timing::RateBounds bounds = rateBounds(r);
    double h = t1;
    double scale = 1.0;  // of the curve's clock after the joint (time-optimal timing retimes it)
    std::shared_ptr<const Curve<G>> path = through;
    std::shared_ptr<const Curve<G>> joined_to;  // the curve after the joint, at its scale
    double best_excess = std::numeric_limits<double>::infinity();
    if (!native)
    {
      const Kinematics entry = kinematicsAt(*through, t1);
      const double chord = std::sqrt((entry.pose.p - s.pose.p).squaredNorm() +
                                     std::pow(rho * entry.pose.q.angularDistance(s.pose.q), 2));
      // The curve after the joint is entered at the start's speed: its clock is scaled so (its
      // timing is the time-optimal one anyway), so that the joining segment blends the two
      // directions instead of hooking into a much faster or slower curve. The scale also scales
      // the entry acceleration (by 1 / scale²), which the joining segment ends with: a start
      // faster than the curve (a start beyond the velocity bounds, say) would enter it with its
      // acceleration multiplied, and no duration of the joining segment could keep within the
      // bounds. So a second scale is tried, the smallest at which the entry acceleration is at
      // most half its bounds.
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
      // The joining segment's shape depends on its duration: too short, it bends sharply out of
      // the start velocity; too long, the start velocity and acceleration carry it far away
      // (its acceleration grows again with the terms in h² of A). Of durations h0 · 2^k
      // (k = −2 … 12), the shortest whose own timing is within the acceleration bounds, else the
      // one that comes closest. Within them at its own timing (path speed 1), every path speed up
      // to 1 is feasible on it, so the recovery from a start faster than the bounds can brake
      // within the acceleration bounds.
      const double scales[] = { matching, calm };
      for (int attempt = 0; attempt < 2 && best_excess > 1.0; ++attempt)
      {
        const double candidate_scale = scales[attempt];
        if (attempt > 0 && candidate_scale == matching)
          break;
        const std::shared_ptr<const Curve<G>> scaled = std::make_shared<TimeScaledCurve<G>>(through, candidate_scale);
        const double guess = 2.0 * chord / (start_speed + entry_speed / candidate_scale);
        const double h0 = guess > 0.0 && std::isfinite(guess) ? guess : t1;
        for (int k = kJoinShortest; k <= kJoinLongest && best_excess > 1.0; ++k)
        {
          const double candidate = std::ldexp(h0, k);
          auto joined = join(scaled, candidate, candidate_scale * t1);
          const double excess = std::max(1.0, accelerationExcess(r, *joined, candidate));
          if (excess < best_excess)
          {
            best_excess = excess;
            h = candidate;
            scale = candidate_scale;
            path = joined;
            joined_to = scaled;
          }
        }
      }
    }
    // The path's own clock has the start state at its start: path speed 1, no path acceleration.
    const auto mapTime = [&](double t) { return native ? t : h + scale * (t - t1); };
    // The timed motion (time-optimal or jerk-limited) replaces the curve: its stretch, its span,
    // the waypoints' times through its s⁻¹, and the path's figures, whose rates the caller then
    // replaces with the timing's.
    const auto adopt = [&](const auto& timed) {
      validateTimeSpan(timed->startTime(), timed->endTime(), boundFields<PoseSpace>());
      for (std::size_t i = 1; i < times.size(); ++i)
        out.waypoint_times[i] = timed->profile().timeAt(mapTime(times[i]));
      out.waypoint_times.back() = timed->endTime();  // (the sum above may round off the path's end)
      // The curve's lengths are measured already (planMotion); a joined path is measured here.
      const std::pair<double, double> lengths =
          path == through ? std::make_pair(fig_io->length, fig_io->rotation_length) : measureLengths(*path);
      *fig_io = CurveFigures();
      std::tie(fig_io->length, fig_io->rotation_length) = lengths;
      curve = timed;
    };
    const auto timeAlongPath = [&]() {
      if (r.timing == Timing::kConstantSpeed)
      {
        // The ramp rises from the joined path's chord speed and acceleration at its start (the start
        // state's: its clock is the start state's there) to the speed.
        timing::ConstantSpeedOptions options;
        options.speed = r.speed;
        options.metric = { 1.0, rho * rho };
        options.continue_start = true;
        auto timed = timing::makeConstantSpeedCurve<G>(path, bounds, options);
        adopt(timed);
        out.constant_speed_start = timed->profile().windowStart();
        out.constant_speed_end = timed->profile().windowEnd();
        setConstantSpeedFigures(*timed, fig_io);
      }
      else if (hasJerkBound(r))
      {
        timing::JerkLimitedOptions options;
        options.start_speed = 1.0;
        auto timed = timing::makeJerkLimitedCurve<G>(path, bounds, options);
        out.time_scale = timed->profile().stretch;
        adopt(timed);
        setJerkLimitedFigures(r, *timed, fig_io);
      }
      else
      {
        timing::TimeOptimalOptions options;
        options.start_speed = 1.0;
        options.hold_start = true;
        auto timed = timing::makeTimeOptimalCurve<G>(path, bounds, options);
        const double excess = timed->profile().recovery_excess;
        if (excess > 1.0 + kBoundTolerance)
        {
          if (native)
            throw InvalidInputError("end_condition: 'start' continues the start state's motion on a spline that bends "
                                    "too sharply to brake from it within the acceleration bounds (braking would take " +
                                    formatNumber(excess) + " times a bound); use end_condition 'natural' or 'clamped', "
                                    "whose joining segment is chosen for the bounds");
          throw InvalidInputError("start_state: the motion starts too fast for the curve it joins: braking along it "
                                  "would take " + formatNumber(excess) + " times an acceleration bound; start more "
                                  "slowly or farther from the first waypoint, or raise the acceleration bounds");
        }
        out.recovery_time = timed->profile().recovery_end - timed->startTime();
        out.time_scale = timed->profile().stretch;
        adopt(timed);
        setTimedFigures(r, timed->profile(), fig_io);
      }
    };
    // A timing that does not converge on this joining segment is tried on longer ones
    // (kJoinRetries); what is refused is refused with the first one's reason.
    int lengthenings = 0;
    const auto lengthenJoin = [&]() {
      while (lengthenings < kJoinRetries)
      {
        ++lengthenings;
        h *= 2.0;
        auto joined = join(joined_to, h, scale * t1);
        if (std::max(1.0, accelerationExcess(r, *joined, h)) <= std::max(1.0, best_excess))
        {
          path = joined;
          return true;
        }
      }
      return false;
    };
    std::exception_ptr first_failure;
    for (;;)
    {
      try
      {
        timeAlongPath();
        break;
      }
      catch (const LimitExceededError&)
      {
        throw;
      }
      catch (const InterpolationError&)
      {
        if (!first_failure)
          first_failure = std::current_exception();
        // Only under jerk bounds, whose final check holds every rate to 1e-6 (jerk_limited.cpp):
        // the time-optimal and constant-speed timings from a moving start leave small excesses
        // between their checked points (docs/curves.md "Known limitations"), and a joining
        // segment they refuse is kept refused rather than traded for one of those.
        if (native || !joined_to || !hasJerkBound(r) || !lengthenJoin())
          std::rethrow_exception(first_failure);
      }
    }
  }
  else
  {
    if (!native)
      curve = join(through, t1, t1);
    *fig_io = measureCurve(*curve, rho);
    measureJerk(r, *curve, fig_io);
    std::string cause = r.times.empty() ? "duration" : "times";
    const double k = stretchFactor(r, *fig_io, &cause);
    validateTimeSpan(0.0, curve->endTime() * k, cause);
    if (k > 1.0 && !at_rest)
      throw InvalidInputError("timing: 'stretch' would slow the motion down " + formatNumber(k) + " times for " +
                              cause + ", which would change the start state's velocity and acceleration; use "
                              "timing 'time_optimal', which keeps the start state and brings the motion within "
                              "the bounds");
    if (k > 1.0)
    {
      curve = std::make_shared<TimeScaledCurve<G>>(curve, k);
      const CurveFigures unscaled = *fig_io;
      *fig_io = measureCurve(*curve, rho);
      fig_io->max_linear_jerk = unscaled.max_linear_jerk / (k * k * k);
      fig_io->max_angular_jerk = unscaled.max_angular_jerk / (k * k * k);
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
                            " long through waypoints whose polygon is " + formatNumber(polygon) +
                            " long (more than " + formatNumber(kMaxStartLengthRatio) +
                            " times: solving forward from the start data amplifies them); use end_condition "
                            "'natural' or 'clamped', or waypoints and times that the start velocity leads into");
}

/// A request's motion before sampling: the timed curve, its figures and the result's fields so far.
template <class Space, class G>
struct PlannedMotion
{
  std::shared_ptr<const Curve<G>> curve;
  CurveFigures figures;
  BasicResult<Space> out;
  /// A fit's control points (those of the fitted B-spline, not of the joined motion).
  std::optional<std::vector<typename Space::Waypoint>> fit_control;
};

template <class Space, class G>
PlannedMotion<Space, G> planMotion(const BasicValidatedRequest<Space>& r, const std::vector<double>& times);

/// Whether a start state that cannot continue along the curve may brake to rest first
/// (planBrakedStart): under time-optimal timing without jerk bounds.
bool mayBrakeToRest(const ValidatedRequest& r)
{
  return r.start_state && r.timing == Timing::kTimeOptimal && !hasJerkBound(r);
}

/// Whether a start state moves faster than a velocity bound in some channel.
bool startExceedsVelocityBound(const ValidatedRequest& r)
{
  const Twist& v = r.start_state->velocity;
  return (r.max_linear_velocity > 0.0 && v.linear.norm() > r.max_linear_velocity) ||
         (r.max_angular_velocity > 0.0 && v.angular.norm() > r.max_angular_velocity);
}

/// The stop of the start state (curves/braked_start.h, B1, B2): each moving channel decelerates at
/// its acceleration bound; a channel without one stops when the bounded ones do. std::nullopt when
/// no channel with an acceleration bound moves: then nothing fixes how fast to stop.
std::optional<BrakeToRest> brakeToRest(const ValidatedRequest& r)
{
  const StartState& s = *r.start_state;
  BrakeToRest b;
  b.start = s.pose;
  b.start_acceleration = s.acceleration;
  const Eigen::Vector3d velocities[2] = { s.velocity.linear, s.velocity.angular };
  const double bounds[2] = { r.max_linear_acceleration, r.max_angular_acceleration };
  ChannelBrake* channels[2] = { &b.linear, &b.angular };
  double stop = 0.0;  // of the bounded channels
  for (int c = 0; c < 2; ++c)
  {
    channels[c]->speed = velocities[c].norm();
    if (channels[c]->speed > 0.0)
      channels[c]->direction = velocities[c] / channels[c]->speed;
    if (bounds[c] > 0.0 && channels[c]->speed > 0.0)
    {
      channels[c]->deceleration = bounds[c];
      stop = std::max(stop, channels[c]->stopTime());
    }
  }
  if (!(stop > 0.0) || !std::isfinite(stop))
    return std::nullopt;
  for (int c = 0; c < 2; ++c)
    if (!(bounds[c] > 0.0) && channels[c]->speed > 0.0)
      channels[c]->deceleration = channels[c]->speed / stop;
  return b;
}

/// The motion of a request whose start state cannot continue along the curve within the bounds
/// (it exceeds a velocity bound, or the time-optimal timing from it is refused): the start state
/// braked to rest along its own directions (curves/braked_start.h), then the request's motion from
/// rest at the stopping pose. Time-optimal timing without jerk bounds only (its acceleration may
/// jump at the stop, as it does at a time-optimal switch).
template <class G>
PlannedMotion<PoseSpace, G> planBrakedStart(const ValidatedRequest& r, const BrakeToRest& brake)
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
  auto braked = std::make_shared<BrakedStartCurve<G>>(brake, m.curve);
  const double stop = braked->stopTime();
  m.curve = braked;
  for (double& t : m.out.waypoint_times)
    t += stop;
  // Every bound holds once each channel that exceeded its velocity bound is within it.
  double recovery = 0.0;
  const double velocity_bounds[2] = { r.max_linear_velocity, r.max_angular_velocity };
  const ChannelBrake* channels[2] = { &brake.linear, &brake.angular };
  for (int c = 0; c < 2; ++c)
    if (velocity_bounds[c] > 0.0 && channels[c]->speed > velocity_bounds[c])
      recovery = std::max(recovery, (channels[c]->speed - velocity_bounds[c]) / channels[c]->deceleration);
  m.out.recovery_time = recovery;
  m.out.stop_time = stop;
  // The figures of the whole motion: the braking's in closed form (B1, B2: speeds falling from the
  // start's, constant decelerations, the start's acceleration at t = 0) with those from rest.
  CurveFigures& f = m.figures;
  const double rho = r.rotation_scale;
  f.length += brake.linear.distance();
  f.rotation_length += brake.angular.distance();
  f.max_linear_speed = std::max(f.max_linear_speed, brake.linear.speed);
  f.max_angular_speed = std::max(f.max_angular_speed, brake.angular.speed);
  f.max_linear_acceleration = std::max({ f.max_linear_acceleration, brake.linear.deceleration,
                                         brake.start_acceleration.linear.norm() });
  f.max_angular_acceleration = std::max({ f.max_angular_acceleration, brake.angular.deceleration,
                                          brake.start_acceleration.angular.norm() });
  f.energy += brake.linear.deceleration * brake.linear.deceleration * brake.linear.stopTime() +
              rho * rho * brake.angular.deceleration * brake.angular.deceleration * brake.angular.stopTime();
  return m;
}

template <class Space, class G>
PlannedMotion<Space, G> planMotion(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
{
  if constexpr (std::is_same_v<Space, PoseSpace>)
  {
    // A start beyond a velocity bound brakes to rest first under time-optimal timing: straight
    // braking is the fastest recovery the acceleration bounds allow (braked_start.h).
    if (mayBrakeToRest(r) && startExceedsVelocityBound(r))
      if (const std::optional<BrakeToRest> brake = brakeToRest(r))
        return planBrakedStart<G>(r, *brake);
  }
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
    m.figures = measureCurve(*m.curve, r.rotation_scale);
  else
    std::tie(m.figures.length, m.figures.rotation_length) = measureLengths(*m.curve);
  requireStableStartSolve(r, m.figures);

  out.waypoint_times = times;
  bool timed = false;
  if constexpr (std::is_same_v<Space, PoseSpace>)
    if (r.start_state)
    {
      try
      {
        applyTimingFromStart<G>(r, times, &m.curve, &m.figures, &out);
      }
      catch (const LimitExceededError&)
      {
        throw;
      }
      catch (const InterpolationError&)
      {
        // A moving start that the time-optimal timing cannot continue along the curve within the
        // bounds (the joining segment bends too sharply for its speed): braked to rest first
        // (brakeToRest has no stop for a start whose bounded channels do not move).
        const std::optional<BrakeToRest> brake = mayBrakeToRest(r) ? brakeToRest(r) : std::nullopt;
        if (!brake)
          throw;
        return planBrakedStart<G>(r, *brake);
      }
      timed = true;
    }
  if (!timed)
    applyTiming<Space, G>(r, &m.curve, &m.figures, &out);
  return m;
}

template <class Space, class G>
BasicResult<Space> run(const BasicValidatedRequest<Space>& r, const PlannerLimits& limits, const SampleSink<Space>* sink)
{
  const std::vector<double> times = waypointTimes(r);
  // Bounded work: refused from the fields alone, before the curve is built or measured.
  const WorkShape shape = workShape(r);
  requireWorkWithin(estimateWork(shape, expectedSamples(shape, times.back() - times.front())), shape, limits);
  PlannedMotion<Space, G> planned = planMotion<Space, G>(r, times);
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
                                const SampleSink<Space>* sink)
{
  Deadline deadline(std::max(kDeadlineFactor * limits.max_work_seconds, kMinDeadlineSeconds), limits.max_work_seconds);
  const ScopedDeadline scope(deadline);
  return dispatch(validateRequest(request, limits), limits, sink);
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

template std::vector<double> waypointTimes<PoseSpace>(const ValidatedRequest&);
template std::vector<double> waypointTimes<SphereSpace>(const ValidatedSphereRequest&);
template TrajectoryResult generate<PoseSpace>(const TrajectoryRequest&, const PlannerLimits&);
template SphereResult generate<SphereSpace>(const SphereRequest&, const PlannerLimits&);
template TrajectoryResult generate<PoseSpace>(const TrajectoryRequest&, const PlannerLimits&,
                                              const SampleSink<PoseSpace>&);
template SphereResult generate<SphereSpace>(const SphereRequest&, const PlannerLimits&, const SampleSink<SphereSpace>&);

}  // namespace se3_interpolation
