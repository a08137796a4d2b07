// src/timing/constant_speed_detail.h: the internal declarations of the constant-speed timing
// (include/se3_interpolation/timing/constant_speed.h, whose file comment describes the method):
// the solver class, the constants and the small functions its units share. Not installed. The
// solver's members are defined in three units:
//   - constant_speed.cpp: the solve (the ramps' lengths and their fitting, the refusals) and the
//     public functions (constantSpeedProfile, ConstantSpeedProfile's inverse maps);
//   - constant_speed_table.cpp: the table of S(σ) (the grid, its quintics and their halving) and
//     the refusal of corners, C¹ joints under a jerk bound and stand-stills;
//   - constant_speed_check.cpp: the dense check of a span of the motion (the rates at the ends and
//     middle of its pieces, their halving, the interior maxima) and the figures.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "se3_interpolation/timing/constant_speed.h"

namespace se3_interpolation
{
namespace timing
{
namespace constant_speed_detail
{
/// Peaks of P′ (the quintic smoothstep's slope 15/8) and P‴ (10/√3) on [0, 1]: a ramp of length T
/// on a straight line peaks at 15/8 V/T in acceleration and 10/√3 V/T² in jerk (file comment).
constexpr double kRampAccelerationPeak = 15.0 / 8.0;
inline const double kRampJerkPeak = 10.0 / std::sqrt(3.0);
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
inline const double kSlopeErrorPeak = 0.5 - 0.5 / std::sqrt(5.0);
/// The chord speed the window is guaranteed to hold, relative (docs/timing.md: 1e-6 promised).
constexpr double kChordSpeedGuarantee = 5e-7;
/// Steps on which a moving start's ramp speed is checked to stay positive.
constexpr int kRampVelocitySteps = 256;
/// Pieces of the check between two checks of the request's deadline.
constexpr std::size_t kPiecesPerDeadlineCheck = 256;

inline const char* const kVelocityName[2] = { "max_linear_velocity", "max_angular_velocity" };
inline const char* const kAccelerationName[2] = { "max_linear_acceleration", "max_angular_acceleration" };
inline const char* const kJerkName[2] = { "max_linear_jerk", "max_angular_jerk" };

/// The chord speed g of eq. 1 and its s-derivative g′ from one-sided path jets.
struct ChordSpeed
{
  double g = 0.0;
  double dg = 0.0;
};

inline ChordSpeed chordSpeed(const PathJet& j, const std::array<double, 2>& w)
{
  ChordSpeed c;
  const double g2 = w[0] * j[0].bb + w[1] * j[1].bb;
  c.g = std::sqrt(g2);
  if (c.g > 0.0)
    c.dg = (w[0] * j[0].ab + w[1] * j[1].ab) / c.g;
  return c;
}

/// The quintic Hermite interpolant on [0, h] of values y, slopes d and second derivatives a at both ends.
inline std::array<double, 6> quinticHermite(double h, double y0, double d0, double a0, double y1, double d1, double a1)
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
inline double slope(const std::array<double, 6>& c, double u)
{
  return c[1] + u * (2.0 * c[2] + u * (3.0 * c[3] + u * (4.0 * c[4] + u * 5.0 * c[5])));
}

inline double quinticValue(const std::array<double, 6>& c, double u)
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

/// What a check finds over a span of the motion: the worst ratio of each rate to its bound and
/// where, the peaks, the chord speed's deviation (in the window) and the energy.
struct Excess
{
  std::array<double, 3> ratio{};  ///< velocity, acceleration, jerk (the worse channel's)
  std::array<int, 3> channel{};
  std::array<double, 3> where{};                ///< path time
  std::array<std::array<double, 2>, 3> peak{};  ///< [rate][channel]
  double deviation = 0.0;
  double energy = 0.0;

  /// Keeps `ratio` of rate k on channel c, at path time `where`, if it is the worst of rate k yet.
  void exceed(int k, int c, double ratio_kc, double where_kc)
  {
    if (ratio_kc > ratio[k])
    {
      ratio[k] = ratio_kc;
      channel[k] = c;
      where[k] = where_kc;
    }
  }
};

/// Rate k (0 speed, 1 acceleration, 2 jerk) of channel c.
inline double rateOf(const Rates& r, int k, int c)
{
  return k == 0 ? r.v[c] : k == 1 ? r.a[c] : r.j[c];
}

/// A piece of the check as finally kept: its ends (time) and the rates at its ends and middle.
struct CheckSpan
{
  double lo, hi;
  Rates r0, rm, r1;
};

/// The constant-speed timing of one path at one speed under one set of bounds
/// (constant_speed.h's file comment).
class ConstantSpeedSolver
{
public:
  ConstantSpeedSolver(const JerkPathModel& path, const RateBounds& bounds, const ConstantSpeedOptions& options)
    : path_(path), bounds_(bounds), options_(options)
  {
    jerk_ = bounds.jerk[0] > 0.0 || bounds.jerk[1] > 0.0;
  }

  /// The table, the ramps fitted to the bounds, the checks and the figures (constant_speed.cpp).
  ConstantSpeedProfile solve();

private:
  // constant_speed.cpp: the ramps and the refusals.
  /// The shortest ramp that changes the chord speed by dv on a straight line (file comment).
  double shortestRamp(double dv) const;
  /// min(a_lin, ρ a_ang) over the bounds given (ρ = √w_ang), 0 when none is.
  double rampBound(const std::array<double, 2>& b) const;
  void requireArguments() const;
  void requireRoomForRamps() const;
  double arcA() const { return p_.rampUpLength(); }
  double arcB() const { return p_.length - p_.rampDownLength(); }
  /// Refuses a speed whose cruise breaks a bound (file comment), naming the bound.
  void requireBoundsHeld(const Excess& e) const;
  /// Lengthens one ramp until every bound holds on it (file comment).
  void fitRamp(bool up);
  /// From a moving start, the ramp up's chord speed must stay above 0 (constant_speed.cpp).
  void requireRisingRamp() const;
  /// A moving start whose ramp breaks a bound the ramp's length cannot bring back: refused naming
  /// start_state.
  [[noreturn]] void refuseStart(const Excess& e) const;
  [[noreturn]] void refuse(int k, const Excess& e) const;

  // constant_speed_table.cpp: the table of S.
  /// The grid of S (file comment) and its quintics; the check's pieces.
  void buildTable();
  /// Appends [s0, s1] (or its halves, where the chord speed of its quintic is off) to the table.
  void addInterval(double s0, const ChordSpeed& c0, double s1, const ChordSpeed& c1, int depth);
  /// Refuses velocity corners (an infinite acceleration at any speed) and, with a jerk bound,
  /// jumps of C″ (an infinite jerk while moving).
  void requireSmoothMotion(const std::vector<double>& b) const;

  // constant_speed_check.cpp: the dense check and the figures.
  /// The rates at time t (one-sided).
  Rates ratesAt(double t, Side side) const;
  /// Checks the pieces of the check between the chord arc lengths lo and hi (file comment); with
  /// `figures`, the interior maxima of the unbounded rates are searched too.
  Excess check(double arc_lo, double arc_hi, bool window, bool figures) const;
  /// The times of the check's piece ends between the chord arc lengths lo and hi, both included.
  std::vector<double> checkPieces(double arc_lo, double arc_hi) const;
  /// The pieces, halved where they vary (varies), with every rate at their ends and middle taken
  /// into e (consider) and the energy summed.
  std::vector<CheckSpan> checkSpans(const std::vector<double>& pieces, bool window, Excess& e) const;
  /// Whether a piece [lo, hi] is to be halved: the path turns or a bounded rate varies too much
  /// across it for its ends and middle to stand for its interior.
  bool varies(double lo, double hi, const Rates& r0, const Rates& rm, const Rates& r1) const;
  /// Takes the rates at one time into e: the peaks, the ratios to the bounds, the deviation of the
  /// chord speed (in the window).
  void consider(const Rates& r, bool window, Excess& e) const;
  /// The integrand of the acceleration energy: |a_lin|² + w_ang |a_ang|².
  double energyDensity(const Rates& r) const;
  /// The interior maxima of the spans' rates, searched where they come near a bound (or, with
  /// `figures`, near the largest value seen), into e.
  void searchInterior(const std::vector<CheckSpan>& spans, bool figures, Excess& e) const;
  /// The bound of rate k (0 velocity, 1 acceleration, 2 jerk) per channel.
  const std::array<double, 2>& bound(int k) const
  {
    return k == 0 ? bounds_.velocity : k == 1 ? bounds_.acceleration : bounds_.jerk;
  }
  /// The figures from the final checks of the ramps and the cruise; the chord speed's deviation in
  /// the window, held to its guarantee.
  void setFigures(const std::array<Excess, 3>& parts);

  const JerkPathModel& path_;
  const RateBounds& bounds_;
  const ConstantSpeedOptions& options_;
  bool jerk_ = false;
  ConstantSpeedProfile p_;
};
}  // namespace constant_speed_detail
}  // namespace timing
}  // namespace se3_interpolation
