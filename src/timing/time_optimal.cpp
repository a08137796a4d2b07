#include "se3_interpolation/timing/time_optimal.h"

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
/// Bisection of the controllable sets' upper ends: relative width (rounding level of x).
constexpr double kBisectionTolerance = 1e-12;
constexpr int kBisectionSteps = 200;
/// Intervals whose middle suggests (by a parabola through ends and middle) a rate within this
/// fraction of the worst one seen are searched for their maximum.
constexpr double kRefineMargin = 1e-3;
/// Local passes: where an interval's middle exceeds a bound by more than kLocalTolerance, the
/// bound is tightened at its ends by the excess and the passes are rerun (at most kLocalPasses
/// times), so that the final uniform stretch only absorbs what is left (typically < 1e-3).
constexpr int kLocalPasses = 4;
constexpr double kLocalTolerance = 1e-4;
/// A motion that starts moving cannot be stretched uniformly (that would change its start
/// velocity): its local passes continue, at most kFixedStartPasses in all, until every checked rate
/// is within kFixedStartTolerance of its bound; from the fifth pass on each tightening carries a
/// margin of kFixedStartMargin, so that the passes converge from above.
constexpr int kFixedStartPasses = 16;
constexpr double kFixedStartTolerance = 1e-8;
constexpr double kFixedStartMargin = 1e-3;
/// Grid refinement: an interval is halved while the path's rates change too much across it for
/// the constraints at its ends to stand for its interior: in a bounded channel, Δ |C″| >
/// kRefineTolerance |C′| (the direction or the speed of C′ turns by more than ~0.25 over the
/// interval) or |C′| at its ends and middle differs by more than the factor 1 + kRefineTolerance,
/// at most kMaxRefineDepth times, and the refined grid has at most kMaxRefineGrowth times the
/// intervals of the uniform one (the final check and correction keep the bounds beyond that).
constexpr double kRefineTolerance = 0.25;
constexpr int kMaxRefineDepth = 24;
constexpr std::size_t kMaxRefineGrowth = 16;
/// The first interval of a motion whose start acceleration is held (TimeOptimalOptions::hold_start):
/// this fraction of the first grid interval.
constexpr double kHoldFraction = 1e-6;
/// x_i above the controllable set by this relative amount is rounding, not a start to recover from.
constexpr double kRoundingExcess = 1e-9;
/// The acceleration bounds' margin while braking out of a start the bounds cannot hold.
constexpr double kRecoveryMargin = 1e-4;
/// Grid points handled between two checks of the request's deadline (deadline.h).
constexpr std::size_t kPointsPerDeadlineCheck = 256;
/// Intervals between two deadline checks in the peak searches, checks and figures, which search
/// inside each interval (each costs about 16 grid points' work).
constexpr std::size_t kIntervalsPerSearchDeadlineCheck = kPointsPerDeadlineCheck / 16;
constexpr const char* kPhase = "timing: 'time_optimal'";

const char* const kVelocityName[2] = { "max_linear_velocity", "max_angular_velocity" };
const char* const kAccelerationName[2] = { "max_linear_acceleration", "max_angular_acceleration" };
const char* const kMotionVerb[2] = { "translates", "rotates" };

struct Interval
{
  double lo = -kInf;
  double hi = kInf;
  bool empty = false;
  bool isEmpty() const { return empty || !(lo <= hi); }
};

/// Intersects u with {u : |a x + w u| ≤ A}, given α = |w|², β = a·w, aa = |a|², cross = |a × w|²
/// (= |a × b|² for w = b + 2Δa): α u² + 2 x β u + aa x² − A² ≤ 0.
void intersectEllipse(double alpha, double beta, double aa, double cross, double a2, double x, Interval* u)
{
  if (alpha > 0.0)
  {
    const double d = alpha * a2 - cross * x * x;
    if (d < 0.0)
    {
      u->empty = true;
      return;
    }
    const double r = std::sqrt(d);
    u->lo = std::max(u->lo, (-x * beta - r) / alpha);
    u->hi = std::min(u->hi, (-x * beta + r) / alpha);
  }
  else if (aa * x * x > a2)
  {
    u->empty = true;
  }
}

/// One side of one grid point, as the constraints see it.
struct PointData
{
  PathJet jet;          ///< for the constraints (floored at stationary points)
  PathJet raw;          ///< the path's own, for the checks
  double x_max = kInf;  ///< from (2) and the extents of the ellipses (3), with the local factors
};

/// The four rates: linear / angular velocity (0, 1), linear / angular acceleration (2, 3).
using Rates = std::array<double, 4>;

class Solver
{
public:
  Solver(const PathModel& path, const RateBounds& bounds, const TimeOptimalOptions& options)
    : path_(path)
    , bounds_(bounds)
    , start_x_(options.start_speed * options.start_speed)
    , hold_start_(options.hold_start)
  {
    if (!(std::isfinite(start_x_) && start_x_ >= 0.0))
      throw InvalidInputError("start_state: its speed along the path is " + formatNumber(options.start_speed) +
                              " (it must be finite)");
    buildGrid(options);
    evaluateGrid(options);
  }

  TimingProfile solve()
  {
    const bool fixed_start = start_x_ > 0.0 || hold_start_;
    const int passes = fixed_start ? kFixedStartPasses : kLocalPasses;
    for (int pass = 0;; ++pass)
    {
      updateCaps();
      backward();
      forward();
      if (pass == passes)
        break;
      if (!tightenWhereTheMiddlesExceed())
      {
        // The middles hold: a fixed start must also hold on the whole check (no stretch after it).
        if (!fixed_start || !tightenWhereTheCheckExceeds(pass >= kLocalPasses ? kFixedStartMargin : 0.0))
          break;
      }
    }
    if (fixed_start)
      verifyFixedStart();
    else
      verifyAndStretch();
    return std::move(profile_);
  }

private:
  bool bounded(int c) const { return bounds_.velocity[c] > 0.0 || bounds_.acceleration[c] > 0.0; }

  /// The largest |C′| of each channel over some jets.
  static void growLargest(const PathJet& j, std::array<double, 2>* largest)
  {
    for (int c = 0; c < 2; ++c)
      (*largest)[c] = std::max((*largest)[c], j[c].bb);
  }

  /// Whether the constraints at the ends of [s_a, s_b] (length d) cannot stand for its interior.
  bool needsSplit(const PathJet& a, const PathJet& m, const PathJet& b, double d) const
  {
    for (int c = 0; c < 2; ++c)
    {
      if (!bounded(c))
        continue;
      const double fastest = std::max({ a[c].bb, m[c].bb, b[c].bb, refine_floor_[c] });
      const double slowest = std::max({ std::min({ a[c].bb, m[c].bb, b[c].bb }), refine_floor_[c] });
      const double curvature = std::sqrt(std::max({ a[c].aa, m[c].aa, b[c].aa }));
      const double least_curvature = std::sqrt(std::min({ a[c].aa, m[c].aa, b[c].aa }));
      if (d * curvature > kRefineTolerance * std::sqrt(fastest) ||
          d * (curvature - least_curvature) > kRefineTolerance * kRefineTolerance * std::sqrt(fastest) ||
          fastest > (1.0 + kRefineTolerance) * (1.0 + kRefineTolerance) * slowest)
        return true;
    }
    return false;
  }

  /// Adds the grid points strictly inside (s_a, s_b) and the jets at the middles of the intervals
  /// they make, halving where needsSplit says so.
  void refine(double sa, const PathJet& ja, double sb, const PathJet& jb, int depth)
  {
    const double sm = 0.5 * (sa + sb);
    const PathJet jm = path_.jet(sm, Side::kRight);
    if (depth < kMaxRefineDepth && profile_.s.size() < grid_limit_ && sm > sa && sm < sb &&
        needsSplit(ja, jm, jb, sb - sa))
    {
      refine(sa, ja, sm, jm, depth + 1);
      addPoint(sm, jm, jm, false);
      refine(sm, jm, sb, jb, depth + 1);
      return;
    }
    middle_.push_back(jm);
  }

  void addPoint(double s, const PathJet& right, const PathJet& left, bool corner)
  {
    profile_.s.push_back(s);
    right_.push_back(PointData{ right, right, kInf });
    left_.push_back(PointData{ left, left, kInf });
    corner_.push_back(corner);
  }

  /// The grid: max(intervals_per_piece, the piece's share of min_intervals) uniform intervals on
  /// every analytic piece, refined where the path's rates vary (refine), with the jets the passes
  /// and checks read: right- and left-sided at each point, and at the middle of each interval.
  void buildGrid(const TimeOptimalOptions& options)
  {
    std::vector<double> b = path_.breakpoints();
    for (double x : b)
      if (!std::isfinite(x))
        throw InvalidInputError("timing: 'time_optimal' needs a path with finite times (a breakpoint is at " +
                                formatNumber(x) + " s)");
    // (Sorted: a joined path's rounding may put a breakpoint a hair before the joint.)
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    if (b.size() < 2 || !(b.back() > b.front()) || !std::isfinite(b.back() - b.front()))
      throw InvalidInputError("timing: 'time_optimal' needs a path of positive duration (this one spans " +
                              formatNumber(b.empty() ? 0.0 : b.back() - b.front()) + " s)");
    const double total = b.back() - b.front();
    const std::size_t pieces = b.size() - 1;
    // The uniform grid's points and their jets first: the scale of each channel's |C′|.
    std::vector<double> s;
    std::vector<PathJet> right, left;
    std::vector<bool> corner;
    std::array<double, 2> largest{};
    for (std::size_t j = 0; j < pieces; ++j)
    {
      checkDeadlineEvery(j, kPointsPerDeadlineCheck / 16, kPhase);
      const double length = b[j + 1] - b[j];
      const std::size_t share = static_cast<std::size_t>(
          std::ceil(static_cast<double>(options.min_intervals) * length / total));
      const std::size_t m = std::max<std::size_t>({ options.intervals_per_piece, share, 2 });
      for (std::size_t k = 0; k < m; ++k)
      {
        s.push_back(b[j] + length * static_cast<double>(k) / static_cast<double>(m));
        right.push_back(path_.jet(s.back(), Side::kRight));
        left.push_back(k == 0 && j > 0 ? path_.jet(s.back(), Side::kLeft) : right.back());
        corner.push_back(k == 0 && j > 0 && path_.isCorner(s.back()));
        growLargest(right.back(), &largest);
        growLargest(left.back(), &largest);
      }
    }
    s.push_back(b.back());
    right.push_back(path_.jet(b.back(), Side::kLeft));
    left.push_back(right.back());
    corner.push_back(false);
    growLargest(right.back(), &largest);
    for (int c = 0; c < 2; ++c)
      refine_floor_[c] = kMoveTolerance * kMoveTolerance * largest[c];
    grid_limit_ = kMaxRefineGrowth * s.size();
    // Then the refined grid.
    const std::size_t n = s.size();
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
      addPoint(s[i], right[i], left[i], corner[i]);
      refine(s[i], right[i], s[i + 1], left[i + 1], 0);
    }
    addPoint(s[n - 1], right[n - 1], left[n - 1], false);
    if (hold_start_)
    {
      // The held first interval [s_0, s_0 + ε]: a new point after s_0, and new middles on both sides.
      const double s0 = profile_.s[0];
      const double held = s0 + kHoldFraction * (profile_.s[1] - s0);
      const PathJet j = path_.jet(held, Side::kRight);
      profile_.s.insert(profile_.s.begin() + 1, held);
      right_.insert(right_.begin() + 1, PointData{ j, j, kInf });
      left_.insert(left_.begin() + 1, PointData{ j, j, kInf });
      corner_.insert(corner_.begin() + 1, false);
      middle_[0] = path_.jet(0.5 * (held + profile_.s[2]), Side::kRight);
      middle_.insert(middle_.begin(), path_.jet(0.5 * (s0 + held), Side::kRight));
    }
  }

  void evaluateGrid(const TimeOptimalOptions& options)
  {
    const std::size_t n = profile_.s.size();
    factor_.assign(n, Rates{ 1.0, 1.0, 1.0, 1.0 });
    if (options.local_limits)
    {
      speed_cap_.assign(n, kInf);
      for (std::size_t i = 0; i < n; ++i)
      {
        const LocalLimit l = options.local_limits(profile_.s[i]);
        factor_[i][2] = factor_[i][3] = l.acceleration_factor;
        speed_cap_[i] = l.speed_cap * l.speed_cap;
      }
    }
    // The largest |C′| of each channel: the scale of "moves".
    std::array<double, 2> largest{};
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c)
        largest[c] = std::max({ largest[c], right_[i].raw[c].bb, left_[i].raw[c].bb });
    for (int c = 0; c < 2; ++c)
      largest[c] = std::sqrt(largest[c]);
    const double scale = std::max(largest[0], largest[1]);
    if (!(scale > 0.0) || !std::isfinite(scale))
      throw InvalidInputError("timing: 'time_optimal' needs a path that moves (the curve stands still)");
    bool any_bound = false;
    for (int c = 0; c < 2; ++c)
    {
      moves_[c] = largest[c] > kMoveTolerance * scale;
      floor_[c] = kMoveTolerance * largest[c] * kMoveTolerance * largest[c];
      any_bound = any_bound || bounds_.velocity[c] > 0.0 || bounds_.acceleration[c] > 0.0;
    }
    if (!any_bound)
      throw InvalidInputError(
          "max_linear_velocity, max_angular_velocity, max_linear_acceleration, max_angular_acceleration: all 0 "
          "(unbounded); timing 'time_optimal' needs bounds (at least an acceleration bound on the motion)");
    for (std::size_t i = 0; i < n; ++i)
    {
      prepare(&right_[i], profile_.s[i]);
      prepare(&left_[i], profile_.s[i]);
    }
    // A start that itself exceeds a bound (its speed, or with hold_start its acceleration): the
    // recovery from it is exempt from the checks (it is what the bounds cannot hold).
    const Rates start = needs(right_[0].raw, start_x_, 0.0);
    for (int q = 0; q < 4; ++q)
      start_exceeds_ = start_exceeds_ || (start_x_ > 0.0 && start[q] > 1.0 + kRoundingExcess && (q < 2 || hold_start_));
  }

  /// Checks that the motion at this point is bounded and floors stationary points.
  void prepare(PointData* p, double s) const
  {
    p->jet = p->raw;
    bool moving = false;
    bool limited = false;
    int unlimited = -1;
    for (int c = 0; c < 2; ++c)
    {
      if (!(moves_[c] && p->raw[c].bb > floor_[c]))
        continue;
      moving = true;
      if (bounds_.acceleration[c] > 0.0)
        limited = true;
      else if (unlimited < 0)
        unlimited = c;
    }
    if (moving && !limited)
    {
      const int c = unlimited;
      const std::string where = "the path " + std::string(kMotionVerb[c]) + " at path time " + formatNumber(s) + " s";
      if (bounds_.velocity[c] > 0.0)
        throw InvalidInputError(std::string(kAccelerationName[c]) +
                                ": 0 (unbounded), but timing 'time_optimal' needs it: " + where +
                                " where no acceleration bound acts (the motion starts and stops at rest)");
      throw InvalidInputError(std::string(kVelocityName[c]) + " and " + kAccelerationName[c] +
                              ": 0 (unbounded), but timing 'time_optimal' needs a bound on this motion: " + where +
                              " where no other bound acts (set " + kAccelerationName[c] + ", and " + kVelocityName[c] +
                              " to cap the speed)");
    }
    if (!moving)
    {
      // A stationary point (C′ = 0 in every channel, e.g. a dwell): any speed is admissible;
      // a fictitious |C′| at the "moves" threshold keeps x and u finite there.
      for (int c = 0; c < 2; ++c)
      {
        ChannelJet& j = p->jet[c];
        if (moves_[c] && (bounds_.velocity[c] > 0.0 || bounds_.acceleration[c] > 0.0) && j.bb < floor_[c])
        {
          j.bb = floor_[c];
          j.cross = std::max(0.0, j.aa * j.bb - j.ab * j.ab);
        }
      }
    }
  }

  double velocityBound(std::size_t i, int c) const { return bounds_.velocity[c] * factor_[i][c]; }
  double accelerationBound(std::size_t i, int c) const { return bounds_.acceleration[c] * factor_[i][2 + c]; }

  /// x_max of both sides of every point with the current local factors.
  void updateCaps()
  {
    for (std::size_t i = 0; i < profile_.s.size(); ++i)
      for (PointData* p : { &right_[i], &left_[i] })
      {
        p->x_max = speed_cap_.empty() ? kInf : speed_cap_[i];
        for (int c = 0; c < 2; ++c)
        {
          const ChannelJet& j = p->jet[c];
          const double v = velocityBound(i, c);
          const double a = accelerationBound(i, c);
          if (v > 0.0 && j.bb > 0.0)
            p->x_max = std::min(p->x_max, v * v / j.bb);
          if (a > 0.0)
          {
            if (j.cross > 0.0)
              p->x_max = std::min(p->x_max, a * std::sqrt(j.bb / j.cross));
            else if (j.bb == 0.0 && j.aa > 0.0)
              p->x_max = std::min(p->x_max, a / std::sqrt(j.aa));
          }
        }
      }
  }

  double delta(std::size_t i) const { return profile_.s[i + 1] - profile_.s[i]; }

  /// Upper end of x_{i+1}: the controllable set and the velocity bound seen from the left.
  double nextLimit(std::size_t i) const { return std::min(k_[i + 1], left_[i + 1].x_max); }

  /// The admissible controls u_i for x_i = x with x_{i+1} ∈ [0, next].
  Interval controls(std::size_t i, double x, double next) const
  {
    const double d = delta(i);
    Interval u;
    u.lo = -x / (2.0 * d);
    u.hi = (next - x) / (2.0 * d);
    const PathJet& a = right_[i].jet;
    const PathJet& b = left_[i + 1].jet;
    for (int c = 0; c < 2; ++c)
    {
      if (!(bounds_.acceleration[c] > 0.0))
        continue;
      // At s_i: |C″ x + C′ u|.
      const double a0 = accelerationBound(i, c);
      intersectEllipse(a[c].bb, a[c].ab, a[c].aa, a[c].cross, a0 * a0, x, &u);
      // At s_{i+1}: |C″ (x + 2Δu) + C′ u| = |C″ x + (C′ + 2Δ C″) u|.
      const ChannelJet& e = b[c];
      const double a1 = accelerationBound(i + 1, c);
      const double alpha = std::max(0.0, 4.0 * d * d * e.aa + 4.0 * d * e.ab + e.bb);
      intersectEllipse(alpha, 2.0 * d * e.aa + e.ab, e.aa, e.cross, a1 * a1, x, &u);
      if (u.empty)
        return u;
    }
    return u;
  }

  void backward()
  {
    const std::size_t n = profile_.s.size();
    // Tightening only shrinks the sets: a later pass starts from the previous one's.
    const std::vector<double> previous = k_.empty() ? std::vector<double>(n, kInf) : k_;
    k_.assign(n, 0.0);
    for (std::size_t i = n - 1; i-- > 0;)
    {
      checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
      // K_0 = {0} for a start at rest; a moving start needs the whole controllable set at s_0.
      if (corner_[i] || (i == 0 && !(start_x_ > 0.0)))
        continue;
      const double next = nextLimit(i);
      auto admissible = [&](double x) { return !controls(i, x, next).isEmpty(); };
      double hi = std::min(right_[i].x_max, previous[i]);
      if (std::isfinite(hi) && admissible(hi))
      {
        k_[i] = hi;
        continue;
      }
      if (!std::isfinite(hi))
      {
        // No pointwise cap: grow a bracket from the next set's size.
        const Interval at_rest = controls(i, 0.0, next);
        hi = std::max({ next, 2.0 * delta(i) * std::abs(at_rest.hi), std::numeric_limits<double>::min() });
        int steps = 0;
        while (admissible(hi) && steps++ < 2100)
          hi *= 4.0;
        if (!std::isfinite(hi))
          throw InvalidInputError("timing: 'time_optimal' found no bound on the speed at path time " +
                                  formatNumber(profile_.s[i]) + " s (set max_linear_velocity or max_angular_velocity)");
      }
      double lo = 0.0;
      for (int step = 0; step < kBisectionSteps && hi - lo > kBisectionTolerance * hi; ++step)
      {
        const double mid = 0.5 * (lo + hi);
        (admissible(mid) ? lo : hi) = mid;
      }
      k_[i] = lo;
    }
  }

  /// The greedy forward pass (Pham & Pham, eq. 12) from x_0 = start_x_ (held for the first interval
  /// with hold_start_). A start outside the controllable sets (faster than the bounds allow, or too
  /// fast to brake for what lies ahead) is brought into them by the hardest braking the acceleration
  /// bounds allow: the recovery, which ends at the grid point recovery_end_. A start that cannot be
  /// brought to rest before a velocity corner or the end of the path is an error.
  void forward()
  {
    const std::size_t n = profile_.s.size();
    std::vector<double>& x = profile_.x;
    std::vector<double>& u = profile_.u;
    std::vector<double>& t = profile_.t;
    x.assign(n, 0.0);
    u.assign(n - 1, 0.0);
    t.assign(n, profile_.s.front());
    x[0] = start_x_;
    recovery_end_ = 0;
    profile_.recovery_excess = 0.0;
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
      const double d = delta(i);
      const double next = nextLimit(i);
      double chosen = 0.0;
      bool recovering = false;
      if (i == 0 && hold_start_)
      {
        recovering = x[0] > next * (1.0 + kRoundingExcess);
      }
      else
      {
        const Interval c = controls(i, x[i], next);
        if (!c.isEmpty())
        {
          chosen = c.hi;
        }
        else if (x[i] <= std::min(k_[i], right_[i].x_max) * (1.0 + kRoundingExcess))
        {
          // Rounding left x_i a hair outside K_i: hold the speed, or slow down to the next set;
          // the final check corrects what that costs.
          chosen = std::min(0.0, (next - x[i]) / (2.0 * d));
        }
        else
        {
          recovering = true;
          // Braking at the acceleration bounds, which hold at the interval's ends: a margin for
          // its interior, which no later pass checks.
          for (std::size_t j : { i, i + 1 })
            for (int c = 2; c < 4; ++c)
              factor_[j][c] = std::min(factor_[j][c], 1.0 - kRecoveryMargin);
          const Interval free = controls(i, x[i], kInf);
          if (free.isEmpty())
          {
            // No braking keeps within the acceleration bounds here: the path bends too sharply
            // for this speed. The least acceleration is taken and its excess reported.
            chosen = leastAccelerationControl(i, x[i], d);
            const Rates r = needs(right_[i].raw, x[i], chosen);
            for (int c = 2; c < 4; ++c)
              profile_.recovery_excess = std::max(profile_.recovery_excess, r[c] * r[c]);
          }
          else
          {
            chosen = std::min(std::max((next - x[i]) / (2.0 * d), free.lo), free.hi);
          }
        }
      }
      double following = std::max(x[i] + 2.0 * d * chosen, 0.0);
      if (recovering)
      {
        recovery_end_ = i + 1;
        if (following > 0.0 && (corner_[i + 1] || i + 2 == n))
          throw InvalidInputError(
              "start_state: the motion starts too fast to come to rest within the bounds before path time " +
              formatNumber(profile_.s[i + 1]) + " s (" + (i + 2 == n ? "the end of the path" : "a corner") +
              "); start slower, place the first waypoint farther away, or raise the acceleration bounds");
      }
      else
      {
        following = std::min(following, next);
      }
      x[i + 1] = following;
      u[i] = (x[i + 1] - x[i]) / (2.0 * d);
      const double rate = std::sqrt(x[i]) + std::sqrt(x[i + 1]);
      if (!(rate > 0.0))
        throw InterpolationError("timing: the time-optimal profile stalls at path time " +
                                 formatNumber(profile_.s[i]) + " s (the bounds are too tight for the path)");
      t[i + 1] = t[i] + 2.0 * d / rate;
    }
    profile_.recovery_end = t[checkedFrom()];
  }

  /// The first interval the checks hold to the bounds: after the recovery from a start that
  /// exceeds a bound; else all of them (a start within the bounds that must brake for what lies
  /// ahead brakes within them).
  std::size_t checkedFrom() const { return start_exceeds_ ? recovery_end_ : 0; }

  /// Where no control keeps the acceleration within a bound at x (the path bends too sharply for
  /// that speed): the control of least acceleration that does not speed up, and at most stops.
  double leastAccelerationControl(std::size_t i, double x, double d) const
  {
    double u = 0.0;
    for (int c = 0; c < 2; ++c)
    {
      const ChannelJet& j = right_[i].jet[c];
      if (bounds_.acceleration[c] > 0.0 && j.bb > 0.0)
        u = std::min(u, -x * j.ab / j.bb);
    }
    return std::max(u, -x / (2.0 * d));
  }

  /// The stretch each bounded rate would need at a point: |v|/v_max, √(|a|/a_max).
  Rates needs(const PathJet& j, double x, double u) const
  {
    Rates r{};
    for (int c = 0; c < 2; ++c)
    {
      if (bounds_.velocity[c] > 0.0)
        r[c] = std::sqrt(j[c].bb * x) / bounds_.velocity[c];
      if (bounds_.acceleration[c] > 0.0)
      {
        const double a2 = j[c].aa * x * x + 2.0 * j[c].ab * x * u + j[c].bb * u * u;
        r[2 + c] = std::sqrt(std::sqrt(std::max(0.0, a2)) / bounds_.acceleration[c]);
      }
    }
    return r;
  }

  /// The needs at s_i + λ Δ_i (x is linear in s on the interval, u constant).
  Rates needsAt(std::size_t i, double lambda) const
  {
    const double x = profile_.x[i] + lambda * (profile_.x[i + 1] - profile_.x[i]);
    return needs(path_.jet(profile_.s[i] + lambda * delta(i), Side::kRight), x, profile_.u[i]);
  }

  Rates needsAtMiddle(std::size_t i) const
  {
    return needs(middle_[i], 0.5 * (profile_.x[i] + profile_.x[i + 1]), profile_.u[i]);
  }

  /// Tightens quantity q at both ends of interval i so that its need r (> 1) would come down to
  /// 1 − margin: velocities scale with the bound, accelerations' needs with its square root.
  void tighten(std::size_t i, int q, double r, double margin)
  {
    const double f = (q < 2 ? 1.0 / r : 1.0 / (r * r)) * (1.0 - margin);
    factor_[i][q] *= f;
    factor_[i + 1][q] *= f;
  }

  /// Where the middle of an interval exceeds a bound (the ends satisfy them by construction),
  /// tightens that bound at both ends by the excess. Returns whether anything was tightened. The
  /// recovery from a start the bounds cannot hold is left as it is.
  bool tightenWhereTheMiddlesExceed()
  {
    bool tightened = false;
    for (std::size_t i = checkedFrom(); i + 1 < profile_.s.size(); ++i)
    {
      const Rates r = needsAtMiddle(i);
      for (int q = 0; q < 4; ++q)
        if (r[q] > 1.0 + kLocalTolerance)
        {
          tighten(i, q, r[q], 0.0);
          tightened = true;
        }
    }
    return tightened;
  }

  /// The needs at both ends and the middle of every interval.
  struct IntervalNeeds
  {
    std::vector<Rates> start, middle, end;
  };

  IntervalNeeds intervalNeeds() const
  {
    const std::size_t n = profile_.s.size();
    IntervalNeeds f{ std::vector<Rates>(n - 1), std::vector<Rates>(n - 1), std::vector<Rates>(n - 1) };
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
      f.start[i] = needs(right_[i].raw, profile_.x[i], profile_.u[i]);
      f.end[i] = needs(left_[i + 1].raw, profile_.x[i + 1], profile_.u[i]);
      f.middle[i] = needsAtMiddle(i);
    }
    return f;
  }

  /// The peak of need q on interval i: the largest of its ends and middle, or, where the parabola
  /// through the three peaks inside at or above `threshold`, the maximum found by localMax on the
  /// exact rates.
  double peak(const IntervalNeeds& f, std::size_t i, int q, double threshold, bool* searched) const
  {
    const double f0 = f.start[i][q], fm = f.middle[i][q], f1 = f.end[i][q];
    *searched = detail::parabolaPeaksInside(f0, fm, f1, threshold);
    return *searched ? localMax(i, q, f0, fm, f1) : std::max({ f0, fm, f1 });
  }

  /// The final check of a motion from rest: the peaks of every interval, then the uniform
  /// stretch k ≥ 1 that brings the worst within its bound.
  void verifyAndStretch()
  {
    const std::size_t n = profile_.s.size();
    const IntervalNeeds f = intervalNeeds();
    double worst = 0.0;
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (int q = 0; q < 4; ++q)
        worst = std::max({ worst, f.start[i][q], f.middle[i][q], f.end[i][q] });
    const double threshold = worst * (1.0 - kRefineMargin);
    double refined = worst;
    Rates searched{};
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
      for (int q = 0; q < 4; ++q)
      {
        bool was_searched = false;
        const double p = peak(f, i, q, threshold, &was_searched);
        if (was_searched)
          searched[q] = std::max(searched[q], p);
        refined = std::max(refined, p);
      }
    }
    const double k = std::max(1.0, refined);
    profile_.stretch = k;
    if (k > 1.0)
    {
      const double t0 = profile_.t.front();
      for (std::size_t i = 0; i < n; ++i)
      {
        profile_.t[i] = t0 + (profile_.t[i] - t0) * k;
        profile_.x[i] /= k * k;
      }
      for (double& ui : profile_.u)
        ui /= k * k;
      profile_.recovery_end = t0 + (profile_.recovery_end - t0) * k;
    }
    figures(searched, k);
  }

  /// The peaks of the intervals after the recovery, searched where they come within
  /// kRefineMargin of a bound; with `tighten_margin` ≥ 0 the bounds are tightened where a peak
  /// exceeds its bound by more than kFixedStartTolerance. Returns the worst need and whether
  /// anything was tightened.
  std::pair<double, bool> checkAfterRecovery(double tighten_margin, Rates* searched)
  {
    const IntervalNeeds f = intervalNeeds();
    double worst = 0.0;
    bool tightened = false;
    for (std::size_t i = checkedFrom(); i + 1 < profile_.s.size(); ++i)
    {
      checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
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

  bool tightenWhereTheCheckExceeds(double margin)
  {
    Rates searched{};
    return checkAfterRecovery(margin, &searched).second;
  }

  /// The final check of a motion whose start is fixed (no stretch can correct it: the start
  /// velocity would change): every interval after the recovery within its bounds.
  void verifyFixedStart()
  {
    Rates searched{};
    const double worst = checkAfterRecovery(-1.0, &searched).first;
    if (worst > 1.0 + kFixedStartTolerance)
      throw InterpolationError("timing: the time-optimal motion from the start state exceeds a bound by " +
                               formatNumber(worst - 1.0) + " (relative) after " + std::to_string(kFixedStartPasses) +
                               " corrections; start more slowly or farther from the first waypoint, or raise the "
                               "acceleration bounds");
    profile_.stretch = 1.0;
    figures(searched, 1.0);
  }

  /// |v| and |a| of both channels at a point with (x, u).
  static std::array<double, 4> magnitudes(const PathJet& j, double x, double u)
  {
    std::array<double, 4> m{};
    for (int c = 0; c < 2; ++c)
    {
      m[c] = std::sqrt(j[c].bb * x);
      m[2 + c] = std::sqrt(std::max(0.0, j[c].aa * x * x + 2.0 * j[c].ab * x * u + j[c].bb * u * u));
    }
    return m;
  }

  /// The timed motion's figures (TimingProfile::max_speed, …) from the cached jets; `searched`:
  /// the largest needs found inside intervals, before the stretch k.
  void figures(const Rates& searched, double k)
  {
    TimingProfile& p = profile_;
    p.max_speed = { 0.0, 0.0 };
    p.max_acceleration = { 0.0, 0.0 };
    p.acceleration_energy = { 0.0, 0.0 };
    for (std::size_t i = 0; i + 1 < p.s.size(); ++i)
    {
      checkDeadlineEvery(i, kIntervalsPerSearchDeadlineCheck, kPhase);
      const double x_mid = 0.5 * (p.x[i] + p.x[i + 1]);
      const std::array<double, 4> a = magnitudes(right_[i].raw, p.x[i], p.u[i]);
      const std::array<double, 4> m = magnitudes(middle_[i], x_mid, p.u[i]);
      const std::array<double, 4> b = magnitudes(left_[i + 1].raw, p.x[i + 1], p.u[i]);
      // Nodes 0, τ_m (the time at the middle of the interval in s), h.
      const double h = p.t[i + 1] - p.t[i];
      const double tm = delta(i) / (std::sqrt(p.x[i]) + std::sqrt(x_mid));
      // The integral of the quadratic through (0, g0), (τ_m, g_m), (h, g1): Lagrange weights.
      const bool inside = h > 0.0 && tm > 0.0 && tm < h;
      const double w0 = inside ? h * (3.0 * tm - h) / (6.0 * tm) : 0.0;
      const double wm = inside ? h * h * h / (6.0 * tm * (h - tm)) : 0.0;
      const double w1 = inside ? h * (2.0 * h - 3.0 * tm) / (6.0 * (h - tm)) : 0.0;
      for (int c = 0; c < 2; ++c)
      {
        p.max_speed[c] = std::max({ p.max_speed[c], a[c], m[c], b[c] });
        p.max_acceleration[c] = std::max({ p.max_acceleration[c], a[2 + c], m[2 + c], b[2 + c] });
        p.acceleration_energy[c] += w0 * a[2 + c] * a[2 + c] + wm * m[2 + c] * m[2 + c] + w1 * b[2 + c] * b[2 + c];
      }
    }
    // Where the parabola through an interval's ends and middle rises above the peak so far (within
    // kRefineMargin), the peak is searched on the exact rates: every figure is a value the motion
    // takes, within ~1e-7 of its true peak.
    std::array<double, 4> peak{ p.max_speed[0], p.max_speed[1], p.max_acceleration[0], p.max_acceleration[1] };
    for (std::size_t i = 0; i + 1 < p.s.size(); ++i)
    {
      const double x_mid = 0.5 * (p.x[i] + p.x[i + 1]);
      const std::array<double, 4> a = magnitudes(right_[i].raw, p.x[i], p.u[i]);
      const std::array<double, 4> m = magnitudes(middle_[i], x_mid, p.u[i]);
      const std::array<double, 4> b = magnitudes(left_[i + 1].raw, p.x[i + 1], p.u[i]);
      for (int q = 0; q < 4; ++q)
      {
        if (!detail::parabolaPeaksInside(a[q], m[q], b[q], peak[q] * (1.0 - kRefineMargin)))
          continue;
        peak[q] = std::max(peak[q], detail::localMaxOf(
                                        [this, i, q](double lambda) {
                                          const TimingProfile& pr = profile_;
                                          const double x = pr.x[i] + lambda * (pr.x[i + 1] - pr.x[i]);
                                          return magnitudes(path_.jet(pr.s[i] + lambda * delta(i), Side::kRight), x,
                                                            pr.u[i])[q];
                                        },
                                        a[q], m[q], b[q]));
      }
    }
    p.max_speed = { peak[0], peak[1] };
    p.max_acceleration = { peak[2], peak[3] };
    for (int c = 0; c < 2; ++c)
    {
      if (bounds_.velocity[c] > 0.0)
        p.max_speed[c] = std::max(p.max_speed[c], searched[c] * bounds_.velocity[c] / k);
      if (bounds_.acceleration[c] > 0.0)
        p.max_acceleration[c] =
            std::max(p.max_acceleration[c], searched[2 + c] * searched[2 + c] * bounds_.acceleration[c] / (k * k));
    }
  }

  /// The largest need q inside interval i: successive parabolic interpolation from the three
  /// known values (superlinear for a smooth maximum), golden-section steps when a parabola fails.
  double localMax(std::size_t i, int q, double f0, double fm, double f1) const
  {
    return detail::localMaxOf([this, i, q](double lambda) { return needsAt(i, lambda)[q]; }, f0, fm, f1);
  }

  const PathModel& path_;
  RateBounds bounds_;
  double start_x_;   ///< the requested ṡ² at s_0 (0: from rest)
  bool hold_start_;  ///< s̈ = 0 on the first interval
  std::array<bool, 2> moves_{};
  std::array<double, 2> floor_{};
  std::array<double, 2> refine_floor_{};  ///< |C′|² below which a channel counts as still (refinement)
  std::size_t grid_limit_ = 0;            ///< most grid points refinement may make
  std::size_t recovery_end_ = 0;          ///< the grid point at which the recovery (forward) ends
  bool start_exceeds_ = false;            ///< the start itself exceeds a bound
  TimingProfile profile_;
  std::vector<PointData> right_;
  std::vector<PointData> left_;
  std::vector<PathJet> middle_;  ///< at the middle of each interval (in s)
  std::vector<bool> corner_;
  std::vector<Rates> factor_;    ///< local tightening of the four bounds at each grid point
  std::vector<double> speed_cap_;  ///< the caller's cap on x at each grid point (empty: none)
  std::vector<double> k_;        ///< upper ends of the controllable sets
};
}  // namespace

double TimingProfile::timeAt(double path_parameter) const
{
  auto it = std::lower_bound(s.begin(), s.end(), path_parameter);
  if (it != s.end() && *it == path_parameter)
    return t[static_cast<std::size_t>(it - s.begin())];
  const std::size_t i = findInterval(s, path_parameter, Side::kRight);
  const double ds = path_parameter - s[i];
  const double v = std::sqrt(x[i]);
  const double v_end = std::sqrt(std::max(0.0, x[i] + 2.0 * u[i] * ds));
  const double rate = v + v_end;
  return rate > 0.0 ? t[i] + 2.0 * ds / rate : t[i];
}

TimingProfile timeOptimalProfile(const PathModel& path, const RateBounds& bounds, const TimeOptimalOptions& options)
{
  return Solver(path, bounds, options).solve();
}

}  // namespace timing
}  // namespace se3_interpolation
