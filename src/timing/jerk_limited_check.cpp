// The final check of the jerk-limited timing (timing/jerk_limited.h, its file comment): the motion's
// pieces (the grid's times and their shifts by the window, the passages of the path's
// breakpoints), the six rates at their ends and middles with exact third-order path jets, the
// searched peaks, the stretch they need and the figures. The solver is declared in
// jerk_limited_solver.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/timing/peak_search.h"
#include "jerk_limited_solver.h"
#include "time_optimal_solver.h"

namespace se3_interpolation
{
namespace timing
{
namespace jerk_limited_detail
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Pieces whose parabola through ends and middle comes within this fraction of the largest value
/// seen are searched for their interior maximum (time_optimal_check.cpp's margin).
constexpr double kRefineMargin = 1e-3;
/// A piece is halved (at most kMaxSplitDepth times) while the path's rates vary across it more than
/// the underlying grid's refinement allows across its intervals (the same rule,
/// time_optimal_detail::channelVaries): where that refinement stopped at its limits (a blended
/// curve whose uneven times make |C′| change 100-fold within one grid interval, found by the
/// request-space grid), the parabola through a piece's ends and middle missed a speed peak by 30 %.
constexpr int kMaxSplitDepth = 12;
}  // namespace

Rates6 JerkSolver::rates(const PathJet3& j, const Jet<3>& s)
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

Side JerkSolver::pathSide(const JerkLimitedProfile::Segment& g, double s, Side side) const
{
  if (s >= profile_.base.s[g.last])
    return Side::kLeft;
  if (s <= g.s_start)
    return Side::kRight;
  return side;
}

Jet<3> JerkSolver::shifted(const Jet<3>& p, double h)
{
  const double c0 = p.coefficient(0), c1 = p.coefficient(1), c2 = p.coefficient(2), c3 = p.coefficient(3);
  Jet<3> q(c0 + h * (c1 + h * (c2 + h * c3)));
  q.coefficient(1) = c1 + h * (2.0 * c2 + 3.0 * h * c3);
  q.coefficient(2) = c2 + 3.0 * h * c3;
  q.coefficient(3) = c3;
  return q;
}

PathJet3 JerkSolver::segmentPathJet(const JerkLimitedProfile::Segment& g, double s, Side side) const
{
  const double c = std::min(std::max(s, g.s_start), profile_.base.s[g.last]);
  return path_.jet3(c, pathSide(g, c, side));
}

Rates6 JerkSolver::ratesInside(const JerkLimitedProfile::Segment& g, const Jet<3>& s) const
{
  return rates(segmentPathJet(g, s.value(), Side::kRight), s);
}

void JerkSolver::pieces(const JerkLimitedProfile::Segment& g, const std::vector<double>& path_breaks,
                        std::vector<double>* times, std::vector<double>* crossing) const
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
  for (auto it = std::upper_bound(path_breaks.begin(), path_breaks.end(), sa); it != path_breaks.end() && *it < sb;
       ++it)
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

void JerkSolver::splitFloor()
{
  for (int c = 0; c < 2; ++c)
  {
    double largest = 0.0;
    for (const PathJet3& j : jets_)
      largest = std::max(largest, j[c].bb);
    split_floor_[c] = kMoveTolerance * kMoveTolerance * largest;
  }
}

bool JerkSolver::pathVaries(const PathJet3& a, const PathJet3& m, const PathJet3& b, double d) const
{
  for (int c = 0; c < 2; ++c)
    if (moves_[c] && time_optimal_detail::channelVaries(a[c], m[c], b[c], d, split_floor_[c]))
      return true;
  return false;
}

double JerkSolver::verify()
{
  const std::vector<double> path_breaks = path_.breakpoints();
  CheckTally tally;
  splitFloor();
  std::vector<double> times;
  std::vector<double> crossing;
  std::vector<double>& motion_breaks = profile_.breakpoints;
  reserveMotionBreaks(path_breaks.size());
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
      const Jet<3> middle = profile_.segmentParameter(g, Jet<3>::variable(mid), Side::kRight);
      const Jet<3> sr = shifted(middle, lo - mid), sl = shifted(middle, hi - mid);
      PathJet3 jr = jl;
      if (i == 0)
        jr = segmentPathJet(g, sr.value(), Side::kRight);
      else if (!std::isnan(crossing[i]))
        jr = segmentPathJet(g, crossing[i], Side::kRight);
      jl = segmentPathJet(g, std::isnan(crossing[i + 1]) ? sl.value() : crossing[i + 1], Side::kLeft);
      checkPiece(k, CheckPart{ lo, hi, middle, jr, jl, rates(jr, sr), rates(jl, sl), 0 }, &tally);
    }
  }
  searchPieces(tally.candidates, &tally.peak);
  peak_ = tally.peak;
  energy_ = tally.energy;
  return stretchNeeded(tally.peak);
}

void JerkSolver::reserveMotionBreaks(std::size_t path_breaks)
{
  profile_.breakpoints.clear();
  // (Reserved: the pieces are about twice the grid's intervals, and growing costs copies.)
  std::size_t room = path_breaks;
  for (const auto& g : profile_.segments)
    room += 2 * (g.last - g.first + 1);
  profile_.breakpoints.reserve(room);
}

void JerkSolver::checkPiece(std::size_t k, const CheckPart& piece, CheckTally* tally) const
{
  const auto& g = profile_.segments[k];
  Rates6& peak = tally->peak;
  std::vector<CheckPart>& parts = tally->parts;
  // The piece, halved while the path's rates vary too much across a part for the parabola
  // through its ends and middle to stand for it (pathVaries).
  parts.clear();
  parts.push_back(piece);
  while (!parts.empty())
  {
    const CheckPart a = parts.back();
    parts.pop_back();
    const PathJet3 jm = segmentPathJet(g, a.middle.value(), Side::kRight);
    const Rates6 fm = rates(jm, a.middle);
    const double quarter = 0.25 * (a.hi - a.lo), centre = 0.5 * (a.lo + a.hi);
    if (a.depth < kMaxSplitDepth &&
        pathVaries(a.jr, jm, a.jl,
                   shifted(a.middle, 2.0 * quarter).value() - shifted(a.middle, -2.0 * quarter).value()))
    {
      parts.push_back(CheckPart{ centre, a.hi, shifted(a.middle, quarter), jm, a.jl, fm, a.f1, a.depth + 1 });
      parts.push_back(CheckPart{ a.lo, centre, shifted(a.middle, -quarter), a.jr, jm, a.f0, fm, a.depth + 1 });
      continue;
    }
    for (int q = 0; q < 6; ++q)
      peak[q] = std::max({ peak[q], a.f0[q], fm[q], a.f1[q] });
    for (int c = 0; c < 2; ++c)
      tally->energy[c] +=
          (a.hi - a.lo) / 6.0 * (a.f0[2 + c] * a.f0[2 + c] + 4.0 * fm[2 + c] * fm[2 + c] + a.f1[2 + c] * a.f1[2 + c]);
    // Only the pieces the search below may take: the peaks only grow, so a piece whose parabola
    // does not reach the threshold of the peaks so far never reaches the final one (the same
    // pieces are searched, in the same order, without holding every piece's values).
    bool candidate = false;
    for (int q = 0; q < 6 && !candidate; ++q)
      candidate = detail::parabolaPeaksInside(a.f0[q], fm[q], a.f1[q], peak[q] * (1.0 - kRefineMargin));
    if (candidate)
      tally->candidates.push_back(CheckPiece{ k, a.lo, a.hi, a.middle, a.f0, fm, a.f1 });
  }
}

void JerkSolver::searchPieces(const std::vector<CheckPiece>& candidates, Rates6* peak_io) const
{
  Rates6& peak = *peak_io;
  // The interior maxima where the parabola through ends and middle peaks near the largest value.
  std::size_t count = 0;
  for (const CheckPiece& p : candidates)
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
}

double JerkSolver::stretchNeeded(const Rates6& peak) const
{
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

void JerkSolver::applyStretch(double k)
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
    // (|a| scales by 1/k², the time by k.)
    p.acceleration_energy[c] = energy_[c] / (k * k * k);
  }
}

}  // namespace jerk_limited_detail
}  // namespace timing
}  // namespace se3_interpolation
