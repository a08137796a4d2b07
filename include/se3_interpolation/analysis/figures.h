// The integral figures of a curve over its domain — length, rotation length, energy and peak
// rates — written once over the geometry: both SE(3) geometries through the pose kinematics
// (kinematics.h), the sphere S^m through its own (geometry/sphere.h), whose motion is the
// angular channel (rad on the unit sphere) with rotation scale 1.
//
// The integrals use 8-point Gauss–Legendre rules (math/quadrature.h) on subintervals of each
// analytic piece (between breakpoints), so they are accurate to near machine precision for the
// smooth curves here; the maxima are located on those nodes and the piece ends, then refined by
// golden-section search around the local maxima that may hold them (kPeakSearchesPerRate). The effort is linear
// in the pieces (work_estimate.h counts it).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
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
  /// (timing/jerk_peaks.h, or the jerk-limited timing's own check); 0 otherwise.
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
/// Peaks refined per rate. Every local maximum among a piece's points (its subintervals' ends and
/// Gauss nodes in time order) is a candidate, ranked by the vertex of the parabola through it and its
/// two neighbours (peakOfParabola); the kPeakSearchesPerRate best, within kPeakCandidateMargin of
/// the largest point, are refined by golden-section search. A curve with two peaks of about the
/// same height can sample the lower one higher: refining only the best point missed a corner
/// blend's peak angular acceleration by 1 % (the request-space grid: 69.496 against 68.830 rad/s²,
/// test_figures, APeakSampledLowerThanAnotherIsFound), and the stretch scaled to the lower peak
/// broke the bound by as much. Two searches per rate are what the work estimate counts
/// (work_estimate.cpp).
constexpr std::size_t kPeakSearchesPerRate = 2;
/// Candidates kept per rate before the best kPeakSearchesPerRate are refined.
constexpr std::size_t kPeakCandidates = 8;
constexpr double kPeakCandidateMargin = 0.25;

namespace detail
{
/// The largest value of the parabola through (t0, v0), (t1, v1), (t2, v2), t0 < t1 < t2, where v1 is
/// the largest of the three (its vertex, which then lies in [t0, t2]); v1 where the three are on a
/// line or the parabola opens upwards.
inline double peakOfParabola(double t0, double v0, double t1, double v1, double t2, double v2)
{
  const double d0 = t0 - t1, d2 = t2 - t1;
  if (!(d0 < 0.0) || !(d2 > 0.0))
    return v1;
  const double s0 = (v0 - v1) / d0, s2 = (v2 - v1) / d2;  // slopes of the chords to t1
  const double a = (s2 - s0) / (d2 - d0);                 // v(t1 + u) = v1 + b u + a u²
  if (!(a < 0.0))
    return v1;
  const double b = s0 - a * d0;
  const double top = v1 - b * b / (4.0 * a);
  return std::isfinite(top) ? top : v1;
}

/// The points where one rate may peak (measureCurve): at most kPeakCandidates separate brackets,
/// each with its best point, ranked by their parabolic estimate of the peak.
struct PeakCandidates
{
  struct Candidate
  {
    double estimate, t, lo, hi;
  };
  std::array<Candidate, kPeakCandidates> candidates{};
  std::size_t size = 0;

  /// Offers the local maximum at t (its parabolic estimate, refinement bracket [lo, hi]).
  void offer(double estimate, double t, double lo, double hi)
  {
    if (!(estimate > 0.0))
      return;
    std::size_t lowest = 0;
    for (std::size_t c = 0; c < size; ++c)
    {
      Candidate& k = candidates[c];
      if ((t >= k.lo && t <= k.hi) || (k.t >= lo && k.t <= hi))  // the same peak's bracket
      {
        if (estimate > k.estimate)
          k = { estimate, t, lo, hi };
        return;
      }
      if (k.estimate < candidates[lowest].estimate)
        lowest = c;
    }
    if (size < kPeakCandidates)
      candidates[size++] = { estimate, t, lo, hi };
    else if (estimate > candidates[lowest].estimate)
      candidates[lowest] = { estimate, t, lo, hi };
  }

  /// The candidates to refine: the best kPeakSearchesPerRate, best first, none below
  /// (1 − kPeakCandidateMargin) of `largest` (the largest point's value).
  std::size_t best(double largest)
  {
    std::sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(size),
              [](const Candidate& x, const Candidate& y) { return x.estimate > y.estimate; });
    std::size_t n = 0;
    while (n < std::min(size, kPeakSearchesPerRate) && candidates[n].estimate >= (1.0 - kPeakCandidateMargin) * largest)
      ++n;
    return n;
  }
};

/// One evaluated point of a piece, in time order (measureCurve): its rates and refinement bracket.
struct RatePoint
{
  Rates rates;
  double t, lo, hi;
};

/// Feeds a piece's points in time order and offers each rate's local maxima (a point at least its
/// left neighbour and above its right one, so that a plateau or a monotone ramp offers one point,
/// not each) to the candidates, with the parabolic estimate through its neighbours.
class LocalMaxima
{
public:
  explicit LocalMaxima(std::array<PeakCandidates, 4>& candidates) : candidates_(candidates) {}

  /// A new piece: the previous one's last point is judged against its left neighbour alone.
  void startPiece()
  {
    flush();
    count_ = 0;
  }

  void push(const RatePoint& p)
  {
    if (count_ > 0 && p.t == last_.t)
      return;  // a subinterval's end, which starts the next one
    if (count_ > 0)
      judge(p);
    left_ = last_;
    last_ = p;
    ++count_;
  }

  /// Judges the last point (the piece's end) against its left neighbour alone.
  void flush()
  {
    if (count_ == 0)
      return;
    for (std::size_t j = 0; j < candidates_.size(); ++j)
      if (count_ == 1 || last_.rates[j] >= left_.rates[j])
        candidates_[j].offer(last_.rates[j], last_.t, last_.lo, last_.hi);
    count_ = 0;
  }

private:
  /// Judges the last point with `right` as its right neighbour.
  void judge(const RatePoint& right)
  {
    for (std::size_t j = 0; j < candidates_.size(); ++j)
    {
      const double v = last_.rates[j];
      if (!(v > right.rates[j]) || (count_ > 1 && v < left_.rates[j]))
        continue;
      const double estimate =
          count_ > 1 ? peakOfParabola(left_.t, left_.rates[j], last_.t, v, right.t, right.rates[j]) : v;
      candidates_[j].offer(estimate, last_.t, last_.lo, last_.hi);
    }
  }

  std::array<PeakCandidates, 4>& candidates_;
  RatePoint left_{}, last_{};
  std::size_t count_ = 0;
};
}  // namespace detail
/// Adaptive subdivision: a subinterval is halved while a channel's speed at its ends and nodes
/// varies by more than kFigureSpeedRatio (the fastest against the slowest) where that channel's
/// share of the length there, bounded by its fastest speed times the width, exceeds
/// kFigureLengthResolution of the largest such bound seen so far on the curve. So a corner blend
/// between uneven times, whose speed changes by orders of magnitude in a sliver, is resolved however
/// slow that sliver is next to the curve's peak speed (a floor at 1 % of the peak left the slow part
/// of such slivers to one Gauss rule: lengths 0.4 % short, test_figures), and near a stationary
/// point the halving stops once what lies there is negligible.
constexpr double kFigureSpeedRatio = 4.0;
constexpr double kFigureLengthResolution = 1e-12;
constexpr int kMaxFigureDepth = 24;
constexpr std::size_t kMaxFigureSplitsPerSpan = 4;
/// Pieces measured between two checks of the request's deadline (deadline.h).
constexpr std::size_t kPiecesPerDeadlineCheck = 64;

namespace detail
{
/// A point's speeds alone (speedsAt), as measureLengths evaluates them.
struct SpeedsOnly
{
  Rates speeds;
};
inline const Rates& rates(const SpeedsOnly& s)
{
  return s.speeds;
}

/// The speeds of a subinterval's points, channel by channel, and the halving rule above.
class SpeedSpread
{
public:
  void add(const Rates& r)
  {
    for (std::size_t j = 0; j < 2; ++j)
    {
      fastest_[j] = std::max(fastest_[j], r[j]);
      slowest_[j] = std::min(slowest_[j], r[j]);
    }
  }
  /// Whether a subinterval of `width` with these speeds is halved; `largest` is the largest bound
  /// on a subinterval's length per channel seen on the curve (updated).
  bool splits(double width, std::array<double, 2>* largest) const
  {
    bool split = false;
    for (std::size_t j = 0; j < 2; ++j)
    {
      const double share = fastest_[j] * width;
      (*largest)[j] = std::max((*largest)[j], share);
      split =
          split || (fastest_[j] > kFigureSpeedRatio * slowest_[j] && share > kFigureLengthResolution * (*largest)[j]);
    }
    return split;
  }

private:
  std::array<double, 2> fastest_{};
  std::array<double, 2> slowest_{ std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
};
}  // namespace detail

inline std::size_t subintervalsPerPiece(std::size_t pieces)
{
  return std::max<std::size_t>(kMinSubintervals, kFigureSubintervals / std::max<std::size_t>(pieces, 1));
}

namespace detail
{
/// The adaptive Gauss–Legendre subdivision that measureCurve and measureLengths share: each piece
/// between the sorted, distinct breakpoints `b` in `sub` equal subintervals, each evaluated at its
/// ends (one-sided, inside it) and its Gauss nodes and halved (at most kMaxFigureDepth times, and
/// kMaxFigureSplitsPerSpan times per initial subinterval on average, so that a curve whose speeds
/// vary everywhere costs a bounded multiple of the uniform rule) by SpeedSpread's rule. Calls
/// start_piece(i) at each piece, then accept(i, a, b, ka, kb, nodes) for each kept subinterval in
/// time order, with ka, kb and the nodes what evaluate(t, side) gives (for which rates() gives the
/// speeds). Checks the request's deadline every kPiecesPerDeadlineCheck pieces, naming `phase`.
template <class Evaluate, class StartPiece, class Accept>
void forEachGaussSpan(Evaluate evaluate, const std::vector<double>& b, std::size_t sub, const char* phase,
                      StartPiece start_piece, Accept accept)
{
  struct Span
  {
    double a, b;
    int depth;
  };
  const std::size_t pieces = b.size() - 1;
  std::vector<Span> stack;
  std::size_t splits_left = kMaxFigureSplitsPerSpan * pieces * sub;
  std::array<decltype(evaluate(0.0, Side::kRight)), kGaussNodes.size()> nodes;
  std::array<double, 2> largest_share{};
  for (std::size_t i = 0; i < pieces; ++i)
  {
    checkDeadlineEvery(i, kPiecesPerDeadlineCheck, phase);
    start_piece(i);
    const double h = (b[i + 1] - b[i]) / static_cast<double>(sub);
    for (std::size_t s = sub; s-- > 0;)
      stack.push_back(
          { b[i] + static_cast<double>(s) * h, s + 1 == sub ? b[i + 1] : b[i] + static_cast<double>(s + 1) * h, 0 });
    while (!stack.empty())
    {
      const Span span = stack.back();
      stack.pop_back();
      const double width = span.b - span.a;
      // The split sees the span's ends too: where the speed changes by orders of magnitude in a
      // sliver at an end, the nodes alone may all look alike.
      const auto ka = evaluate(span.a, Side::kRight);
      const auto kb = evaluate(span.b, Side::kLeft);
      SpeedSpread spread;
      spread.add(rates(ka));
      spread.add(rates(kb));
      for (std::size_t g = 0; g < kGaussNodes.size(); ++g)
      {
        nodes[g] = evaluate(span.a + 0.5 * width * (1.0 + kGaussNodes[g]), Side::kRight);
        spread.add(rates(nodes[g]));
      }
      const bool split = spread.splits(width, &largest_share);
      const double middle = 0.5 * (span.a + span.b);
      if (split && span.depth < kMaxFigureDepth && splits_left > 0 && middle > span.a && middle < span.b)
      {
        --splits_left;
        stack.push_back({ middle, span.b, span.depth + 1 });
        stack.push_back({ span.a, middle, span.depth + 1 });
        continue;
      }
      accept(i, span.a, span.b, ka, kb, nodes);
    }
  }
}
}  // namespace detail

template <class G>
CurveFigures measureCurve(const Curve<G>& curve, double rotation_scale)
{
  CurveFigures fig;
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  const std::size_t pieces = b.size() - 1;
  const std::size_t sub = subintervalsPerPiece(pieces);

  // The four peak quantities: the largest point value of each, and the points to refine.
  Rates peak{};
  std::array<detail::PeakCandidates, 4> candidates{};
  detail::LocalMaxima local_maxima(candidates);
  auto add = [&](const Rates& r, double t, double lo, double hi) {
    for (std::size_t j = 0; j < peak.size(); ++j)
      peak[j] = std::max(peak[j], r[j]);
    local_maxima.push({ r, t, lo, hi });
  };

  // Each subinterval: its ends and Gauss nodes, halved where the speeds seen there differ by more
  // than kFigureSpeedRatio in a channel (a piece whose time runs 10⁵ times faster at one end than
  // at the other, e.g. a corner blend between uneven times, whose peaks lie in a sliver of it).
  detail::forEachGaussSpan([&curve](double t, Side side) { return kinematicsAt(curve, t, side); }, b, sub,
                           "the trajectory's figures",
                           [&local_maxima](std::size_t) {
                             local_maxima.startPiece();
                           },  // a breakpoint: the rates may jump there
                           [&](std::size_t i, double a, double z, const auto& ka, const auto& kb, const auto& nodes) {
                             const double width = z - a;
                             const double bracket_width = kPeakBracketFraction * width;
                             add(rates(ka), a, std::max(b[i], a - bracket_width), std::min(z, a + bracket_width));
                             for (std::size_t g = 0; g < kGaussNodes.size(); ++g)
                             {
                               const double t = a + 0.5 * width * (1.0 + kGaussNodes[g]);
                               const double w = 0.5 * width * kGaussWeights[g];
                               const Rates r = rates(nodes[g]);
                               fig.length += w * r[kLinearSpeed];
                               fig.rotation_length += w * r[kAngularSpeed];
                               fig.energy += w * energyDensity(nodes[g], rotation_scale);
                               add(r, t, std::max(a, t - bracket_width), std::min(z, t + bracket_width));
                             }
                             add(rates(kb), z, std::max(a, z - bracket_width), std::min(b[i + 1], z + bracket_width));
                           });
  local_maxima.flush();
  for (std::size_t j = 0; j < peak.size(); ++j)
  {
    const std::size_t searches = candidates[j].best(peak[j]);
    for (std::size_t c = 0; c < searches; ++c)
    {
      const detail::PeakCandidates::Candidate& k = candidates[j].candidates[c];
      if (k.hi <= k.lo)
        continue;
      // Evaluate from the side of the bracket so that a peak at a breakpoint is kept.
      const Side side = k.t >= k.hi ? Side::kLeft : Side::kRight;
      peak[j] = goldenMax([&](double t) { return rates(kinematicsAt(curve, t, side))[j]; }, k.lo, k.hi, peak[j]);
    }
  }
  fig.max_linear_speed = peak[kLinearSpeed];
  fig.max_angular_speed = peak[kAngularSpeed];
  fig.max_linear_acceleration = peak[kLinearAcceleration];
  fig.max_angular_acceleration = peak[kAngularAcceleration];
  return fig;
}

/// measureLengths' Gauss–Legendre subintervals per piece: one, and about kFigureSubintervals over
/// the whole curve when it has few pieces.
inline std::size_t lengthSubintervalsPerPiece(std::size_t pieces)
{
  return std::max<std::size_t>(1, kFigureSubintervals / std::max<std::size_t>(pieces, 1));
}

/// The path's lengths ∫ |ṗ| dt and ∫ |ω| dt (on the sphere: ∫ |ẋ| dt) alone, for a timing that
/// supplies the rates and the energy itself (the time-optimal, jerk-limited and constant-speed
/// timings: a timing does not change the path's lengths). One 8-point Gauss–Legendre rule per
/// analytic piece (kFigureSubintervals in all at least), halved by measureCurve's rule where a
/// channel's speed at the nodes and ends varies by more than kFigureSpeedRatio: a quarter of
/// measureCurve's evaluations (no peak searches) on a curve of many pieces, each of the speeds
/// alone (speedsAt: first-order jets). Within 1e-6 of chord sums on corner blends between uneven
/// times, and agrees with measureCurve to rounding on splines (test_figures).
template <class G>
std::pair<double, double> measureLengths(const Curve<G>& curve)
{
  std::vector<double> b = curve.breakpoints();
  b.erase(std::unique(b.begin(), b.end()), b.end());
  const std::size_t pieces = b.size() - 1;
  double length = 0.0;
  double rotation_length = 0.0;
  detail::forEachGaussSpan([&curve](double t, Side side) { return detail::SpeedsOnly{ speedsAt(curve, t, side) }; }, b,
                           lengthSubintervalsPerPiece(pieces), "the path's length", [](std::size_t) {},
                           [&](std::size_t, double a, double z, const auto&, const auto&, const auto& nodes) {
                             for (std::size_t g = 0; g < kGaussNodes.size(); ++g)
                             {
                               const double w = 0.5 * (z - a) * kGaussWeights[g];
                               const Rates& r = nodes[g].speeds;
                               length += w * r[kLinearSpeed];
                               rotation_length += w * r[kAngularSpeed];
                             }
                           });
  return { length, rotation_length };
}

}  // namespace se3_interpolation
