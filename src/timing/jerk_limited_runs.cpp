// The runs of the underlying time-optimal timing of the jerk-limited timing (timing/jerk_limited.h,
// its file comment): the stopping path, the three runs with their local limits (the path's share
// of the jerk, the short segments' factors, the plateaus' caps), the segments' windows, and the
// profile built from the last run. The solver is declared in jerk_limited_solver.h.
#include <algorithm>
#include <cmath>
#include <deque>
#include <string>
#include <utility>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "jerk_limited_solver.h"
#include "time_optimal_solver.h"

namespace se3_interpolation
{
namespace timing
{
namespace jerk_limited_detail
{
namespace
{
/// A change of s̈_T within one window counts as a switch to be given a plateau where it exceeds the
/// window's jerk budget J_s τ by this fraction (eq. 2; below it, the final check's stretch absorbs it).
constexpr double kSwitchTolerance = 1e-3;
/// Local passes of the underlying timing's last run from rest (TimeOptimalSolver::localPasses):
/// where the middle of a grid interval exceeds a bound, the bound is tightened there, so that the
/// final check's uniform stretch does not slow the whole motion for one interval. One: the
/// tightenings after it are below 1e-4 (time_optimal's kLocalTolerance), far below the stretch
/// the jerk bounds ask of the final check; on test_jerk_limited's paths and bench_time_optimal's
/// 1000 waypoints the durations with one pass and with time_optimal's four agree to 2e-6.
constexpr int kUnderlyingLocalPasses = 1;
/// Bisection steps for a peak's cap (to rounding of ṡ).
constexpr int kCapBisectionSteps = 60;
/// The largest share β of the jerk bound left to the path's terms of eq. 1 (|C‴| ṡ³ + 3 |C″| ṡ s̈):
/// the speed is capped so that |C‴| ṡ³ keeps to it, and each segment's window is widened by
/// 1/(1 − β), β the share its path terms take (at most this), so that the window's term C′ s⃛
/// keeps to the rest. Half: an even split between the window's term and the path's.
constexpr double kPathJerkShare = 0.5;
/// Segments shorter than this many windows are short moves (Biagiotti & Melchiorri §3.4, neither
/// v_max nor a_max reached: L < 2 a³/j², for the triangular underlying profile T = 2√(L/a) < 2√2 τ).
constexpr double kShortSegment = 2.8284271247461903;
/// Relative distance below which a breakpoint of the path counts as the moving start's s_a′.
constexpr double kSameBreakpoint = 1e-12;
/// Where the path nearly stands still (C′ → 0: a clamped end at rest, a cusp), the acceleration
/// bounds do not limit s̈_T, and the first run accelerates the path parameter almost without
/// limit; a window later the motion is where C′ is not small, and the window's term C′ s⃛ =
/// C′ (s̈_T(t) − s̈_T(t − τ)) / τ is then far beyond the jerk bound (a clamped interpolating spline
/// was stretched 265 times by the final check). So |s̈_T| at a grid point is capped at what the
/// acceleration bounds allow where the motion passes within a window of it, A / max |C′| over the
/// base times [t_i − τ, t_i + τ], wherever that max is more than this factor above the point's own
/// |C′| (elsewhere the point's own bound A / |C′| is as tight, and nothing changes). Only when the
/// final check of the run without the caps asks for a stretch above kStationaryStretch
/// (jerk_limited.cpp): the caps cost a run, and on most paths they change little.
constexpr double kStationaryGrowth = 2.0;

/// The path as the underlying timing sees it: starting at `start` (the moving start's s_a′), and
/// with stops where C″ jumps as well as at velocity corners.
class StoppingPath final : public PathModel
{
public:
  StoppingPath(const JerkPathModel& path, double start) : path_(path), start_(start)
  {
    const std::vector<double> b = path_.breakpoints();
    breakpoints_.push_back(start_);
    for (double x : b)
      if (x > start_ + kSameBreakpoint * std::max(1.0, std::abs(start_)))
        breakpoints_.push_back(x);
    for (std::size_t i = 1; i + 1 < breakpoints_.size(); ++i)
    {
      checkDeadlineEvery(i, kPointsPerDeadlineCheck / 4, kPhase);
      const double s = breakpoints_[i];
      const double h = std::min(s - breakpoints_[i - 1], breakpoints_[i + 1] - s);
      if (path_.isCorner(s) || path_.accelerationJumps(s, h))
        stops_.push_back(s);
    }
  }
  double start() const override { return start_; }
  double end() const override { return path_.end(); }
  std::vector<double> breakpoints() const override { return breakpoints_; }
  PathJet jet(double s, Side side) const override { return path_.jet(s, side); }
  bool isCorner(double s) const override { return std::binary_search(stops_.begin(), stops_.end(), s); }
  const std::vector<double>& stops() const { return stops_; }

private:
  const JerkPathModel& path_;
  double start_;
  std::vector<double> breakpoints_;
  std::vector<double> stops_;
};
}  // namespace

void JerkSolver::run(const RateBounds& b)
{
  const double s_start = startRun(b);
  StoppingPath stopping(path_, s_start);
  const double first_stop = stopping.stops().empty() ? path_.end() : stopping.stops().front();
  if (fixed_start_ && !(s_start < first_stop))
    throw InvalidInputError(
        "start_state: the motion starts too fast to come to rest with these jerk bounds "
        "before path time " +
        formatNumber(first_stop) + " s; start slower, place the first waypoint farther away, or raise the bounds");
  TimeOptimalOptions o = options_.grid;
  o.start_speed = lead_speed_;
  o.hold_start = false;
  collectGridJets(stopping.breakpoints().size() - 1, &o);
  // One solver for all runs: the grid and its jets depend on the path and the grid options only,
  // so the reruns reuse them (TimeOptimalSolver::firstPassAgain). Each run's first pass decides
  // the next run; only the last gets local passes (kUnderlyingLocalPasses), and its final check
  // only for a moving start (whose corrections it makes): from rest, the final check of the
  // jerk-limited motion (verify) holds it to the bounds and stretches it once.
  time_optimal_detail::TimeOptimalSolver underlying(stopping, b, o, true);
  TimingProfile base = underlying.firstPass();
  if (grid_ != base.s)
    throw InterpolationError("timing: the jerk-limited timing's grid changed between its runs");
  factor_.assign(grid_.size(), 1.0);
  cap_.resize(grid_.size());
  for (std::size_t i = 0; i < grid_.size(); ++i)
    cap_[i] = path_caps_[i] * path_caps_[i];
  evaluateSpeeds();
  o.local_limits = [this](double s) { return localLimit(s); };
  findSegments(base);
  if (cap_stationary_ && capStationaryPoints(base))
    rerun(&underlying, o, &base);
  if (slowShortSegments(base))
    rerun(&underlying, o, &base);
  // Plateaus where s̈_T switches sign within a window.
  setWindows(base);
  if (addPlateaus(base))
    rerun(&underlying, o, &base);
  base = fixed_start_ ? underlying.finish() : underlying.localPasses(kUnderlyingLocalPasses);
  keepSegments(base);
  if (seg_tau_.size() != seg_first_.size())
    setWindows(base);
  buildProfile(std::move(base));
}

double JerkSolver::startRun(const RateBounds& b)
{
  under_ = b;
  tau_ = options_.window;
  for (int c = 0; c < 2; ++c)
    if (moves_[c] && b.jerk[c] > 0.0 && b.acceleration[c] > 0.0)
      tau_ = std::max(tau_, b.acceleration[c] / b.jerk[c]);
  // The moving start: the underlying timing starts at s_a′ at ṡ_T0 (file comment).
  const double sd0 = options_.start_speed, sdd0 = options_.start_acceleration;
  lead_speed_ = sd0 + 0.5 * sdd0 * tau_;
  const double s_start = path_.start() + 0.5 * lead_speed_ * tau_ - sdd0 * tau_ * tau_ / 6.0;
  if (fixed_start_ && !(lead_speed_ >= 0.0 && lead_speed_ - sdd0 * tau_ >= 0.0))
    throw InvalidInputError("start_state: it brakes along the path at " + formatNumber(sdd0) +
                            " while moving at only " + formatNumber(sd0) +
                            " (the jerk-limited timing needs a speed of at least |acceleration| * " +
                            formatNumber(0.5 * tau_) + " s)");
  for (double x : path_.breakpoints())
    if (fixed_start_ && x > path_.start() && x <= s_start &&
        (path_.isCorner(x) || path_.accelerationJumps(x, x - path_.start())))
      throw InvalidInputError(
          "start_state: the motion starts too fast to come to rest with these jerk bounds "
          "before path time " +
          formatNumber(x) + " s; start slower, place the first waypoint farther away, or raise the bounds");
  return s_start;
}

void JerkSolver::collectGridJets(std::size_t pieces, TimeOptimalOptions* o)
{
  // The first run evaluates the path's third-order jets at its grid points and caps the speed
  // for the path's share of the jerk there (pathSpeedCap); the later runs reuse them.
  grid_.clear();
  u_cap_.clear();
  jets_.clear();
  path_caps_.clear();
  {
    // (Room for the grid: about twice the uniform one at most, time_optimal.cpp.)
    const std::size_t uniform = std::max(o->min_intervals, pieces * o->intervals_per_piece) + pieces + 1;
    grid_.reserve(2 * uniform);
    jets_.reserve(2 * uniform);
    path_caps_.reserve(2 * uniform);
  }
  o->local_limits = [this](double s) {
    grid_.push_back(s);
    jets_.push_back(path_.jet3(s, s >= path_.end() ? Side::kLeft : Side::kRight));
    path_caps_.push_back(pathSpeedCap(jets_.back()));
    LocalLimit l;
    l.speed_cap = path_caps_.back();
    return l;
  };
}

bool JerkSolver::slowShortSegments(const TimingProfile& base)
{
  // Short segments: lower the acceleration (and the window) by f.
  bool short_segments = false;
  for (std::size_t k = 0; k < seg_first_.size(); ++k)
  {
    const double duration = base.t[seg_last_[k]] - base.t[seg_first_[k]];
    if ((k > 0 || !fixed_start_) && duration < kShortSegment * tau_)
    {
      seg_f_[k] = std::cbrt(duration * duration / (8.0 * tau_ * tau_));
      short_segments = true;
      for (std::size_t i = seg_first_[k]; i <= seg_last_[k]; ++i)
        factor_[i] = std::min(factor_[i], seg_f_[k]);
    }
  }
  return short_segments;
}

bool JerkSolver::capStationaryPoints(const TimingProfile& base)
{
  const std::size_t n = grid_.size();
  u_cap_.assign(n, kInf);
  bool capped = false;
  for (int c = 0; c < 2; ++c)
  {
    if (!(moves_[c] && under_.jerk[c] > 0.0 && under_.acceleration[c] > 0.0))
      continue;
    const auto speed = [&](std::size_t j) { return std::sqrt(jets_[j][c].bb); };
    for (std::size_t k = 0; k < seg_first_.size(); ++k)
    {
      // The largest |C′| over the base times [t_i − τ, t_i + τ] within the segment of i (each has
      // its own windows): a sliding maximum (a deque of indices with decreasing |C′|), both ends
      // moving forward with i. An interior stop's jet is its right side's, the next segment's: it
      // belongs to that segment.
      const std::size_t first = seg_first_[k];
      const std::size_t last = k + 1 < seg_first_.size() ? seg_last_[k] - 1 : seg_last_[k];
      std::deque<std::size_t> window;
      std::size_t ahead = first;
      for (std::size_t i = first; i <= last; ++i)
      {
        checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
        while (ahead <= last && base.t[ahead] <= base.t[i] + tau_)
        {
          while (!window.empty() && speed(window.back()) <= speed(ahead))
            window.pop_back();
          window.push_back(ahead++);
        }
        while (base.t[window.front()] < base.t[i] - tau_)
          window.pop_front();
        const double largest = speed(window.front());
        if (largest > kStationaryGrowth * speed(i))
        {
          u_cap_[i] = std::min(u_cap_[i], under_.acceleration[c] / largest);
          capped = true;
        }
      }
    }
  }
  return capped;
}

void JerkSolver::rerun(time_optimal_detail::TimeOptimalSolver* underlying, const TimeOptimalOptions& o,
                       TimingProfile* base)
{
  *base = underlying->firstPassAgain(o);
  keepSegments(*base);
}

void JerkSolver::keepSegments(const TimingProfile& base)
{
  const std::vector<double> f = seg_f_;
  findSegments(base);
  if (f.size() == seg_f_.size())
    seg_f_ = f;
  else
    seg_tau_.clear();
}

LocalLimit JerkSolver::localLimit(double s) const
{
  LocalLimit l;
  const auto it = std::lower_bound(grid_.begin(), grid_.end(), s);
  if (it == grid_.end() || *it != s)
    return l;
  const std::size_t i = static_cast<std::size_t>(it - grid_.begin());
  l.acceleration_factor = factor_[i];
  l.speed_cap = std::sqrt(cap_[i]);
  l.path_acceleration_cap = u_cap_.empty() ? kInf : u_cap_[i];
  return l;
}

double JerkSolver::pathJerkShare(const PathJet3& j, double sd, double sdd) const
{
  double share = 0.0;
  for (int c = 0; c < 2; ++c)
    if (moves_[c] && under_.jerk[c] > 0.0)
      share = std::max(share, (std::sqrt(j[c].cc) * sd * sd * sd + 3.0 * std::sqrt(j[c].aa) * sd * std::abs(sdd)) /
                                  under_.jerk[c]);
  return share;
}

double JerkSolver::pathSpeedCap(const PathJet3& j) const
{
  double cap = kInf;
  for (int c = 0; c < 2; ++c)
    if (moves_[c] && under_.jerk[c] > 0.0 && j[c].cc > 0.0)
      cap = std::min(cap, std::cbrt(kPathJerkShare * under_.jerk[c] / std::sqrt(j[c].cc)));
  return cap;
}

void JerkSolver::evaluateSpeeds()
{
  jerk_s_.assign(grid_.size(), kInf);
  for (std::size_t i = 0; i < grid_.size(); ++i)
    for (int c = 0; c < 2; ++c)
      if (moves_[c] && under_.jerk[c] > 0.0 && jets_[i][c].bb > 0.0)
        jerk_s_[i] = std::min(jerk_s_[i], under_.jerk[c] / std::sqrt(jets_[i][c].bb));
}

void JerkSolver::setWindows(const TimingProfile& base)
{
  seg_tau_.assign(seg_first_.size(), 0.0);
  seg_budget_.assign(seg_first_.size(), 1.0);
  for (std::size_t k = 0; k < seg_first_.size(); ++k)
  {
    double share = 0.0;
    // (The first segment of a moving start keeps the window its start was laid out for.)
    if (k > 0 || !fixed_start_)
      for (std::size_t i = seg_first_[k]; i <= seg_last_[k]; ++i)
      {
        const double u =
            std::max(i > seg_first_[k] ? std::abs(base.u[i - 1]) : 0.0, i < seg_last_[k] ? std::abs(base.u[i]) : 0.0);
        share = std::max(share, pathJerkShare(jets_[i], std::sqrt(base.x[i]), u));
      }
    seg_budget_[k] = 1.0 - std::min(share, kPathJerkShare);
    seg_tau_[k] = seg_f_[k] * tau_ / seg_budget_[k];
  }
}

void JerkSolver::findSegments(const TimingProfile& base)
{
  seg_first_.assign(1, 0);
  seg_last_.clear();
  for (std::size_t i = 1; i + 1 < base.s.size(); ++i)
    if (base.x[i] == 0.0)
    {
      seg_last_.push_back(i);
      seg_first_.push_back(i);
    }
  seg_last_.push_back(base.s.size() - 1);
  seg_f_.assign(seg_first_.size(), 1.0);
}

std::pair<double, double> JerkSolver::crossing(const TimingProfile& b, std::size_t p, int step, double x,
                                               std::size_t lo, std::size_t hi)
{
  std::size_t i = p;
  while (b.x[i] > x && i != (step < 0 ? lo : hi))
    i = step < 0 ? i - 1 : i + 1;
  const std::size_t j = step < 0 ? i + 1 : i - 1;  // the neighbour above x
  if (b.x[i] > x || j == i)
    return { b.s[i], 0.0 };
  const double lambda = (x - b.x[i]) / (b.x[j] - b.x[i]);
  return { b.s[i] + lambda * (b.s[j] - b.s[i]), std::abs(b.s[j] - b.s[i]) };
}

void JerkSolver::cap(double lo, double hi, double x)
{
  for (auto it = std::lower_bound(grid_.begin(), grid_.end(), lo); it != grid_.end() && *it <= hi; ++it)
  {
    const std::size_t i = static_cast<std::size_t>(it - grid_.begin());
    cap_[i] = std::min(cap_[i], x);
  }
}

bool JerkSolver::addPlateaus(const TimingProfile& b)
{
  bool added = false;
  for (std::size_t k = 0; k < seg_first_.size(); ++k)
  {
    const std::size_t first = seg_first_[k], last = seg_last_[k];
    const double tau = seg_tau_[k];
    std::deque<std::size_t> high, low;  // interval indices with decreasing / increasing u
    std::size_t window = first;
    std::size_t done_peak = first, done_dip = first;  // extrema handled (grid points)
    for (std::size_t i = first; i < last; ++i)
    {
      checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
      while (!high.empty() && b.u[high.back()] <= b.u[i])
        high.pop_back();
      high.push_back(i);
      while (!low.empty() && b.u[low.back()] >= b.u[i])
        low.pop_back();
      low.push_back(i);
      // The window never passes i (which both deques hold): with a τ that is not positive, or
      // intervals of zero duration, it ran off the profile (a sphere request found by fuzz_sphere,
      // test/fuzz/corpus_sphere/jerk_window_overrun).
      while (window < i && b.t[window + 1] <= b.t[i] - tau)
      {
        if (high.front() == window)
          high.pop_front();
        if (low.front() == window)
          low.pop_front();
        ++window;
      }
      const double budget = std::min(jerk_s_[i], jerk_s_[i + 1]) * seg_budget_[k] * tau * (1.0 + kSwitchTolerance);
      const std::size_t h = high.front(), l = low.front();
      if (b.u[i] < 0.0 && b.u[h] > 0.0 && b.u[h] - b.u[i] > budget && h + 1 > done_peak)
      {
        std::size_t p = h + 1;
        for (std::size_t q = h + 1; q <= i; ++q)
          if (b.x[q] > b.x[p])
            p = q;
        done_peak = i + 1;
        added = capPeak(b, p, first, last, tau) || added;
      }
      if (b.u[i] > 0.0 && b.u[l] < 0.0 && b.u[i] - b.u[l] > budget && l + 1 > done_dip)
      {
        std::size_t p = l + 1;
        for (std::size_t q = l + 1; q <= i; ++q)
          if (b.x[q] < b.x[p])
            p = q;
        done_dip = i + 1;
        const double c = std::sqrt(b.x[p]);
        const double grid_step = std::max(b.s[p] - b.s[p - 1], b.s[p + 1] - b.s[p]);
        const double half = 0.5 * c * tau + grid_step;
        cap(b.s[p] - half, b.s[p] + half, b.x[p]);
        added = true;
      }
    }
  }
  return added;
}

bool JerkSolver::capPeak(const TimingProfile& b, std::size_t p, std::size_t first, std::size_t last, double tau)
{
  double lo = 0.0, hi = std::sqrt(b.x[p]);
  std::pair<double, double> range{ b.s[p], b.s[p] };
  for (int step = 0; step < kCapBisectionSteps; ++step)
  {
    const double c = 0.5 * (lo + hi);
    const auto left = crossing(b, p, -1, c * c, first, last);
    const auto right = crossing(b, p, 1, c * c, first, last);
    const double cruise = right.first - left.first - left.second - right.second;
    if (cruise >= c * tau)
    {
      lo = c;
      range = { left.first, right.first };
    }
    else
    {
      hi = c;
    }
  }
  if (!(lo > 0.0))
    return false;
  cap(range.first, range.second, lo * lo);
  return true;
}

void JerkSolver::buildProfile(TimingProfile base)
{
  profile_ = JerkLimitedProfile();
  profile_.t0 = path_.start();
  double start = profile_.t0;
  for (std::size_t k = 0; k < seg_first_.size(); ++k)
  {
    JerkLimitedProfile::Segment g;
    g.first = seg_first_[k];
    g.last = seg_last_[k];
    g.tau = seg_tau_[k];
    g.start = start;
    g.s_start = k == 0 ? path_.start() : base.s[g.first];
    if (k == 0)
    {
      g.lead_speed = lead_speed_;
      g.lead_acceleration = options_.start_acceleration;
    }
    g.integral.assign(g.last - g.first + 1, 0.0);
    const double sa = base.s[g.first];
    for (std::size_t i = g.first; i < g.last; ++i)
    {
      const double h = base.t[i + 1] - base.t[i];
      g.integral[i + 1 - g.first] = g.integral[i - g.first] + (base.s[i] - sa) * h +
                                    0.5 * std::sqrt(base.x[i]) * h * h + base.u[i] / 6.0 * h * h * h;
    }
    start += g.duration(base);
    profile_.segments.push_back(std::move(g));
  }
  profile_.base = std::move(base);
}

}  // namespace jerk_limited_detail
}  // namespace timing
}  // namespace se3_interpolation
