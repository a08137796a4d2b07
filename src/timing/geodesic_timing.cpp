// The closed-form timing of geodesic chains (timing/geodesic_timing.h): the rest-to-rest profile of
// Biagiotti & Melchiorri §3.4, the chain's runs and scalar bounds, and the timed motion's figures.
#include "se3_interpolation/timing/geodesic_timing.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace se3_interpolation
{
namespace timing
{
namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();
/// Bisection steps of s⁻¹ (each halves the bracket; far more than a double's 52 bits need).
constexpr int kTimeBisectionSteps = 200;

/// The profile with a jerk bound J (Biagiotti & Melchiorri §3.4, eqs. 3.30–3.32 from rest to rest):
/// the acceleration reached is a = min(A, √(V J)) (A is not reached when V J < A²), with jerk
/// phases t_j = a / J; the cruise lasts L / V − t_a when that is not negative; else the speed is not
/// reached and, when L ≥ 2 a³ / J², the acceleration phase t_a = t_j / 2 + √(t_j² / 4 + L / a) solves
/// L = a t_a (t_a − t_j); else neither the speed nor A is reached: four jerk phases of
/// t_j = ∛(L / (2 J)) (L = 2 J t_j³).
std::optional<RestToRestProfile> doubleS(double distance, double velocity, double acceleration, double jerk)
{
  RestToRestProfile p;
  p.distance = distance;
  p.jerk = jerk;
  const double a = std::min(acceleration, std::sqrt(velocity * jerk));
  if (!(std::isfinite(a) && a > 0.0))
    return std::nullopt;
  p.t_j = a / jerk;
  p.peak_acceleration = a;
  if (std::isfinite(velocity))
  {
    p.t_a = p.t_j + velocity / a;
    p.t_v = distance / velocity - p.t_a;
    if (p.t_v >= 0.0)
    {
      p.peak_speed = velocity;
      return p;
    }
  }
  p.t_v = 0.0;
  if (distance >= 2.0 * a * p.t_j * p.t_j)
  {
    p.t_a = 0.5 * p.t_j + std::sqrt(0.25 * p.t_j * p.t_j + distance / a);
    p.peak_speed = a * (p.t_a - p.t_j);
    return p;
  }
  p.t_j = std::cbrt(distance / (2.0 * jerk));
  p.t_a = 2.0 * p.t_j;
  p.peak_acceleration = jerk * p.t_j;
  p.peak_speed = jerk * p.t_j * p.t_j;
  return p;
}

/// The trapezoid without a jerk bound (Biagiotti & Melchiorri §3.2.2): acceleration A for V / A,
/// a cruise of L / V − V / A when L ≥ V² / A; else the triangle of t_a = √(L / A).
std::optional<RestToRestProfile> trapezoid(double distance, double velocity, double acceleration)
{
  if (!(std::isfinite(acceleration) && acceleration > 0.0))
    return std::nullopt;
  RestToRestProfile p;
  p.distance = distance;
  p.jerk = kInf;
  p.peak_acceleration = acceleration;
  if (std::isfinite(velocity) && distance * acceleration >= velocity * velocity)
  {
    p.t_a = velocity / acceleration;
    p.t_v = distance / velocity - p.t_a;
    p.peak_speed = velocity;
    return p;
  }
  p.t_a = std::sqrt(distance / acceleration);
  p.peak_speed = acceleration * p.t_a;
  return p;
}

/// A bound as the scalar profile reads it: +∞ for 0 (unbounded).
double scalarBound(double bound, double rate)
{
  return bound > 0.0 ? bound / rate : kInf;
}

/// The finite, non-negative bounds this timing reads (others are the general timing's to refuse).
bool validBounds(const RateBounds& b)
{
  for (int c = 0; c < 2; ++c)
    for (double x : { b.velocity[c], b.acceleration[c], b.jerk[c] })
      if (!(std::isfinite(x) && x >= 0.0))
        return false;
  return true;
}

/// The run's profile under the scalar bounds V, A, J: the smallest bound over its moving channels.
/// The general timing needs one moving channel whose acceleration is bounded (with a jerk bound
/// that acts, by √(v_c j_c) too: jerk_limited.cpp's underlying bounds); without it, none here.
std::optional<RestToRestProfile> runProfile(const GeodesicRun& run, const RateBounds& b, bool jerk_acts)
{
  double v = kInf, a = kInf, j = kInf;
  bool limited = false;
  for (int c = 0; c < 2; ++c)
  {
    if (!run.moves[c])
      continue;
    v = std::min(v, scalarBound(b.velocity[c], run.rate[c]));
    a = std::min(a, scalarBound(b.acceleration[c], run.rate[c]));
    if (jerk_acts)
      j = std::min(j, scalarBound(b.jerk[c], run.rate[c]));
    limited = limited || b.acceleration[c] > 0.0 || (jerk_acts && b.jerk[c] > 0.0 && b.velocity[c] > 0.0);
  }
  if (!limited)
    return std::nullopt;
  return restToRestProfile(run.s_end - run.s_begin, v, a, j);
}

/// The run's share of the figures: each channel moves at its rate times the profile's.
void addFigures(const GeodesicRun& run, const RestToRestProfile& p, GeodesicChainProfile* out)
{
  for (int c = 0; c < 2; ++c)
  {
    const double r = run.rate[c];
    if (!(r > 0.0))
      continue;
    out->max_speed[c] = std::max(out->max_speed[c], r * p.peak_speed);
    out->max_acceleration[c] = std::max(out->max_acceleration[c], r * p.peak_acceleration);
    out->max_jerk[c] = std::max(out->max_jerk[c], r * p.peakJerk());
    out->acceleration_energy[c] += r * r * p.accelerationEnergy();
  }
}
}  // namespace

std::optional<RestToRestProfile> restToRestProfile(double distance, double velocity, double acceleration, double jerk)
{
  if (!(distance > 0.0 && std::isfinite(distance)) || !(velocity > 0.0) || !(acceleration > 0.0) || !(jerk > 0.0))
    return std::nullopt;
  std::optional<RestToRestProfile> p = std::isfinite(jerk) ? doubleS(distance, velocity, acceleration, jerk) :
                                                             trapezoid(distance, velocity, acceleration);
  if (p && !(std::isfinite(p->duration()) && p->duration() > 0.0))
    return std::nullopt;
  return p;
}

double RestToRestProfile::timeAt(double s) const
{
  if (!(s > 0.0))
    return 0.0;
  if (s >= distance)
    return duration();
  double lo = 0.0, hi = duration();
  for (int step = 0; step < kTimeBisectionSteps; ++step)
  {
    const double mid = 0.5 * (lo + hi);
    if (!(mid > lo && mid < hi))
      break;
    (position(mid, Side::kRight) < s ? lo : hi) = mid;
  }
  return hi;
}

std::size_t GeodesicChainProfile::runAt(double t, Side side) const
{
  const auto it = side == Side::kRight ? std::upper_bound(start.begin(), start.end(), t) :
                                         std::lower_bound(start.begin(), start.end(), t);
  const std::ptrdiff_t i = (it - start.begin()) - 1;
  return i < 0 ? 0 : static_cast<std::size_t>(i);
}

double GeodesicChainProfile::timeAt(double s) const
{
  // The first run that ends at or after s.
  const auto it =
      std::lower_bound(runs.begin(), runs.end(), s, [](const GeodesicRun& run, double x) { return run.s_end < x; });
  const std::size_t k = std::min(static_cast<std::size_t>(it - runs.begin()), runs.size() - 1);
  return start[k] + profiles[k].timeAt(s - runs[k].s_begin);
}

std::vector<double> GeodesicChainProfile::breakpoints() const
{
  std::vector<double> b;
  b.reserve(8 * profiles.size());
  for (std::size_t i = 0; i < profiles.size(); ++i)
  {
    const RestToRestProfile& p = profiles[i];
    const double t = start[i], total = p.duration();
    for (double x : { 0.0, p.t_j, p.t_a - p.t_j, p.t_a, p.t_a + p.t_v, total - p.t_a + p.t_j, total - p.t_j })
      b.push_back(t + x);
  }
  b.push_back(endTime());
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

std::optional<GeodesicChainProfile> geodesicChainProfile(const GeodesicChain& chain, const RateBounds& bounds)
{
  if (chain.runs.empty() || !validBounds(bounds))
    return std::nullopt;
  // The jerk bounds act where a channel they bound moves (as jerk_limited.h's jerkActs).
  bool jerk_acts = false;
  for (const GeodesicRun& run : chain.runs)
    for (int c = 0; c < 2; ++c)
      jerk_acts = jerk_acts || (run.moves[c] && bounds.jerk[c] > 0.0);
  GeodesicChainProfile out;
  out.runs = chain.runs;
  out.profiles.reserve(chain.runs.size());
  out.start.reserve(chain.runs.size());
  double t = chain.runs.front().s_begin;
  for (const GeodesicRun& run : chain.runs)
  {
    const std::optional<RestToRestProfile> p = runProfile(run, bounds, jerk_acts);
    if (!p)
      return std::nullopt;
    out.start.push_back(t);
    out.profiles.push_back(*p);
    addFigures(run, *p, &out);
    t += p->duration();
  }
  if (!std::isfinite(t))
    return std::nullopt;
  return out;
}

namespace geodesic_detail
{
std::optional<GeodesicChain> chainOf(const std::vector<double>& b, const std::vector<PieceRates>& pieces,
                                     const std::vector<bool>& corner)
{
  std::array<double, 2> largest{};
  for (const PieceRates& p : pieces)
    for (int c = 0; c < 2; ++c)
      largest[c] = std::max(largest[c], p.rate[c]);
  const double scale = std::max(largest[0], largest[1]);
  if (pieces.empty() || !(scale > 0.0) || !std::isfinite(scale))
    return std::nullopt;
  // Which channels move at all, and where (time_optimal.h's kMoveTolerance, as the general timing).
  std::array<bool, 2> moves{};
  for (int c = 0; c < 2; ++c)
    moves[c] = largest[c] > kMoveTolerance * scale;
  GeodesicChain chain;
  chain.max_rate = largest;
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    const PieceRates& p = pieces[i];
    GeodesicRun piece{ b[i], b[i + 1], p.rate, {} };
    for (int c = 0; c < 2; ++c)
    {
      if (p.curvature[c] > kGeodesicStraightness * (p.rate[c] + kMoveTolerance * scale))
        return std::nullopt;
      piece.moves[c] = moves[c] && p.rate[c] > kMoveTolerance * largest[c];
      chain.length[c] += p.rate[c] * (b[i + 1] - b[i]);
    }
    if (!piece.moves[0] && !piece.moves[1])
      return std::nullopt;  // a dwell: the general timing's
    if (i == 0 || corner[i])
    {
      chain.runs.push_back(piece);
      continue;
    }
    GeodesicRun& run = chain.runs.back();
    run.s_end = piece.s_end;
    for (int c = 0; c < 2; ++c)
    {
      run.rate[c] = std::max(run.rate[c], piece.rate[c]);
      run.moves[c] = run.moves[c] || piece.moves[c];
    }
  }
  return chain;
}
}  // namespace geodesic_detail

}  // namespace timing
}  // namespace se3_interpolation
