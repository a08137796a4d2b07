// The jerk-limited timing (timing/jerk_limited.h): the solve's loop, the moving channels and the
// underlying bounds, and the public functions. The runs of the underlying timing are in
// jerk_limited_runs.cpp, the final check in jerk_limited_check.cpp; the solver's declaration in
// jerk_limited_solver.h.
#include "se3_interpolation/timing/jerk_limited.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "se3_interpolation/exceptions.h"
#include "jerk_limited_solver.h"

namespace se3_interpolation
{
namespace timing
{
namespace jerk_limited_detail
{
namespace
{
/// A moving start cannot be stretched: the underlying bounds are lowered by the excess (with this
/// margin) and everything rerun, at most kFixedStartPasses times, until every rate is within
/// kFixedStartTolerance of its bound.
constexpr int kFixedStartPasses = 8;
constexpr double kFixedStartTolerance = 1e-6;
constexpr double kFixedStartMargin = 1e-3;
/// A final check asking for a stretch above this reruns the timing with |s̈_T| capped where the
/// path nearly stands still (jerk_limited_runs.cpp, capStationaryPoints), and keeps the faster of
/// the two: on the paths of the tests and benchmarks without such points the stretch is at most
/// about 1.08, at a clamped end at rest it was in the hundreds.
constexpr double kStationaryStretch = 1.25;
/// Bisection steps for the time at which the motion passes a path parameter (to rounding).
constexpr int kTimeBisectionSteps = 100;

const char* const kJerkName[2] = { "max_linear_jerk", "max_angular_jerk" };

void requireJerkBounds(const RateBounds& bounds)
{
  for (int c = 0; c < 2; ++c)
    if (!(std::isfinite(bounds.jerk[c]) && bounds.jerk[c] >= 0.0))
      throw InvalidInputError(std::string(kJerkName[c]) + ": " + formatNumber(bounds.jerk[c]) +
                              " (it must be a finite number, at least 0; 0 means unbounded)");
}
}  // namespace

JerkSolver::JerkSolver(const JerkPathModel& path, const RateBounds& bounds, const JerkLimitedOptions& options)
  : path_(path), bounds_(bounds), options_(options)
{
  const double sd0 = options.start_speed, sdd0 = options.start_acceleration;
  if (!(std::isfinite(sd0) && sd0 >= 0.0 && std::isfinite(sdd0)))
    throw InvalidInputError("start_state: its speed along the path is " + formatNumber(sd0) + " and its acceleration " +
                            formatNumber(sdd0) + " (the speed must be finite and at least 0, the acceleration finite)");
  if (!(std::isfinite(options.window) && options.window >= 0.0))
    throw InvalidInputError("jerk-limited timing: its least window is " + formatNumber(options.window) +
                            " s (it must be finite and at least 0)");
  fixed_start_ = sd0 > 0.0 || sdd0 != 0.0;
  findMovingChannels();
}

bool JerkSolver::jerkActs() const
{
  if (options_.window > 0.0)
    return true;
  for (int c = 0; c < 2; ++c)
    if (moves_[c] && bounds_.jerk[c] > 0.0)
      return true;
  return false;
}

JerkLimitedProfile JerkSolver::solve()
{
  double scale = 1.0;
  for (int pass = 0;; ++pass)
  {
    run(scaled(scale));
    const double k = verify();
    if (!fixed_start_)
    {
      if (k > kStationaryStretch)
      {
        JerkLimitedProfile uncapped = std::move(profile_);
        const Rates6 uncapped_peak = peak_;
        cap_stationary_ = true;
        run(scaled(scale));
        const double capped = verify();
        if (capped < k)
        {
          applyStretch(capped);
          return std::move(profile_);
        }
        profile_ = std::move(uncapped);
        peak_ = uncapped_peak;
      }
      applyStretch(k);
      return std::move(profile_);
    }
    if (k <= 1.0 + kFixedStartTolerance)
    {
      applyStretch(1.0);
      return std::move(profile_);
    }
    if (pass + 1 == kFixedStartPasses)
      throw InterpolationError("start_state: the jerk-limited motion from the start state exceeds a bound by " +
                               formatNumber(k - 1.0) + " (relative) after " + std::to_string(kFixedStartPasses) +
                               " corrections; start more slowly or farther from the first waypoint, or raise the "
                               "bounds");
    scale *= k * (1.0 + kFixedStartMargin);
  }
}

void JerkSolver::findMovingChannels()
{
  const std::vector<double> b = path_.breakpoints();
  std::array<double, 2> largest{};
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
    for (double s : { b[i], 0.5 * (b[i] + b[i + 1]) })
    {
      const PathJet j = path_.jet(s, Side::kRight);
      for (int c = 0; c < 2; ++c)
        largest[c] = std::max(largest[c], j[c].bb);
    }
  const double scale = std::max(largest[0], largest[1]);
  for (int c = 0; c < 2; ++c)
    moves_[c] = largest[c] > kMoveTolerance * kMoveTolerance * scale;
}

RateBounds JerkSolver::scaled(double scale) const
{
  RateBounds b = bounds_;
  for (int c = 0; c < 2; ++c)
  {
    const double v = bounds_.velocity[c], a = bounds_.acceleration[c], j = bounds_.jerk[c];
    if (j > 0.0 && v > 0.0)
      b.acceleration[c] = a > 0.0 ? std::min(a, std::sqrt(v * j)) : std::sqrt(v * j);
    b.velocity[c] /= scale;
    b.acceleration[c] /= scale * scale;
    b.jerk[c] /= scale * scale * scale;
  }
  return b;
}

}  // namespace jerk_limited_detail

double JerkLimitedProfile::segmentTime(const Segment& g, double path_parameter) const
{
  if (path_parameter <= g.s_start)
    return base.t[g.first];
  if (path_parameter >= base.s[g.last])
    return base.t[g.last] + g.tau;
  // s(t) is nondecreasing and passes s between the base's passage and τ after it.
  double lo = std::max(base.t[g.first], base.timeAt(path_parameter));
  double hi = std::min(lo + g.tau, base.t[g.last] + g.tau);
  // On [lo, hi] s(t) is a cubic between the segment's grid times and those times shifted by τ
  // (eq. 2): the bracket is narrowed to one such piece by bisection over the grid times inside
  // it, then over the shifted ones, and the piece's cubic (its Taylor coefficients at the middle)
  // is solved by bisection: a few evaluations of s(t) instead of one per step.
  const auto grid_begin = base.t.begin() + static_cast<std::ptrdiff_t>(g.first);
  const auto grid_end = base.t.begin() + static_cast<std::ptrdiff_t>(g.last) + 1;
  for (const double shift : { 0.0, g.tau })
  {
    auto a = std::upper_bound(grid_begin, grid_end, lo - shift);
    auto b = std::lower_bound(a, grid_end, hi - shift);
    while (a != b)
    {
      const auto m = a + (b - a) / 2;
      const double t = *m + shift;
      if (!(t > lo && t < hi))
        break;
      if (segmentParameter(g, t, Side::kRight) < path_parameter)
      {
        lo = t;
        a = m + 1;
      }
      else
      {
        hi = t;
        b = m;
      }
    }
  }
  const double mid = 0.5 * (lo + hi);
  const Jet<3> cubic = segmentParameter(g, Jet<3>::variable(mid), Side::kRight);
  const double c0 = cubic.coefficient(0), c1 = cubic.coefficient(1), c2 = cubic.coefficient(2),
               c3 = cubic.coefficient(3);
  for (int step = 0; step < jerk_limited_detail::kTimeBisectionSteps; ++step)
  {
    const double t = 0.5 * (lo + hi);
    if (!(t > lo && t < hi))
      break;
    const double h = t - mid;
    (c0 + h * (c1 + h * (c2 + h * c3)) < path_parameter ? lo : hi) = t;
  }
  return hi;
}

double JerkLimitedProfile::timeAt(double path_parameter) const
{
  if (segments.empty())
    return base.timeAt(path_parameter);
  std::size_t k = 0;
  while (k + 1 < segments.size() && base.s[segments[k].last] < path_parameter)
    ++k;
  const Segment& g = segments[k];
  return t0 + (g.start + (segmentTime(g, path_parameter) - g.baseStart(base)) - t0) * stretch;
}

std::size_t JerkLimitedProfile::segmentAt(double time, Side side) const
{
  const double local = t0 + (time - t0) / stretch;
  // The last segment starting before `local` (at its start: the one on `side`).
  std::size_t lo = 0, hi = segments.size();
  while (hi - lo > 1)
  {
    const std::size_t mid = (lo + hi) / 2;
    const double s = segments[mid].start;
    (local > s || (local == s && side == Side::kRight) ? lo : hi) = mid;
  }
  return lo;
}

JerkLimitedProfile jerkLimitedProfile(const JerkPathModel& path, const RateBounds& bounds,
                                      const JerkLimitedOptions& options)
{
  jerk_limited_detail::requireJerkBounds(bounds);
  jerk_limited_detail::JerkSolver solver(path, bounds, options);
  if (!solver.jerkActs())
  {
    // No jerk bound on a moving channel: the acceleration-only timing, unchanged.
    JerkLimitedProfile p;
    TimeOptimalOptions o = options.grid;
    o.start_speed = options.start_speed;
    p.base = timeOptimalProfile(path, bounds, o);
    p.t0 = p.base.t.front();
    p.stretch = p.base.stretch;
    p.max_speed = p.base.max_speed;
    p.max_acceleration = p.base.max_acceleration;
    p.acceleration_energy = p.base.acceleration_energy;
    for (int c = 0; c < 2; ++c)
      p.max_jerk[c] = p.max_acceleration[c] > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    return p;
  }
  return solver.solve();
}

}  // namespace timing
}  // namespace se3_interpolation
