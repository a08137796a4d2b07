// The table of S(σ) of the constant-speed timing (timing/constant_speed.h's file comment): the grid
// of the path parameter, the quintic Hermite interpolant of S on each interval, halved where its
// chord speed is off, and the check's piece ends; with the refusal of paths no constant speed can
// pass (corners, C¹ joints under a jerk bound, stand-stills). The solver is declared in
// constant_speed_detail.h.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "constant_speed_detail.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/quadrature.h"

namespace se3_interpolation
{
namespace timing
{
namespace constant_speed_detail
{
/// The grid of S (file comment) and its quintics; the check's pieces.
void ConstantSpeedSolver::buildTable()
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
    const std::size_t n =
        2 * std::max<std::size_t>(options_.intervals_per_piece, static_cast<std::size_t>(std::ceil(share)));
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
void ConstantSpeedSolver::addInterval(double s0, const ChordSpeed& c0, double s1, const ChordSpeed& c1, int depth)
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
void ConstantSpeedSolver::requireSmoothMotion(const std::vector<double>& b) const
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
                              formatNumber(s) +
                              " s (its velocity jumps), which a constant speed would pass with an "
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
}  // namespace constant_speed_detail
}  // namespace timing
}  // namespace se3_interpolation
