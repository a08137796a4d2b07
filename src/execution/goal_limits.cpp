// The peaks of a goal's six rates between its points and its checks against the bounds
// (goal_trajectory.h: peaks, boundExcess, checkLimits, requireEndsAtRest).
#include <algorithm>
#include <cmath>
#include <utility>

#include "goal_trajectory_internal.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
using namespace goal_detail;

namespace
{
/// The largest of f on a subinterval [lo, hi] of segment `segment`, with f's values at its ends and
/// middle: refined by timing::detail::localMaxOf, which reports values only, so the argument of the
/// largest is kept by the function it calls.
template <class F>
RatePeak refinedPeak(F f, double lo, double hi, std::size_t segment, double f0, double fm, double f1)
{
  RatePeak best{ f0, lo, segment };
  for (const auto& [v, t] : { std::make_pair(fm, 0.5 * (lo + hi)), std::make_pair(f1, hi) })
    if (v > best.value)
      best = { v, t, segment };
  timing::detail::localMaxOf(
      [&](double lambda) {
        const double t = lo + lambda * (hi - lo);
        const double v = f(t);
        if (v > best.value)
          best = { v, t, segment };
        return v;
      },
      f0, fm, f1);
  return best;
}
}  // namespace

MotionPeaks goal_detail::peaksOf(const GoalTrajectory::Interpolant& m, const SixRates* ceilings)
{
  MotionPeaks peaks{};
  const std::vector<double>& b = m.times();
  auto consider = [&peaks](const SixRates& r, double t, std::size_t segment) {
    for (std::size_t c = 0; c < r.size(); ++c)
      if (r[c] > peaks[c].value)
        peaks[c] = { r[c], t, segment };
  };
  if (b.size() == 1)
  {
    consider(m.ratesAt(b[0], Side::kRight), b[0], 0);
    return peaks;
  }
  struct Span
  {
    double lo, hi;
    std::size_t segment;
    SixRates f0, fm, f1;
  };
  std::vector<Span> spans;
  spans.reserve((b.size() - 1) * kPeakSubintervals);
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
  {
    const double step = (b[i + 1] - b[i]) / static_cast<double>(kPeakSubintervals);
    for (std::size_t s = 0; s < kPeakSubintervals; ++s)
    {
      const double lo = b[i] + static_cast<double>(s) * step;
      const double hi = s + 1 == kPeakSubintervals ? b[i + 1] : lo + step;
      const double mid = 0.5 * (lo + hi);
      Span span{ lo, hi, i, m.ratesAt(lo, Side::kRight), m.ratesAt(mid, Side::kRight), m.ratesAt(hi, Side::kLeft) };
      consider(span.f0, lo, i);
      consider(span.fm, mid, i);
      consider(span.f1, hi, i);
      spans.push_back(span);
    }
  }
  for (const Span& span : spans)
    for (std::size_t c = 0; c < peaks.size(); ++c)
    {
      const double largest = std::max({ span.f0[c], span.fm[c], span.f1[c] });
      if (ceilings && (!((*ceilings)[c] > 0.0) || largest > (*ceilings)[c]))
        continue;
      const double threshold = (ceilings ? (*ceilings)[c] : peaks[c].value) * (1.0 - kPeakRefineMargin);
      if (largest < threshold && !timing::detail::parabolaPeaksInside(span.f0[c], span.fm[c], span.f1[c], threshold))
        continue;
      const RatePeak p = refinedPeak([&m, c](double t) { return m.ratesAt(t, Side::kRight)[c]; }, span.lo, span.hi,
                                     span.segment, span.f0[c], span.fm[c], span.f1[c]);
      if (p.value > peaks[c].value)
        peaks[c] = p;
    }
  return peaks;
}

namespace
{
/// Refuses a velocity jump at an interior point where an acceleration (or jerk) is bounded, and an
/// acceleration jump where a jerk is: the bounded rate is an impulse there.
void requireNoJumps(const GoalTrajectory::Interpolant& m, const SixRates& bounds)
{
  if (m.order() >= 2)
    return;  // C² by construction
  const std::vector<double>& b = m.times();
  for (std::size_t i = 1; i + 1 < b.size(); ++i)
  {
    const Kinematics l = m.at(b[i], Side::kLeft);
    const Kinematics r = m.at(b[i], Side::kRight);
    const double h = std::min(b[i] - b[i - 1], b[i + 1] - b[i]);
    for (std::size_t c = 0; c < 2; ++c)
    {
      const Eigen::Vector3d& vl = c == 0 ? l.velocity.linear : l.velocity.angular;
      const Eigen::Vector3d& vr = c == 0 ? r.velocity.linear : r.velocity.angular;
      const Eigen::Vector3d& al = c == 0 ? l.acceleration.linear : l.acceleration.angular;
      const Eigen::Vector3d& ar = c == 0 ? r.acceleration.linear : r.acceleration.angular;
      const bool velocity_jumps = (vl - vr).norm() > timing::kCornerTolerance * (vl.norm() + vr.norm());
      const bool acceleration_jumps =
          (al - ar).norm() > timing::kAccelerationJumpTolerance * (al.norm() + ar.norm() + vl.norm() / h);
      for (std::size_t rate : { accelerationRate(c), jerkRate(c) })
      {
        const bool jumps = velocity_jumps || (rate == jerkRate(c) && acceleration_jumps);
        if (bounds[rate] <= 0.0 || !jumps)
          continue;
        const std::size_t cause = velocity_jumps ? velocityRate(c) : accelerationRate(c);
        const Eigen::Vector3d jump = velocity_jumps ? Eigen::Vector3d(vr - vl) : Eigen::Vector3d(ar - al);
        refuse(pointField(i) + ": the " + kRateNames[cause].name + " jumps there by " + formatNumber(jump.norm()) +
               " " + kRateNames[cause].unit + ", so the " + kRateNames[rate].name + " is unbounded (" +
               kRateNames[rate].bound + " = " + formatNumber(bounds[rate]) + " " + kRateNames[rate].unit +
               "); give every point velocities and accelerations (a C² trajectory)");
      }
    }
  }
}

/// The peaks checkLimits compares with the bounds: the velocities' and accelerations' of the
/// motion, the jerks as each segment's mean |Δp̈| / h and |Δω̇| / h between its points (file comment).
MotionPeaks checkedPeaks(const GoalTrajectory::Interpolant& m, const SixRates* ceilings)
{
  MotionPeaks peaks = peaksOf(m, ceilings);
  const std::vector<double>& b = m.times();
  peaks[4] = RatePeak();
  peaks[5] = RatePeak();
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
  {
    const Kinematics k0 = m.at(b[i], Side::kRight);
    const Kinematics k1 = m.at(b[i + 1], Side::kLeft);
    const double h = b[i + 1] - b[i];
    const double linear = (k1.acceleration.linear - k0.acceleration.linear).norm() / h;
    const double angular = (k1.acceleration.angular - k0.acceleration.angular).norm() / h;
    if (linear > peaks[4].value)
      peaks[4] = { linear, b[i], i };
    if (angular > peaks[5].value)
      peaks[5] = { angular, b[i], i };
  }
  return peaks;
}
}  // namespace

double GoalTrajectory::boundExcess(const MotionLimits& limits, double tolerance) const
{
  const SixRates bounds = boundsOf(limits);
  SixRates ceilings;
  for (std::size_t c = 0; c < bounds.size(); ++c)
    ceilings[c] = bounds[c] * (1.0 + tolerance);
  const MotionPeaks peaks = checkedPeaks(*interpolant_, &ceilings);
  double excess = -1.0;
  for (std::size_t c = 0; c < bounds.size(); ++c)
    if (bounds[c] > 0.0)
      excess = std::max(excess, peaks[c].value / bounds[c] - 1.0);
  return excess;
}

void GoalTrajectory::checkLimits(const MotionLimits& limits, double tolerance) const
{
  const SixRates bounds = boundsOf(limits);
  requireNoJumps(*interpolant_, bounds);
  const MotionPeaks peaks = checkedPeaks(*interpolant_, nullptr);
  std::size_t worst = bounds.size();
  double worst_ratio = 1.0 + tolerance;
  for (std::size_t c = 0; c < bounds.size(); ++c)
    if (bounds[c] > 0.0 && peaks[c].value > worst_ratio * bounds[c])
    {
      worst = c;
      worst_ratio = peaks[c].value / bounds[c];
    }
  if (worst == bounds.size())
    return;
  const RatePeak& p = peaks[worst];
  const RateName& r = kRateNames[worst];
  const bool mean = worst >= 4;
  refuse(pointField(p.segment) + ": between it and " + pointField(p.segment + 1) + " the " + (mean ? "mean " : "") +
         r.name + " reaches " + formatNumber(p.value) + " " + r.unit + " at time_from_start " + formatNumber(p.time) +
         " s, above " + r.bound + " = " + formatNumber(bounds[worst]) + " " + r.unit +
         (worst == 2 || worst == 3 ?
              " (where a trajectory's acceleration jumps between two points, as time_optimal's does without a jerk "
              "bound, its interpolation overshoots: generate it with max_linear_jerk and max_angular_jerk)" :
              ""));
}

void GoalTrajectory::requireEndsAtRest() const
{
  const Kinematics k = interpolant_->at(endTime(), Side::kLeft);
  const double linear = k.velocity.linear.norm();
  const double angular = k.velocity.angular.norm();
  if (linear <= kRestLinear && angular <= kRestAngular)
    return;
  refuse(pointField(size() - 1) + ": the motion ends moving (linear speed " + formatNumber(linear) +
         " m/s, angular speed " + formatNumber(angular) + " rad/s; at rest is below " + shortNumber(kRestLinear) +
         " m/s and " + shortNumber(kRestAngular) +
         " rad/s): give the last point zero velocities, or plan it to stop there (the ~generate service's "
         "end_condition: clamped, or timing: time_optimal)");
}

}  // namespace se3_interpolation
