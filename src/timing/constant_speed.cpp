// The constant-speed timing (timing/constant_speed.h): the table of S(σ), the ramps and the check.
#include "se3_interpolation/timing/constant_speed.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/quadrature.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
namespace timing
{
namespace
{
/// Peaks of P′ (the quintic smoothstep's slope 15/8) and P‴ (10/√3) on [0, 1]: a ramp of length T
/// on a straight line peaks at 15/8 V/T in acceleration and 10/√3 V/T² in jerk (file comment).
constexpr double kRampAccelerationPeak = 15.0 / 8.0;
const double kRampJerkPeak = 10.0 / std::sqrt(3.0);
/// A rate checked at a piece's ends and middle is searched inside the piece when it, or the
/// parabola through the three values, comes within this fraction of its bound.
constexpr double kNearBound = 0.1;
/// A piece of the check is halved where a bounded rate above kVariationNearBound of its bound
/// varies by more than kRateVariation of its largest value across it, at most kMaxCheckSplits times.
constexpr double kVariationNearBound = 0.5;
constexpr double kRateVariation = 0.25;
constexpr int kMaxCheckSplits = 20;
/// ... and where the path turns by more than this across it (rad, in the chord metric).
constexpr double kMaxCheckTurn = 0.25;
/// A rate whose three values on a piece agree to this (relative) is flat there: not searched.
constexpr double kFlatRelative = 1e-9;
/// A bound is broken when a rate exceeds it by more than this (relative): rounding of the jets.
constexpr double kBreakTolerance = 1e-9;
/// Where the slope error of a quintic Hermite interpolant peaks on its interval: ½ − 1/(2√5).
const double kSlopeErrorPeak = 0.5 - 0.5 / std::sqrt(5.0);
/// The chord speed the window is guaranteed to hold, relative (docs/timing.md: 1e-6 promised).
constexpr double kChordSpeedGuarantee = 5e-7;
/// Steps on which a moving start's ramp speed is checked to stay positive.
constexpr int kRampVelocitySteps = 256;
/// Bisection steps of the inverse maps (to rounding).
constexpr int kBisectionSteps = 100;
/// Pieces of the check between two checks of the request's deadline.
constexpr std::size_t kPiecesPerDeadlineCheck = 256;

const char* const kVelocityName[2] = { "max_linear_velocity", "max_angular_velocity" };
const char* const kAccelerationName[2] = { "max_linear_acceleration", "max_angular_acceleration" };
const char* const kJerkName[2] = { "max_linear_jerk", "max_angular_jerk" };

/// The chord speed g of eq. 1 and its s-derivative g′ from one-sided path jets.
struct ChordSpeed
{
  double g = 0.0;
  double dg = 0.0;
};

ChordSpeed chordSpeed(const PathJet& j, const std::array<double, 2>& w)
{
  ChordSpeed c;
  const double g2 = w[0] * j[0].bb + w[1] * j[1].bb;
  c.g = std::sqrt(g2);
  if (c.g > 0.0)
    c.dg = (w[0] * j[0].ab + w[1] * j[1].ab) / c.g;
  return c;
}

/// The quintic Hermite interpolant on [0, h] of values y, slopes d and second derivatives a at both ends.
std::array<double, 6> quinticHermite(double h, double y0, double d0, double a0, double y1, double d1, double a1)
{
  const double delta = y1 - y0 - d0 * h - 0.5 * a0 * h * h;
  const double dd = (d1 - d0 - a0 * h) * h;
  const double da = (a1 - a0) * h * h;
  const double h3 = h * h * h;
  return { y0,
           d0,
           0.5 * a0,
           (10.0 * delta - 4.0 * dd + 0.5 * da) / h3,
           (-15.0 * delta + 7.0 * dd - da) / (h3 * h),
           (6.0 * delta - 3.0 * dd + 0.5 * da) / (h3 * h * h) };
}

/// S′ of a quintic at u.
double slope(const std::array<double, 6>& c, double u)
{
  return c[1] + u * (2.0 * c[2] + u * (3.0 * c[3] + u * (4.0 * c[4] + u * 5.0 * c[5])));
}

double quinticValue(const std::array<double, 6>& c, double u)
{
  return c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * c[5]))));
}

/// The rates of the motion at one time: per channel speed, acceleration, jerk, and the chord speed.
struct Rates
{
  std::array<double, 2> v{}, a{}, j{};
  double chord = 0.0;
  double s = 0.0;          ///< the path parameter there
  double curvature = 0.0;  ///< |d²C/dσ²| in the chord metric (1/m): how fast the path turns there
};

/// The curvature of the path in the chord metric from the inner products of C′ and C″ per channel
/// (ChannelJet or ChannelJet3): with D(σ) = C(S(σ)), D″ = (C″ − (g′/g) C′)/g², so
/// |D″|² = Σ w (aa − 2 (g′/g) ab + (g′/g)² bb) / g⁴.
template <class J>
double chordCurvature(const std::array<J, 2>& j, const std::array<double, 2>& w)
{
  const double g2 = w[0] * j[0].bb + w[1] * j[1].bb;
  if (!(g2 > 0.0))
    return 0.0;
  const double r = (w[0] * j[0].ab + w[1] * j[1].ab) / g2;  // g′/g
  double k2 = 0.0;
  for (int c = 0; c < 2; ++c)
    k2 += w[c] * (j[c].aa - 2.0 * r * j[c].ab + r * r * j[c].bb);
  return std::sqrt(std::max(0.0, k2)) / g2;
}

class Solver
{
public:
  Solver(const JerkPathModel& path, const RateBounds& bounds, const ConstantSpeedOptions& options)
    : path_(path), bounds_(bounds), options_(options)
  {
    jerk_ = bounds.jerk[0] > 0.0 || bounds.jerk[1] > 0.0;
  }

  ConstantSpeedProfile solve()
  {
    p_.speed = options_.speed;
    p_.t0 = path_.start();
    requireArguments();
    buildTable();
    p_.length = p_.sigma.back();
    if (options_.continue_start)
    {
      // σ̇ = g ṡ and σ̈ = g′ṡ² + g s̈ at ṡ = 1, s̈ = 0.
      const ChordSpeed c = chordSpeed(path_.jet(p_.s.front(), Side::kRight), options_.metric);
      p_.start_speed = c.g;
      p_.start_acceleration = c.dg;
    }
    // The straight line's shortest ramps under the ramps' bounds (file comment); from a moving start,
    // for the change of speed it makes (at least a millionth of the cruise, so that T_u > 0).
    p_.ramp_up = std::max(shortestRamp(std::abs(p_.speed - p_.start_speed)), 1e-6 * p_.length / p_.speed);
    p_.ramp_down = shortestRamp(p_.speed);
    requireRoomForRamps();
    // The speed held between the shortest ramps (lengthening them only shortens the cruise).
    const double shortest_a = arcA(), shortest_b = arcB();
    Excess cruise = check(shortest_a, shortest_b, true, true);
    requireBoundsHeld(cruise);
    for (const bool up : { true, false })
      fitRamp(up);
    // The figures of the motion as fitted: the cruise checked again only where the ramps grew.
    if (arcA() != shortest_a || arcB() != shortest_b)
      cruise = check(arcA(), arcB(), true, true);
    setFigures({ check(0.0, arcA(), false, true), cruise, check(arcB(), p_.length, false, true) });
    return std::move(p_);
  }

private:
  /// The shortest ramp that changes the chord speed by dv on a straight line (file comment).
  double shortestRamp(double dv) const
  {
    double ramp = 0.0;
    const double a = rampBound(bounds_.acceleration);
    const double j = rampBound(bounds_.jerk);
    if (a > 0.0)
      ramp = kRampAccelerationPeak * dv / a;
    if (j > 0.0)
      ramp = std::max(ramp, std::sqrt(kRampJerkPeak * dv / j));
    return ramp;
  }

  /// min(a_lin, ρ a_ang) over the bounds given (ρ = √w_ang), 0 when none is.
  double rampBound(const std::array<double, 2>& b) const
  {
    double r = std::numeric_limits<double>::infinity();
    if (b[0] > 0.0)
      r = b[0];
    if (b[1] > 0.0 && options_.metric[1] > 0.0)
      r = std::min(r, std::sqrt(options_.metric[1]) * b[1]);
    return std::isfinite(r) ? r : 0.0;
  }

  void requireArguments() const
  {
    if (!(std::isfinite(options_.speed) && options_.speed > 0.0))
      throw InvalidInputError("speed: " + formatNumber(options_.speed) +
                              " (timing 'constant_speed' needs the chord speed to hold: a finite number above 0, m/s)");
    if (!(bounds_.acceleration[0] > 0.0 || bounds_.acceleration[1] > 0.0))
      throw InvalidInputError("max_linear_acceleration: timing 'constant_speed' needs it to bound its start and stop "
                              "ramps (m/s^2, above 0)");
  }

  /// The grid of S (file comment) and its quintics; the check's pieces.
  void buildTable()
  {
    const std::vector<double> b = path_.breakpoints();
    const double total = b.back() - b.front();
    std::vector<double> grid;
    std::vector<bool> breakpoint, checked;  // per grid point: a path breakpoint; a piece end of the check
    for (std::size_t i = 0; i + 1 < b.size(); ++i)
    {
      const double len = b[i + 1] - b[i];
      if (!(len > 0.0))
        continue;
      const double share = total > 0.0 ? static_cast<double>(options_.min_intervals) * len / total : 0.0;
      const std::size_t n = 2 * std::max<std::size_t>(options_.intervals_per_piece, static_cast<std::size_t>(std::ceil(share)));
      for (std::size_t k = 0; k < n; ++k)
      {
        grid.push_back(k == 0 ? b[i] : b[i] + len * static_cast<double>(k) / static_cast<double>(n));
        breakpoint.push_back(k == 0);
        checked.push_back(k % 2 == 0);
      }
    }
    grid.push_back(b.back());
    breakpoint.push_back(true);
    checked.push_back(true);
    requireSmoothMotion(b);
    // The stand-stills: g at every grid point (from both sides at the breakpoints).
    std::vector<ChordSpeed> right(grid.size()), left(grid.size());
    double g_max = 0.0;
    for (std::size_t i = 0; i < grid.size(); ++i)
    {
      checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the constant-speed timing");
      right[i] = chordSpeed(path_.jet(grid[i], Side::kRight), options_.metric);
      left[i] = breakpoint[i] ? chordSpeed(path_.jet(grid[i], Side::kLeft), options_.metric) : right[i];
      g_max = std::max({ g_max, right[i].g, left[i].g });
    }
    for (std::size_t i = 0; i < grid.size(); ++i)
      if (!(std::min(i + 1 < grid.size() ? right[i].g : left[i].g, i > 0 ? left[i].g : right[i].g) >
            kStandStillFraction * g_max))
        throw InvalidInputError("speed: the path stands still at path time " + formatNumber(grid[i]) +
                                " s (its velocity is zero there: a clamped end at rest, a dwell or a cusp), where no "
                                "path speed gives a constant chord speed; use end_condition 'natural', or clamped "
                                "end velocities that move");
    p_.s.push_back(grid.front());
    p_.sigma.push_back(0.0);
    for (std::size_t i = 0; i + 1 < grid.size(); ++i)
    {
      checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the constant-speed timing");
      if (checked[i])
        p_.check_sigma.push_back(p_.sigma.back());
      addInterval(grid[i], right[i], grid[i + 1], left[i + 1], 0);
    }
    p_.check_sigma.push_back(p_.sigma.back());
  }

  /// Appends [s0, s1] (or its halves, where the chord speed of its quintic is off) to the table.
  void addInterval(double s0, const ChordSpeed& c0, double s1, const ChordSpeed& c1, int depth)
  {
    double arc = 0.0;
    const double half = 0.5 * (s1 - s0), mid = 0.5 * (s0 + s1);
    for (std::size_t q = 0; q < kGauss4Nodes.size(); ++q)
      arc += kGauss4Weights[q] * chordSpeed(path_.jet(mid + half * kGauss4Nodes[q], Side::kRight), options_.metric).g;
    arc *= half;
    const auto S2 = [](const ChordSpeed& c) { return -c.dg / (c.g * c.g * c.g); };
    const std::array<double, 6> q = quinticHermite(arc, s0, 1.0 / c0.g, S2(c0), s1, 1.0 / c1.g, S2(c1));
    if (depth < kMaxChordSplits)
    {
      // The error of a quintic Hermite interpolant is ∝ u³(u − h)³ near its ends' data: its slope's
      // error vanishes at the middle and peaks at u/h = ½ ∓ 1/(2√5); checked there.
      bool off = false;
      for (const double at : { kSlopeErrorPeak, 1.0 - kSlopeErrorPeak })
      {
        const double u = at * arc;
        const double g = chordSpeed(path_.jet(quinticValue(q, u), Side::kRight), options_.metric).g;
        off = off || !(std::abs(g * slope(q, u) - 1.0) <= kChordSpeedTolerance);
      }
      if (off)
      {
        const ChordSpeed cm = chordSpeed(path_.jet(mid, Side::kRight), options_.metric);
        addInterval(s0, c0, mid, cm, depth + 1);
        addInterval(mid, cm, s1, c1, depth + 1);
        return;
      }
    }
    // A halved interval's start is a piece end of the check too: the table is halved where the
    // path's parameter speed varies so much that its quintic is off (uneven waypoint times put a
    // bend of a few millimetres in a piece metres long), and the check's pieces, twice as long as
    // the table's intervals, would see such a bend only at their ends and middle.
    if (depth > 0 && p_.check_sigma.back() < p_.sigma.back())
      p_.check_sigma.push_back(p_.sigma.back());
    p_.quintic.push_back(q);
    p_.s.push_back(s1);
    p_.sigma.push_back(p_.sigma.back() + arc);
  }

  /// Refuses velocity corners (an infinite acceleration at any speed) and, with a jerk bound,
  /// jumps of C″ (an infinite jerk while moving).
  void requireSmoothMotion(const std::vector<double>& b) const
  {
    for (std::size_t i = 1; i + 1 < b.size(); ++i)
    {
      const double s = b[i];
      if (path_.isCorner(s))
      {
        // Named by the channel that turns there: the linear one where the position moves.
        const PathJet l = path_.jet(s, Side::kLeft);
        const int c = l[0].bb > 0.0 && bounds_.acceleration[0] > 0.0 ? 0 : 1;
        throw InvalidInputError(std::string(kAccelerationName[c]) + ": the path has a corner at path time " +
                                formatNumber(s) + " s (its velocity jumps), which a constant speed would pass with an "
                                "unbounded acceleration; use a blend_radius or a smooth curve");
      }
      if (jerk_ && path_.accelerationJumps(s, std::min(s - b[i - 1], b[i + 1] - s)))
        throw InvalidInputError(std::string(bounds_.jerk[0] > 0.0 ? kJerkName[0] : kJerkName[1]) +
                                ": the path's acceleration jumps at path time " + formatNumber(s) +
                                " s (the curve is only C1 there), which a constant speed would pass with an "
                                "unbounded jerk; use a C2 curve (interpolating, blended continuity 2, a cubic "
                                "B-spline) or no jerk bound");
    }
  }

  void requireRoomForRamps() const
  {
    const double needed = p_.rampUpLength() + p_.rampDownLength();
    if (needed > p_.length)
      throw InvalidInputError("speed: the path is " + formatNumber(p_.length) + " long (chord length), shorter than "
                              "its start and stop ramps to " + formatNumber(p_.speed) + " m/s (" +
                              formatNumber(needed) + "); lower the speed or raise the acceleration and jerk bounds");
  }

  /// The rates at time t (one-sided).
  Rates ratesAt(double t, Side side) const
  {
    const Jet<3> s = p_.pathParameter(Jet<3>::variable(t), side);
    const double sd = s.coefficient(1), sdd = 2.0 * s.coefficient(2), sddd = 6.0 * s.coefficient(3);
    const double sv = std::min(std::max(s.value(), p_.s.front()), p_.s.back());
    const Side path_side = sv <= p_.s.front() ? Side::kRight : sv >= p_.s.back() ? Side::kLeft : side;
    Rates r;
    r.s = sv;
    if (jerk_)
    {
      const PathJet3 j = path_.jet3(sv, path_side);
      for (int c = 0; c < 2; ++c)
      {
        r.v[c] = j[c].speed(sd);
        r.a[c] = j[c].acceleration(sd, sdd);
        r.j[c] = j[c].jerk(sd, sdd, sddd);
      }
      r.chord = std::sqrt(options_.metric[0] * j[0].bb + options_.metric[1] * j[1].bb) * sd;
      r.curvature = chordCurvature(j, options_.metric);
      return r;
    }
    const PathJet j = path_.jet(sv, path_side);
    for (int c = 0; c < 2; ++c)
    {
      r.v[c] = std::sqrt(j[c].bb) * sd;
      const double x = sd * sd;
      r.a[c] = std::sqrt(std::max(0.0, j[c].aa * x * x + 2.0 * j[c].ab * x * sdd + j[c].bb * sdd * sdd));
    }
    r.chord = std::sqrt(options_.metric[0] * j[0].bb + options_.metric[1] * j[1].bb) * sd;
    r.curvature = chordCurvature(j, options_.metric);
    return r;
  }

  /// What a check finds over a span of the motion: the worst ratio of each rate to its bound and
  /// where, the peaks, the chord speed's deviation (in the window) and the energy.
  struct Excess
  {
    std::array<double, 3> ratio{};  ///< velocity, acceleration, jerk (the worse channel's)
    std::array<int, 3> channel{};
    std::array<double, 3> where{};  ///< path time
    std::array<std::array<double, 2>, 3> peak{};  ///< [rate][channel]
    double deviation = 0.0;
    double energy = 0.0;
  };

  /// Checks the pieces of the check between the chord arc lengths lo and hi (file comment); with
  /// `figures`, the interior maxima of the unbounded rates are searched too.
  Excess check(double arc_lo, double arc_hi, bool window, bool figures) const
  {
    Excess e;
    std::vector<double> pieces;
    pieces.push_back(p_.timeAtArcLength(arc_lo));
    for (auto it = std::upper_bound(p_.check_sigma.begin(), p_.check_sigma.end(), arc_lo);
         it != p_.check_sigma.end() && *it < arc_hi; ++it)
      pieces.push_back(p_.timeAtArcLength(*it));
    pieces.push_back(p_.timeAtArcLength(arc_hi));
    const std::array<const std::array<double, 2>*, 3> bound = { &bounds_.velocity, &bounds_.acceleration,
                                                                 &bounds_.jerk };
    const auto pick = [](const Rates& r, int k, int c) { return k == 0 ? r.v[c] : k == 1 ? r.a[c] : r.j[c]; };
    const auto exceed = [&e](int k, int c, double ratio, double where) {
      if (ratio > e.ratio[k])
      {
        e.ratio[k] = ratio;
        e.channel[k] = c;
        e.where[k] = where;
      }
    };
    const auto consider = [&](const Rates& r) {
      for (int c = 0; c < 2; ++c)
        for (int k = 0; k < 3; ++k)
        {
          e.peak[k][c] = std::max(e.peak[k][c], pick(r, k, c));
          if ((*bound[k])[c] > 0.0)
            exceed(k, c, pick(r, k, c) / (*bound[k])[c], r.s);
        }
      if (window)
        e.deviation = std::max(e.deviation, std::abs(r.chord / p_.speed - 1.0));
    };
    const auto density = [this](const Rates& r) {
      return r.a[0] * r.a[0] + (r.a[1] > 0.0 ? options_.metric[1] * r.a[1] * r.a[1] : 0.0);
    };
    struct Span
    {
      double lo, hi;
      Rates r0, rm, r1;
    };
    std::vector<Span> spans;
    spans.reserve(pieces.size());
    // A piece across which the path turns by more than kMaxCheckTurn, or whose bounded rates vary
    // by more than kRateVariation of their largest value near their bound, is halved (at most
    // kMaxCheckSplits times): where uneven waypoint times make the path's parameter speed change by
    // orders of magnitude within a piece, a bend of a few millimetres may lie in a piece metres long
    // in chord length, and its ends and middle would not stand for its interior (as time_optimal's
    // grid is halved where the path's rates vary).
    const auto varies = [&](double lo, double hi, const Rates& r0, const Rates& rm, const Rates& r1) {
      // The path turns by more than kMaxCheckTurn across the piece (Simpson's rule on its curvature
      // over its chord length): a bend narrower than the piece may hide between its points.
      const double turn = (r0.curvature + 4.0 * rm.curvature + r1.curvature) / 6.0 *
                          std::abs(p_.arcLength(hi) - p_.arcLength(lo));
      if (turn > kMaxCheckTurn)
        return true;
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 2; ++c)
        {
          const double b = (*bound[k])[c];
          const double f0 = pick(r0, k, c), fm = pick(rm, k, c), f1 = pick(r1, k, c);
          const double top = std::max({ f0, fm, f1 });
          if (b > 0.0 && top > kVariationNearBound * b && top - std::min({ f0, fm, f1 }) > kRateVariation * top)
            return true;
        }
      return false;
    };
    struct Pending
    {
      double lo, hi;
      Rates r0, r1;
      int depth;
    };
    std::vector<Pending> stack;
    std::size_t visited = 0;
    for (std::size_t i = 0; i + 1 < pieces.size(); ++i)
    {
      if (!(pieces[i + 1] > pieces[i]))
        continue;
      stack.push_back({ pieces[i], pieces[i + 1], ratesAt(pieces[i], Side::kRight), ratesAt(pieces[i + 1], Side::kLeft), 0 });
      while (!stack.empty())
      {
        checkDeadlineEvery(visited++, kPiecesPerDeadlineCheck, "the constant-speed timing's check");
        const Pending p = stack.back();
        stack.pop_back();
        const double mid = 0.5 * (p.lo + p.hi);
        const Rates rm = ratesAt(mid, Side::kRight);
        if (p.depth < kMaxCheckSplits && varies(p.lo, p.hi, p.r0, rm, p.r1))
        {
          // Halves, the left one on top of the stack (the spans stay in time order).
          stack.push_back({ mid, p.hi, rm, p.r1, p.depth + 1 });
          stack.push_back({ p.lo, mid, p.r0, rm, p.depth + 1 });
          continue;
        }
        spans.push_back({ p.lo, p.hi, p.r0, rm, p.r1 });
        for (const Rates* r : { &p.r0, &rm, &p.r1 })
          consider(*r);
        e.energy += (p.hi - p.lo) / 6.0 * (density(p.r0) + 4.0 * density(rm) + density(p.r1));
      }
    }
    // The interior maxima: of a bounded rate where it, or the parabola through its three values,
    // comes near its bound (the guarantee); with `figures`, of every rate where they come near the
    // largest value seen (as jerk_peaks.h and the figures search). A rate flat to rounding over a piece (the chord speed of
    // the window, a linear speed at the velocity bound) has no interior maximum worth searching.
    for (int k = 0; k < (jerk_ ? 3 : 2); ++k)
      for (int c = 0; c < 2; ++c)
      {
        const double b = (*bound[k])[c];
        const double near = b > 0.0 ? (1.0 - kNearBound) * b : std::numeric_limits<double>::infinity();
        const double figure_near = figures ? (1.0 - kNearBound) * e.peak[k][c] : std::numeric_limits<double>::infinity();
        if (!(std::min(near, figure_near) > 0.0) || std::isinf(std::min(near, figure_near)))
          continue;
        for (std::size_t i = 0; i < spans.size(); ++i)
        {
          checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the constant-speed timing's check");
          const Span& sp = spans[i];
          const double f0 = pick(sp.r0, k, c), fm = pick(sp.rm, k, c), f1 = pick(sp.r1, k, c);
          const double top = std::max({ f0, fm, f1 });
          const double threshold = std::min(near, figure_near);
          if (top - std::min({ f0, fm, f1 }) <= kFlatRelative * top ||
              (top < threshold && !detail::parabolaPeaksInside(f0, fm, f1, threshold)))
            continue;
          double best = top, where = sp.rm.s;
          const double peak = detail::localMaxOf(
              [&](double lambda) {
                const Rates r = ratesAt(sp.lo + lambda * (sp.hi - sp.lo), Side::kRight);
                const double f = pick(r, k, c);
                if (f > best)
                {
                  best = f;
                  where = r.s;
                }
                return f;
              },
              f0, fm, f1);
          if (b > 0.0)
            exceed(k, c, peak / b, where);
          e.peak[k][c] = std::max(e.peak[k][c], peak);
        }
      }
    return e;
  }

  double arcA() const { return p_.rampUpLength(); }
  double arcB() const { return p_.length - p_.rampDownLength(); }

  /// Refuses a speed whose cruise breaks a bound (file comment), naming the bound.
  void requireBoundsHeld(const Excess& e) const
  {
    for (int k = 0; k < 3; ++k)
      if (e.ratio[k] > 1.0 + kBreakTolerance)
        refuse(k, e);
  }

  /// Lengthens one ramp until every bound holds on it (file comment).
  void fitRamp(bool up)
  {
    const bool moving = up && options_.continue_start;
    for (int pass = 0; pass < kMaxRampPasses; ++pass)
    {
      requireRoomForRamps();
      if (moving)
        requireRisingRamp();
      const Excess e = up ? check(0.0, arcA(), false, false) : check(arcB(), p_.length, false, false);
      if (moving && std::max({ e.ratio[0], e.ratio[1], e.ratio[2] }) > 1.0 + kBreakTolerance && pass + 1 == kMaxRampPasses)
        refuseStart(e);
      if (e.ratio[0] > 1.0 + kBreakTolerance)
        moving ? refuseStart(e) : refuse(0, e);
      const double f = std::max({ 1.0, std::sqrt(e.ratio[1]), std::cbrt(e.ratio[2]) });
      if (f <= 1.0 + kBreakTolerance)
        return;
      (up ? p_.ramp_up : p_.ramp_down) *= f * (1.0 + 1e-3);
    }
    if (moving)
      throw InvalidInputError("start_state: the ramp from its chord speed " + formatNumber(p_.start_speed) + " to " +
                              formatNumber(p_.speed) + " m/s keeps exceeding the acceleration or jerk bounds");
    throw InvalidInputError(std::string("speed: its ") + (up ? "start" : "stop") + " ramp to " +
                            formatNumber(p_.speed) + " m/s keeps exceeding the acceleration or jerk bounds (the "
                            "path bends too sharply there); lower the speed");
  }

  /// The figures from the final checks of the ramps and the cruise; the chord speed's deviation in
  /// the window, held to its guarantee.
  void setFigures(const std::array<Excess, 3>& parts)
  {
    for (const Excess& e : parts)
    {
      for (int c = 0; c < 2; ++c)
      {
        p_.max_speed[c] = std::max(p_.max_speed[c], e.peak[0][c]);
        p_.max_acceleration[c] = std::max(p_.max_acceleration[c], e.peak[1][c]);
        p_.max_jerk[c] = std::max(p_.max_jerk[c], e.peak[2][c]);
      }
      p_.chord_speed_deviation = std::max(p_.chord_speed_deviation, e.deviation);
      p_.acceleration_energy += e.energy;
    }
    if (!(p_.chord_speed_deviation <= kChordSpeedGuarantee))
      throw InterpolationError("speed: the chord speed of the window is off " + formatNumber(p_.speed) + " m/s by " +
                               formatNumber(p_.chord_speed_deviation) + " (relative) where its table could not be "
                               "refined further (the path's parameter speed varies too fast); give more even times");
  }

  /// From a moving start, the ramp up's chord speed v_0 + (V − v_0) P′(τ) + a_0 T_u H₁(τ) must stay
  /// above 0 (the motion would turn back along the path): checked on 256 steps of the quintic.
  void requireRisingRamp() const
  {
    const double v0 = p_.start_speed, dv = p_.speed - p_.start_speed, a0t = p_.start_acceleration * p_.ramp_up;
    for (int i = 1; i <= kRampVelocitySteps; ++i)
    {
      const double tau = static_cast<double>(i) / kRampVelocitySteps;
      if (!(v0 + dv * rampSlope(tau) + a0t * startSlope(tau) > 0.0))
        throw InvalidInputError("start_state: its chord acceleration " + formatNumber(p_.start_acceleration) +
                                " m/s^2 would turn the motion back along the path before it reaches " +
                                formatNumber(p_.speed) + " m/s; replan when it brakes less, or use timing "
                                "'time_optimal'");
    }
  }

  /// A moving start whose ramp breaks a bound the ramp's length cannot bring back (the start state
  /// itself beyond one, or braking from it): refused naming start_state.
  [[noreturn]] void refuseStart(const Excess& e) const
  {
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (e.ratio[i] > e.ratio[k])
        k = i;
    const char* const* names = k == 0 ? kVelocityName : k == 1 ? kAccelerationName : kJerkName;
    throw InvalidInputError("start_state: the ramp from its chord speed " + formatNumber(p_.start_speed) + " to " +
                            formatNumber(p_.speed) + " m/s takes " + formatNumber(e.ratio[k]) + " times " +
                            names[e.channel[k]] + " at path time " + formatNumber(e.where[k]) +
                            " s (timing 'constant_speed' does not recover from a start beyond the bounds); use "
                            "timing 'time_optimal', or replan from a slower state");
  }

  [[noreturn]] void refuse(int k, const Excess& e) const
  {
    const char* const* names = k == 0 ? kVelocityName : k == 1 ? kAccelerationName : kJerkName;
    const char* what = k == 0 ? "speed" : k == 1 ? "acceleration (the bend's centripetal share)" : "jerk";
    throw InvalidInputError(std::string(names[e.channel[k]]) + ": holding the chord speed " +
                            formatNumber(p_.speed) + " m/s takes " + formatNumber(e.ratio[k]) + " times this bound's " +
                            what + " at path time " + formatNumber(e.where[k]) +
                            " s; lower the speed or raise the bound");
  }

  const JerkPathModel& path_;
  const RateBounds& bounds_;
  const ConstantSpeedOptions& options_;
  bool jerk_ = false;
  ConstantSpeedProfile p_;
};
}  // namespace

std::size_t ConstantSpeedProfile::intervalAt(double arc, Side side) const
{
  const std::size_t n = quintic.size();
  const auto it = side == Side::kRight ? std::upper_bound(sigma.begin(), sigma.end(), arc)
                                       : std::lower_bound(sigma.begin(), sigma.end(), arc);
  const std::ptrdiff_t k = (it - sigma.begin()) - 1;
  return static_cast<std::size_t>(std::min<std::ptrdiff_t>(std::max<std::ptrdiff_t>(k, 0), static_cast<std::ptrdiff_t>(n) - 1));
}

double ConstantSpeedProfile::timeAtArcLength(double arc) const
{
  const double a = rampUpLength(), b = length - rampDownLength();
  if (arc <= 0.0)
    return t0;
  if (arc >= length)
    return endTime();
  if (arc >= a && arc <= b)
    return windowStart() + (arc - a) / speed;
  // P is increasing on [0, 1]: bisection for the ramp's fraction.
  // σ is increasing over each ramp (the ramp up's speed is checked to stay positive): bisection
  // for the ramp's fraction.
  const bool up = arc < a;
  const auto reached = [&](double tau) {
    return up ? arcLength(t0 + tau * ramp_up) < arc : length - speed * ramp_down * rampShape(tau) > arc;
  };
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < kBisectionSteps && hi - lo > 0.0; ++i)
  {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi)
      break;
    (reached(mid) ? lo : hi) = mid;
  }
  const double tau = 0.5 * (lo + hi);
  return up ? t0 + tau * ramp_up : endTime() - tau * ramp_down;
}

double ConstantSpeedProfile::timeAt(double path_parameter) const
{
  if (path_parameter <= s.front())
    return t0;
  if (path_parameter >= s.back())
    return endTime();
  const auto it = std::upper_bound(s.begin(), s.end(), path_parameter);
  const std::size_t k = std::min(static_cast<std::size_t>(it - s.begin()) - 1, quintic.size() - 1);
  double lo = 0.0, hi = sigma[k + 1] - sigma[k];
  for (int i = 0; i < kBisectionSteps; ++i)
  {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi)
      break;
    (quinticValue(quintic[k], mid) < path_parameter ? lo : hi) = mid;
  }
  return timeAtArcLength(sigma[k] + 0.5 * (lo + hi));
}

std::vector<double> ConstantSpeedProfile::breakpoints() const
{
  std::vector<double> b;
  b.reserve(check_sigma.size() + 2);
  for (double arc : check_sigma)
    b.push_back(timeAtArcLength(arc));
  b.push_back(windowStart());
  b.push_back(windowEnd());
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

ConstantSpeedProfile constantSpeedProfile(const JerkPathModel& path, const RateBounds& bounds,
                                          const ConstantSpeedOptions& options)
{
  return Solver(path, bounds, options).solve();
}

}  // namespace timing
}  // namespace se3_interpolation
