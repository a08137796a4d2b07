#include "se3_interpolation/timing/jerk_limited.h"

#include <deque>
#include <limits>
#include <string>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
namespace timing
{
namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// A change of s̈_T within one window counts as a switch to be given a plateau where it exceeds the
/// window's jerk budget J_s τ by this fraction (eq. 2; below it, the final check's stretch absorbs it).
constexpr double kSwitchTolerance = 1e-3;
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
/// Pieces whose parabola through ends and middle comes within this fraction of the largest value
/// seen are searched for their interior maximum (time_optimal.cpp's margin).
constexpr double kRefineMargin = 1e-3;
/// A moving start cannot be stretched: the underlying bounds are lowered by the excess (with this
/// margin) and everything rerun, at most kFixedStartPasses times, until every rate is within
/// kFixedStartTolerance of its bound.
constexpr int kFixedStartPasses = 8;
constexpr double kFixedStartTolerance = 1e-6;
constexpr double kFixedStartMargin = 1e-3;
/// Relative distance below which a breakpoint of the path counts as the moving start's s_a′.
constexpr double kSameBreakpoint = 1e-12;
constexpr std::size_t kPointsPerDeadlineCheck = 256;
/// Bisection steps for the time at which the motion passes a path parameter (to rounding).
constexpr int kTimeBisectionSteps = 100;
constexpr const char* kPhase = "timing: jerk-limited 'time_optimal'";

const char* const kJerkName[2] = { "max_linear_jerk", "max_angular_jerk" };

/// The six rates in the order v_lin, v_ang, a_lin, a_ang, j_lin, j_ang.
using Rates6 = std::array<double, 6>;

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

void requireJerkBounds(const RateBounds& bounds)
{
  for (int c = 0; c < 2; ++c)
    if (!(std::isfinite(bounds.jerk[c]) && bounds.jerk[c] >= 0.0))
      throw InvalidInputError(std::string(kJerkName[c]) + ": " + formatNumber(bounds.jerk[c]) +
                              " (it must be a finite number, at least 0; 0 means unbounded)");
}

class JerkSolver
{
public:
  JerkSolver(const JerkPathModel& path, const RateBounds& bounds, const JerkLimitedOptions& options)
    : path_(path), bounds_(bounds), options_(options)
  {
    const double sd0 = options.start_speed, sdd0 = options.start_acceleration;
    if (!(std::isfinite(sd0) && sd0 >= 0.0 && std::isfinite(sdd0)))
      throw InvalidInputError("start_state: its speed along the path is " + formatNumber(sd0) +
                              " and its acceleration " + formatNumber(sdd0) +
                              " (the speed must be finite and at least 0, the acceleration finite)");
    fixed_start_ = sd0 > 0.0 || sdd0 != 0.0;
    findMovingChannels();
  }

  /// Whether a jerk bound acts on a channel that moves.
  bool jerkActs() const
  {
    for (int c = 0; c < 2; ++c)
      if (moves_[c] && bounds_.jerk[c] > 0.0)
        return true;
    return false;
  }

  JerkLimitedProfile solve()
  {
    double scale = 1.0;
    for (int pass = 0;; ++pass)
    {
      run(scaled(scale));
      const double k = verify();
      if (!fixed_start_)
      {
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

private:
  /// The channels that move: time_optimal's rule on the path's jets at its breakpoints and the
  /// middles of its pieces.
  void findMovingChannels()
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

  /// The underlying bounds (file comment: a′ = min(a, √(v j))), all lowered by `scale` as a stretch
  /// by that factor would lower the rates.
  RateBounds scaled(double scale) const
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

  /// The three runs of the underlying timing (file comment) and the segments of the result.
  void run(const RateBounds& b)
  {
    under_ = b;
    tau_ = 0.0;
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
        throw InvalidInputError("start_state: the motion starts too fast to come to rest with these jerk bounds "
                                "before path time " + formatNumber(x) +
                                " s; start slower, place the first waypoint farther away, or raise the bounds");
    StoppingPath stopping(path_, s_start);
    const double first_stop = stopping.stops().empty() ? path_.end() : stopping.stops().front();
    if (fixed_start_ && !(s_start < first_stop))
      throw InvalidInputError("start_state: the motion starts too fast to come to rest with these jerk bounds "
                              "before path time " + formatNumber(first_stop) +
                              " s; start slower, place the first waypoint farther away, or raise the bounds");
    TimeOptimalOptions o = options_.grid;
    o.start_speed = lead_speed_;
    o.hold_start = false;
    // The first run evaluates the path's third-order jets at its grid points and caps the speed
    // for the path's share of the jerk there (pathSpeedCap); the later runs reuse them.
    grid_.clear();
    jets_.clear();
    path_caps_.clear();
    o.local_limits = [this](double s) {
      grid_.push_back(s);
      jets_.push_back(path_.jet3(s, s >= path_.end() ? Side::kLeft : Side::kRight));
      path_caps_.push_back(pathSpeedCap(jets_.back()));
      LocalLimit l;
      l.speed_cap = path_caps_.back();
      return l;
    };
    TimingProfile base = timeOptimalProfile(stopping, b, o);
    if (grid_ != base.s)
      throw InterpolationError("timing: the jerk-limited timing's grid changed between its runs");
    factor_.assign(grid_.size(), 1.0);
    cap_.resize(grid_.size());
    for (std::size_t i = 0; i < grid_.size(); ++i)
      cap_[i] = path_caps_[i] * path_caps_[i];
    evaluateSpeeds();
    o.local_limits = [this](double s) { return localLimit(s); };
    // Short segments: lower the acceleration (and the window) by f.
    findSegments(base);
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
    if (short_segments)
      rerun(stopping, b, o, &base);
    // Plateaus where s̈_T switches sign within a window.
    setWindows(base);
    if (addPlateaus(base))
      rerun(stopping, b, o, &base);
    if (seg_tau_.size() != seg_first_.size())
      setWindows(base);
    buildProfile(std::move(base));
  }

  /// The underlying timing again with the local limits; the segments keep their factors (they
  /// stop at the same points: the corners and the ends).
  void rerun(const PathModel& path, const RateBounds& b, const TimeOptimalOptions& o, TimingProfile* base)
  {
    const std::vector<double> f = seg_f_;
    *base = timeOptimalProfile(path, b, o);
    findSegments(*base);
    if (f.size() == seg_f_.size())
      seg_f_ = f;
    else
      seg_tau_.clear();
  }

  /// The underlying timing's local limit at a grid point (the previous run's grid: the grid
  /// depends on the path and the options only).
  LocalLimit localLimit(double s) const
  {
    LocalLimit l;
    const auto it = std::lower_bound(grid_.begin(), grid_.end(), s);
    if (it == grid_.end() || *it != s)
      return l;
    const std::size_t i = static_cast<std::size_t>(it - grid_.begin());
    l.acceleration_factor = factor_[i];
    l.speed_cap = std::sqrt(cap_[i]);
    return l;
  }

  /// The path's share of the jerk at (ṡ, s̈) (eq. 1 without C′ s⃛): |C‴| ṡ³ + 3 |C″| ṡ |s̈|,
  /// relative to the bound, the largest over the jerk-bounded channels.
  double pathJerkShare(const PathJet3& j, double sd, double sdd) const
  {
    double share = 0.0;
    for (int c = 0; c < 2; ++c)
      if (moves_[c] && under_.jerk[c] > 0.0)
        share = std::max(share, (std::sqrt(j[c].cc) * sd * sd * sd + 3.0 * std::sqrt(j[c].aa) * sd * std::abs(sdd)) /
                                    under_.jerk[c]);
    return share;
  }

  /// The speed at which the path's jerk at constant ṡ, |C‴| ṡ³, is kPathJerkShare of the bound,
  /// the least over the channels; ∞ where C‴ = 0 (a straight line).
  double pathSpeedCap(const PathJet3& j) const
  {
    double cap = kInf;
    for (int c = 0; c < 2; ++c)
      if (moves_[c] && under_.jerk[c] > 0.0 && j[c].cc > 0.0)
        cap = std::min(cap, std::cbrt(kPathJerkShare * under_.jerk[c] / std::sqrt(j[c].cc)));
    return cap;
  }

  /// The jerk budget of the window in path units at each grid point: J_s = min_c j_c / |C′_c|
  /// over the moving, jerk-bounded channels.
  void evaluateSpeeds()
  {
    jerk_s_.assign(grid_.size(), kInf);
    for (std::size_t i = 0; i < grid_.size(); ++i)
      for (int c = 0; c < 2; ++c)
        if (moves_[c] && under_.jerk[c] > 0.0 && jets_[i][c].bb > 0.0)
          jerk_s_[i] = std::min(jerk_s_[i], under_.jerk[c] / std::sqrt(jets_[i][c].bb));
  }

  /// The window of each segment: f τ, widened by 1/(1 − β) where the path takes the share β of
  /// the jerk (pathJerkShare at the timing's speeds, at most kPathJerkShare by the caps).
  void setWindows(const TimingProfile& base)
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
          const double u = std::max(i > seg_first_[k] ? std::abs(base.u[i - 1]) : 0.0,
                                    i < seg_last_[k] ? std::abs(base.u[i]) : 0.0);
          share = std::max(share, pathJerkShare(jets_[i], std::sqrt(base.x[i]), u));
        }
      seg_budget_[k] = 1.0 - std::min(share, kPathJerkShare);
      seg_tau_[k] = seg_f_[k] * tau_ / seg_budget_[k];
    }
  }

  /// The segments of the underlying timing: between its interior points at rest.
  void findSegments(const TimingProfile& base)
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

  /// The crossing of x = c² on the branch from grid point p towards `step` (±1), within [lo, hi]:
  /// its path parameter and the length of the grid interval it lies in.
  static std::pair<double, double> crossing(const TimingProfile& b, std::size_t p, int step, double x,
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

  /// Caps the grid points on [lo, hi] at x.
  void cap(double lo, double hi, double x)
  {
    for (auto it = std::lower_bound(grid_.begin(), grid_.end(), lo); it != grid_.end() && *it <= hi; ++it)
    {
      const std::size_t i = static_cast<std::size_t>(it - grid_.begin());
      cap_[i] = std::min(cap_[i], x);
    }
  }

  /// Finds where s̈_T changes sign by more than the window's budget within one window (eq. 2) and
  /// caps ṡ there for a cruise of τ (file comment). Returns whether any cap was added.
  bool addPlateaus(const TimingProfile& b)
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
        while (b.t[window + 1] <= b.t[i] - tau)
        {
          if (high.front() == window)
            high.pop_front();
          if (low.front() == window)
            low.pop_front();
          ++window;
        }
        const double budget =
            std::min(jerk_s_[i], jerk_s_[i + 1]) * seg_budget_[k] * tau * (1.0 + kSwitchTolerance);
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

  /// The highest cap below the peak at grid point p whose cruise lasts τ (bisection on the
  /// timing's own ṡ(s), which the cap leaves unchanged below it).
  bool capPeak(const TimingProfile& b, std::size_t p, std::size_t first, std::size_t last, double tau)
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

  /// The profile from the underlying timing: segments, their windows and integrals.
  void buildProfile(TimingProfile base)
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

  /// The rates at base time tb of segment g (one-sided), with the path's jet given.
  static Rates6 rates(const PathJet3& j, const Jet<3>& s)
  {
    const double sd = s.derivative(1), sdd = s.derivative(2), sddd = s.derivative(3);
    Rates6 r{};
    for (int c = 0; c < 2; ++c)
    {
      r[c] = j[c].speed(sd);
      r[2 + c] = j[c].acceleration(sd, sdd);
      r[4 + c] = j[c].jerk(sd, sdd, sddd);
    }
    return r;
  }

  /// The path's side at s within segment g (time side while moving; at its ends, inwards).
  Side pathSide(const JerkLimitedProfile::Segment& g, double s, Side side) const
  {
    if (s >= profile_.base.s[g.last])
      return Side::kLeft;
    if (s <= g.s_start)
      return Side::kRight;
    return side;
  }

  /// The Taylor coefficients of the cubic p at h from those at 0: s(t) is a cubic polynomial on
  /// each piece, so the jet at its middle gives it exactly on the whole piece, ends included
  /// (one-sided by construction: no rounding of t − τ can pick a neighbouring piece).
  static Jet<3> shifted(const Jet<3>& p, double h)
  {
    const double c0 = p.coefficient(0), c1 = p.coefficient(1), c2 = p.coefficient(2), c3 = p.coefficient(3);
    Jet<3> q(c0 + h * (c1 + h * (c2 + h * c3)));
    q.coefficient(1) = c1 + h * (2.0 * c2 + 3.0 * h * c3);
    q.coefficient(2) = c2 + 3.0 * h * c3;
    q.coefficient(3) = c3;
    return q;
  }

  /// The path's jet at s within segment g: s clamped to the segment (the cubic of a piece
  /// evaluated at its end rounds to either side of a stop), from `side` inside, inwards at its ends.
  PathJet3 segmentPathJet(const JerkLimitedProfile::Segment& g, double s, Side side) const
  {
    const double c = std::min(std::max(s, g.s_start), profile_.base.s[g.last]);
    return path_.jet3(c, pathSide(g, c, side));
  }

  /// The rates at the point of a piece whose cubic is `s` (inside the piece: no breakpoint).
  Rates6 ratesInside(const JerkLimitedProfile::Segment& g, const Jet<3>& s) const
  {
    return rates(segmentPathJet(g, s.value(), Side::kRight), s);
  }

  /// The pieces of segment g in base time: the grid's times, shifted by τ, and the passages of the
  /// path's breakpoints; `crossing` holds the breakpoint passed at each time (NaN: none), where
  /// the path's C‴ jumps.
  void pieces(const JerkLimitedProfile::Segment& g, const std::vector<double>& path_breaks, std::vector<double>* times,
              std::vector<double>* crossing) const
  {
    const TimingProfile& b = profile_.base;
    std::vector<double> t;
    t.reserve(2 * (g.last - g.first + 1));
    std::size_t i = g.first, j = g.first;
    while (i <= g.last || j <= g.last)
    {
      const double a = i <= g.last ? b.t[i] : kInf;
      const double c = j <= g.last ? b.t[j] + g.tau : kInf;
      if (a <= c)
      {
        t.push_back(a);
        ++i;
      }
      else
      {
        t.push_back(c);
        ++j;
      }
    }
    std::vector<double> cross, cross_s;
    const double sa = g.s_start, sb = b.s[g.last];
    for (auto it = std::upper_bound(path_breaks.begin(), path_breaks.end(), sa);
         it != path_breaks.end() && *it < sb; ++it)
    {
      cross.push_back(profile_.segmentTime(g, *it));
      cross_s.push_back(*it);
    }
    times->clear();
    crossing->clear();
    std::size_t k = 0;
    for (double x : t)
    {
      while (k < cross.size() && cross[k] <= x)
      {
        if (times->empty() || cross[k] > times->back())
        {
          times->push_back(cross[k]);
          crossing->push_back(cross_s[k]);
        }
        else
        {
          crossing->back() = cross_s[k];
        }
        ++k;
      }
      if (times->empty() || x > times->back())
      {
        times->push_back(x);
        crossing->push_back(kNaN);
      }
    }
  }

  /// The final check (file comment): the peaks of the six rates over every piece, the figures,
  /// and the stretch k they need. Returns k.
  double verify()
  {
    const std::vector<double> path_breaks = path_.breakpoints();
    struct Piece
    {
      std::size_t segment;
      double lo, hi;
      Jet<3> middle;  ///< s at the middle: the piece's cubic
      Rates6 f0, fm, f1;
    };
    std::vector<Piece> all;
    Rates6 peak{};
    std::vector<double> times;
    std::vector<double> crossing;
    std::vector<double>& motion_breaks = profile_.breakpoints;
    motion_breaks.clear();
    std::size_t count = 0;
    for (std::size_t k = 0; k < profile_.segments.size(); ++k)
    {
      const auto& g = profile_.segments[k];
      pieces(g, path_breaks, &times, &crossing);
      const double shift = g.start - g.baseStart(profile_.base);
      for (std::size_t i = 0; i < times.size(); ++i)
        if (motion_breaks.empty() || times[i] + shift > motion_breaks.back())
          motion_breaks.push_back(times[i] + shift);
      // The path jet at each piece boundary: one for both sides unless a path breakpoint is
      // passed there (evaluated at the breakpoint itself, from each side).
      PathJet3 jl{};
      for (std::size_t i = 0; i + 1 < times.size(); ++i)
      {
        checkDeadlineEvery(count++, kPointsPerDeadlineCheck / 4, kPhase);
        const double lo = times[i], hi = times[i + 1], mid = 0.5 * (lo + hi);
        Piece p{ k, lo, hi, profile_.segmentParameter(g, Jet<3>::variable(mid), Side::kRight), {}, {}, {} };
        const Jet<3> sr = shifted(p.middle, lo - mid), sl = shifted(p.middle, hi - mid);
        PathJet3 jr = jl;
        if (i == 0)
          jr = segmentPathJet(g, sr.value(), Side::kRight);
        else if (!std::isnan(crossing[i]))
          jr = segmentPathJet(g, crossing[i], Side::kRight);
        p.f0 = rates(jr, sr);
        p.fm = ratesInside(g, p.middle);
        jl = segmentPathJet(g, std::isnan(crossing[i + 1]) ? sl.value() : crossing[i + 1], Side::kLeft);
        p.f1 = rates(jl, sl);
        for (int q = 0; q < 6; ++q)
          peak[q] = std::max({ peak[q], p.f0[q], p.fm[q], p.f1[q] });
        all.push_back(p);
      }
    }
    // The interior maxima where the parabola through ends and middle peaks near the largest value.
    count = 0;
    for (const Piece& p : all)
    {
      checkDeadlineEvery(count++, kPointsPerDeadlineCheck / 16, kPhase);
      const auto& g = profile_.segments[p.segment];
      for (int q = 0; q < 6; ++q)
      {
        if (!detail::parabolaPeaksInside(p.f0[q], p.fm[q], p.f1[q], peak[q] * (1.0 - kRefineMargin)))
          continue;
        peak[q] = std::max(peak[q], detail::localMaxOf(
                                        [&](double lambda) {
                                          const double h = (lambda - 0.5) * (p.hi - p.lo);
                                          return ratesInside(g, shifted(p.middle, h))[q];
                                        },
                                        p.f0[q], p.fm[q], p.f1[q]));
      }
    }
    peak_ = peak;
    double k = 1.0;
    for (int c = 0; c < 2; ++c)
    {
      if (bounds_.velocity[c] > 0.0)
        k = std::max(k, peak[c] / bounds_.velocity[c]);
      if (bounds_.acceleration[c] > 0.0)
        k = std::max(k, std::sqrt(peak[2 + c] / bounds_.acceleration[c]));
      if (bounds_.jerk[c] > 0.0)
        k = std::max(k, std::cbrt(peak[4 + c] / bounds_.jerk[c]));
    }
    return k;
  }

  /// Runs the motion slower by k and sets the figures.
  void applyStretch(double k)
  {
    JerkLimitedProfile& p = profile_;
    p.stretch = k;
    for (double& t : p.breakpoints)
      t = p.t0 + (t - p.t0) * k;
    for (int c = 0; c < 2; ++c)
    {
      p.max_speed[c] = peak_[c] / k;
      p.max_acceleration[c] = peak_[2 + c] / (k * k);
      p.max_jerk[c] = peak_[4 + c] / (k * k * k);
    }
  }

  const JerkPathModel& path_;
  RateBounds bounds_;
  JerkLimitedOptions options_;
  bool fixed_start_ = false;
  std::array<bool, 2> moves_{};
  RateBounds under_;          ///< the underlying timing's bounds of the current run
  double tau_ = 0.0;          ///< the window before the short segments' factor
  double lead_speed_ = 0.0;   ///< ṡ_T0
  std::vector<double> grid_;  ///< the underlying grid
  std::vector<double> factor_;  ///< its acceleration factor at each grid point
  std::vector<double> cap_;     ///< its cap on x at each grid point
  std::vector<double> jerk_s_;  ///< J_s at each grid point
  std::vector<PathJet3> jets_;  ///< the path's third-order jets at the grid points
  std::vector<double> path_caps_;  ///< pathSpeedCap at the grid points
  std::vector<double> seg_tau_;     ///< the window of each segment
  std::vector<double> seg_budget_;  ///< 1 − β: the window's share of the jerk in each segment
  std::vector<std::size_t> seg_first_, seg_last_;
  std::vector<double> seg_f_;   ///< the short-segment factor f of each segment
  Rates6 peak_{};
  JerkLimitedProfile profile_;
};
}  // namespace

double JerkLimitedProfile::segmentTime(const Segment& g, double path_parameter) const
{
  if (path_parameter <= g.s_start)
    return base.t[g.first];
  if (path_parameter >= base.s[g.last])
    return base.t[g.last] + g.tau;
  // s(t) is nondecreasing and passes s between the base's passage and τ after it.
  double lo = std::max(base.t[g.first], base.timeAt(path_parameter));
  double hi = std::min(lo + g.tau, base.t[g.last] + g.tau);
  for (int step = 0; step < kTimeBisectionSteps; ++step)
  {
    const double mid = 0.5 * (lo + hi);
    if (!(mid > lo && mid < hi))
      break;
    (segmentParameter(g, mid, Side::kRight) < path_parameter ? lo : hi) = mid;
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
  requireJerkBounds(bounds);
  JerkSolver solver(path, bounds, options);
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
    for (int c = 0; c < 2; ++c)
      p.max_jerk[c] = p.max_acceleration[c] > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    return p;
  }
  return solver.solve();
}

}  // namespace timing
}  // namespace se3_interpolation
