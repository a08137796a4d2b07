// The box constraint of the time-optimal timing (timing/time_optimal.h, (4) and (5)): limits on
// components that move at w ṡ and accelerate at w s̈ + a ṡ² (an arm's joints). In the passes they
// are a cap on x and, per end of an interval, the band |w u + a x| ≤ A, which is the ellipse (3) of
// a one-dimensional channel (|C′ × C″| = 0): the controls' intersection takes them as ellipses with
// cross = 0. Their checks between the grid points mirror the norm bounds': ends, middle, and a
// peak search where a parabola through those peaks inside. The solver is declared in
// time_optimal_solver.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/timing/peak_search.h"
#include "time_optimal_solver.h"

namespace se3_interpolation
{
namespace timing
{
namespace time_optimal_detail
{
namespace
{
/// Intervals whose parabola through ends and middle peaks inside within this fraction of the
/// worst level seen are searched for their maximum (as the norm bounds' check does).
constexpr double kBoxSearchMargin = 1e-3;
/// The same for each component's figures (boxFigures), which the check's worst level does not
/// bound: a parabola underestimates a sharp peak by more than 1e-3.
constexpr double kBoxFigureSearchMargin = 1e-2;
}  // namespace

void TimeOptimalSolver::evaluateBoxJets()
{
  const std::size_t n = profile_.s.size();
  const std::size_t m = box_count_;
  box_right_.assign(2 * m * n, 0.0);
  box_left_.assign(2 * m * distinct_left_.size(), 0.0);
  box_middle_.assign(2 * m * (n - 1), 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
    double* r = &box_right_[2 * m * i];
    boxes_->jet(profile_.s[i], i + 1 == n ? Side::kLeft : Side::kRight, r, r + m);
    if (left_of_[i] != kSameAsRight)
    {
      double* l = &box_left_[2 * m * static_cast<std::size_t>(left_of_[i])];
      boxes_->jet(profile_.s[i], Side::kLeft, l, l + m);
    }
    if (i + 1 < n)
    {
      double* c = &box_middle_[2 * m * i];
      boxes_->jet(profile_.s[i] + 0.5 * delta(i), Side::kRight, c, c + m);
    }
  }
}

bool TimeOptimalSolver::startExceedsBoxes() const
{
  if (box_count_ == 0 || !(start_x_ > 0.0))
    return false;
  // As the norm bounds' test: the velocities always, the accelerations (a x at u = 0) with hold_start.
  std::array<double, 2 * kMaxBoxComponents> per;
  boxLevel(boxJet(0, false), start_x_, 0.0, per.data());
  for (std::size_t q = 0; q < (hold_start_ ? 2 : 1) * box_count_; ++q)
    if (per[q] > 1.0 + kRoundingExcess)
      return true;
  return false;
}

bool TimeOptimalSolver::boxesBoundTheMotion() const
{
  if (box_count_ == 0)
    return false;
  for (std::size_t k = 0; k < box_count_; ++k)
    if (!(boxes_->accelerationLimit(k) > 0.0))
      return false;
  return true;
}

const double* TimeOptimalSolver::boxJet(std::size_t i, bool left) const
{
  if (left && left_of_[i] != kSameAsRight)
    return &box_left_[2 * box_count_ * static_cast<std::size_t>(left_of_[i])];
  return &box_right_[2 * box_count_ * i];
}

double TimeOptimalSolver::boxCap(const double* jet, std::size_t i) const
{
  const std::size_t m = box_count_;
  double cap = kInf;
  for (std::size_t k = 0; k < m; ++k)
  {
    const double w = std::abs(jet[k]);
    const double a = std::abs(jet[m + k]);
    const double v_max = boxes_->velocityLimit(k) * box_factor_[2 * m * i + k];
    const double a_max = boxes_->accelerationLimit(k) * box_factor_[2 * m * i + m + k];
    if (v_max > 0.0 && w > 0.0)
      cap = std::min(cap, (v_max / w) * (v_max / w));
    // (5) with w = 0: |a| x ≤ A.
    if (a_max > 0.0 && w == 0.0 && a > 0.0)
      cap = std::min(cap, a_max / a);
  }
  return cap;
}

void TimeOptimalSolver::addBoxBands(std::size_t i, ControlConstants* c) const
{
  const std::size_t m = box_count_;
  const double d = delta(i);
  const double* a0 = boxJet(i, false);
  const double* a1 = boxJet(i + 1, true);
  for (std::size_t k = 0; k < m; ++k)
  {
    const double limit = boxes_->accelerationLimit(k);
    if (!(limit > 0.0))
      continue;
    // At s_i: |w u + a x_i| ≤ A; at s_{i+1}: x_{i+1} = x_i + 2Δu, so |(w + 2Δa) u + a x_i| ≤ A.
    const double l0 = limit * box_factor_[2 * m * i + m + k];
    const double w0 = a0[k], c0 = a0[m + k];
    c->ellipse[c->ellipses++] = { w0 * w0, c0 * w0, c0 * c0, 0.0, l0 * l0 };
    const double l1 = limit * box_factor_[2 * m * (i + 1) + m + k];
    const double w1 = a1[k] + 2.0 * d * a1[m + k], c1 = a1[m + k];
    c->ellipse[c->ellipses++] = { w1 * w1, c1 * w1, c1 * c1, 0.0, l1 * l1 };
  }
}

double TimeOptimalSolver::boxLeastControl(std::size_t i, double x, double lo) const
{
  // The control in [lo, 0] of the least largest ratio |w u + a x| / A over the components at point
  // i: a maximum of absolute values of affine functions of u, convex, so a ternary search finds it
  // (to 2^-60 of the range: 100 steps of 2/3).
  const std::size_t m = box_count_;
  const double* j = boxJet(i, false);
  const auto worst = [&](double u) {
    double r = 0.0;
    for (std::size_t k = 0; k < m; ++k)
    {
      const double limit = boxes_->accelerationLimit(k);
      if (limit > 0.0)
        r = std::max(r, std::abs(j[k] * u + j[m + k] * x) / limit);
    }
    return r;
  };
  double a = std::min(lo, 0.0), b = 0.0;
  for (int step = 0; step < 100 && b - a > 0.0; ++step)
  {
    const double l = a + (b - a) / 3.0, r = b - (b - a) / 3.0;
    if (worst(l) <= worst(r))
      b = r;
    else
      a = l;
  }
  return 0.5 * (a + b);
}

double TimeOptimalSolver::boxLevel(const double* jet, double x, double u, double* per) const
{
  const std::size_t m = box_count_;
  double worst = 0.0;
  for (std::size_t k = 0; k < m; ++k)
  {
    const double v_max = boxes_->velocityLimit(k);
    const double a_max = boxes_->accelerationLimit(k);
    const double v = v_max > 0.0 ? std::abs(jet[k]) * std::sqrt(std::max(0.0, x)) / v_max : 0.0;
    const double a = a_max > 0.0 ? std::sqrt(std::abs(jet[k] * u + jet[m + k] * x) / a_max) : 0.0;
    if (per)
    {
      per[k] = v;
      per[m + k] = a;
    }
    worst = std::max({ worst, v, a });
  }
  return worst;
}

double TimeOptimalSolver::boxLevelAt(std::size_t i, double lambda) const
{
  std::array<double, 2 * kMaxBoxComponents> jet;
  const std::size_t m = box_count_;
  boxes_->jet(profile_.s[i] + lambda * delta(i), Side::kRight, jet.data(), jet.data() + m);
  const double x = profile_.x[i] + lambda * (profile_.x[i + 1] - profile_.x[i]);
  return boxLevel(jet.data(), x, profile_.u[i]);
}

double TimeOptimalSolver::boxPeak(std::size_t i, double threshold) const
{
  const double a = boxLevel(boxJet(i, false), profile_.x[i], profile_.u[i]);
  const double c = boxLevel(&box_middle_[2 * box_count_ * i], 0.5 * (profile_.x[i] + profile_.x[i + 1]), profile_.u[i]);
  const double b = boxLevel(boxJet(i + 1, true), profile_.x[i + 1], profile_.u[i]);
  if (!detail::parabolaPeaksInside(a, c, b, threshold))
    return std::max({ a, c, b });
  return detail::localMaxOf([this, i](double lambda) { return boxLevelAt(i, lambda); }, a, c, b);
}

bool TimeOptimalSolver::tightenBoxesWhereTheMiddlesExceed()
{
  if (box_count_ == 0)
    return false;
  const std::size_t m = box_count_;
  std::array<double, 2 * kMaxBoxComponents> per;
  bool tightened = false;
  for (std::size_t i = std::max(checkedFrom(), first_step_); i + 1 < profile_.s.size(); ++i)
  {
    const double x = 0.5 * (profile_.x[i] + profile_.x[i + 1]);
    if (!(boxLevel(&box_middle_[2 * m * i], x, profile_.u[i], per.data()) > 1.0 + kLocalTolerance))
      continue;
    for (std::size_t q = 0; q < 2 * m; ++q)
    {
      if (!(per[q] > 1.0 + kLocalTolerance))
        continue;
      // Velocity levels scale with the limit, acceleration levels with its square root.
      const double f = q < m ? 1.0 / per[q] : 1.0 / (per[q] * per[q]);
      box_factor_[2 * m * i + q] *= f;
      box_factor_[2 * m * (i + 1) + q] *= f;
      changed_[i] = changed_[i + 1] = 1;
      tightened = true;
    }
  }
  return tightened;
}

std::pair<double, bool> TimeOptimalSolver::checkBoxes(double tighten_margin)
{
  if (box_count_ == 0)
    return { 0.0, false };
  const std::size_t m = box_count_;
  double worst = 0.0;
  bool tightened = false;
  for (std::size_t i = checkedFrom(); i + 1 < profile_.s.size(); ++i)
  {
    checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
    // (The stretch needs the worst peak; the fixed start's tightening every peak above its limit.)
    const double threshold = (tighten_margin >= 0.0 ? 1.0 : worst) * (1.0 - kBoxSearchMargin);
    const double p = boxPeak(i, threshold);
    worst = std::max(worst, p);
    if (!(tighten_margin >= 0.0 && p > 1.0 + kFixedStartTolerance))
      continue;
    // Every component at the interval's ends, by the interval's peak: a slow-down of the interval.
    const double f = (1.0 / (p * p)) * (1.0 - tighten_margin);
    for (std::size_t q = 0; q < 2 * m; ++q)
    {
      box_factor_[2 * m * i + q] *= q < m ? std::sqrt(f) : f;
      box_factor_[2 * m * (i + 1) + q] *= q < m ? std::sqrt(f) : f;
    }
    changed_[i] = changed_[i + 1] = 1;
    tightened = true;
  }
  return { worst, tightened };
}

void TimeOptimalSolver::boxFigures()
{
  profile_.boxes = boxes_;
  profile_.box_peaks.assign(box_count_, BoxPeak());
  if (box_count_ == 0)
    return;
  // The whole motion, a start's recovery included: the figures say what the motion does.
  for (std::size_t i = 0; i + 1 < profile_.s.size(); ++i)
  {
    checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
    const std::array<const double*, 3> jets{ boxJet(i, false), &box_middle_[2 * box_count_ * i], boxJet(i + 1, true) };
    for (std::size_t k = 0; k < box_count_; ++k)
      raiseBoxPeaks(i, k, jets);
  }
}

void TimeOptimalSolver::raiseBoxPeaks(std::size_t i, std::size_t k, const std::array<const double*, 3>& jets)
{
  const std::size_t m = box_count_;
  const double u = profile_.u[i];
  // x = ṡ² is linear in s on an interval (constant s̈): its middle is the mean of its ends.
  const auto x_at = [this, i](double lambda) { return profile_.x[i] + lambda * (profile_.x[i + 1] - profile_.x[i]); };
  const auto rate = [k, m, u](const double* jet, double x, bool velocity) {
    return velocity ? std::abs(jet[k]) * std::sqrt(std::max(0.0, x)) : std::abs(jet[k] * u + jet[m + k] * x);
  };
  BoxPeak& p = profile_.box_peaks[k];
  for (const bool velocity : { true, false })
  {
    double& peak = velocity ? p.velocity : p.acceleration;
    double& when = velocity ? p.velocity_time : p.acceleration_time;
    const std::array<double, 3> f{ rate(jets[0], x_at(0.0), velocity), rate(jets[1], x_at(0.5), velocity),
                                   rate(jets[2], x_at(1.0), velocity) };
    double best = std::max({ f[0], f[1], f[2] });
    if (detail::parabolaPeaksInside(f[0], f[1], f[2], peak * (1.0 - kBoxFigureSearchMargin)))
      best =
          std::max(best, detail::localMaxOf(
                             [&](double lambda) {
                               std::array<double, 2 * kMaxBoxComponents> jet;
                               boxes_->jet(profile_.s[i] + lambda * delta(i), Side::kRight, jet.data(), jet.data() + m);
                               return rate(jet.data(), x_at(lambda), velocity);
                             },
                             f[0], f[1], f[2]));
    if (!(best > peak))
      continue;
    peak = best;
    when = best == f[0] ? profile_.t[i] :
                          (best == f[2] ? profile_.t[i + 1] : profile_.timeAt(profile_.s[i] + 0.5 * delta(i)));
  }
}

}  // namespace time_optimal_detail
}  // namespace timing
}  // namespace se3_interpolation
