#include "se3_interpolation/timing/time_optimal.h"

#include <limits>
#include <string>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace timing
{
namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();
/// A channel moves at a grid point when |C′| exceeds this fraction of its largest |C′| on the
/// path; a channel whose largest |C′| is below this fraction of the other's does not move at all
/// (rounding of a pure rotation's translation, or vice versa).
constexpr double kMoveTolerance = 1e-9;
/// Bisection of the controllable sets' upper ends: relative width (rounding level of x).
constexpr double kBisectionTolerance = 1e-12;
constexpr int kBisectionSteps = 200;
/// Intervals whose middle suggests (by a parabola through ends and middle) a rate within this
/// fraction of the worst one seen are searched for their maximum.
constexpr double kRefineMargin = 1e-4;
/// That search: steps, and the step (fraction of the interval) at which it stops; the maximum's
/// value is then exact to ~(1e-7)² relative.
constexpr int kLocalMaxSteps = 12;
constexpr double kLocalMaxTolerance = 1e-7;
/// Local passes: where an interval's middle exceeds a bound by more than kLocalTolerance, the
/// bound is tightened at its ends by the excess and the passes are rerun (at most kLocalPasses
/// times), so that the final uniform stretch only absorbs what is left (typically < 1e-3).
constexpr int kLocalPasses = 4;
constexpr double kLocalTolerance = 1e-4;

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
    : path_(path), bounds_(bounds)
  {
    buildGrid(options);
    evaluateGrid();
  }

  TimingProfile solve()
  {
    for (int pass = 0;; ++pass)
    {
      updateCaps();
      backward();
      forward();
      if (pass == kLocalPasses || !tightenWhereTheMiddlesExceed())
        break;
    }
    verifyAndStretch();
    return std::move(profile_);
  }

private:
  void buildGrid(const TimeOptimalOptions& options)
  {
    std::vector<double> b = path_.breakpoints();
    b.erase(std::unique(b.begin(), b.end()), b.end());
    const double total = b.back() - b.front();
    const std::size_t pieces = b.size() - 1;
    std::vector<double>& s = profile_.s;
    for (std::size_t j = 0; j < pieces; ++j)
    {
      const double length = b[j + 1] - b[j];
      const std::size_t share = static_cast<std::size_t>(
          std::ceil(static_cast<double>(options.min_intervals) * length / total));
      const std::size_t m = std::max<std::size_t>({ options.intervals_per_piece, share, 2 });
      breakpoint_.push_back(s.size());
      for (std::size_t k = 0; k < m; ++k)
        s.push_back(b[j] + length * static_cast<double>(k) / static_cast<double>(m));
    }
    breakpoint_.push_back(s.size());
    s.push_back(b.back());
  }

  void evaluateGrid()
  {
    const std::vector<double>& s = profile_.s;
    const std::size_t n = s.size();
    right_.resize(n);
    left_.resize(n);
    middle_.resize(n - 1);
    corner_.assign(n, false);
    factor_.assign(n, Rates{ 1.0, 1.0, 1.0, 1.0 });
    std::vector<bool> at_breakpoint(n, false);
    for (std::size_t i : breakpoint_)
      at_breakpoint[i] = true;
    for (std::size_t i = 0; i < n; ++i)
    {
      right_[i].raw = path_.jet(s[i], Side::kRight);
      left_[i].raw = at_breakpoint[i] ? path_.jet(s[i], Side::kLeft) : right_[i].raw;
      if (at_breakpoint[i] && i > 0 && i + 1 < n)
        corner_[i] = path_.isCorner(s[i]);
      if (i + 1 < n)
        middle_[i] = path_.jet(0.5 * (s[i] + s[i + 1]), Side::kRight);
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
      prepare(&right_[i], s[i]);
      prepare(&left_[i], s[i]);
    }
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
        p->x_max = kInf;
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
      if (corner_[i] || i == 0)
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

  void forward()
  {
    const std::size_t n = profile_.s.size();
    std::vector<double>& x = profile_.x;
    std::vector<double>& u = profile_.u;
    std::vector<double>& t = profile_.t;
    x.assign(n, 0.0);
    u.assign(n - 1, 0.0);
    t.assign(n, profile_.s.front());
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      const double d = delta(i);
      const double next = nextLimit(i);
      const Interval c = controls(i, x[i], next);
      // Rounding may leave x_i a hair outside K_i (no admissible control): hold the speed, or
      // slow down to the next set; the final check corrects what that costs.
      const double chosen = c.isEmpty() ? std::min(0.0, (next - x[i]) / (2.0 * d)) : c.hi;
      x[i + 1] = std::min(std::max(x[i] + 2.0 * d * chosen, 0.0), next);
      u[i] = (x[i + 1] - x[i]) / (2.0 * d);
      const double rate = std::sqrt(x[i]) + std::sqrt(x[i + 1]);
      if (!(rate > 0.0))
        throw InterpolationError("timing: the time-optimal profile stalls at path time " +
                                 formatNumber(profile_.s[i]) + " s (the bounds are too tight for the path)");
      t[i + 1] = t[i] + 2.0 * d / rate;
    }
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

  /// Where the middle of an interval exceeds a bound (the ends satisfy them by construction),
  /// tightens that bound at both ends by the excess. Returns whether anything was tightened.
  bool tightenWhereTheMiddlesExceed()
  {
    bool tightened = false;
    for (std::size_t i = 0; i + 1 < profile_.s.size(); ++i)
    {
      const Rates r = needsAtMiddle(i);
      for (int q = 0; q < 4; ++q)
      {
        if (!(r[q] > 1.0 + kLocalTolerance))
          continue;
        // Velocities scale with the bound, accelerations' needs with its square root.
        const double f = q < 2 ? 1.0 / r[q] : 1.0 / (r[q] * r[q]);
        factor_[i][q] = std::min(factor_[i][q], f * factor_[i][q]);
        factor_[i + 1][q] = std::min(factor_[i + 1][q], f * factor_[i + 1][q]);
        tightened = true;
      }
    }
    return tightened;
  }

  void verifyAndStretch()
  {
    const std::size_t n = profile_.s.size();
    const std::vector<double>& x = profile_.x;
    const std::vector<double>& u = profile_.u;
    std::vector<Rates> f0(n - 1), fm(n - 1), f1(n - 1);
    double worst = 0.0;
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      f0[i] = needs(right_[i].raw, x[i], u[i]);
      f1[i] = needs(left_[i + 1].raw, x[i + 1], u[i]);
      fm[i] = needsAtMiddle(i);
      for (int q = 0; q < 4; ++q)
        worst = std::max({ worst, f0[i][q], fm[i][q], f1[i][q] });
    }
    const double threshold = worst * (1.0 - kRefineMargin);
    double refined = worst;
    Rates searched{};
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (int q = 0; q < 4; ++q)
      {
        // The parabola through (0, f0), (½, fm), (1, f1): f0 + c1 λ + c2 λ².
        const double c1 = -3.0 * f0[i][q] + 4.0 * fm[i][q] - f1[i][q];
        const double c2 = 2.0 * f0[i][q] - 4.0 * fm[i][q] + 2.0 * f1[i][q];
        if (!(c2 < 0.0))
          continue;
        const double vertex = -c1 / (2.0 * c2);
        if (!(vertex > 0.0 && vertex < 1.0))
          continue;
        const double predicted = f0[i][q] + c1 * vertex + c2 * vertex * vertex;
        if (predicted < threshold)
          continue;
        searched[q] = std::max(searched[q], localMax(i, q, f0[i][q], fm[i][q], f1[i][q]));
        refined = std::max(refined, searched[q]);
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
    }
    figures(searched, k);
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
    std::array<double, 3> l{ 0.0, 0.5, 1.0 };
    std::array<double, 3> f{ f0, fm, f1 };
    double best = std::max({ f0, fm, f1 });
    for (int step = 0; step < kLocalMaxSteps; ++step)
    {
      // The vertex of the parabola through the three points (l sorted, f[1] the largest inside).
      const double d1 = (l[1] - l[0]) * (f[1] - f[2]);
      const double d2 = (l[1] - l[2]) * (f[1] - f[0]);
      const double den = 2.0 * (d1 - d2);
      double next = den != 0.0 ? l[1] - ((l[1] - l[0]) * d1 - (l[1] - l[2]) * d2) / den : -1.0;
      if (!(next > l[0] && next < l[2]) || next == l[1])
        next = l[2] - l[1] > l[1] - l[0] ? l[1] + 0.381966 * (l[2] - l[1]) : l[1] - 0.381966 * (l[1] - l[0]);
      const double fn = needsAt(i, next)[q];
      best = std::max(best, fn);
      const double moved = std::abs(next - l[1]);
      // Keep the bracket around the best interior point.
      if (fn >= f[1])
      {
        if (next > l[1])
        {
          l = { l[1], next, l[2] };
          f = { f[1], fn, f[2] };
        }
        else
        {
          l = { l[0], next, l[1] };
          f = { f[0], fn, f[1] };
        }
      }
      else if (next > l[1])
      {
        l[2] = next;
        f[2] = fn;
      }
      else
      {
        l[0] = next;
        f[0] = fn;
      }
      if (moved < kLocalMaxTolerance)
        break;
    }
    return best;
  }

  const PathModel& path_;
  RateBounds bounds_;
  std::array<bool, 2> moves_{};
  std::array<double, 2> floor_{};
  TimingProfile profile_;
  std::vector<std::size_t> breakpoint_;
  std::vector<PointData> right_;
  std::vector<PointData> left_;
  std::vector<PathJet> middle_;  ///< at the middle of each interval (in s)
  std::vector<bool> corner_;
  std::vector<Rates> factor_;    ///< local tightening of the four bounds at each grid point
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
