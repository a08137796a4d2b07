// The integral figures of a curve over its domain — length, rotation length, energy and peak
// rates — written once over the geometry: both SE(3) geometries through the pose kinematics
// (kinematics.h), the sphere S^m through its own (geometry/sphere.h), whose motion is the
// angular channel (rad on the unit sphere) with rotation scale 1.
//
// The integrals use 8-point Gauss–Legendre rules (math/quadrature.h) on subintervals of each
// analytic piece (between breakpoints), so they are accurate to near machine precision for the
// smooth curves here; the maxima are located on those nodes and the piece ends, then refined by
// golden-section search. The effort is linear in the pieces (work_estimate.h counts it).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/math/quadrature.h"

namespace se3_interpolation
{
/// Length, rotation length, energy and peak rates of a curve over its whole domain.
struct CurveFigures
{
  double length = 0.0;           ///< ∫ |ṗ| dt, m (0 on the sphere)
  double rotation_length = 0.0;  ///< ∫ |ω| dt, rad (on the sphere: ∫ |ẋ| dt)
  double energy = 0.0;           ///< ∫ |p̈|² + ρ²|ω̇|² dt (Crouch et al. eq. 32)
  double max_linear_speed = 0.0;
  double max_angular_speed = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  /// Peak |d³p/dt³| (m/s³) and |ω̈| (rad/s³): measured only when a jerk bound is set
  /// (analysis/jerk_figures.h, or the jerk-limited timing's own check); 0 otherwise.
  double max_linear_jerk = 0.0;
  double max_angular_jerk = 0.0;
};

/// Gauss–Legendre subintervals per piece: at least kMinSubintervals, and about
/// kFigureSubintervals over the whole curve when it has few pieces (a single Bézier or a
/// two-waypoint spline still gets 64 × 8 nodes; measured: the figures then agree with a
/// 10-times finer rule to 1e-12).
constexpr std::size_t kMinSubintervals = 4;
constexpr std::size_t kFigureSubintervals = 64;
/// Each peak is refined in a bracket of ± a quarter subinterval around its best node.
constexpr double kPeakBracketFraction = 0.25;
/// Adaptive subdivision: a subinterval is halved while a channel's speed at its ends and nodes
/// varies by more than this factor (the fastest against the slowest, floored at kFigureSpeedFloor
/// of the curve's fastest so far, so that near a stationary point the halving stops once the
/// speeds there are negligible).
constexpr double kFigureSpeedRatio = 4.0;
constexpr double kFigureSpeedFloor = 1e-2;
constexpr int kMaxFigureDepth = 24;
constexpr std::size_t kMaxFigureSplitsPerSpan = 4;
/// Pieces measured between two checks of the request's deadline (deadline.h).
constexpr std::size_t kPiecesPerDeadlineCheck = 64;

inline std::size_t subintervalsPerPiece(std::size_t pieces)
{
  return std::max<std::size_t>(kMinSubintervals, kFigureSubintervals / std::max<std::size_t>(pieces, 1));
}

template <class G>
CurveFigures measureCurve(const Curve<G>& curve, double rotation_scale)
{
  CurveFigures fig;
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  const std::size_t pieces = b.size() - 1;
  const std::size_t sub = subintervalsPerPiece(pieces);

  // The four peak quantities, each with the node where it was largest.
  Rates peak{};
  std::array<double, 4> where{};
  std::array<std::pair<double, double>, 4> bracket{};
  auto consider = [&](const auto& k, double t, double lo, double hi) {
    const Rates r = rates(k);
    for (std::size_t j = 0; j < r.size(); ++j)
      if (r[j] > peak[j])
      {
        peak[j] = r[j];
        where[j] = t;
        bracket[j] = { lo, hi };
      }
  };

  // Each subinterval: its ends and Gauss nodes, halved (at most kMaxFigureDepth times) where the
  // speeds seen there differ by more than kFigureSpeedRatio in a channel (a piece whose time runs
  // 10⁵ times faster at one end than at the other, e.g. a corner blend between uneven times, whose
  // peaks lie in a sliver of it).
  struct Span
  {
    double a, b;
    int depth;
  };
  std::vector<Span> stack;
  // At most kMaxFigureSplitsPerSpan halvings per initial subinterval on average, so that a curve
  // whose speeds vary everywhere costs a bounded multiple of the uniform rule.
  std::size_t splits_left = kMaxFigureSplitsPerSpan * pieces * sub;
  std::array<decltype(kinematicsAt(curve, 0.0)), kGaussNodes.size()> nodes;
  for (std::size_t i = 0; i < pieces; ++i)
  {
    checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the trajectory's figures");
    const double h = (b[i + 1] - b[i]) / static_cast<double>(sub);
    for (std::size_t s = sub; s-- > 0;)
      stack.push_back({ b[i] + static_cast<double>(s) * h, s + 1 == sub ? b[i + 1] : b[i] + static_cast<double>(s + 1) * h, 0 });
    while (!stack.empty())
    {
      const Span span = stack.back();
      stack.pop_back();
      const double width = span.b - span.a;
      const double bracket_width = kPeakBracketFraction * width;
      const auto ka = kinematicsAt(curve, span.a, Side::kRight);
      const auto kb = kinematicsAt(curve, span.b, Side::kLeft);
      Rates fastest = rates(ka), slowest = fastest;
      auto widen = [&fastest, &slowest](const Rates& r) {
        for (std::size_t j = 0; j < 2; ++j)
        {
          fastest[j] = std::max(fastest[j], r[j]);
          slowest[j] = std::min(slowest[j], r[j]);
        }
      };
      widen(rates(kb));
      for (std::size_t g = 0; g < kGaussNodes.size(); ++g)
      {
        nodes[g] = kinematicsAt(curve, span.a + 0.5 * width * (1.0 + kGaussNodes[g]));
        widen(rates(nodes[g]));
      }
      bool split = false;
      for (std::size_t j = 0; j < 2; ++j)
        split = split || fastest[j] > kFigureSpeedRatio * std::max(slowest[j],
                                                                    kFigureSpeedFloor * std::max(fastest[j], peak[j]));
      const double middle = 0.5 * (span.a + span.b);
      if (split && span.depth < kMaxFigureDepth && splits_left > 0 && middle > span.a && middle < span.b)
      {
        --splits_left;
        stack.push_back({ middle, span.b, span.depth + 1 });
        stack.push_back({ span.a, middle, span.depth + 1 });
        continue;
      }
      consider(ka, span.a, std::max(b[i], span.a - bracket_width), std::min(span.b, span.a + bracket_width));
      consider(kb, span.b, std::max(span.a, span.b - bracket_width), std::min(b[i + 1], span.b + bracket_width));
      for (std::size_t g = 0; g < kGaussNodes.size(); ++g)
      {
        const double t = span.a + 0.5 * width * (1.0 + kGaussNodes[g]);
        const double w = 0.5 * width * kGaussWeights[g];
        const Rates r = rates(nodes[g]);
        fig.length += w * r[kLinearSpeed];
        fig.rotation_length += w * r[kAngularSpeed];
        fig.energy += w * energyDensity(nodes[g], rotation_scale);
        consider(nodes[g], t, std::max(span.a, t - bracket_width), std::min(span.b, t + bracket_width));
      }
    }
  }
  for (std::size_t j = 0; j < peak.size(); ++j)
  {
    if (peak[j] <= 0.0 || bracket[j].second <= bracket[j].first)
      continue;
    const double lo = bracket[j].first;
    const double hi = bracket[j].second;
    // Evaluate from the side of the bracket so that a peak at a breakpoint is kept.
    const Side side = where[j] >= hi ? Side::kLeft : Side::kRight;
    peak[j] = goldenMax([&](double t) { return rates(kinematicsAt(curve, t, side))[j]; }, lo, hi, peak[j]);
  }
  fig.max_linear_speed = peak[kLinearSpeed];
  fig.max_angular_speed = peak[kAngularSpeed];
  fig.max_linear_acceleration = peak[kLinearAcceleration];
  fig.max_angular_acceleration = peak[kAngularAcceleration];
  return fig;
}

}  // namespace se3_interpolation
