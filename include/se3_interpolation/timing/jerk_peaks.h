// timing/: jerk_peaks.h (this header): the peak jerk of a curve on its own clock, which the uniform
// stretch (timing `stretch`) divides by k³ to meet max_linear_jerk / max_angular_jerk.
//
// The jerk of a pose curve is (p⃛, ω̈) (spatial; path_jet3.h, kinematics3FromJet), of a sphere
// curve the covariant D³x/dt³ (sphereKinematics3FromJet), both exact from the curve's third-order
// jets. Within an analytic piece the jerk is smooth: each piece is cut into subintervals
// (subintervalsPerPiece, as the figures are), every subinterval evaluated at its two ends (one-sided)
// and its middle, and searched for its maximum (peak_search.h) where a value or the parabola through
// the three values comes near the largest. At an interior breakpoint where the acceleration itself
// jumps (a curve that is only C¹ there: hermite, blended continuity 1, a B-spline of degree ≤ 2),
// or the velocity does (the corners of a piecewise_geodesic), the jerk is an impulse: no stretch
// bounds it, and the breakpoint is reported.
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
namespace timing
{
/// The peaks of a curve's jerk per channel (kLinear, kAngular) and where its acceleration jumps.
struct JerkPeaks
{
  std::array<double, 2> peak{};  ///< m/s³ and rad/s³ (on the sphere only the angular channel)
  /// The first interior breakpoint at which the acceleration (or the velocity: a corner of a
  /// piecewise_geodesic) jumps: the jerk is an impulse there, and `peak` covers the pieces only.
  /// NaN where none does.
  double acceleration_jump = std::numeric_limits<double>::quiet_NaN();
};

/// |p⃛| and |ω̈| of a pose curve at t (one-sided at a breakpoint).
template <class G>
std::array<double, 2> jerkRates(const Curve<G>& curve, double t, Side side)
{
  const Kinematics3 k = kinematics3FromJet(jet3Of(curve, Jet<3>::variable(t), side));
  return { k.jerk.linear.norm(), k.jerk.angular.norm() };
}

/// The covariant jerk of a sphere curve, in the angular channel.
inline std::array<double, 2> jerkRates(const Curve<Sphere>& curve, double t, Side side)
{
  const auto k = sphereKinematics3FromJet(jet3Of(curve, Jet<3>::variable(t), side));
  return { 0.0, k[2].norm() };
}

/// Subintervals with a value, or a parabola through their three values, within this fraction of the
/// largest value so far are searched for their maximum (the others cannot hold the peak).
constexpr double kJerkRefineMargin = 0.1;

/// The peak jerk of `curve` over its domain (file comment).
/// @throws InvalidInputError for a curve without third-order jets (jet3Of)
template <class G>
JerkPeaks jerkPeaks(const Curve<G>& curve)
{
  JerkPeaks out;
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  const std::size_t pieces = b.size() - 1;
  const std::size_t sub = subintervalsPerPiece(pieces);
  struct Span
  {
    double lo, hi;
    std::array<double, 2> f0, fm, f1;
  };
  std::vector<Span> spans;
  spans.reserve(pieces * sub);
  for (std::size_t i = 0; i < pieces; ++i)
  {
    checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the trajectory's jerk");
    if (i > 0 && std::isnan(out.acceleration_jump) &&
        (velocityJumps(curve, b[i]) || accelerationJumps(curve, b[i], std::min(b[i] - b[i - 1], b[i + 1] - b[i]))))
      out.acceleration_jump = b[i];
    const double h = (b[i + 1] - b[i]) / static_cast<double>(sub);
    for (std::size_t s = 0; s < sub; ++s)
    {
      const double lo = b[i] + static_cast<double>(s) * h;
      const double hi = s + 1 == sub ? b[i + 1] : lo + h;
      Span span{ lo, hi, jerkRates(curve, lo, Side::kRight), jerkRates(curve, 0.5 * (lo + hi), Side::kRight),
                 jerkRates(curve, hi, Side::kLeft) };
      for (int c = 0; c < 2; ++c)
        out.peak[c] = std::max({ out.peak[c], span.f0[c], span.fm[c], span.f1[c] });
      spans.push_back(span);
    }
  }
  for (const Span& span : spans)
    for (int c = 0; c < 2; ++c)
      if (std::max({ span.f0[c], span.fm[c], span.f1[c] }) >= out.peak[c] * (1.0 - kJerkRefineMargin) ||
          detail::parabolaPeaksInside(span.f0[c], span.fm[c], span.f1[c], out.peak[c] * (1.0 - kJerkRefineMargin)))
        out.peak[c] = std::max(out.peak[c], detail::localMaxOf(
                                                [&](double lambda) {
                                                  const double t = span.lo + lambda * (span.hi - span.lo);
                                                  return jerkRates(curve, t, Side::kRight)[c];
                                                },
                                                span.f0[c], span.fm[c], span.f1[c]));
  return out;
}

}  // namespace timing
}  // namespace se3_interpolation
