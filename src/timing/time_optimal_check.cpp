// The final dense check of the time-optimal timing (timing/time_optimal.h: between grid points
// the bounds are not imposed by the scheme, the guarantee comes from checks): the needs of every
// interval at its ends, middle and searched peaks, the local tightening of the bounds, the uniform
// stretch of a motion from rest or the check of a fixed start, and the motion's figures. The
// solver is declared in time_optimal_solver.h.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

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
/// Intervals whose middle suggests (by a parabola through ends and middle) a rate within this
/// fraction of the worst one seen are searched for their maximum.
constexpr double kRefineMargin = 1e-3;
}  // namespace

Rates TimeOptimalSolver::needs(const PathJet& j, double x, double u) const
{
  Rates r = levels(j, x, u);
  for (int c = 0; c < 2; ++c)
  {
    if (!(bounds_.velocity[c] > 0.0))
      r[c] = 0.0;
    if (!(bounds_.acceleration[c] > 0.0))
      r[2 + c] = 0.0;
  }
  return r;
}

Rates TimeOptimalSolver::levelsAt(std::size_t i, double lambda) const
{
  const double x = profile_.x[i] + lambda * (profile_.x[i + 1] - profile_.x[i]);
  return levels(path_.jet(profile_.s[i] + lambda * delta(i), Side::kRight), x, profile_.u[i]);
}

Rates TimeOptimalSolver::needsAtMiddle(std::size_t i) const
{
  return needs(middle_[i], 0.5 * (profile_.x[i] + profile_.x[i + 1]), profile_.u[i]);
}

const PathJet& TimeOptimalSolver::quarterJet(std::size_t i, int k) const
{
  if (has_quarter_.size() != middle_.size())
  {
    has_quarter_.assign(middle_.size(), false);
    quarter_.resize(2 * middle_.size());
  }
  if (!has_quarter_[i])
  {
    quarter_[2 * i] = path_.jet(profile_.s[i] + 0.25 * delta(i), Side::kRight);
    quarter_[2 * i + 1] = path_.jet(profile_.s[i] + 0.75 * delta(i), Side::kRight);
    has_quarter_[i] = true;
  }
  return quarter_[2 * i + k];
}

Rates TimeOptimalSolver::needsAtQuarter(std::size_t i, int k) const
{
  const double lambda = k == 0 ? 0.25 : 0.75;
  return needs(quarterJet(i, k), profile_.x[i] + lambda * (profile_.x[i + 1] - profile_.x[i]), profile_.u[i]);
}

void TimeOptimalSolver::tighten(std::size_t i, int q, double r, double margin)
{
  const double f = (q < 2 ? 1.0 / r : 1.0 / (r * r)) * (1.0 - margin);
  factor_[i][q] *= f;
  factor_[i + 1][q] *= f;
  changed_[i] = changed_[i + 1] = 1;
}

bool TimeOptimalSolver::tightenWhereTheMiddlesExceed()
{
  bool tightened = false;
  // The intervals before the forward pass's first recomputed step have the motion they had when an
  // earlier round found their middles within the bounds.
  for (std::size_t i = std::max(checkedFrom(), first_step_); i + 1 < profile_.s.size(); ++i)
  {
    const Rates inside = needsInside(i);
    for (int q = 0; q < 4; ++q)
      if (inside[q] > 1.0 + kLocalTolerance)
      {
        tighten(i, q, inside[q], 0.0);
        tightened = true;
      }
  }
  return tightened;
}

Rates TimeOptimalSolver::needsInside(std::size_t i) const
{
  // (Without the quarters the ends' needs decide nothing here: the middle's alone.)
  if (!check_quarters_)
    return needsAtMiddle(i);
  const IntervalNeeds f = intervalNeeds(i);
  Rates r = f.at[2];
  if (f.quarters)
    for (int q = 0; q < 4; ++q)
      r[q] = std::max({ r[q], f.at[1][q], f.at[3][q] });
  return r;
}

TimeOptimalSolver::IntervalNeeds TimeOptimalSolver::intervalNeeds(std::size_t i) const
{
  IntervalNeeds f;
  f.at[0] = needs(right_[i].raw, profile_.x[i], profile_.u[i]);
  f.at[2] = needsAtMiddle(i);
  f.at[4] = needs(left(i + 1).raw, profile_.x[i + 1], profile_.u[i]);
  double top = 0.0;
  for (int q = 0; q < 4; ++q)
    top = std::max({ top, f.at[0][q], f.at[2][q], f.at[4][q] });
  if (check_quarters_ && top >= kQuarterFloor)
  {
    f.quarters = true;
    f.at[1] = needsAtQuarter(i, 0);
    f.at[3] = needsAtQuarter(i, 1);
  }
  return f;
}

double TimeOptimalSolver::peak(const IntervalNeeds& f, std::size_t i, int q, double threshold, bool* searched) const
{
  const std::array<double, 5> at{ f.at[0][q], f.at[1][q], f.at[2][q], f.at[3][q], f.at[4][q] };
  return detail::localMaxOfChecked([this, i, q](double lambda) { return levelsAt(i, lambda)[q]; }, at, f.quarters,
                                   threshold, searched);
}

Rates TimeOptimalSolver::levels(const PathJet& j, double x, double u) const
{
  Rates r = magnitudes(j, x, u);
  for (int c = 0; c < 2; ++c)
  {
    if (bounds_.velocity[c] > 0.0)
      r[c] /= bounds_.velocity[c];
    if (bounds_.acceleration[c] > 0.0)
      r[2 + c] = std::sqrt(r[2 + c] / bounds_.acceleration[c]);
  }
  return r;
}

double TimeOptimalSolver::magnitudeOfLevel(int q, double level) const
{
  const int c = q % 2;
  if (q < 2)
    return bounds_.velocity[c] > 0.0 ? level * bounds_.velocity[c] : level;
  return bounds_.acceleration[c] > 0.0 ? level * level * bounds_.acceleration[c] : level;
}

void TimeOptimalSolver::verifyAndStretch()
{
  const std::size_t n = profile_.s.size();
  const std::vector<double>& x = profile_.x;
  const std::vector<double>& u = profile_.u;
  // Every rate's levels at the ends and middle of every interval; an interval is kept where the
  // parabola through a rate's three levels peaks inside at or above that rate's largest level so
  // far (within kRefineMargin). The largest only grows, so no interval left out is searched below
  // (and an unsearched interval's peak, the largest of its checked levels, is at most the largest).
  // One search per rate serves both the stretch (the bounded rates' needs) and the figures (every
  // rate's peak: the stretch scales a rate without moving its peak, x and u alike by 1/k²).
  struct Candidate
  {
    std::size_t i;
    std::array<Rates, 3> at;
  };
  // The acceleration energy comes from the same levels, as the figures would take it (its
  // magnitudes at the three points).
  std::vector<Candidate> candidates;
  Rates top{};
  Energy energy{};
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
    const std::array<Rates, 3> at{ levels(right_[i].raw, x[i], u[i]), levels(middle_[i], 0.5 * (x[i] + x[i + 1]), u[i]),
                                   levels(left(i + 1).raw, x[i + 1], u[i]) };
    const std::array<double, 3> w = energyWeights(profile_, i);
    for (int c = 0; c < 2; ++c)
    {
      const int q = 2 + c;
      energy[c] += energyOfInterval(w, magnitudeOfLevel(q, at[0][q]), magnitudeOfLevel(q, at[1][q]),
                                    magnitudeOfLevel(q, at[2][q]));
    }
    bool keep = false;
    for (int q = 0; q < 4; ++q)
    {
      top[q] = std::max({ top[q], at[0][q], at[1][q], at[2][q] });
      keep = keep || detail::parabolaPeaksInside(at[0][q], at[1][q], at[2][q], top[q] * (1.0 - kRefineMargin));
    }
    if (keep)
      candidates.push_back({ i, at });
  }
  Rates peak = top;
  std::size_t count = 0;
  for (const Candidate& c : candidates)
  {
    checkDeadlineEvery(count++, kIntervalsPerSearchDeadlineCheck, kPhase);
    for (int q = 0; q < 4; ++q)
    {
      const std::array<Rates, 3>& at = c.at;
      if (!detail::parabolaPeaksInside(at[0][q], at[1][q], at[2][q], top[q] * (1.0 - kRefineMargin)))
        continue;
      const std::size_t i = c.i;
      const auto level = [this, i, q](double lambda) { return levelsAt(i, lambda)[q]; };
      peak[q] = std::max(peak[q], detail::localMaxOf(level, at[0][q], at[1][q], at[2][q]));
    }
  }
  double worst = 0.0;
  for (int c = 0; c < 2; ++c)
  {
    if (bounds_.velocity[c] > 0.0)
      worst = std::max(worst, peak[c]);
    if (bounds_.acceleration[c] > 0.0)
      worst = std::max(worst, peak[2 + c]);
  }
  worst = std::max(worst, checkBoxes(-1.0).first);
  const double k = std::max(1.0, worst);
  stretchUniformly(k);
  figures(peak, k, energy);
  boxFigures();
}

void TimeOptimalSolver::stretchUniformly(double k)
{
  profile_.stretch = k;
  if (k > 1.0)
  {
    const double t0 = profile_.t.front();
    for (std::size_t i = 0; i < profile_.s.size(); ++i)
    {
      profile_.t[i] = t0 + (profile_.t[i] - t0) * k;
      profile_.x[i] /= k * k;
    }
    for (double& ui : profile_.u)
      ui /= k * k;
    profile_.recovery_end = t0 + (profile_.recovery_end - t0) * k;
  }
}

std::pair<double, bool> TimeOptimalSolver::checkAfterRecovery(double tighten_margin, Rates* searched)
{
  double worst = 0.0;
  bool tightened = false;
  for (std::size_t i = checkedFrom(); i + 1 < profile_.s.size(); ++i)
  {
    checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
    const IntervalNeeds f = intervalNeeds(i);
    for (int q = 0; q < 4; ++q)
    {
      bool was_searched = false;
      const double p = peak(f, i, q, 1.0 - kRefineMargin, &was_searched);
      if (was_searched)
        (*searched)[q] = std::max((*searched)[q], p);
      worst = std::max(worst, p);
      if (tighten_margin >= 0.0 && p > 1.0 + kFixedStartTolerance)
      {
        tighten(i, q, p, tighten_margin);
        tightened = true;
      }
    }
  }
  return { worst, tightened };
}

bool TimeOptimalSolver::tightenWhereTheCheckExceeds(double margin)
{
  Rates searched{};
  return checkAfterRecovery(margin, &searched).second;
}

void TimeOptimalSolver::verifyFixedStart()
{
  Rates searched{};
  const double worst = std::max(checkAfterRecovery(-1.0, &searched).first, checkBoxes(-1.0).first);
  // A recovery that itself had to exceed an acceleration bound (recovery_excess) is the caller's to
  // refuse or accept: what follows it exceeds because the recovery did.
  if (worst > 1.0 + kFixedStartTolerance && !(profile_.recovery_excess > 1.0 + kRecoveryExcessTolerance))
    throw InterpolationError("timing: the time-optimal motion from the start state exceeds a bound by " +
                             formatNumber(worst - 1.0) + " (relative) after " + std::to_string(kFixedStartPasses) +
                             " corrections; start more slowly or farther from the first waypoint, or raise the "
                             "acceleration bounds");
  profile_.stretch = 1.0;
  figures(searched, 1.0, std::nullopt);
  boxFigures();
}

std::array<double, 4> TimeOptimalSolver::magnitudes(const PathJet& j, double x, double u)
{
  std::array<double, 4> m{};
  for (int c = 0; c < 2; ++c)
  {
    m[c] = std::sqrt(j[c].bb * x);
    m[2 + c] = std::sqrt(std::max(0.0, j[c].aa * x * x + 2.0 * j[c].ab * x * u + j[c].bb * u * u));
  }
  return m;
}

std::array<double, 3> TimeOptimalSolver::energyWeights(const TimingProfile& p, std::size_t i) const
{
  // Nodes 0, τ_m (the time at the middle of the interval in s), h.
  const double x_mid = 0.5 * (p.x[i] + p.x[i + 1]);
  const double h = p.t[i + 1] - p.t[i];
  const double tm = delta(i) / (std::sqrt(p.x[i]) + std::sqrt(x_mid));
  // The integral of the quadratic through (0, g0), (τ_m, g_m), (h, g1): Lagrange weights.
  if (!(h > 0.0 && tm > 0.0 && tm < h))
    return { 0.0, 0.0, 0.0 };
  return { h * (3.0 * tm - h) / (6.0 * tm), h * h * h / (6.0 * tm * (h - tm)),
           h * (2.0 * h - 3.0 * tm) / (6.0 * (h - tm)) };
}

double TimeOptimalSolver::energyOfInterval(const std::array<double, 3>& w, double a, double m, double b)
{
  return w[0] * a * a + w[1] * m * m + w[2] * b * b;
}

void TimeOptimalSolver::figures(const Rates& searched, double k, const std::optional<Energy>& energy)
{
  TimingProfile& p = profile_;
  if (energy)
  {
    // The check of a motion from rest has every rate's peak and the energy before the stretch k:
    // velocities scale by 1/k, accelerations by 1/k², times by k, so the energy by 1/k³.
    for (int c = 0; c < 2; ++c)
    {
      p.max_speed[c] = magnitudeOfLevel(c, searched[c]) / k;
      p.max_acceleration[c] = magnitudeOfLevel(2 + c, searched[2 + c]) / (k * k);
      p.acceleration_energy[c] = (*energy)[c] / (k * k * k);
    }
    return;
  }
  p.max_speed = { 0.0, 0.0 };
  p.max_acceleration = { 0.0, 0.0 };
  p.acceleration_energy = { 0.0, 0.0 };
  for (std::size_t i = 0; i + 1 < p.s.size(); ++i)
  {
    checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
    const double x_mid = 0.5 * (p.x[i] + p.x[i + 1]);
    const std::array<double, 4> a = magnitudes(right_[i].raw, p.x[i], p.u[i]);
    const std::array<double, 4> m = magnitudes(middle_[i], x_mid, p.u[i]);
    const std::array<double, 4> b = magnitudes(left(i + 1).raw, p.x[i + 1], p.u[i]);
    const std::array<double, 3> w = energyWeights(p, i);
    for (int c = 0; c < 2; ++c)
    {
      p.max_speed[c] = std::max({ p.max_speed[c], a[c], m[c], b[c] });
      p.max_acceleration[c] = std::max({ p.max_acceleration[c], a[2 + c], m[2 + c], b[2 + c] });
      p.acceleration_energy[c] += energyOfInterval(w, a[2 + c], m[2 + c], b[2 + c]);
    }
  }
  // Where a parabola through an interval's checked points rises above the peak so far (within
  // kRefineMargin), the peak is searched on the exact rates: every figure is a value the motion
  // takes, within ~1e-7 of its true peak.
  std::array<double, 4> peak{ p.max_speed[0], p.max_speed[1], p.max_acceleration[0], p.max_acceleration[1] };
  for (std::size_t i = 0; i + 1 < p.s.size(); ++i)
  {
    const double x_mid = 0.5 * (p.x[i] + p.x[i + 1]);
    const bool quarters = i < has_quarter_.size() && has_quarter_[i];
    const std::array<double, 4> a = magnitudes(right_[i].raw, p.x[i], p.u[i]);
    const std::array<double, 4> m = magnitudes(middle_[i], x_mid, p.u[i]);
    const std::array<double, 4> b = magnitudes(left(i + 1).raw, p.x[i + 1], p.u[i]);
    std::array<double, 4> qa{}, qb{};
    if (quarters)
    {
      qa = magnitudes(quarter_[2 * i], p.x[i] + 0.25 * (p.x[i + 1] - p.x[i]), p.u[i]);
      qb = magnitudes(quarter_[2 * i + 1], p.x[i] + 0.75 * (p.x[i + 1] - p.x[i]), p.u[i]);
    }
    for (int q = 0; q < 4; ++q)
      peak[q] = std::max(peak[q], magnitudePeak(p, i, q, { a[q], qa[q], m[q], qb[q], b[q] }, quarters,
                                                peak[q] * (1.0 - kRefineMargin)));
  }
  for (int c = 0; c < 2; ++c)
  {
    p.max_speed[c] = std::max(peak[c], magnitudeOfLevel(c, searched[c]) / k);
    p.max_acceleration[c] = std::max(peak[2 + c], magnitudeOfLevel(2 + c, searched[2 + c]) / (k * k));
  }
}

double TimeOptimalSolver::magnitudePeak(const TimingProfile& p, std::size_t i, int q, const std::array<double, 5>& at,
                                        bool quarters, double threshold) const
{
  const auto value = [this, &p, i, q](double lambda) {
    const double x = p.x[i] + lambda * (p.x[i + 1] - p.x[i]);
    return magnitudes(path_.jet(p.s[i] + lambda * delta(i), Side::kRight), x, p.u[i])[q];
  };
  bool searched = false;
  return detail::localMaxOfChecked(value, at, quarters, threshold, &searched);
}

}  // namespace time_optimal_detail
}  // namespace timing
}  // namespace se3_interpolation
