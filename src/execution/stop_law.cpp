#include "se3_interpolation/execution/stop_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace se3_interpolation
{
namespace
{
constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// The check's spacing (s): the 1 kHz at which a controller may sample the setpoint; candidates
/// are first checked at kCoarseCheckStep, which rejects most that fail for a fraction of the cost.
constexpr double kCheckStep = 1e-3;
constexpr double kCoarseCheckStep = 8e-3;
/// Path time over which the motion's acceleration is differenced for its jerk (s): far below the
/// motions' time scales (a goal's segments last milliseconds at least), far above the rounding of
/// their accelerations (~1e-16 relative: the difference is exact to ~1e-10 relative).
constexpr double kJerkStep = 1e-5;
/// Relative rounding allowed on a norm compared with its allowance (a line stopped at exactly A
/// computes |v| α = A to ~1e-16).
constexpr double kBoundRounding = 1e-6;
/// The rates' scale factors k = kScaleRatio^i and the delays 2^i ms (file comment of the header).
constexpr double kScaleRatio = 0.8;
constexpr int kScales = 32;
constexpr int kDelays = 17;  // up to 2^16 ms = 65 s
/// A stop longer than this (s), its own end apart, is not a candidate.
constexpr double kMaxStopSeconds = 60.0;
/// Points the search may check (each one to three evaluations of the motion, a few µs each): the
/// stop is computed while the motion plays on, so it must take milliseconds, not seconds.
constexpr long kMaxStopChecks = 20000;
/// Without a jerk bound: β = kUnboundedJerkShape α², the acceleration ramping in α/β = 1/(10 α).
constexpr double kUnboundedJerkShape = 10.0;
/// Where no bounded part moves at the start, the ramp's length is about stop_time: T = 1.1/α₀.
constexpr double kRampLengthPerAlpha = 1.1;

/// The law at one instant: advance u = τ − τ_c, rate r = τ̇, its derivatives ṙ and r̈.
struct LawPoint
{
  double u = 0.0, r = 1.0, rd = 0.0, rdd = 0.0;
};

/// A bounded part of the played motion (linear or angular).
struct Part
{
  bool angular = false;
  double acceleration_bound = 0.0;
  double jerk_bound = 0.0;

  const Eigen::Vector3d& velocity(const TrajectorySample& s) const
  {
    return angular ? s.velocity.angular : s.velocity.linear;
  }
  const Eigen::Vector3d& acceleration(const TrajectorySample& s) const
  {
    return angular ? s.acceleration.angular : s.acceleration.linear;
  }
};

StopLaw::Ramp makeRamp(double delay, double alpha, double beta)
{
  StopLaw::Ramp ramp;
  ramp.delay = delay;
  ramp.alpha = alpha;
  ramp.beta = beta;
  if (alpha * alpha >= beta)
  {
    ramp.t1 = 1.0 / std::sqrt(beta);
    ramp.t2 = 0.0;
  }
  else
  {
    ramp.t1 = alpha / beta;
    ramp.t2 = 1.0 / alpha - alpha / beta;
  }
  ramp.rest = delay + 2.0 * ramp.t1 + ramp.t2;
  return ramp;
}

/// The law in phase `phase` (1: τ̈ falling, 2: plateau, 3: rising) at s s after the phase's start.
LawPoint phasePoint(const StopLaw::Ramp& ramp, int phase, double s)
{
  const double b = ramp.beta, t1 = ramp.t1, t2 = ramp.t2;
  if (phase == 1)
    return { ramp.delay + s - b * s * s * s / 6.0, 1.0 - 0.5 * b * s * s, -b * s, -b };
  const double r1 = 1.0 - 0.5 * b * t1 * t1, rd1 = -b * t1, u1 = ramp.delay + t1 - b * t1 * t1 * t1 / 6.0;
  if (phase == 2)
    return { u1 + r1 * s + 0.5 * rd1 * s * s, r1 + rd1 * s, rd1, 0.0 };
  const double r2 = r1 + rd1 * t2, u2 = u1 + r1 * t2 + 0.5 * rd1 * t2 * t2;
  return { u2 + r2 * s + 0.5 * rd1 * s * s + b * s * s * s / 6.0, std::max(r2 + rd1 * s + 0.5 * b * s * s, 0.0),
           std::min(rd1 + b * s, 0.0), b };
}

/// The law at t s after the stop's start, before the ramp's end.
LawPoint rampPoint(const StopLaw::Ramp& ramp, double t)
{
  if (t < ramp.delay)
    return { t, 1.0, 0.0, 0.0 };
  double s = t - ramp.delay;
  if (s < ramp.t1)
    return phasePoint(ramp, 1, s);
  s -= ramp.t1;
  if (s < ramp.t2)
    return phasePoint(ramp, 2, s);
  return phasePoint(ramp, 3, std::min(s - ramp.t2, ramp.t1));
}

/// Checks candidates against the allowances of the header's file comment.
class Checker
{
public:
  Checker(const StoppedPath& path, std::vector<Part> parts) : path_(path), parts_(std::move(parts)) {}

  bool exhausted() const { return checks_ >= kMaxStopChecks; }

  /// Whether `ramp` keeps the allowances at points `step` s apart (and at the ramp's switches);
  /// where it reaches the motion's end first, ramp->rest becomes that instant.
  bool passes(StopLaw::Ramp* ramp, double step)
  {
    const double lengths[3] = { ramp->t1, ramp->t2, ramp->t1 };
    double start = ramp->delay;
    double previous = start;
    for (int phase = 1; phase <= 3; ++phase)
    {
      const double length = lengths[phase - 1];
      if (length <= 0.0)
        continue;
      const int n = std::max(1, static_cast<int>(std::ceil(length / step)));
      for (int i = 0; i <= n; ++i)
      {
        const double s = length * i / n;
        const LawPoint p = phasePoint(*ramp, phase, s);
        if (p.u >= path_.end_advance)
        {
          ramp->rest = reachesEnd(*ramp, previous, start + s);
          return true;
        }
        if (exhausted() || !within(p))
          return false;
        previous = start + s;
      }
      start += length;
    }
    return true;
  }

private:
  /// The first instant in [lo, hi] at which the ramp's advance reaches the motion's end.
  double reachesEnd(const StopLaw::Ramp& ramp, double lo, double hi) const
  {
    for (int i = 0; i < 60 && hi - lo > 1e-12; ++i)
    {
      const double mid = 0.5 * (lo + hi);
      (rampPoint(ramp, mid).u >= path_.end_advance ? hi : lo) = mid;
    }
    return hi;
  }

  bool within(const LawPoint& p)
  {
    ++checks_;
    bool moving = true;
    const TrajectorySample s = path_.at(p.u, &moving);
    std::optional<TrajectorySample> before, after;
    for (const Part& part : parts_)
    {
      const Eigen::Vector3d& v = part.velocity(s);
      const Eigen::Vector3d& a = part.acceleration(s);
      if (part.acceleration_bound > 0.0)
      {
        const double allowed = std::max(part.acceleration_bound, a.norm()) * (1.0 + kBoundRounding);
        if ((a * (p.r * p.r) + v * p.rd).norm() > allowed)
          return false;
      }
      if (part.jerk_bound > 0.0)
      {
        if (!before)
        {
          checks_ += 2;
          before = path_.at(p.u - kJerkStep, &moving);
          after = path_.at(p.u + kJerkStep, &moving);
        }
        const Eigen::Vector3d j = (part.acceleration(*after) - part.acceleration(*before)) / (2.0 * kJerkStep);
        const double allowed = std::max(part.jerk_bound, j.norm()) * (1.0 + kBoundRounding);
        if ((j * (p.r * p.r * p.r) + 3.0 * p.r * p.rd * a + v * p.rdd).norm() > allowed)
          return false;
      }
    }
    return true;
  }

  const StoppedPath& path_;
  std::vector<Part> parts_;
  long checks_ = 0;
};

std::vector<Part> partsOf(const StopLimits& l)
{
  std::vector<Part> parts;
  if (l.max_linear_acceleration > 0.0 || l.max_linear_jerk > 0.0)
    parts.push_back({ false, l.max_linear_acceleration, l.max_linear_jerk });
  if (l.max_angular_acceleration > 0.0 || l.max_angular_jerk > 0.0)
    parts.push_back({ true, l.max_angular_acceleration, l.max_angular_jerk });
  return parts;
}

/// α₀ and β₀ of the header's file comment, from the start state `s`.
std::pair<double, double> baseRates(const TrajectorySample& s, const std::vector<Part>& parts, double stop_time)
{
  double alpha = kInfinity, beta = kInfinity;
  for (const Part& part : parts)
  {
    const double speed = part.velocity(s).norm();
    if (!(speed > 0.0))
      continue;
    if (part.acceleration_bound > 0.0)
      alpha = std::min(alpha, part.acceleration_bound / speed);
    if (part.jerk_bound > 0.0)
      beta = std::min(beta, part.jerk_bound / speed);
  }
  if (std::isinf(alpha) && std::isinf(beta))
    alpha = kRampLengthPerAlpha / (stop_time > 0.0 && std::isfinite(stop_time) ? stop_time : 1.0);
  if (std::isinf(beta))
    beta = kUnboundedJerkShape * alpha * alpha;
  return { alpha, beta };
}
}  // namespace

PathPoint smoothRamp(double T, double t)
{
  const double sigma = std::min(std::max(t / T, 0.0), 1.0);
  PathPoint p;
  p.rate = 1.0 - 3.0 * sigma * sigma + 2.0 * sigma * sigma * sigma;
  p.rate_dot = sigma < 1.0 ? 6.0 * (sigma * sigma - sigma) / T : 0.0;
  p.advance = T * (sigma - sigma * sigma * sigma + 0.5 * sigma * sigma * sigma * sigma);
  return p;
}

StopLaw::StopLaw(const StoppedPath& path, const StopLimits& limits)
{
  const std::vector<Part> parts = partsOf(limits);
  bool moving = true;
  const auto [alpha0, beta0] = baseRates(path.at(0.0, &moving), parts, limits.stop_time);
  const double end = path.end_advance;
  std::vector<Ramp> candidates;
  Ramp slowest;
  for (int i = 0; i < kScales; ++i)
  {
    const double k = std::pow(kScaleRatio, i);
    for (int d = 0; d <= kDelays; ++d)
    {
      const double delay = d == 0 ? 0.0 : 1e-3 * std::ldexp(1.0, d - 1);
      const Ramp ramp = makeRamp(delay, k * alpha0, k * beta0);
      if (delay < end && ramp.rest <= kMaxStopSeconds)
        candidates.push_back(ramp);
      if (d == 0 && ramp.rest <= kMaxStopSeconds)
        slowest = ramp;
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Ramp& x, const Ramp& y) { return x.rest < y.rest; });
  Checker checker(path, parts);
  for (Ramp& candidate : candidates)
  {
    if (candidate.rest >= end || checker.exhausted())
      break;
    if (checker.passes(&candidate, kCoarseCheckStep) && checker.passes(&candidate, kCheckStep))
    {
      ramp_ = candidate;
      return;
    }
  }
  if (std::isfinite(end))
  {
    // The motion's own course to its end (at rest, as a goal's): nothing added to it.
    ramp_ = Ramp();
    ramp_.delay = end;
    ramp_.rest = end;
    return;
  }
  ramp_ = slowest.rest > 0.0 ? slowest : makeRamp(0.0, alpha0, beta0);
}

double StopLaw::restTime() const
{
  return ramp_.rest;
}

PathPoint StopLaw::at(double t) const
{
  PathPoint p;
  if (t >= ramp_.rest)
  {
    p.advance = ramp_.rest <= ramp_.delay ? ramp_.rest : rampPoint(ramp_, ramp_.rest).u;
    return p;
  }
  const LawPoint l = rampPoint(ramp_, t);
  p.advance = l.u;
  p.rate = l.r;
  p.rate_dot = l.rd;
  return p;
}

}  // namespace se3_interpolation
