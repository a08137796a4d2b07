// The invariants every outcome of generate() must satisfy, whatever the request (docs/curves.md,
// "What each curve accepts"): a served request gives a motion that is finite, sign-continuous,
// starts in its start state, keeps every bound on a dense evaluation of the continuous motion
// (after the reported recovery interval when the start state itself exceeds one), passes the
// waypoints its curve promises, has derivatives that agree with finite differences of its poses and
// figures that agree with the measured peaks; a refused request throws a std::invalid_argument
// whose message names a request field. A served motion, executed as an action goal (its samples as
// the node's toMsg writes them, execution/goal_trajectory.h), replays its samples, ends at rest
// exactly when its last sample does, and keeps its bounds wherever the node's check accepts it
// (checkGoal). With an arm (the request's joint_seed, generate()'s arm) the samples' joints also hold
// the joint invariants of joint_invariants.h. Shared by test_request_space.cpp (the grid and the
// random sweep of the request space).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "invariant_basics.h"
#include "joint_invariants.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/math/lie_groups.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/geodesic_timing.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace test
{
/// Sanitizer builds run a reduced, deterministic subset of the cases.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

/// The request fields an error message may name (srv/GenerateTrajectory.srv; `start_state` is the
/// CLI's name of the service's `from_current`).
inline const std::vector<std::string>& requestFieldNames()
{
  static const std::vector<std::string> kNames = {
    "waypoints",
    "times",
    "curve",
    "geometry",
    "degree",
    "knots",
    "continuity",
    "end_condition",
    "start_velocity",
    "end_velocity",
    "start_acceleration",
    "velocities",
    "parameterization",
    "rotation_scale",
    "duration",
    "max_linear_velocity",
    "max_angular_velocity",
    "max_linear_acceleration",
    "max_angular_acceleration",
    "max_linear_jerk",
    "max_angular_jerk",
    "timing",
    "speed",
    "sample_times",
    "sample_period",
    "sample_count",
    "sample_tolerance",
    "blend_radius",
    "start_state",
    "from_current",
    "outputs",
    "control_period",
    "smoothing",
    "loss",
    "loss_scale",
    "joint_seed",
  };
  return kNames;
}

inline bool isIdentifierChar(char c)
{
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

/// Whether `text` contains `word` as a whole identifier (so "times" is not found in "sample_times").
inline bool containsWord(const std::string& text, const std::string& word)
{
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1))
  {
    const bool before = at == 0 || !isIdentifierChar(text[at - 1]);
    const std::size_t end = at + word.size();
    const bool after = end == text.size() || !isIdentifierChar(text[end]);
    if (before && after)
      return true;
  }
  return false;
}

/// The request fields named in an error message.
inline std::vector<std::string> namedFields(const std::string& message)
{
  std::vector<std::string> named;
  for (const std::string& f : requestFieldNames())
    if (containsWord(message, f))
      named.push_back(f);
  return named;
}

/// The request field named first in a message ("(no field)" when none is).
inline std::string firstNamedField(const std::string& message)
{
  std::string first = "(no field)";
  std::size_t first_at = std::string::npos;
  for (const std::string& f : requestFieldNames())
    for (std::size_t at = message.find(f); at != std::string::npos; at = message.find(f, at + 1))
    {
      const bool before = at == 0 || !isIdentifierChar(message[at - 1]);
      const std::size_t end = at + f.size();
      const bool after = end == message.size() || !isIdentifierChar(message[end]);
      if (before && after)
      {
        if (at < first_at)
        {
          first_at = at;
          first = f;
        }
        break;
      }
    }
  return first;
}

/// BasicResult::recovery_time when the core has it (the interval after a start state that itself
/// exceeds a bound, in which that bound may still be exceeded), else 0.
template <class R, class = void>
struct HasRecoveryTime : std::false_type
{
};
template <class R>
struct HasRecoveryTime<R, std::void_t<decltype(std::declval<const R&>().recovery_time)>> : std::true_type
{
};
template <class R>
double recoveryTime(const R& result)
{
  if constexpr (HasRecoveryTime<R>::value)
    return static_cast<double>(result.recovery_time);
  else
    return 0.0;
}

/// Which waypoints the curve of a request passes, at result.waypoint_times: `fit` approximates
/// them and passes none (not even the last: the motion ends where the fitted curve does).
enum class PassedWaypoints
{
  kAll,
  kFirstAndLast,
  kNone
};

inline PassedWaypoints passedWaypoints(const TrajectoryRequest& r)
{
  const std::string curve = r.curve.empty() ? "interpolating" : r.curve;
  if (curve == "fit")
    return PassedWaypoints::kNone;
  if (curve == "interpolating" || curve == "hermite" || curve == "blended")
    return PassedWaypoints::kAll;
  if (curve == "piecewise_geodesic" && !(r.blend_radius > 0.0))
    return PassedWaypoints::kAll;
  return PassedWaypoints::kFirstAndLast;
}

/// Peak rates measured on the dense evaluation (|ṗ|, |ω|, |p̈|, |ω̇|).
struct MeasuredPeaks
{
  double value[4] = { 0.0, 0.0, 0.0, 0.0 };
};

inline double rateOf(const TrajectorySample& s, int j)
{
  switch (j)
  {
    case 0:
      return s.velocity.linear.norm();
    case 1:
      return s.velocity.angular.norm();
    case 2:
      return s.acceleration.linear.norm();
    default:
      return s.acceleration.angular.norm();
  }
}

inline const char* kBoundFields[4] = { "max_linear_velocity", "max_angular_velocity", "max_linear_acceleration",
                                       "max_angular_acceleration" };
inline const char* kFigureFields[4] = { "max_linear_speed", "max_angular_speed", "max_linear_acceleration",
                                        "max_angular_acceleration" };

inline double boundOf(const TrajectoryRequest& r, int j)
{
  const double b[4] = { r.max_linear_velocity, r.max_angular_velocity, r.max_linear_acceleration,
                        r.max_angular_acceleration };
  return b[j];
}

inline double figureOf(const CurveFigures& f, int j)
{
  const double v[4] = { f.max_linear_speed, f.max_angular_speed, f.max_linear_acceleration,
                        f.max_angular_acceleration };
  return v[j];
}

inline bool finitePose(const Pose<double>& x)
{
  return x.p.allFinite() && x.q.coeffs().allFinite();
}

inline bool finiteSample(const TrajectorySample& s)
{
  return std::isfinite(s.time) && finitePose(s.pose) && s.velocity.linear.allFinite() &&
         s.velocity.angular.allFinite() && s.acceleration.linear.allFinite() && s.acceleration.angular.allFinite();
}

/// |a − b| ≤ tol (|a| + |b| + 1)·… : the absolute-plus-relative error of two vectors.
inline double relativeGap(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return (a - b).norm() / (1.0 + std::max(a.norm(), b.norm()));
}

inline double poseGap(const Pose<double>& a, const Pose<double>& b)
{
  const double dp = (a.p - b.p).norm() / (1.0 + std::max(a.p.norm(), b.p.norm()));
  return std::max(dp, rotationAngle(Quaternion<double>(a.q.conjugate() * b.q)));
}

/// The normalised requested waypoint i (validation normalises the quaternion).
inline Pose<double> normalisedWaypoint(const TrajectoryRequest& r, std::size_t i)
{
  Pose<double> x = r.waypoints[i];
  x.q.normalize();
  return x;
}

/// The outputs of a served `fit` (fitting/bspline_fit.h): the fitted B-spline's knots, clamped and
/// uniform on the fitted times [t_0, t_N] (with a start state the start pose is fitted too, at
/// time 0, so t_0 = 0), of the requested degree (default min(3, points − 1)), as many control
/// points as knots − degree − 1 and at most one per fitted point, and finite residuals ≥ 0.
inline void checkFitOutputs(const TrajectoryRequest& request, const TrajectoryResult& result, std::vector<Violation>& v)
{
  auto fail = [&v](const std::string& detail) { v.push_back({ "fit outputs", 0.0, detail }); };
  if (!std::isfinite(result.residual_linear) || result.residual_linear < 0.0 ||
      !std::isfinite(result.residual_angular) || result.residual_angular < 0.0)
    fail("residual_linear " + num(result.residual_linear) + ", residual_angular " + num(result.residual_angular));
  if (request.times.empty())
  {
    fail("a fit served without times");
    return;
  }
  // A start state at times[0] = 0 is waypoints[0] itself (validation refuses any other); at a
  // later times[0] it is an extra point at 0.
  const bool start_inserted = request.start_state && request.times.front() != 0.0;
  const std::size_t points = request.waypoints.size() + (start_inserted ? 1 : 0);
  const double first = request.start_state ? 0.0 : request.times.front();
  const double last = request.times.back();
  const int m = request.degree > 0 ? request.degree : std::min(3, static_cast<int>(points) - 1);
  const std::vector<double>& u = result.knots;
  const std::size_t need = 2 * static_cast<std::size_t>(std::max(m, 0) + 1);
  if (m < 1 || u.size() < need)
  {
    fail(std::to_string(u.size()) + " knots for degree " + std::to_string(m) + " (at least " + std::to_string(need) +
         ")");
    return;
  }
  if (result.control_points.size() + static_cast<std::size_t>(m) + 1 != u.size())
    fail(std::to_string(result.control_points.size()) + " control points for " + std::to_string(u.size()) +
         " knots of degree " + std::to_string(m));
  if (result.control_points.size() > points)
    fail(std::to_string(result.control_points.size()) + " control points for " + std::to_string(points) +
         " fitted points");
  const double tol = 1e-12 * std::max({ 1.0, std::abs(first), std::abs(last) });
  const std::size_t k = u.size();
  for (std::size_t i = 0; i <= static_cast<std::size_t>(m); ++i)
    if (std::abs(u[i] - first) > tol || std::abs(u[k - 1 - i] - last) > tol)
    {
      fail("knots not clamped to [" + num(first) + ", " + num(last) + "]: knots[" + std::to_string(i) +
           "] = " + num(u[i]) + ", knots[" + std::to_string(k - 1 - i) + "] = " + num(u[k - 1 - i]));
      return;
    }
  const double step = (last - first) / static_cast<double>(k - 2 * static_cast<std::size_t>(m) - 1);
  for (std::size_t i = static_cast<std::size_t>(m) + 1; i + static_cast<std::size_t>(m) < k; ++i)
    if (std::abs(u[i] - u[i - 1] - step) > tol)
    {
      fail("knots not uniform: knots[" + std::to_string(i) + "] - knots[" + std::to_string(i - 1) +
           "] = " + num(u[i] - u[i - 1]) + ", the uniform step " + num(step));
      return;
    }
}

/// Checks a served request's result; returns the broken invariants (empty: all hold).
inline std::vector<Violation> checkInvariants(const TrajectoryRequest& request, const TrajectoryResult& result,
                                              const CheckOptions& options = CheckOptions())
{
  std::vector<Violation> v;
  auto fail = [&v](const std::string& kind, double magnitude, const std::string& detail) {
    v.push_back({ kind, magnitude, detail });
  };

  // --- Finite numbers, times, quaternions -------------------------------------------------
  const double t0 = result.start_time;
  const double T = result.duration;
  if (!std::isfinite(t0) || !std::isfinite(T) || !(T > 0.0))
  {
    fail("span", T, "start_time " + num(t0) + ", duration " + num(T));
    return v;
  }
  const double t1 = t0 + T;
  const double time_tol = 1e-12 * std::max(1.0, std::max(std::abs(t0), std::abs(t1)));
  if (result.samples.empty())
    fail("samples", 0.0, "no samples");
  if (!result.state_at)
  {
    fail("state_at", 0.0, "no state_at");
    return v;
  }
  const bool explicit_sample_times = !request.sample_times.empty();
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    if (!finiteSample(s))
    {
      fail("finite", 0.0, "samples[" + std::to_string(i) + "] not finite");
      return v;
    }
    if (s.time < t0 - time_tol || s.time > t1 + time_tol)
      fail("sample time", s.time,
           "samples[" + std::to_string(i) + "].time " + num(s.time) + " outside [" + num(t0) + ", " + num(t1) + "]");
    if (i > 0)
    {
      const double prev = result.samples[i - 1].time;
      if (explicit_sample_times ? s.time < prev : !(s.time > prev))
        fail("sample order", s.time - prev,
             "samples[" + std::to_string(i) + "].time " + num(s.time) + " not after " + num(prev));
      const double dot = s.pose.q.coeffs().dot(result.samples[i - 1].pose.q.coeffs());
      if (dot < 0.0)
        fail("quaternion sign", dot, "samples[" + std::to_string(i) + "]: dot with the previous " + num(dot));
    }
    const double qn = std::abs(s.pose.q.norm() - 1.0);
    if (qn > 1e-9)
      fail("unit quaternion", qn, "samples[" + std::to_string(i) + "]: |q| - 1 = " + num(qn));
  }
  if (!result.samples.empty() && result.samples.front().pose.q.w() < 0.0)
    fail("quaternion sign", result.samples.front().pose.q.w(), "first sample has w < 0");
  if (!explicit_sample_times && !result.samples.empty())
  {
    if (std::abs(result.samples.front().time - t0) > time_tol || std::abs(result.samples.back().time - t1) > time_tol)
      fail("sample ends", 0.0,
           "samples span [" + num(result.samples.front().time) + ", " + num(result.samples.back().time) +
               "], trajectory [" + num(t0) + ", " + num(t1) + "]");
  }
  const double figures[] = { result.figures.length,
                             result.figures.rotation_length,
                             result.figures.energy,
                             result.figures.max_linear_speed,
                             result.figures.max_angular_speed,
                             result.figures.max_linear_acceleration,
                             result.figures.max_angular_acceleration,
                             result.time_scale };
  for (double f : figures)
    if (!std::isfinite(f) || f < 0.0)
    {
      fail("figures", f, "a figure is " + num(f));
      return v;
    }

  // --- The start state ------------------------------------------------------------------
  if (request.start_state)
  {
    const StartState& s = *request.start_state;
    Pose<double> sp = s.pose;
    sp.q.normalize();
    auto compare = [&](const TrajectorySample& x, const char* where) {
      const double dp = poseGap(x.pose, sp);
      const double dv = std::max(relativeGap(x.velocity.linear, s.velocity.linear),
                                 relativeGap(x.velocity.angular, s.velocity.angular));
      const double da = std::max(relativeGap(x.acceleration.linear, s.acceleration.linear),
                                 relativeGap(x.acceleration.angular, s.acceleration.angular));
      if (dp > 1e-9 || dv > 1e-9 || da > 1e-9)
        fail("start state", std::max({ dp, dv, da }),
             std::string(where) + ": pose " + num(dp) + ", velocity " + num(dv) + ", acceleration " + num(da) +
                 " from the start state");
    };
    compare(result.state_at(t0), "state_at(start_time)");
    if (!result.samples.empty() && std::abs(result.samples.front().time - t0) <= time_tol)
      compare(result.samples.front(), "samples[0]");
  }

  // --- Dense evaluation: bounds, recovery, peaks --------------------------------------------
  // The dense times: evenly spaced over the motion, evenly spaced within every waypoint interval
  // (uneven times make short, fast segments), the sample and waypoint times; then each peak is
  // refined on a fine grid around the dense point where it was largest.
  std::vector<double> ts;
  const std::size_t m = std::max<std::size_t>(options.dense_points, 2);
  ts.reserve(2 * m + result.samples.size() + result.waypoint_times.size());
  for (std::size_t i = 0; i < m; ++i)
    ts.push_back(t0 + T * static_cast<double>(i) / static_cast<double>(m - 1));
  for (const TrajectorySample& s : result.samples)
    ts.push_back(s.time);
  std::vector<double> knots{ t0 };
  for (double t : result.waypoint_times)
    if (std::isfinite(t) && t > knots.back() && t <= t1)
      knots.push_back(t);
  const std::size_t per_interval = std::max<std::size_t>(8, m / std::max<std::size_t>(knots.size(), 1));
  for (std::size_t k = 0; k + 1 < knots.size(); ++k)
    for (std::size_t i = 0; i <= per_interval; ++i)
      ts.push_back(knots[k] + (knots[k + 1] - knots[k]) * static_cast<double>(i) / static_cast<double>(per_interval));
  for (double& t : ts)
    t = std::min(std::max(t, t0), t1);
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end()), ts.end());

  const double recovery = recoveryTime(result);
  const TrajectorySample first = result.state_at(t0);
  bool exceeded_at_start[4] = { false, false, false, false };
  bool any_exceeded = false;
  for (int j = 0; j < 4; ++j)
  {
    const double b = boundOf(request, j);
    exceeded_at_start[j] = request.start_state && b > 0.0 && rateOf(first, j) > b * (1.0 + 1e-6);
    any_exceeded = any_exceeded || exceeded_at_start[j];
  }
  if (!std::isfinite(recovery) || recovery < 0.0 || recovery > T * (1.0 + 1e-12))
    fail("recovery_time", recovery, "recovery_time " + num(recovery) + " outside [0, duration " + num(T) + "]");
  if (!any_exceeded && recovery != 0.0)
    fail("recovery_time", recovery, "recovery_time " + num(recovery) + " without a start state above a bound");

  MeasuredPeaks peaks;
  std::size_t peak_at[4] = { 0, 0, 0, 0 };
  double worst[4] = { 0.0, 0.0, 0.0, 0.0 };
  double worst_t[4] = { 0.0, 0.0, 0.0, 0.0 };
  double worst_increase[4] = { 0.0, 0.0, 0.0, 0.0 };
  bool bad_state = false;
  // Evaluates a sequence of times in order: peaks, bounds, and inside the recovery interval the
  // exceeded quantities, which may not grow while they are above their bound.
  auto evaluate = [&](const std::vector<double>& times, bool track_peaks) {
    double previous[4] = { 0.0, 0.0, 0.0, 0.0 };
    bool in_recovery_prev = false;
    for (std::size_t i = 0; i < times.size() && !bad_state; ++i)
    {
      const double t = times[i];
      const TrajectorySample s = result.state_at(t);
      if (!finiteSample(s))
      {
        fail("finite", t, "state_at(" + num(t) + ") not finite");
        bad_state = true;
        return;
      }
      const double qn = std::abs(s.pose.q.norm() - 1.0);
      if (qn > 1e-9)
        fail("unit quaternion", qn, "state_at(" + num(t) + "): |q| - 1 = " + num(qn));
      const bool in_recovery = any_exceeded && t <= t0 + recovery;
      for (int j = 0; j < 4; ++j)
      {
        const double r = rateOf(s, j);
        if (r > peaks.value[j])
        {
          peaks.value[j] = r;
          if (track_peaks)
            peak_at[j] = i;
        }
        const double b = boundOf(request, j);
        if (b > 0.0)
        {
          if (in_recovery && exceeded_at_start[j])
          {
            if (in_recovery_prev && r > b && r > previous[j] * (1.0 + 1e-9) + 1e-12)
              worst_increase[j] = std::max(worst_increase[j], r / previous[j] - 1.0);
          }
          else if (r > b * (1.0 + 1e-6) && r / b > worst[j])
          {
            worst[j] = r / b;
            worst_t[j] = t;
          }
        }
        previous[j] = r;
      }
      in_recovery_prev = in_recovery;
    }
  };
  // Each peak refined on 65 points between the dense neighbours of where it was largest.
  auto refinePeaks = [&](const std::vector<double>& times) {
    for (int j = 0; j < 4; ++j)
    {
      const std::size_t i = peak_at[j];
      const double lo = times[i > 0 ? i - 1 : 0];
      const double hi = times[std::min(i + 1, times.size() - 1)];
      std::vector<double> fine;
      for (int k = 0; k <= 64; ++k)
        fine.push_back(lo + (hi - lo) * k / 64.0);
      evaluate(fine, false);
    }
  };
  evaluate(ts, true);
  if (bad_state)
    return v;
  refinePeaks(ts);
  if (bad_state)
    return v;

  for (int j = 0; j < 4; ++j)
  {
    if (worst[j] > 0.0)
      fail(std::string("bound ") + kBoundFields[j], worst[j],
           std::string(kBoundFields[j]) + " " + num(boundOf(request, j)) + " exceeded " + num(worst[j]) + "x at t = " +
               num(worst_t[j]) + " of [" + num(t0) + ", " + num(t1) + "] (recovery_time " + num(recovery) + ")");
    if (worst_increase[j] > 0.0)
      fail(std::string("recovery ") + kBoundFields[j], worst_increase[j],
           std::string(kBoundFields[j]) + " exceeded at the start grows by " + num(worst_increase[j]) +
               " (relative) inside the recovery interval");
  }

  // Figures equal the dense peaks (the dense evaluation may miss a peak slightly).
  // Below 1e-12 of the largest rate a peak is rounding noise.
  const double noise = 1e-12 * std::max({ 1.0, peaks.value[0], peaks.value[1], peaks.value[2], peaks.value[3] });
  for (int j = 0; j < 4; ++j)
  {
    const double f = figureOf(result.figures, j);
    const double measured = peaks.value[j];
    if (f < measured * (1.0 - 1e-6) - noise)
      fail(std::string("figure ") + kFigureFields[j], measured / f,
           std::string("figures.") + kFigureFields[j] + " " + num(f) + " below the measured peak " + num(measured));
    else if (f > measured * (1.0 + 1e-3) + std::max(1e-12, noise))
    {
      // The figures are values the motion takes (at the timing's grid points, or found by a search
      // on the exact rates), so a figure above every dense sample is a peak in a sliver that the
      // dense times stepped over: a failure only where it exceeds a bound after the recovery.
      const double b = boundOf(request, j);
      if (b > 0.0 && f > b * (1.0 + 1e-6) && !exceeded_at_start[j])
        fail(std::string("bound ") + kBoundFields[j], f / b,
             std::string("figures.") + kFigureFields[j] + " " + num(f) + " above its bound " + num(b) +
                 " (the dense samples reach " + num(measured) + ")");
    }
  }

  // --- Jerk: the differences of the acceleration on an even grid --------------------------
  // With a jerk bound the acceleration is continuous and its mean rate of change over each step
  // (a lower bound of the peak jerk there) is within the bound; the figure is never below it.
  if (request.max_linear_jerk > 0.0 || request.max_angular_jerk > 0.0)
  {
    const double bound[2] = { request.max_linear_jerk, request.max_angular_jerk };
    const double figure[2] = { result.figures.max_linear_jerk, result.figures.max_angular_jerk };
    const char* field[2] = { "max_linear_jerk", "max_angular_jerk" };
    double mean[2] = { 0.0, 0.0 };
    double mean_t[2] = { 0.0, 0.0 };
    TrajectorySample previous = result.state_at(t0);
    for (std::size_t i = 1; i < m; ++i)
    {
      const double t = t0 + T * static_cast<double>(i) / static_cast<double>(m - 1);
      const TrajectorySample s = result.state_at(std::min(t, t1));
      const double dt = s.time - previous.time > 0.0 ? s.time - previous.time : T / static_cast<double>(m - 1);
      const double d[2] = { (s.acceleration.linear - previous.acceleration.linear).norm() / dt,
                            (s.acceleration.angular - previous.acceleration.angular).norm() / dt };
      for (int c = 0; c < 2; ++c)
        if (d[c] > mean[c])
        {
          mean[c] = d[c];
          mean_t[c] = t;
        }
      previous = s;
    }
    for (int c = 0; c < 2; ++c)
    {
      // Rounding: of the accelerations (1e-12 of the largest) over a step, and a floor of 1e-6 of
      // the bounds (a channel that hardly moves, on a motion of 10⁵ s, shows rounding of 1e-7).
      const double rounding = std::max(1e-12 * std::max(1.0, peaks.value[2 + c]) * static_cast<double>(m) / T,
                                       1e-6 * std::max(bound[0], bound[1]));
      if (bound[c] > 0.0 && mean[c] > bound[c] * (1.0 + 1e-6) + rounding)
        fail(std::string("bound ") + field[c], mean[c] / bound[c],
             std::string(field[c]) + " " + num(bound[c]) + ": the acceleration changes at " + num(mean[c]) +
                 " on average over the step ending at t = " + num(mean_t[c]));
      if (figure[c] < mean[c] * (1.0 - 1e-6) - rounding)
        fail(std::string("figure peak jerk ") + field[c], mean[c] / figure[c],
             std::string("figures jerk ") + num(figure[c]) + " below the measured " + num(mean[c]));
    }
  }

  // --- Constant speed: the chord speed of the window ------------------------------------------
  // timing constant_speed holds √(|ṗ|² + ρ²|ω|²) at `speed` (1e-6 relative) inside
  // [constant_speed_start, constant_speed_end], a window within the motion, by the reported
  // velocities and by central differences of the poses (h = 1e-5 s, less in a short window: the
  // chord of an arc of curvature κ is short of it by about (κ V h)²/6, below 1e-7 here up to κ = 10³).
  if (request.timing == "constant_speed")
  {
    const double a = result.constant_speed_start, b = result.constant_speed_end;
    const double rho = request.rotation_scale > 0.0 ? request.rotation_scale : 1.0;
    if (!(a > t0 && b > a && b < t1))
      fail("constant speed window", b - a,
           "window [" + num(a) + ", " + num(b) + "] not inside the motion (" + num(t0) + ", " + num(t1) + ")");
    else
    {
      // (On a motion of 10⁵ s through positions of 10³ m the poses' rounding, 1e-13 m, over 2h must
      // stay below 1e-8 of the speed: h grows with the times and the positions.)
      double reach = 0.0;
      for (const Pose<double>& w : request.waypoints)
        reach = std::max(reach, w.p.norm());
      const double h = std::max(std::min(1e-5, 1e-5 * (b - a)),
                                1e-9 * std::max({ 1.0, std::abs(b), (reach + result.figures.length) / request.speed }));
      double worst = 0.0, worst_t = a, worst_reported = 0.0;
      for (int i = 0; i < 64; ++i)
      {
        const double t = a + (b - a) * (i + 0.5) / 64.0;
        const TrajectorySample s = result.state_at(t);
        const double reported = std::hypot(s.velocity.linear.norm(), rho * s.velocity.angular.norm());
        const TrajectorySample before = result.state_at(t - h), after = result.state_at(t + h);
        const double dt = after.time - before.time;  // (the times as evaluated, rounding included)
        const double dp = (after.pose.p - before.pose.p).norm() / dt;
        const double dtheta = rotationAngle(Quaternion<double>(before.pose.q.conjugate() * after.pose.q)) / dt;
        const double differenced = std::hypot(dp, rho * dtheta);
        for (double c : { reported, differenced })
          if (std::abs(c / request.speed - 1.0) > worst)
          {
            worst = std::abs(c / request.speed - 1.0);
            worst_t = t;
            worst_reported = reported / request.speed - 1.0;
          }
      }
      if (worst > 1e-6)
        fail("constant speed", worst,
             "the chord speed is off " + num(request.speed) + " by " + num(worst) +
                 " (relative) at t = " + num(worst_t) + " (by the reported velocity: " + num(worst_reported) + ")");
    }
  }

  // --- Waypoints passed -------------------------------------------------------------------
  const std::size_t n = request.waypoints.size();
  // With explicit knots a B-spline's waypoints are control points on the knots' own time axis:
  // neither their times nor their passage is promised.
  const bool explicit_knots = !request.knots.empty();
  if (explicit_knots)
  {
  }
  else if (result.waypoint_times.size() != n)
    fail("waypoint_times", static_cast<double>(result.waypoint_times.size()),
         "waypoint_times has " + std::to_string(result.waypoint_times.size()) + " entries for " + std::to_string(n) +
             " waypoints");
  else
  {
    for (std::size_t i = 1; i < n; ++i)
      if (!(result.waypoint_times[i] >= result.waypoint_times[i - 1]))
        fail("waypoint_times", result.waypoint_times[i], "waypoint_times not increasing at " + std::to_string(i));
    if (std::abs(result.waypoint_times.back() - t1) > 1e-9 * std::max(1.0, std::abs(t1)))
      fail("waypoint_times", result.waypoint_times.back() - t1,
           "last waypoint time " + num(result.waypoint_times.back()) + " is not the end " + num(t1));
    const PassedWaypoints passed = passedWaypoints(request);
    for (std::size_t i = 0; i < n && passed != PassedWaypoints::kNone; ++i)
    {
      const bool promised = passed == PassedWaypoints::kAll || i + 1 == n || (i == 0 && !request.start_state);
      if (!promised)
        continue;
      const double t = result.waypoint_times[i];
      if (!std::isfinite(t) || t < t0 - time_tol || t > t1 + time_tol)
      {
        fail("waypoint_times", t, "waypoint_times[" + std::to_string(i) + "] = " + num(t) + " outside the motion");
        continue;
      }
      const TrajectorySample s = result.state_at(std::min(std::max(t, t0), t1));
      // A time mapped through a timing profile carries its rounding: allow its effect.
      const double slack = 1e-9 * std::max(1.0, std::abs(t)) * (s.velocity.linear.norm() + s.velocity.angular.norm());
      const double gap = poseGap(s.pose, normalisedWaypoint(request, i));
      if (gap > 1e-8 + slack)
        fail("waypoint passed", gap,
             "waypoints[" + std::to_string(i) + "] missed by " + num(gap) + " at t = " + num(t));
    }
    // With a start state, curves that pass only their ends end at the last waypoint and start at
    // the start state (checked above).
  }
  if (passedWaypoints(request) == PassedWaypoints::kNone)
    checkFitOutputs(request, result, v);
  else if (!explicit_knots)
  {
    const TrajectorySample end = result.state_at(t1);
    const double gap = poseGap(end.pose, normalisedWaypoint(request, n - 1));
    if (gap > 1e-8)
      fail("waypoint passed", gap, "the motion ends " + num(gap) + " from the last waypoint");
  }

  // --- Derivatives against finite differences of the poses ----------------------------------
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> where(0.0, 1.0);
  const double pos_scale = 1.0 + std::max(result.figures.length, 0.0);
  double worst_v = 0.0, worst_a = 0.0;
  std::string worst_v_at, worst_a_at;
  for (std::size_t k = 0; k < options.difference_points; ++k)
  {
    // The step: small against the motion and against its local time scales |v|/|a| and 1/|ω|
    // (a fast rotation turns the stencil's points too far apart).
    const double u = where(rng);
    const TrajectorySample here = result.state_at(t0 + T * (0.01 + 0.98 * u));
    double h = T * 2e-5;
    const double vl = here.velocity.linear.norm(), al = here.acceleration.linear.norm();
    const double va = here.velocity.angular.norm(), aa = here.acceleration.angular.norm();
    if (al > 0.0 && vl > 0.0)
      h = std::min(h, 1e-2 * vl / al);
    if (aa > 0.0 && va > 0.0)
      h = std::min(h, 1e-2 * va / aa);
    if (va > 0.0)
      h = std::min(h, 1e-2 / va);
    if (!(h > 1e-9 * std::max(1.0, std::abs(t0) + T)))
      continue;
    const double t = std::min(std::max(t0 + T * (0.01 + 0.98 * u), t0 + 4 * h), t1 - 4 * h);
    if (t - 3 * h < t0 || t + 3 * h > t1)
      continue;
    TrajectorySample f[7];
    for (int i = 0; i < 7; ++i)
      f[i] = result.state_at(t + (i - 3) * h);
    const Pose<double>& c = f[3].pose;
    Eigen::Vector3d p[7], phi[7];
    for (int i = 0; i < 7; ++i)
    {
      p[i] = f[i].pose.p - c.p;
      const Quaternion<double> rel(f[i].pose.q * c.q.conjugate());
      phi[i] = rotationAngle(rel) < 3.0 ? so3Log(rel) : Eigen::Vector3d(1e300, 0, 0);
    }
    auto check = [&](const Eigen::Vector3d* x, const Eigen::Vector3d& vel, const Eigen::Vector3d& acc,
                     double magnitude_scale, const char* channel) {
      // Fourth-order central, second-order one-sided differences.
      const Eigen::Vector3d vc = (-x[5] + 8.0 * x[4] - 8.0 * x[2] + x[1]) / (12.0 * h);
      const Eigen::Vector3d vf = (-3.0 * x[3] + 4.0 * x[4] - x[5]) / (2.0 * h);
      const Eigen::Vector3d vb = (3.0 * x[3] - 4.0 * x[2] + x[1]) / (2.0 * h);
      const Eigen::Vector3d ac = (-x[5] + 16.0 * x[4] - 30.0 * x[3] + 16.0 * x[2] - x[1]) / (12.0 * h * h);
      const Eigen::Vector3d af = (2.0 * x[3] - 5.0 * x[4] + 4.0 * x[5] - x[6]) / (h * h);
      const Eigen::Vector3d ab = (2.0 * x[3] - 5.0 * x[2] + 4.0 * x[1] - x[0]) / (h * h);
      double vmax = 0.0, amax = 0.0;
      for (int i = 1; i < 6; ++i)
      {
        vmax = std::max(vmax, channel[0] == 'l' ? f[i].velocity.linear.norm() : f[i].velocity.angular.norm());
        amax = std::max(amax, channel[0] == 'l' ? f[i].acceleration.linear.norm() : f[i].acceleration.angular.norm());
      }
      // Rounding of the pose differences: ε |x| / h and ε |x| / h², and of the times themselves
      // (ε |t| moves the pose by ε |t| |v|).
      const double eps = 4e-16 * magnitude_scale + 4e-16 * std::abs(t) * vmax;
      const double vtol = 1e-5 * (vmax + amax * h) + 30.0 * eps / h;
      const double atol = 1e-5 * amax + 300.0 * eps / (h * h);
      if ((vf - vb).norm() <= 0.1 * vtol)
      {
        const double e = (vc - vel).norm();
        if (e > vtol && e / std::max(vtol, 1e-300) > worst_v)
        {
          worst_v = e / vtol;
          worst_v_at = std::string(channel) + " velocity at t = " + num(t) + ": analytic " + num(vel.norm()) +
                       ", differences " + num(vc.norm()) + ", error " + num(e);
        }
      }
      if ((af - ab).norm() <= 0.1 * atol)
      {
        const double e = (ac - acc).norm();
        if (e > atol && e / std::max(atol, 1e-300) > worst_a)
        {
          worst_a = e / atol;
          worst_a_at = std::string(channel) + " acceleration at t = " + num(t) + ": analytic " + num(acc.norm()) +
                       ", differences " + num(ac.norm()) + ", error " + num(e);
        }
      }
    };
    if (phi[0].x() > 1e299 || phi[6].x() > 1e299)
      continue;  // rotating too fast for the step: no difference to take
    check(p, f[3].velocity.linear, f[3].acceleration.linear, pos_scale + c.p.norm(), "linear");
    check(phi, f[3].velocity.angular, f[3].acceleration.angular, 4.0, "angular");
  }
  if (worst_v > 0.0)
    fail("velocity vs differences", worst_v, worst_v_at);
  if (worst_a > 0.0)
    fail("acceleration vs differences", worst_a, worst_a_at);
  return v;
}

/// What the goal check found of one served request (checkGoal).
struct GoalCheck
{
  bool checked = false;         ///< the goal was built (the check ran and construction succeeded)
  bool ends_at_rest = false;    ///< the last sample's speeds are within kRestLinear and kRestAngular
  bool accepted = false;        ///< checkLimits(the request's bounds, kGoalLimitTolerance) accepted it
  std::string refusal;          ///< checkLimits' message where it refused
  bool repeated_times = false;  ///< two samples at one time (explicit sample_times): not a goal
};

/// A time as it comes back from a trajectory_msgs point: ros::Duration(t) keeps whole seconds and
/// round((t − sec)·1e9) nanoseconds, toSec() gives sec + 1e-9·nsec (roscpp_core's fromSec/toSec).
inline double rosDurationSeconds(double t)
{
  const double sec = std::floor(t);
  const double nsec = std::round((t - sec) * 1e9);
  return sec + 1e-9 * nsec;
}

/// The served samples as the goal's points, as the node converts them: toMsg(TrajectoryResult, ...,
/// MultiDOFJointTrajectory) writes each sample's pose, velocity and acceleration and
/// time_from_start = sample.time (not shifted to the first sample: both count from the request's
/// stamp), fromMsg(MultiDOFJointTrajectoryPoint) reads them back; only the time is rounded (to ns).
inline std::vector<GoalPoint> goalPointsOf(const TrajectoryResult& result)
{
  std::vector<GoalPoint> points;
  points.reserve(result.samples.size());
  for (const TrajectorySample& s : result.samples)
  {
    GoalPoint p;
    p.time_from_start = rosDurationSeconds(s.time);
    p.pose = s.pose;
    p.velocity = s.velocity;
    p.acceleration = s.acceleration;
    points.push_back(p);
  }
  return points;
}

/// The served motion executed as an action goal (`~follow_trajectory`) on the request's geometry:
///  (a) the goal is built without an exception;
///  (b) it passes every sample: pose (1e-8), velocity and acceleration (1e-9, relative plus absolute,
///      and for the velocity the rounding of the accelerations over the segment);
///  (c) requireEndsAtRest passes exactly when the last sample is at rest (and it is, when the
///      samples reach the end of a time_optimal or constant_speed motion), else it refuses naming
///      the last point;
///  (d) where checkLimits(the request's bounds, kGoalLimitTolerance) accepts it, a brute-force
///      evaluation (options.goal_evaluations_per_segment states per segment and the end, both
///      channels' speeds and acceleration norms; the jerk as each segment's mean |Δa|/h from the
///      points' accelerations) stays within bound × (1 + kGoalLimitTolerance) (+ 1e-6 relative,
///      the accuracy checkLimits' peak search promises, and rounding): the node's acceptance
///      checked independently of its peak search; where it refuses, its message names a "~max_"
///      bound and "trajectory.points[";
///  (e) with sample_tolerance, the goal's pose stays within 1.5 × the tolerance of the motion's
///      (result.state_at) at options.goal_evaluations_per_segment points of every segment.
/// Runs when options.goal is set and the result has 1 … options.goal_max_samples samples.
inline GoalCheck checkGoal(const TrajectoryRequest& request, const TrajectoryResult& result,
                           const CheckOptions& options, std::vector<Violation>& v)
{
  GoalCheck g;
  if (!options.goal || result.samples.empty() || result.samples.size() > options.goal_max_samples)
    return g;
  auto fail = [&v](const std::string& kind, double magnitude, const std::string& detail) {
    v.push_back({ kind, magnitude, detail });
  };
  const std::vector<GoalPoint> points = goalPointsOf(result);
  const std::size_t n = points.size();
  // Explicit sample_times may repeat a time (they need only be non-decreasing): no goal has two
  // points at one time, and the goal is refused naming the repeated time_from_start.
  for (std::size_t i = 1; i < n; ++i)
    if (!(points[i].time_from_start > points[i - 1].time_from_start))
    {
      g.repeated_times = true;
      try
      {
        GoalTrajectory(points, parseName(request.geometry, "geometry", RequestDefaults::kGeometry));
        fail("goal construction", 0.0, "a goal with a repeated time_from_start is accepted");
      }
      catch (const std::exception& e)
      {
        if (std::string(e.what()).find("time_from_start") == std::string::npos)
          fail("goal construction", 0.0,
               std::string("a repeated time_from_start refused naming another field: ") + e.what());
      }
      return g;
    }
  std::optional<GoalTrajectory> goal;
  try
  {
    // (A served request's geometry is a valid name.)
    goal.emplace(points, parseName(request.geometry, "geometry", RequestDefaults::kGeometry));
  }
  catch (const std::exception& e)
  {
    fail("goal construction", 0.0, std::string("the served samples as a goal are refused: ") + e.what());
    return g;
  }
  g.checked = true;

  // (b) The goal replays the samples.
  double worst = 0.0;
  std::string worst_at;
  for (std::size_t i = 0; i < n; ++i)
  {
    const TrajectorySample s = goal->stateAt(points[i].time_from_start);
    const TrajectorySample& x = result.samples[i];
    const double gaps[3] = { poseGap(s.pose, x.pose),
                             std::max(relativeGap(s.velocity.linear, x.velocity.linear),
                                      relativeGap(s.velocity.angular, x.velocity.angular)),
                             std::max(relativeGap(s.acceleration.linear, x.acceleration.linear),
                                      relativeGap(s.acceleration.angular, x.acceleration.angular)) };
    // The last point is the end of a polynomial (from the left): its velocity carries the rounding
    // of the segment's accelerations over h (a planner's last sample has shown |p̈| = 2.7e9 m/s²,
    // sweep #1059: 1.3e-7 m/s); a pose gap below 1e-8 is the gap's own rounding on long motions
    // (sweep #2346, t = 4586 s: 1.1e-9).
    double slack = 0.0;
    if (i > 0)
    {
      const double h = points[i].time_from_start - points[i - 1].time_from_start;
      slack = 1e-15 * h *
              (x.acceleration.linear.norm() + x.acceleration.angular.norm() +
               result.samples[i - 1].acceleration.linear.norm() + result.samples[i - 1].acceleration.angular.norm());
    }
    const double gap = std::max({ gaps[0] * 0.1, gaps[1] - slack, gaps[2] });
    if (gap > 1e-9 && gap > worst)
    {
      worst = gap;
      worst_at = "the goal at trajectory.points[" + std::to_string(i) + "] (t = " + num(x.time) +
                 ") is off the sample: pose " + num(gaps[0]) + ", velocity " + num(gaps[1]) + ", acceleration " +
                 num(gaps[2]);
    }
  }
  if (worst > 0.0)
    fail("goal replay", worst, worst_at);

  // (c) At rest at the end exactly when the last sample is.
  const TrajectorySample& last = result.samples.back();
  const double end_linear = last.velocity.linear.norm(), end_angular = last.velocity.angular.norm();
  g.ends_at_rest = end_linear <= kRestLinear && end_angular <= kRestAngular;
  const std::string last_point = "trajectory.points[" + std::to_string(n - 1) + "]";
  const double t1 = result.start_time + result.duration;
  const bool reaches_end = std::abs(last.time - t1) <= 1e-12 * std::max(1.0, std::abs(t1));
  if (!g.ends_at_rest && reaches_end && (request.timing == "time_optimal" || request.timing == "constant_speed"))
    fail("goal ends moving", std::max(end_linear, end_angular),
         "timing " + request.timing + " ends moving: the last sample's speeds are " + num(end_linear) + " m/s, " +
             num(end_angular) + " rad/s");
  try
  {
    goal->requireEndsAtRest();
    if (!g.ends_at_rest)
      fail("goal rest", std::max(end_linear, end_angular),
           "requireEndsAtRest accepts a motion whose last sample moves at " + num(end_linear) + " m/s, " +
               num(end_angular) + " rad/s");
  }
  catch (const std::exception& e)
  {
    if (g.ends_at_rest)
      fail("goal rest", std::max(end_linear, end_angular),
           std::string("requireEndsAtRest refuses a motion whose last sample is at rest: ") + e.what());
    else if (std::string(e.what()).find(last_point) == std::string::npos)
      fail("goal rest message", 0.0,
           std::string("requireEndsAtRest's refusal does not name ") + last_point + ": " + e.what());
  }

  // (e) With sample_tolerance, the goal follows the motion: its pose within the tolerance (× 1.5: the
  // refinement tests the eighths of each interval) of result.state_at's at
  // options.goal_evaluations_per_segment points of every segment, in the chord distance of the
  // request's rotation_scale; (rounding: the times' nanoseconds at the motion's speed).
  if (request.sample_tolerance > 0.0 && result.state_at)
  {
    const double rho = request.rotation_scale > 0.0 ? request.rotation_scale : RequestDefaults::kRotationScale;
    const std::size_t per = std::max<std::size_t>(options.goal_evaluations_per_segment, 1);
    double deviation = 0.0, deviation_t = 0.0;
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (std::size_t k = 1; k < per; ++k)
      {
        const double ta = result.samples[i].time, tb = result.samples[i + 1].time;
        const double t = ta + (tb - ta) * static_cast<double>(k) / static_cast<double>(per);
        const Pose<double> g = goal->stateAt(points[i].time_from_start + (t - ta)).pose;
        const Pose<double> m = result.state_at(t).pose;
        const double theta = rho * m.q.angularDistance(g.q);
        const double d = std::sqrt((m.p - g.p).squaredNorm() + theta * theta);
        if (d > deviation)
        {
          deviation = d;
          deviation_t = t;
        }
      }
    if (deviation > 1.5 * request.sample_tolerance + 1e-9 * (1.0 + result.duration))
      fail("goal deviation", deviation / request.sample_tolerance,
           "with sample_tolerance " + num(request.sample_tolerance) + " the goal is " + num(deviation) +
               " from the motion at t = " + num(deviation_t) + " (" + std::to_string(n) + " points)");
  }

  // (d) The bounds: checkLimits' verdict, and where it accepts, a brute-force evaluation.
  const MotionLimits limits = motionLimitsOf(request);
  try
  {
    goal->checkLimits(limits, kGoalLimitTolerance);
    g.accepted = true;
  }
  catch (const std::exception& e)
  {
    g.refusal = e.what();
    if (g.refusal.find("~max_") == std::string::npos || g.refusal.find("trajectory.points[") == std::string::npos)
      fail("goal limits message", 0.0,
           "checkLimits' refusal names no ~max_ bound or no trajectory.points[: " + g.refusal);
    return g;
  }
  const double bound[6] = { limits.max_linear_velocity,     limits.max_angular_velocity,
                            limits.max_linear_acceleration, limits.max_angular_acceleration,
                            limits.max_linear_jerk,         limits.max_angular_jerk };
  static const char* const kGoalBounds[6] = { "~max_linear_velocity",     "~max_angular_velocity",
                                              "~max_linear_acceleration", "~max_angular_acceleration",
                                              "~max_linear_jerk",         "~max_angular_jerk" };
  double ratio[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
  double ratio_t[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
  auto observe = [&](int j, double value, double slack, double t) {
    if (bound[j] > 0.0 && value > bound[j] * (1.0 + kGoalLimitTolerance) * (1.0 + 1e-6) + slack &&
        value / bound[j] > ratio[j])
    {
      ratio[j] = value / bound[j];
      ratio_t[j] = t;
    }
  };
  const std::size_t per_segment = std::max<std::size_t>(options.goal_evaluations_per_segment, 1);
  auto rates = [&](const TrajectorySample& s) {
    for (int j = 0; j < 4; ++j)
      observe(j, rateOf(s, j), 1e-12, s.time);
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    const double ta = points[i].time_from_start, tb = points[i + 1].time_from_start;
    for (std::size_t k = 0; k < per_segment; ++k)
      rates(goal->stateAt(ta + (tb - ta) * static_cast<double>(k) / static_cast<double>(per_segment)));
    const double h = tb - ta;
    const Twist& a0 = *points[i].acceleration;
    const Twist& a1 = *points[i + 1].acceleration;
    // Rounding of the two accelerations over h.
    observe(4, (a1.linear - a0.linear).norm() / h, 4e-16 * (a0.linear.norm() + a1.linear.norm()) / h, ta);
    observe(5, (a1.angular - a0.angular).norm() / h, 4e-16 * (a0.angular.norm() + a1.angular.norm()) / h, ta);
  }
  rates(goal->stateAt(goal->endTime()));
  for (int j = 0; j < 6; ++j)
    if (ratio[j] > 0.0)
      fail(std::string("goal bound ") + kGoalBounds[j], ratio[j],
           std::string("checkLimits accepts the goal, but ") + (j >= 4 ? "the mean jerk of a segment" : "its motion") +
               " reaches " + num(ratio[j]) + " x " + kGoalBounds[j] + " = " + num(bound[j]) +
               " at t = " + num(ratio_t[j]) + " (" + std::to_string(n) + " points)");
  return g;
}

/// A valid brake of one channel of a start state (velocity v, acceleration a; bounds 0 = unbounded):
/// the acceleration ramped linearly to zero at the jerk bound (T_r = |a|/J), then the velocity
/// left, v + a T_r/2, stopped along its own direction by the closed-form double S or, without a jerk
/// bound, at constant deceleration (L. Biagiotti, C. Melchiorri, "Trajectory Planning for Automatic
/// Machines and Robots", §3.4); its duration, a bound of its distance, and its displacement (for
/// the rotation, the rotation vector in the chart at the start). Without either bound the channel
/// stops with the other: stopWithin fills it in.
struct ReferenceBrake
{
  double duration = 0.0;
  double distance = 0.0;
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
};

inline ReferenceBrake referenceBrake(const Eigen::Vector3d& v, const Eigen::Vector3d& a, double a_max, double j_max)
{
  ReferenceBrake b;
  if (!(a_max > 0.0) && !(j_max > 0.0))
    return b;
  Eigen::Vector3d v1 = v;
  double ramp = 0.0;
  if (j_max > 0.0)
  {
    ramp = a.norm() / j_max;
    v1 = v + 0.5 * a * ramp;
    b.displacement = v * ramp + a * (ramp * ramp / 3.0);
    b.distance = (v.norm() + a.norm() * ramp) * ramp;
  }
  const double speed = v1.norm();
  double stop;
  if (!(j_max > 0.0))
    stop = speed / a_max;
  else if (!(a_max > 0.0) || speed < a_max * a_max / j_max)
    stop = 2.0 * std::sqrt(speed / j_max);
  else
    stop = speed / a_max + a_max / j_max;
  // The stop's speed is symmetric about its middle: it covers half its start speed times its duration.
  b.duration = ramp + stop;
  b.distance += 0.5 * speed * stop;
  if (speed > 0.0)
    b.displacement += v1 * (0.5 * stop);
  return b;
}

/// A channel without bounds stopping uniformly within the other's duration T.
inline void stopWithin(const Eigen::Vector3d& v, double T, ReferenceBrake* b)
{
  b->distance = 0.5 * v.norm() * T;
  b->displacement = 0.5 * v * T;
}

/// The brake-and-go bound of a motion from a moving start (docs/timing.md "Start states and
/// replanning"): the test's own valid brake of each channel (referenceBrake) and the planner's
/// motion from rest at its stopping pose, times kDetourFactor: the planner serves the joined motion
/// up to 10 % beyond its own brake-and-go motion, whose brake may stop elsewhere
/// (curves/jerk_brake.h shares the jerk bound between two axes).
struct BrakeAndGo
{
  double duration = 0.0;
  double length = 0.0;  ///< |p| length + ρ · rotation length
};

constexpr double kDetourFactor = 1.3;

inline double chordLength(const TrajectoryRequest& r, const CurveFigures& f)
{
  const double rho = r.rotation_scale > 0.0 ? r.rotation_scale : 1.0;
  return f.length + (f.rotation_length > 0.0 ? rho * f.rotation_length : 0.0);
}

inline BrakeAndGo brakeAndGoBound(const TrajectoryRequest& request, const PlannerLimits& limits)
{
  const StartState& s = *request.start_state;
  ReferenceBrake lin = referenceBrake(s.velocity.linear, s.acceleration.linear, request.max_linear_acceleration,
                                      request.max_linear_jerk);
  ReferenceBrake ang = referenceBrake(s.velocity.angular, s.acceleration.angular, request.max_angular_acceleration,
                                      request.max_angular_jerk);
  if (!(request.max_linear_acceleration > 0.0) && !(request.max_linear_jerk > 0.0))
    stopWithin(s.velocity.linear, ang.duration, &lin);
  if (!(request.max_angular_acceleration > 0.0) && !(request.max_angular_jerk > 0.0))
    stopWithin(s.velocity.angular, lin.duration, &ang);
  const Pose<double> stop(Quaternion<double>(so3Exp<double>(ang.displacement) * s.pose.q), s.pose.p + lin.displacement);
  TrajectoryRequest rest = request;
  rest.start_state = StartState{ stop, Twist{}, Twist{} };
  const TrajectoryResult from_rest = generate(rest, limits);
  const double rho = request.rotation_scale > 0.0 ? request.rotation_scale : 1.0;
  BrakeAndGo b;
  b.duration = kDetourFactor * (std::max(lin.duration, ang.duration) + from_rest.duration);
  b.length = kDetourFactor * (lin.distance + rho * ang.distance + chordLength(request, from_rest.figures));
  return b;
}

/// Whether a served request is a moving start under a timing that replans by braking when the
/// joined motion is longer (time_optimal, constant_speed; docs/timing.md).
inline bool replansByBraking(const TrajectoryRequest& r)
{
  if (!r.start_state || (r.timing != "time_optimal" && r.timing != "constant_speed"))
    return false;
  const StartState& s = *r.start_state;
  return !(s.velocity.linear.isZero(0.0) && s.velocity.angular.isZero(0.0) && s.acceleration.linear.isZero(0.0) &&
           s.acceleration.angular.isZero(0.0));
}

/// A served motion from a moving start is no longer than the brake-and-go bound (duration, path).
inline void checkNoDetour(const TrajectoryRequest& request, const TrajectoryResult& result, const PlannerLimits& limits,
                          std::vector<Violation>& v)
{
  if (!replansByBraking(request))
    return;
  BrakeAndGo bound;
  try
  {
    bound = brakeAndGoBound(request, limits);
  }
  catch (const std::invalid_argument&)
  {
    return;  // no motion from rest at the start pose: no bound to hold it to
  }
  if (result.duration > bound.duration * (1.0 + 1e-9))
    v.push_back({ "detour duration", result.duration / bound.duration,
                  "duration " + num(result.duration) + " above the brake-and-go bound " + num(bound.duration) });
  const double length = chordLength(request, result.figures);
  if (length > bound.length * (1.0 + 1e-9) + 1e-12)
    v.push_back({ "detour length", length / bound.length,
                  "path length " + num(length) + " above the brake-and-go bound " + num(bound.length) });
}

/// A motion the closed-form timing serves (timing/geodesic_timing.h: a geodesic chain from rest
/// under time_optimal) against the general timing of the same path (jerk-limited with a jerk bound,
/// else time-optimal), run here directly: the served duration is the closed form's, never longer
/// than the general one, and, on a single stretch between two stops, at most 1 % shorter (the
/// general timing's tolerance) wherever one channel decides the profile. Only "never longer" is
/// checked where translation and rotation both move under jerk bounds (the general timing's window
/// may be longer than the double S's, docs/timing.md) and on chains of several stops (where the
/// grid found the general timing up to 3.5 % longer, on three waypoints at uneven times).
/// Returns whether the request took the closed form.
template <class G>
bool checkClosedForm(const ValidatedRequest& r, const TrajectoryResult& result, std::vector<Violation>& v)
{
  const std::shared_ptr<const Curve<G>> path = makeFamilyCurve<G>(r, waypointTimes(r)).curve;
  timing::RateBounds b;
  b.velocity = { r.max_linear_velocity, r.max_angular_velocity };
  b.acceleration = { r.max_linear_acceleration, r.max_angular_acceleration };
  b.jerk = { r.max_linear_jerk, r.max_angular_jerk };
  const auto closed = timing::makeGeodesicTimedCurve<G>(path, b);
  if (!closed)
    return false;
  const double exact = closed->endTime() - closed->startTime();
  if (!(std::abs(result.duration - exact) <= 1e-12 * exact))
    v.push_back({ "closed form duration", result.duration / exact,
                  "served " + num(result.duration) + " s, the closed form gives " + num(exact) + " s" });
  const bool jerk = b.jerk[0] > 0.0 || b.jerk[1] > 0.0;
  double general = 0.0;
  try
  {
    general = jerk ? timing::makeJerkLimitedCurve<G>(path, b)->endTime() - path->startTime() :
                     timing::makeTimeOptimalCurve<G>(path, b)->endTime() - path->startTime();
  }
  catch (const std::exception& e)
  {
    v.push_back({ "closed form: the general timing refuses", 0.0, e.what() });
    return true;
  }
  bool both_move = false;
  for (const timing::GeodesicRun& run : closed->profile().runs)
    both_move = both_move || (run.moves[0] && run.moves[1]);
  const bool one_stretch = closed->profile().runs.size() == 1;
  if (general < exact * (1.0 - 1e-9) || (one_stretch && !(jerk && both_move) && general > exact * 1.01))
    v.push_back({ "closed form against the general timing", general / exact,
                  "the general timing takes " + num(general) + " s, the closed form " + num(exact) + " s" });
  return true;
}

/// checkClosedForm for a served pose request from rest under time_optimal; whether it took the
/// closed form.
inline bool checkClosedFormOf(const TrajectoryRequest& request, const TrajectoryResult& result,
                              const PlannerLimits& limits, std::vector<Violation>& v)
{
  if (request.timing != "time_optimal" || request.start_state)
    return false;
  const ValidatedRequest r = validateRequest(request, limits);
  if (r.geometry == GeometryType::kScrew)
    return checkClosedForm<ScrewSe3>(r, result, v);
  return checkClosedForm<DoubleGeodesicSe3>(r, result, v);
}

/// The outcome of one request: served (with the invariants it broke) or refused (with its message).
struct Outcome
{
  bool served = false;
  std::string message;  ///< the refusal's message
  std::vector<Violation> violations;
  GoalCheck goal;  ///< the goal check of a served request (checkGoal)
  /// The served motion's recovery interval (a start above a bound; a goal of it exceeds the bound).
  double recovery_time = 0.0;
  bool closed_form = false;  ///< served by the closed-form timing of geodesic chains (checkClosedForm)
};

/// Whether a refusal of a request with an arm names where the arm cannot follow: a joint
/// ("joint 'elbow_joint' would pass its position limit ...") or a time along the motion ("the pose
/// at t = 1.5 s (position ...) is out of the arm's reach").
inline bool namesJointOrTime(const std::string& message)
{
  return message.find("joint '") != std::string::npos || message.find("t = ") != std::string::npos;
}

/// Runs one request through generate() (with the arm when one is given), the checker (with an arm
/// also checkJointInvariants) and, when served, the goal check. A refusal must be a
/// std::invalid_argument (the core's InterpolationError family) whose message names a request
/// field, or with an arm a joint or a time (namesJointOrTime); any other exception is a violation.
/// With an arm the brake-and-go bound (checkNoDetour: the Cartesian motion's, which the joint
/// limits may lengthen) and the closed form (checkClosedFormOf: the planner times an arm's motion
/// with its joint limits in the general timing) are not checked; without one the samples carry no
/// joints.
inline Outcome runAndCheck(const TrajectoryRequest& request, const PlannerLimits& limits,
                           const CheckOptions& options = CheckOptions(),
                           const std::shared_ptr<const arm::ArmModel>& arm = nullptr)
{
  Outcome out;
  try
  {
    const TrajectoryResult result = arm ? generate(request, limits, arm) : generate(request, limits);
    out.served = true;
    out.recovery_time = result.recovery_time;
    out.violations = checkInvariants(request, result, options);
    if (arm)
      checkJointInvariants(result, *arm, options, out.violations);
    else
    {
      checkNoDetour(request, result, limits, out.violations);
      out.closed_form = checkClosedFormOf(request, result, limits, out.violations);
      for (const TrajectorySample& s : result.samples)
        if (s.joint_position.size() + s.joint_velocity.size() + s.joint_acceleration.size() > 0)
        {
          out.violations.push_back({ "joints without an arm", 0.0, "a sample carries joint vectors" });
          break;
        }
    }
    try
    {
      out.goal = checkGoal(request, result, options, out.violations);
    }
    catch (const std::exception& e)
    {
      out.violations.push_back({ "goal exception", 0.0, e.what() });
    }
  }
  catch (const std::invalid_argument& e)
  {
    out.message = e.what();
    if (namedFields(out.message).empty() && !(arm && namesJointOrTime(out.message)))
      out.violations.push_back({ "refusal names no field", 0.0, out.message });
  }
  catch (const std::exception& e)
  {
    out.message = e.what();
    out.violations.push_back({ "exception not std::invalid_argument", 0.0, out.message });
  }
  catch (...)
  {
    out.message = "(non-standard exception)";
    out.violations.push_back({ "non-standard exception", 0.0, out.message });
  }
  return out;
}

}  // namespace test
}  // namespace se3_interpolation
