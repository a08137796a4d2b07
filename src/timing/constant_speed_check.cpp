// The dense check of the constant-speed timing (timing/constant_speed.h's file comment): the rates
// of a span of the motion at the ends and middle of the check's pieces, the pieces halved where
// they vary, the interior maxima searched where a rate comes near its bound, and the motion's
// figures from the final checks. The solver is declared in constant_speed_detail.h.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "constant_speed_detail.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
namespace timing
{
namespace constant_speed_detail
{
/// The rates at time t (one-sided).
Rates ConstantSpeedSolver::ratesAt(double t, Side side) const
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

/// Checks the pieces of the check between the chord arc lengths lo and hi (file comment); with
/// `figures`, the interior maxima of the unbounded rates are searched too.
Excess ConstantSpeedSolver::check(double arc_lo, double arc_hi, bool window, bool figures) const
{
  Excess e;
  const std::vector<CheckSpan> spans = checkSpans(checkPieces(arc_lo, arc_hi), window, e);
  searchInterior(spans, figures, e);
  return e;
}

std::vector<double> ConstantSpeedSolver::checkPieces(double arc_lo, double arc_hi) const
{
  std::vector<double> pieces;
  pieces.push_back(p_.timeAtArcLength(arc_lo));
  for (auto it = std::upper_bound(p_.check_sigma.begin(), p_.check_sigma.end(), arc_lo);
       it != p_.check_sigma.end() && *it < arc_hi; ++it)
    pieces.push_back(p_.timeAtArcLength(*it));
  pieces.push_back(p_.timeAtArcLength(arc_hi));
  return pieces;
}

void ConstantSpeedSolver::consider(const Rates& r, bool window, Excess& e) const
{
  for (int c = 0; c < 2; ++c)
    for (int k = 0; k < 3; ++k)
    {
      e.peak[k][c] = std::max(e.peak[k][c], rateOf(r, k, c));
      if (bound(k)[c] > 0.0)
        e.exceed(k, c, rateOf(r, k, c) / bound(k)[c], r.s);
    }
  if (window)
    e.deviation = std::max(e.deviation, std::abs(r.chord / p_.speed - 1.0));
}

double ConstantSpeedSolver::energyDensity(const Rates& r) const
{
  return r.a[0] * r.a[0] + (r.a[1] > 0.0 ? options_.metric[1] * r.a[1] * r.a[1] : 0.0);
}

// A piece across which the path turns by more than kMaxCheckTurn, or whose bounded rates vary by
// more than kRateVariation of their largest value near their bound, is halved (at most
// kMaxCheckSplits times): where uneven waypoint times make the path's parameter speed change by
// orders of magnitude within a piece, a bend of a few millimetres may lie in a piece metres long
// in chord length, and its ends and middle would not stand for its interior (as time_optimal's
// grid is halved where the path's rates vary).
bool ConstantSpeedSolver::varies(double lo, double hi, const Rates& r0, const Rates& rm, const Rates& r1) const
{
  // The path turns by more than kMaxCheckTurn across the piece (Simpson's rule on its curvature
  // over its chord length): a bend narrower than the piece may hide between its points.
  const double turn =
      (r0.curvature + 4.0 * rm.curvature + r1.curvature) / 6.0 * std::abs(p_.arcLength(hi) - p_.arcLength(lo));
  if (turn > kMaxCheckTurn)
    return true;
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 2; ++c)
    {
      const double b = bound(k)[c];
      const double f0 = rateOf(r0, k, c), fm = rateOf(rm, k, c), f1 = rateOf(r1, k, c);
      const double top = std::max({ f0, fm, f1 });
      if (b > 0.0 && top > kVariationNearBound * b && top - std::min({ f0, fm, f1 }) > kRateVariation * top)
        return true;
    }
  return false;
}

std::vector<CheckSpan> ConstantSpeedSolver::checkSpans(const std::vector<double>& pieces, bool window, Excess& e) const
{
  std::vector<CheckSpan> spans;
  spans.reserve(pieces.size());
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
    stack.push_back(
        { pieces[i], pieces[i + 1], ratesAt(pieces[i], Side::kRight), ratesAt(pieces[i + 1], Side::kLeft), 0 });
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
        consider(*r, window, e);
      e.energy += (p.hi - p.lo) / 6.0 * (energyDensity(p.r0) + 4.0 * energyDensity(rm) + energyDensity(p.r1));
    }
  }
  return spans;
}

// The interior maxima: of a bounded rate where it, or the parabola through its three values, comes
// near its bound (the guarantee); with `figures`, of every rate where they come near the largest
// value seen (as jerk_peaks.h and the figures search). A rate flat to rounding over a piece (the
// chord speed of the window, a linear speed at the velocity bound) has no interior maximum worth
// searching.
void ConstantSpeedSolver::searchInterior(const std::vector<CheckSpan>& spans, bool figures, Excess& e) const
{
  for (int k = 0; k < (jerk_ ? 3 : 2); ++k)
    for (int c = 0; c < 2; ++c)
    {
      const double b = bound(k)[c];
      const double near = b > 0.0 ? (1.0 - kNearBound) * b : std::numeric_limits<double>::infinity();
      const double figure_near = figures ? (1.0 - kNearBound) * e.peak[k][c] : std::numeric_limits<double>::infinity();
      if (!(std::min(near, figure_near) > 0.0) || std::isinf(std::min(near, figure_near)))
        continue;
      for (std::size_t i = 0; i < spans.size(); ++i)
      {
        checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the constant-speed timing's check");
        const CheckSpan& sp = spans[i];
        const double f0 = rateOf(sp.r0, k, c), fm = rateOf(sp.rm, k, c), f1 = rateOf(sp.r1, k, c);
        const double top = std::max({ f0, fm, f1 });
        const double threshold = std::min(near, figure_near);
        if (top - std::min({ f0, fm, f1 }) <= kFlatRelative * top ||
            (top < threshold && !detail::parabolaPeaksInside(f0, fm, f1, threshold)))
          continue;
        double best = top, where = sp.rm.s;
        const double peak = detail::localMaxOf(
            [&](double lambda) {
              const Rates r = ratesAt(sp.lo + lambda * (sp.hi - sp.lo), Side::kRight);
              const double f = rateOf(r, k, c);
              if (f > best)
              {
                best = f;
                where = r.s;
              }
              return f;
            },
            f0, fm, f1);
        if (b > 0.0)
          e.exceed(k, c, peak / b, where);
        e.peak[k][c] = std::max(e.peak[k][c], peak);
      }
    }
}

/// The figures from the final checks of the ramps and the cruise; the chord speed's deviation in
/// the window, held to its guarantee.
void ConstantSpeedSolver::setFigures(const std::array<Excess, 3>& parts)
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
                             formatNumber(p_.chord_speed_deviation) +
                             " (relative) where its table could not be "
                             "refined further (the path's parameter speed varies too fast); give more even times");
}
}  // namespace constant_speed_detail
}  // namespace timing
}  // namespace se3_interpolation
