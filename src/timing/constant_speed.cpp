// The constant-speed timing (timing/constant_speed.h): the solve (the ramps' shortest lengths and
// their fitting to the bounds, the refusals that name what to change) and the public functions. The
// solver is declared in constant_speed_detail.h; its table of S is built in constant_speed_table.cpp
// and its dense check and figures are in constant_speed_check.cpp.
#include "se3_interpolation/timing/constant_speed.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "constant_speed_detail.h"
#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace timing
{
namespace constant_speed_detail
{
ConstantSpeedProfile ConstantSpeedSolver::solve()
{
  p_.speed = options_.speed;
  p_.t0 = path_.start();
  requireArguments();
  buildTable();
  p_.length = p_.sigma.back();
  if (options_.continue_start)
  {
    // σ̇ = g ṡ and σ̈ = g′ṡ² + g s̈ at ṡ = 1, s̈ = 0.
    const ChordSpeed c = chordSpeed(path_.jet(p_.s.front(), Side::kRight), options_.metric);
    p_.start_speed = c.g;
    p_.start_acceleration = c.dg;
  }
  // The straight line's shortest ramps under the ramps' bounds (file comment); from a moving start,
  // for the change of speed it makes (at least a millionth of the cruise, so that T_u > 0).
  p_.ramp_up = std::max(shortestRamp(std::abs(p_.speed - p_.start_speed)), 1e-6 * p_.length / p_.speed);
  p_.ramp_down = shortestRamp(p_.speed);
  requireRoomForRamps();
  // The speed held between the shortest ramps (lengthening them only shortens the cruise).
  const double shortest_a = arcA(), shortest_b = arcB();
  Excess cruise = check(shortest_a, shortest_b, true, true);
  requireBoundsHeld(cruise);
  for (const bool up : { true, false })
    fitRamp(up);
  // The figures of the motion as fitted: the cruise checked again only where the ramps grew.
  if (arcA() != shortest_a || arcB() != shortest_b)
    cruise = check(arcA(), arcB(), true, true);
  setFigures({ check(0.0, arcA(), false, true), cruise, check(arcB(), p_.length, false, true) });
  return std::move(p_);
}

/// The shortest ramp that changes the chord speed by dv on a straight line (file comment).
double ConstantSpeedSolver::shortestRamp(double dv) const
{
  double ramp = 0.0;
  const double a = rampBound(bounds_.acceleration);
  const double j = rampBound(bounds_.jerk);
  if (a > 0.0)
    ramp = kRampAccelerationPeak * dv / a;
  if (j > 0.0)
    ramp = std::max(ramp, std::sqrt(kRampJerkPeak * dv / j));
  return ramp;
}

/// min(a_lin, ρ a_ang) over the bounds given (ρ = √w_ang), 0 when none is.
double ConstantSpeedSolver::rampBound(const std::array<double, 2>& b) const
{
  double r = std::numeric_limits<double>::infinity();
  if (b[0] > 0.0)
    r = b[0];
  if (b[1] > 0.0 && options_.metric[1] > 0.0)
    r = std::min(r, std::sqrt(options_.metric[1]) * b[1]);
  return std::isfinite(r) ? r : 0.0;
}

void ConstantSpeedSolver::requireArguments() const
{
  if (!(std::isfinite(options_.speed) && options_.speed > 0.0))
    throw InvalidInputError("speed: " + formatNumber(options_.speed) +
                            " (timing 'constant_speed' needs the chord speed to hold: a finite number above 0, m/s)");
  if (!(bounds_.acceleration[0] > 0.0 || bounds_.acceleration[1] > 0.0))
    throw InvalidInputError(
        "max_linear_acceleration: timing 'constant_speed' needs it to bound its start and stop "
        "ramps (m/s^2, above 0)");
}

void ConstantSpeedSolver::requireRoomForRamps() const
{
  const double needed = p_.rampUpLength() + p_.rampDownLength();
  if (needed > p_.length)
    throw InvalidInputError("speed: the path is " + formatNumber(p_.length) +
                            " long (chord length), shorter than "
                            "its start and stop ramps to " +
                            formatNumber(p_.speed) + " m/s (" + formatNumber(needed) +
                            "); lower the speed or raise the acceleration and jerk bounds");
}

/// Refuses a speed whose cruise breaks a bound (file comment), naming the bound.
void ConstantSpeedSolver::requireBoundsHeld(const Excess& e) const
{
  for (int k = 0; k < 3; ++k)
    if (e.ratio[k] > 1.0 + kBreakTolerance)
      refuse(k, e);
}

/// Lengthens one ramp until every bound holds on it (file comment).
void ConstantSpeedSolver::fitRamp(bool up)
{
  const bool moving = up && options_.continue_start;
  for (int pass = 0; pass < kMaxRampPasses; ++pass)
  {
    requireRoomForRamps();
    if (moving)
      requireRisingRamp();
    const Excess e = up ? check(0.0, arcA(), false, false) : check(arcB(), p_.length, false, false);
    if (moving && std::max({ e.ratio[0], e.ratio[1], e.ratio[2] }) > 1.0 + kBreakTolerance &&
        pass + 1 == kMaxRampPasses)
      refuseStart(e);
    if (e.ratio[0] > 1.0 + kBreakTolerance)
      moving ? refuseStart(e) : refuse(0, e);
    const double f = std::max({ 1.0, std::sqrt(e.ratio[1]), std::cbrt(e.ratio[2]) });
    if (f <= 1.0 + kBreakTolerance)
      return;
    (up ? p_.ramp_up : p_.ramp_down) *= f * (1.0 + 1e-3);
  }
  if (moving)
    throw InvalidInputError("start_state: the ramp from its chord speed " + formatNumber(p_.start_speed) + " to " +
                            formatNumber(p_.speed) + " m/s keeps exceeding the acceleration or jerk bounds");
  throw InvalidInputError(std::string("speed: its ") + (up ? "start" : "stop") + " ramp to " + formatNumber(p_.speed) +
                          " m/s keeps exceeding the acceleration or jerk bounds (the "
                          "path bends too sharply there); lower the speed");
}

/// From a moving start, the ramp up's chord speed v_0 + (V − v_0) P′(τ) + a_0 T_u H₁(τ) must stay
/// above 0 (the motion would turn back along the path): checked on 256 steps of the quintic.
void ConstantSpeedSolver::requireRisingRamp() const
{
  const double v0 = p_.start_speed, dv = p_.speed - p_.start_speed, a0t = p_.start_acceleration * p_.ramp_up;
  for (int i = 1; i <= kRampVelocitySteps; ++i)
  {
    const double tau = static_cast<double>(i) / kRampVelocitySteps;
    if (!(v0 + dv * rampSlope(tau) + a0t * startSlope(tau) > 0.0))
      throw InvalidInputError("start_state: its chord acceleration " + formatNumber(p_.start_acceleration) +
                              " m/s^2 would turn the motion back along the path before it reaches " +
                              formatNumber(p_.speed) +
                              " m/s; replan when it brakes less, or use timing "
                              "'time_optimal'");
  }
}

/// A moving start whose ramp breaks a bound the ramp's length cannot bring back (the start state
/// itself beyond one, or braking from it): refused naming start_state.
void ConstantSpeedSolver::refuseStart(const Excess& e) const
{
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (e.ratio[i] > e.ratio[k])
      k = i;
  const char* const* names = k == 0 ? kVelocityName : k == 1 ? kAccelerationName : kJerkName;
  throw InvalidInputError("start_state: the ramp from its chord speed " + formatNumber(p_.start_speed) + " to " +
                          formatNumber(p_.speed) + " m/s takes " + formatNumber(e.ratio[k]) + " times " +
                          names[e.channel[k]] + " at path time " + formatNumber(e.where[k]) +
                          " s (timing 'constant_speed' does not recover from a start beyond the bounds); use "
                          "timing 'time_optimal', or replan from a slower state");
}

void ConstantSpeedSolver::refuse(int k, const Excess& e) const
{
  const char* const* names = k == 0 ? kVelocityName : k == 1 ? kAccelerationName : kJerkName;
  const char* what = k == 0 ? "speed" : k == 1 ? "acceleration (the bend's centripetal share)" : "jerk";
  throw InvalidInputError(std::string(names[e.channel[k]]) + ": holding the chord speed " + formatNumber(p_.speed) +
                          " m/s takes " + formatNumber(e.ratio[k]) + " times this bound's " + what + " at path time " +
                          formatNumber(e.where[k]) + " s; lower the speed or raise the bound");
}
}  // namespace constant_speed_detail

namespace
{
/// Bisection steps of the inverse maps (to rounding).
constexpr int kBisectionSteps = 100;
}  // namespace

using constant_speed_detail::quinticValue;

std::size_t ConstantSpeedProfile::intervalAt(double arc, Side side) const
{
  const std::size_t n = quintic.size();
  const auto it = side == Side::kRight ? std::upper_bound(sigma.begin(), sigma.end(), arc) :
                                         std::lower_bound(sigma.begin(), sigma.end(), arc);
  const std::ptrdiff_t k = (it - sigma.begin()) - 1;
  return static_cast<std::size_t>(
      std::min<std::ptrdiff_t>(std::max<std::ptrdiff_t>(k, 0), static_cast<std::ptrdiff_t>(n) - 1));
}

double ConstantSpeedProfile::timeAtArcLength(double arc) const
{
  const double a = rampUpLength(), b = length - rampDownLength();
  if (arc <= 0.0)
    return t0;
  if (arc >= length)
    return endTime();
  if (arc >= a && arc <= b)
    return windowStart() + (arc - a) / speed;
  // σ is increasing over each ramp (the ramp up's speed is checked to stay positive): bisection
  // for the ramp's fraction.
  const bool up = arc < a;
  const auto reached = [&](double tau) {
    return up ? arcLength(t0 + tau * ramp_up) < arc : length - speed * ramp_down * rampShape(tau) > arc;
  };
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < kBisectionSteps && hi - lo > 0.0; ++i)
  {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi)
      break;
    (reached(mid) ? lo : hi) = mid;
  }
  const double tau = 0.5 * (lo + hi);
  return up ? t0 + tau * ramp_up : endTime() - tau * ramp_down;
}

double ConstantSpeedProfile::timeAt(double path_parameter) const
{
  if (path_parameter <= s.front())
    return t0;
  if (path_parameter >= s.back())
    return endTime();
  const auto it = std::upper_bound(s.begin(), s.end(), path_parameter);
  const std::size_t k = std::min(static_cast<std::size_t>(it - s.begin()) - 1, quintic.size() - 1);
  double lo = 0.0, hi = sigma[k + 1] - sigma[k];
  for (int i = 0; i < kBisectionSteps; ++i)
  {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi)
      break;
    (quinticValue(quintic[k], mid) < path_parameter ? lo : hi) = mid;
  }
  return timeAtArcLength(sigma[k] + 0.5 * (lo + hi));
}

std::vector<double> ConstantSpeedProfile::breakpoints() const
{
  std::vector<double> b;
  b.reserve(check_sigma.size() + 2);
  for (double arc : check_sigma)
    b.push_back(timeAtArcLength(arc));
  b.push_back(windowStart());
  b.push_back(windowEnd());
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

ConstantSpeedProfile constantSpeedProfile(const JerkPathModel& path, const RateBounds& bounds,
                                          const ConstantSpeedOptions& options)
{
  return constant_speed_detail::ConstantSpeedSolver(path, bounds, options).solve();
}

}  // namespace timing
}  // namespace se3_interpolation
