// timing/: the interior-maximum search shared by the timings' final checks (time_optimal_check.cpp,
// jerk_limited_check.cpp): a rate checked at the two ends and the middle of an interval is searched
// inside it where the parabola through the three values peaks inside; checked also at the quarters,
// each half is searched where the parabola through its three values peaks inside it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace se3_interpolation
{
namespace timing
{
namespace detail
{
/// The search's steps, and the step (fraction of the interval) at which it stops; the maximum's
/// value is then exact to ~(1e-7)² relative.
constexpr int kLocalMaxSteps = 12;
constexpr double kLocalMaxTolerance = 1e-7;
/// It also stops, after its first step, where the parabola through its bracket promises less than
/// this (relative) above the best value found: the value is what the search is for, and near a
/// smooth maximum the parabola's error is far below its promise. (The time-optimal timing's final
/// check on a 1000-waypoint line: 4 200 path jets in its searches with this rule, 50 000 without,
/// the same duration and figures to 12 digits.)
constexpr double kLocalMaxValueTolerance = 1e-13;

/// Whether the parabola through (0, f0), (½, fm), (1, f1), f0 + c1 λ + c2 λ², has a maximum
/// inside the interval at or above `threshold` (where a rate could rise above the checked points).
inline bool parabolaPeaksInside(double f0, double fm, double f1, double threshold)
{
  const double c1 = -3.0 * f0 + 4.0 * fm - f1;
  const double c2 = 2.0 * f0 - 4.0 * fm + 2.0 * f1;
  if (!(c2 < 0.0))
    return false;
  const double vertex = -c1 / (2.0 * c2);
  return vertex > 0.0 && vertex < 1.0 && f0 + c1 * vertex + c2 * vertex * vertex >= threshold;
}

/// The largest value of `value(λ)` on [0, 1] (λ the fraction of an interval) from its values at
/// 0, ½, 1: successive parabolic interpolation, golden-section steps when a parabola fails.
template <class F>
double localMaxOf(F value, double f0, double fm, double f1)
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
    if (step > 0 && next > l[0] && next < l[2])
    {
      // The parabola's value at its vertex (Newton's form through the bracket): where it promises
      // less than kLocalMaxValueTolerance above the best, the maximum is found to that.
      const double a1 = (f[1] - f[0]) / (l[1] - l[0]);
      const double a2 = ((f[2] - f[1]) / (l[2] - l[1]) - a1) / (l[2] - l[0]);
      const double promised = f[0] + (next - l[0]) * (a1 + a2 * (next - l[1]));
      if (promised - best <= kLocalMaxValueTolerance * std::abs(best))
        break;
    }
    if (!(next > l[0] && next < l[2]) || next == l[1])
      next = l[2] - l[1] > l[1] - l[0] ? l[1] + 0.381966 * (l[2] - l[1]) : l[1] - 0.381966 * (l[1] - l[0]);
    const double fn = value(next);
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
/// The largest value of `value(λ)` on [0, 1] from its values at 0, ¼, ½, ¾, 1 (f): each half whose
/// parabola (through its ends and middle) peaks inside it at or above `threshold` is searched by
/// localMaxOf; otherwise the largest of the five. `*searched` says whether a half was searched.
/// Five points see what three cannot: a rate at its bound at an end of the interval that rises
/// before it falls to the middle (the parabola through 0, ½, 1 then peaks at the end).
template <class F>
double localMaxOfQuarters(F value, const std::array<double, 5>& f, double threshold, bool* searched)
{
  double best = std::max({ f[0], f[1], f[2], f[3], f[4] });
  *searched = false;
  for (int half = 0; half < 2; ++half)
  {
    const double a = f[2 * half], m = f[2 * half + 1], b = f[2 * half + 2];
    if (!parabolaPeaksInside(a, m, b, threshold))
      continue;
    *searched = true;
    const double from = 0.5 * half;
    best = std::max(best, localMaxOf([&value, from](double lambda) { return value(from + 0.5 * lambda); }, a, m, b));
  }
  return best;
}
/// The largest value of `value(λ)` on [0, 1] from its values `at` λ = 0, ¼, ½, ¾, 1, of which the
/// quarters are read only where `quarters`: localMaxOfQuarters, or from the ends and middle alone
/// localMaxOf where the parabola through them peaks inside at or above `threshold` (else the
/// largest of the three). `*searched` says whether anything was searched.
template <class F>
double localMaxOfChecked(F value, const std::array<double, 5>& at, bool quarters, double threshold, bool* searched)
{
  if (quarters)
    return localMaxOfQuarters(value, at, threshold, searched);
  *searched = parabolaPeaksInside(at[0], at[2], at[4], threshold);
  return *searched ? localMaxOf(value, at[0], at[2], at[4]) : std::max({ at[0], at[2], at[4] });
}
}  // namespace detail
}  // namespace timing
}  // namespace se3_interpolation
