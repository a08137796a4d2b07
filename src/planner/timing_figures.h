// The bounds of a request and the figures of its timed motion (planner.cpp's private part): the
// uniform stretch that meets the bounds (docs/timing.md), the corners and acceleration jumps it
// refuses, the peak jerk it divides by k³, the six bounds handed to the timings, the figures of a
// time-optimal or jerk-limited motion, and the lengths and own-clock figures of a path (a geodesic
// chain's in closed form).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/request.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/constant_speed.h"
#include "se3_interpolation/timing/geodesic_timing.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/jerk_peaks.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "joint_space.h"

namespace se3_interpolation
{
namespace planner_detail
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
  auto jerk = [&bind](double peak, double bound, const char* field) {
    if (bound > 0.0)
      bind(std::cbrt(peak / bound), field);
  };
  jerk(f.max_linear_jerk, r.max_linear_jerk, "max_linear_jerk");
  jerk(f.max_angular_jerk, r.max_angular_jerk, "max_angular_jerk");
  return k;
}

template <class Space>
bool hasJerkBound(const BasicValidatedRequest<Space>& r)
{
  return r.max_linear_jerk > 0.0 || r.max_angular_jerk > 0.0;
}

/// `timing()`, the jerk-limited timing; where it serves only the arm's jerk limits (no Cartesian
/// jerk bound) its refusals say so, since the request does not name a jerk. The work limit's
/// refusal passes unchanged.
template <class Space, class Timing>
auto explainingArmJerk(const BasicValidatedRequest<Space>& r, Timing&& timing) -> decltype(timing())
{
  if (hasJerkBound(r))
    return timing();
  const std::string why = " (the jerk-limited timing, which holds the arm's joint jerk limits)";
  try
  {
    return timing();
  }
  catch (const LimitExceededError&)
  {
    throw;
  }
  catch (const InvalidInputError& e)
  {
    throw InvalidInputError(e.what() + why);
  }
  catch (const InterpolationError& e)
  {
    throw InterpolationError(e.what() + why);
  }
}

/// The six bounds of the request (timing/time_optimal.h, RateBounds; 0 = unbounded).
template <class Space>
timing::RateBounds rateBounds(const BasicValidatedRequest<Space>& r)
{
  timing::RateBounds bounds;
  bounds.velocity = { r.max_linear_velocity, r.max_angular_velocity };
  bounds.acceleration = { r.max_linear_acceleration, r.max_angular_acceleration };
  bounds.jerk = { r.max_linear_jerk, r.max_angular_jerk };
  return bounds;
}

/// Under `stretch` with an acceleration bound: a velocity corner of a channel it bounds (the corners
/// of a piecewise_geodesic without blend_radius, a B-spline of degree 1, the start of a dwell) is
/// an impulse of acceleration, which no stretch bounds and the figures, peaks of the pieces, do
/// not show: refused naming the bound. A channel without one may jump; a jump below
/// timing::kCornerTolerance of the channel's peak speed (`fig`, of `curve`) is rounding.
template <class Space, class G>
void refuseVelocityCorners(const BasicValidatedRequest<Space>& r, const Curve<G>& curve, const CurveFigures& fig)
{
  const std::array<double, 2> bounds = { r.max_linear_acceleration, r.max_angular_acceleration };
  if (!(bounds[timing::kLinear] > 0.0) && !(bounds[timing::kAngular] > 0.0))
    return;
  const std::array<double, 2> floor = { timing::kCornerTolerance * fig.max_linear_speed,
                                        timing::kCornerTolerance * fig.max_angular_speed };
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  for (std::size_t i = 1; i + 1 < b.size(); ++i)
  {
    checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the trajectory's corners");
    const std::array<bool, 2> jumps = timing::velocityJumpsByChannel(curve, b[i], floor);
    for (const int c : { timing::kLinear, timing::kAngular })
      if (jumps[c] && bounds[c] > 0.0)
        throw InvalidInputError(
            std::string(c == timing::kLinear ? "max_linear_acceleration" : "max_angular_acceleration") +
            ": the curve's velocity jumps at t = " + formatNumber(b[i]) +
            " s (a corner: piecewise_geodesic without blend_radius, a B-spline of degree 1, a "
            "dwell), so no uniform stretch bounds its acceleration; use blend_radius "
            "(piecewise_geodesic), or timing 'time_optimal', whose motion stops there");
  }
}

/// The checks of `stretch` beyond the figures `fig` of `curve`: velocity corners under an
/// acceleration bound (refuseVelocityCorners), then, with a jerk bound or an arm's jerk limit (the
/// arm's check measures its joints' jerk), the peak jerks of `curve`
/// (on its own clock) into `fig`, which the stretch then divides by k³. A curve whose acceleration jumps has an
/// impulse of jerk there, which no stretch bounds: refused naming the jerk bound, suggesting
/// time_optimal.
template <class Space, class G>
void measureJerk(const BasicValidatedRequest<Space>& r, const Curve<G>& curve, CurveFigures* fig)
{
  refuseVelocityCorners(r, curve, *fig);
  if (!hasJerkBound(r) && !(jointJerkWindow(r) > 0.0))
    return;
  const timing::JerkPeaks j = timing::jerkPeaks(curve);
  const char* bound = !hasJerkBound(r)        ? "the arm's joint jerk limits (its limits file)" :
                      r.max_linear_jerk > 0.0 ? "max_linear_jerk" :
                                                "max_angular_jerk";
  if (!std::isnan(j.acceleration_jump))
    throw InvalidInputError(std::string(bound) +
                            ": the curve's acceleration jumps at t = " + formatNumber(j.acceleration_jump) +
                            " s (it is only C1 there, or a corner), so no uniform stretch bounds its jerk; use timing "
                            "'time_optimal', whose jerk-limited motion stops there");
  if (!hasJerkBound(r))
    return;
  fig->max_linear_jerk = j.peak[timing::kLinear];
  fig->max_angular_jerk = j.peak[timing::kAngular];
}

/// ∫ |p̈|² + ρ²|ω̇|² dt from each channel's ∫|a|² dt.
template <class Space>
double channelEnergy(const BasicValidatedRequest<Space>& r, const std::array<double, 2>& energy)
{
  const double angular = energy[timing::kAngular];
  // (ρ² · 0 must stay 0 for a huge ρ, as in measureCurve.)
  return energy[timing::kLinear] + (angular > 0.0 ? r.rotation_scale * r.rotation_scale * angular : 0.0);
}

/// The figures of a time-optimal motion: length and rotation length are the path's (timing does not
/// change them); the rates and the energy are the timed motion's (TimingProfile).
template <class Space>
void setTimedFigures(const BasicValidatedRequest<Space>& r, const timing::TimingProfile& p, CurveFigures* fig)
{
  fig->max_linear_speed = p.max_speed[timing::kLinear];
  fig->max_angular_speed = p.max_speed[timing::kAngular];
  fig->max_linear_acceleration = p.max_acceleration[timing::kLinear];
  fig->max_angular_acceleration = p.max_acceleration[timing::kAngular];
  fig->energy = channelEnergy(r, p.acceleration_energy);
}

/// The peaks a timing verified densely (JerkLimitedProfile, ConstantSpeedProfile: their
/// max_speed, max_acceleration, max_jerk per channel) as the response's figures.
template <class Profile>
void setVerifiedPeaks(const Profile& p, CurveFigures* fig)
{
  fig->max_linear_speed = p.max_speed[timing::kLinear];
  fig->max_angular_speed = p.max_speed[timing::kAngular];
  fig->max_linear_acceleration = p.max_acceleration[timing::kLinear];
  fig->max_angular_acceleration = p.max_acceleration[timing::kAngular];
  fig->max_linear_jerk = p.max_jerk[timing::kLinear];
  fig->max_angular_jerk = p.max_jerk[timing::kAngular];
}

/// The figures of a jerk-limited motion: length and rotation length are the path's; the peaks
/// and the energy are the timing's, from its final check (JerkLimitedProfile).
template <class Space, class G>
void setJerkLimitedFigures(const BasicValidatedRequest<Space>& r, const timing::JerkLimitedCurve<G>& timed,
                           CurveFigures* fig)
{
  setVerifiedPeaks(timed.profile(), fig);
  fig->energy = channelEnergy(r, timed.profile().acceleration_energy);
}

/// The lengths of a path (translation, rotation): a geodesic chain's in closed form
/// (timing/geodesic_timing.h), any other path's by quadrature (measureLengths).
template <class G>
std::pair<double, double> pathLengths(const Curve<G>& path)
{
  if constexpr (!std::is_same_v<G, Sphere>)
    if (const std::optional<timing::GeodesicChain> chain = timing::geodesicChain(path))
      return { chain->length[timing::kLinear], chain->length[timing::kAngular] };
  return measureLengths(path);
}

/// The figures of a curve on its own clock (what the stretch scales): a geodesic chain's in closed
/// form (its speeds are its rates, its accelerations and energy 0), any other's measured.
template <class G>
CurveFigures curveFigures(const Curve<G>& curve, double rotation_scale)
{
  if constexpr (!std::is_same_v<G, Sphere>)
    if (const std::optional<timing::GeodesicChain> chain = timing::geodesicChain(curve))
    {
      CurveFigures f;
      f.length = chain->length[timing::kLinear];
      f.rotation_length = chain->length[timing::kAngular];
      f.max_linear_speed = chain->max_rate[timing::kLinear];
      f.max_angular_speed = chain->max_rate[timing::kAngular];
      return f;
    }
  return measureCurve(curve, rotation_scale);
}

/// The figures of a geodesic chain's closed-form timing (GeodesicChainProfile): peaks and energy
/// in closed form; the peak jerks only with a jerk bound (as the general timings report them).
template <class Space>
void setGeodesicFigures(const BasicValidatedRequest<Space>& r, const timing::GeodesicChainProfile& p, CurveFigures* fig)
{
  setVerifiedPeaks(p, fig);
  if (!hasJerkBound(r))
    fig->max_linear_jerk = fig->max_angular_jerk = 0.0;
  fig->energy = channelEnergy(r, p.acceleration_energy);
}

/// The figures of a constant-speed motion: length and rotation length are the path's; the peaks and
/// the energy are the timing's, from its final check (ConstantSpeedProfile; the jerk's with a jerk
/// bound, else 0 as for the other timings without one).
template <class G>
void setConstantSpeedFigures(const timing::ConstantSpeedCurve<G>& timed, CurveFigures* fig)
{
  setVerifiedPeaks(timed.profile(), fig);
  fig->energy = timed.profile().acceleration_energy;
}

}  // namespace planner_detail
}  // namespace se3_interpolation
