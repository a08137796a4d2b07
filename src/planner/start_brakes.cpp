// The brakes of a moving start state (src/planner/start_state.cpp's braked candidate): B1, B2
// without jerk bounds (curves/braked_start.h) and the jerk brake (curves/jerk_brake.h), designed so
// that its rates, measured on exact third-order jets, hold every bound.
#include "start_brakes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace planner_detail
{
namespace
{
/// Samples per piece of a jerk brake (between its switches) at which its rates are evaluated
/// from exact third-order jets.
constexpr int kBrakeSamplesPerPiece = 64;
/// Scalings of the jerk brake's per-axis bounds tried (each by kBrakeScaleStep) before the start is
/// left without one: the rotation's rates exceed the axes' by terms of the angle it turns.
constexpr int kBrakeScalings = 32;
/// The most a scaling keeps of the bounds (at least 1 % off), and the margin beyond the measured
/// excess it takes off (a rotation's rates do not scale exactly with its bounds).
constexpr double kBrakeScaleStep = 0.99;
constexpr double kBrakeScaleMargin = 1e-3;
/// Steps of the along-axis share of the acceleration bound (curves/jerk_brake.h), down to the
/// smallest before none (the share the sideways acceleration leaves at all times).
constexpr double kShareStep = 0.6;
/// The ramp time of a channel without a jerk bound when the other channel's gives none (s).
constexpr double kDefaultRampTime = 0.1;
constexpr double kSmallestShare = 0.02;

/// The rates of a jerk brake at τ: |v|, |a|, |j| per channel.
std::array<std::array<double, 2>, 3> brakeRates(const JerkBrake& b, double tau, Side side)
{
  const timing::Kinematics3 k = timing::kinematics3FromJet(b.at(Jet<3>::variable(tau), side));
  return { { { k.velocity.linear.norm(), k.velocity.angular.norm() },
             { k.acceleration.linear.norm(), k.acceleration.angular.norm() },
             { k.jerk.linear.norm(), k.jerk.angular.norm() } } };
}

/// The jerk brake's rates at kBrakeSamplesPerPiece + 1 points of every piece (a start within the
/// bounds: a start beyond one has no jerk brake, brakedCandidate): its figures and whether it holds
/// every bound.
struct JerkBrakeCheck
{
  BrakeFigures figures;
  bool within = true;
  /// Per channel, the largest ratio of a rate to its bound where it must hold (velocity,
  /// acceleration, jerk; 0 without a bound): an acceleration above its bound is helped by a smaller
  /// along-axis share, a jerk (or an acceleration with no share left) by lower bounds; a velocity
  /// by neither.
  std::array<std::array<double, 3>, 2> worst{};
  /// Per rate (velocity, acceleration, jerk) and channel: the samples on either side of its
  /// largest sample, between which refineBrakePeaks searches its maximum.
  std::array<std::array<std::pair<double, double>, 2>, 3> peak_span{};
};

/// Iterations of the golden-section search of a peak between two samples: (0.618)^40 of their span.
constexpr int kPeakSearchIterations = 40;

/// The figures' peaks of a jerk brake, each searched between the samples around its largest sample
/// (golden section: the rates are smooth within a piece), so that no reported peak is below the
/// motion's between the samples.
void refineBrakePeaks(const JerkBrake& b, JerkBrakeCheck* check)
{
  BrakeFigures& f = check->figures;
  std::array<double, 2>* peaks[3] = { &f.max_speed, &f.max_acceleration, &f.max_jerk };
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int order = 0; order < 3; ++order)
    for (int c = 0; c < 2; ++c)
    {
      double lo = check->peak_span[order][c].first;
      double hi = check->peak_span[order][c].second;
      const auto rate = [&](double t) { return brakeRates(b, t, Side::kRight)[order][c]; };
      double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
      double f1 = rate(x1), f2 = rate(x2);
      for (int k = 0; k < kPeakSearchIterations && hi > lo; ++k)
      {
        if (f1 < f2)
        {
          lo = x1;
          x1 = x2;
          f1 = f2;
          x2 = lo + ratio * (hi - lo);
          f2 = rate(x2);
        }
        else
        {
          hi = x2;
          x2 = x1;
          f2 = f1;
          x1 = hi - ratio * (hi - lo);
          f1 = rate(x1);
        }
      }
      (*peaks[order])[c] = std::max({ (*peaks[order])[c], f1, f2 });
    }
}

JerkBrakeCheck checkJerkBrake(const ValidatedRequest& r, const JerkBrake& b)
{
  const std::array<std::array<double, 2>, 3> bounds = { { { r.max_linear_velocity, r.max_angular_velocity },
                                                          { r.max_linear_acceleration, r.max_angular_acceleration },
                                                          { r.max_linear_jerk, r.max_angular_jerk } } };
  std::vector<double> ends{ 0.0 };
  for (double x : b.breakpoints())
    ends.push_back(x);
  ends.push_back(b.stopTime());
  JerkBrakeCheck check;
  BrakeFigures& f = check.figures;
  std::array<double, 2>* peaks[3] = { &f.max_speed, &f.max_acceleration, &f.max_jerk };
  std::array<std::array<double, 2>, 3> previous{};
  double previous_tau = 0.0;
  for (std::size_t piece = 0; piece + 1 < ends.size(); ++piece)
    for (int k = 0; k <= kBrakeSamplesPerPiece; ++k)
    {
      const double step = (ends[piece + 1] - ends[piece]) / kBrakeSamplesPerPiece;
      const double tau = ends[piece] + step * k;
      const auto rates = brakeRates(b, tau, k == kBrakeSamplesPerPiece ? Side::kLeft : Side::kRight);
      for (int c = 0; c < 2; ++c)
        for (int order = 0; order < 3; ++order)
        {
          if (rates[order][c] > (*peaks[order])[c])
          {
            (*peaks[order])[c] = rates[order][c];
            check.peak_span[order][c] = { std::max(ends[piece], tau - step), std::min(ends[piece + 1], tau + step) };
          }
          const double bound = bounds[order][c];
          if (!(bound > 0.0))
            continue;
          check.worst[c][order] = std::max(check.worst[c][order], rates[order][c] / bound);
          check.within = check.within && rates[order][c] <= bound * (1.0 + kRateTolerance);
        }
      const double dt = tau - previous_tau;
      if (dt > 0.0)
      {
        f.length += 0.5 * dt * (rates[0][0] + previous[0][0]);
        f.rotation_length += 0.5 * dt * (rates[0][1] + previous[0][1]);
        f.energy += 0.5 * dt * (rates[1][0] * rates[1][0] + previous[1][0] * previous[1][0]) +
                    0.5 * dt * r.rotation_scale * r.rotation_scale *
                        (rates[1][1] * rates[1][1] + previous[1][1] * previous[1][1]);
      }
      previous = rates;
      previous_tau = tau;
    }
  return check;
}

/// The jerk brake of the start state within every bound (curves/jerk_brake.h): the along-axis share
/// of the acceleration bound lowered towards what the sideways acceleration leaves of it while an
/// acceleration bound fails, every bound scaled down while a jerk bound (or, with no share left,
/// an acceleration bound) fails, until the measured rates hold them. std::nullopt when no channel
/// with a bound moves, or none of these keeps every bound (a start within a velocity bound whose
/// forward acceleration carries it past the bound, or a rotation whose ω₀ × ω̇₀ alone exceeds the
/// jerk bound).
/// The bounds a jerk brake is designed with: the request's, and for a channel without a jerk bound
/// (while the other has one) a jerk that ramps its acceleration bound in the other channel's ramp
/// time A/J (its acceleration stays continuous, as the jerk-limited timing keeps it), and for a
/// channel with neither bound the acceleration that stops it about when the other stops.
std::pair<std::array<double, 2>, std::array<double, 2>> brakeDesignBounds(const ValidatedRequest& r)
{
  const StartState& s = *r.start_state;
  std::array<double, 2> a = { r.max_linear_acceleration, r.max_angular_acceleration };
  std::array<double, 2> j = { r.max_linear_jerk, r.max_angular_jerk };
  const double speed[2] = { s.velocity.linear.norm(), s.velocity.angular.norm() };
  const double accel[2] = { s.acceleration.linear.norm(), s.acceleration.angular.norm() };
  for (int c = 0; c < 2; ++c)
  {
    const int o = 1 - c;
    if (j[c] > 0.0 || !(j[o] > 0.0))
      continue;
    double ramp = a[o] > 0.0 ? a[o] / j[o] : std::sqrt(speed[o] / j[o]);
    if (!(ramp > 0.0) || !std::isfinite(ramp))
      ramp = kDefaultRampTime;
    if (!(a[c] > 0.0))
    {
      const double stop = std::max(JerkStop(speed[o], 0.0, a[o], j[o]).stopTime(), ramp);
      a[c] = std::max(accel[c], 2.0 * speed[c] / stop);
    }
    j[c] = a[c] / ramp;
  }
  return { a, j };
}

std::optional<std::pair<JerkBrake, BrakeFigures>> jerkBrakeWithin(const ValidatedRequest& r,
                                                                  const std::array<StopDesign, 2>& design)
{
  const StartState& s = *r.start_state;
  const auto [a_max, j_max] = brakeDesignBounds(r);
  std::array<double, 2> scale = { 1.0, 1.0 };
  std::array<double, 2> share = { 1.0, 1.0 };
  for (int attempt = 0; attempt < kBrakeScalings; ++attempt)
  {
    const JerkBrake b = makeJerkBrake(s.pose, s.velocity, s.acceleration, a_max, j_max, scale, share, design);
    if (!(b.stopTime() > 0.0) || !std::isfinite(b.stopTime()))
      return std::nullopt;
    JerkBrakeCheck check = checkJerkBrake(r, b);
    if (check.within)
    {
      refineBrakePeaks(b, &check);
      return std::make_pair(b, check.figures);
    }
    for (int c = 0; c < 2; ++c)
    {
      const std::array<double, 3>& w = check.worst[c];
      if (w[0] > 1.0 + kRateTolerance)
        return std::nullopt;
      if (w[1] > 1.0 + kRateTolerance && share[c] > 0.0)
        share[c] = share[c] > kSmallestShare ? share[c] * kShareStep : 0.0;
      else if (w[1] > 1.0 + kRateTolerance || w[2] > 1.0 + kRateTolerance)
        scale[c] *= std::min(kBrakeScaleStep, 1.0 / (std::max(w[1], w[2]) * (1.0 + kBrakeScaleMargin)));
    }
  }
  return std::nullopt;
}
}  // namespace

/// The stop of the start state without jerk bounds (curves/braked_start.h, B1, B2): each moving
/// channel decelerates at its acceleration bound; a channel without one stops when the bounded
/// ones do. std::nullopt when no channel with an acceleration bound moves.
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

/// B1, B2's figures in closed form: speeds falling from the start's, constant decelerations, the
/// start's acceleration at t = 0; every bound holds once each channel that exceeded its velocity
/// bound is within it.
BrakeFigures brakeFigures(const ValidatedRequest& r, const BrakeToRest& brake)
{
  BrakeFigures f;
  const double rho = r.rotation_scale;
  f.length = brake.linear.distance();
  f.rotation_length = brake.angular.distance();
  f.max_speed = { brake.linear.speed, brake.angular.speed };
  f.max_acceleration = { std::max(brake.linear.deceleration, brake.start_acceleration.linear.norm()),
                         std::max(brake.angular.deceleration, brake.start_acceleration.angular.norm()) };
  f.energy = brake.linear.deceleration * brake.linear.deceleration * brake.linear.stopTime() +
             rho * rho * brake.angular.deceleration * brake.angular.deceleration * brake.angular.stopTime();
  const double velocity_bounds[2] = { r.max_linear_velocity, r.max_angular_velocity };
  const ChannelBrake* channels[2] = { &brake.linear, &brake.angular };
  for (int c = 0; c < 2; ++c)
    if (velocity_bounds[c] > 0.0 && channels[c]->speed > velocity_bounds[c])
      f.recovery = std::max(f.recovery, (channels[c]->speed - velocity_bounds[c]) / channels[c]->deceleration);
  return f;
}

/// The jerk brakes to try (curves/jerk_brake.h): the fastest of both designs per channel that
/// holds every bound (jerkBrakeWithin), and the acceleration ramped first in both channels (the
/// stop along the velocity left, whose stopping pose the braked motion may prefer).
std::vector<std::pair<JerkBrake, BrakeFigures>> jerkBrakes(const ValidatedRequest& r)
{
  std::optional<std::pair<JerkBrake, BrakeFigures>> best;
  std::optional<std::pair<JerkBrake, BrakeFigures>> ramp;
  for (StopDesign linear : { StopDesign::kSplit, StopDesign::kRamp })
    for (StopDesign angular : { StopDesign::kSplit, StopDesign::kRamp })
    {
      auto brake = jerkBrakeWithin(r, { linear, angular });
      if (brake && linear == StopDesign::kRamp && angular == StopDesign::kRamp)
        ramp = brake;
      if (brake && (!best || brake->first.stopTime() < best->first.stopTime()))
        best = std::move(brake);
    }
  std::vector<std::pair<JerkBrake, BrakeFigures>> brakes;
  if (best)
    brakes.push_back(*best);
  if (ramp && best && ramp->first.stopTime() != best->first.stopTime())
    brakes.push_back(*ramp);
  return brakes;
}
}  // namespace planner_detail
}  // namespace se3_interpolation
