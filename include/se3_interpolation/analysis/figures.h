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
};

/// Gauss–Legendre subintervals per piece: at least kMinSubintervals, and about
/// kFigureSubintervals over the whole curve when it has few pieces (a single Bézier or a
/// two-waypoint spline still gets 64 × 8 nodes; measured: the figures then agree with a
/// 10-times finer rule to 1e-12).
constexpr std::size_t kMinSubintervals = 4;
constexpr std::size_t kFigureSubintervals = 64;
/// Each peak is refined in a bracket of ± a quarter subinterval around its best node.
constexpr double kPeakBracketFraction = 0.25;
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

  for (std::size_t i = 0; i < pieces; ++i)
  {
    checkDeadlineEvery(i, kPiecesPerDeadlineCheck, "the trajectory's figures");
    const double h = (b[i + 1] - b[i]) / static_cast<double>(sub);
    consider(kinematicsAt(curve, b[i], Side::kRight), b[i], b[i], b[i] + h);
    consider(kinematicsAt(curve, b[i + 1], Side::kLeft), b[i + 1], b[i + 1] - h, b[i + 1]);
    for (std::size_t s = 0; s < sub; ++s)
    {
      const double a = b[i] + static_cast<double>(s) * h;
      for (std::size_t g = 0; g < kGaussNodes.size(); ++g)
      {
        const double t = a + 0.5 * h * (1.0 + kGaussNodes[g]);
        const double w = 0.5 * h * kGaussWeights[g];
        const auto k = kinematicsAt(curve, t);
        const Rates r = rates(k);
        fig.length += w * r[kLinearSpeed];
        fig.rotation_length += w * r[kAngularSpeed];
        fig.energy += w * energyDensity(k, rotation_scale);
        consider(k, t, std::max(b[i], t - kPeakBracketFraction * h), std::min(b[i + 1], t + kPeakBracketFraction * h));
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
