// src/timing/jerk_limited_solver.h: the internal declarations of the jerk-limited timing
// (include/se3_interpolation/timing/jerk_limited.h, whose file comment describes the method): the
// solver class and the constants its units share. Not installed. The solver's members are
// defined in three units:
//   - jerk_limited.cpp: the solve's loop (the stretch, or a moving start's corrections), the
//     moving channels and the underlying bounds, and the public functions (jerkLimitedProfile,
//     JerkLimitedProfile's times and segments);
//   - jerk_limited_runs.cpp: the runs of the underlying time-optimal timing on the stopping path,
//     the segments' windows, the short segments and the plateaus, and the profile built from them;
//   - jerk_limited_check.cpp: the final check (the six rates' peaks over every piece, with exact
//     third-order path jets), the stretch and the figures.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "se3_interpolation/math/jet.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace timing
{
namespace time_optimal_detail
{
class TimeOptimalSolver;
}

namespace jerk_limited_detail
{
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kPointsPerDeadlineCheck = 256;
constexpr const char* kPhase = "timing: jerk-limited 'time_optimal'";

/// The six rates in the order v_lin, v_ang, a_lin, a_ang, j_lin, j_ang.
using Rates6 = std::array<double, 6>;

/// The jerk-limited timing of one path under one set of bounds (jerk_limited.h's file comment).
class JerkSolver
{
public:
  JerkSolver(const JerkPathModel& path, const RateBounds& bounds, const JerkLimitedOptions& options);

  /// Whether a jerk bound acts on a channel that moves.
  bool jerkActs() const;

  JerkLimitedProfile solve();

private:
  // The channels and the bounds (jerk_limited.cpp).
  /// The channels that move: time_optimal's rule on the path's jets at its breakpoints and the
  /// middles of its pieces.
  void findMovingChannels();

  /// The underlying bounds (file comment: a′ = min(a, √(v j))), all lowered by `scale` as a stretch
  /// by that factor would lower the rates.
  RateBounds scaled(double scale) const;

  // The runs of the underlying timing, their windows, short segments and plateaus
  // (jerk_limited_runs.cpp).
  /// The three runs of the underlying timing (file comment) and the segments of the result.
  void run(const RateBounds& b);

  /// The start of a run: the underlying bounds b, the window τ and the lead speed ṡ_T0; returns
  /// s_a′, where the underlying timing starts (file comment). A moving start that brakes too hard
  /// for the window, or passes a corner or a C¹ joint before s_a′, is refused.
  double startRun(const RateBounds& b);

  /// Sets o's local limits to collect the grid's points, the path's third-order jets there and
  /// the speed caps for the path's share of the jerk (pathSpeedCap) on the first run; room for
  /// the grid of a stopping path of `pieces` analytic pieces.
  void collectGridJets(std::size_t pieces, TimeOptimalOptions* o);

  /// Lowers the acceleration factor (and the window) of the segments shorter than kShortSegment
  /// windows by f = ∛(T² / (8 τ²)), T the segment's duration; returns whether any segment is short.
  bool slowShortSegments(const TimingProfile& base);

  /// The underlying timing's first pass again with the local limits (firstPassAgain); the
  /// segments keep their factors (keepSegments).
  void rerun(time_optimal_detail::TimeOptimalSolver* underlying, const TimeOptimalOptions& o, TimingProfile* base);

  /// The segments of a new result of the underlying timing: they keep their factors (they stop at
  /// the same points: the corners and the ends); if their number changed, the windows are reset.
  void keepSegments(const TimingProfile& base);

  /// The underlying timing's local limit at a grid point (the previous run's grid: the grid
  /// depends on the path and the options only).
  LocalLimit localLimit(double s) const;

  /// The path's share of the jerk at (ṡ, s̈) (eq. 1 without C′ s⃛): |C‴| ṡ³ + 3 |C″| ṡ |s̈|,
  /// relative to the bound, the largest over the jerk-bounded channels.
  double pathJerkShare(const PathJet3& j, double sd, double sdd) const;

  /// The speed at which the path's jerk at constant ṡ, |C‴| ṡ³, is kPathJerkShare of the bound,
  /// the least over the channels; ∞ where C‴ = 0 (a straight line).
  double pathSpeedCap(const PathJet3& j) const;

  /// The jerk budget of the window in path units at each grid point: J_s = min_c j_c / |C′_c|
  /// over the moving, jerk-bounded channels.
  void evaluateSpeeds();

  /// The window of each segment: f τ, widened by 1/(1 − β) where the path takes the share β of
  /// the jerk (pathJerkShare at the timing's speeds, at most kPathJerkShare by the caps).
  void setWindows(const TimingProfile& base);

  /// The segments of the underlying timing: between its interior points at rest.
  void findSegments(const TimingProfile& base);

  /// The crossing of x = c² on the branch from grid point p towards `step` (±1), within [lo, hi]:
  /// its path parameter and the length of the grid interval it lies in.
  static std::pair<double, double> crossing(const TimingProfile& b, std::size_t p, int step, double x, std::size_t lo,
                                            std::size_t hi);

  /// Caps the grid points on [lo, hi] at x.
  void cap(double lo, double hi, double x);

  /// Finds where s̈_T changes sign by more than the window's budget within one window (eq. 2) and
  /// caps ṡ there for a cruise of τ (file comment). Returns whether any cap was added.
  bool addPlateaus(const TimingProfile& b);

  /// The highest cap below the peak at grid point p whose cruise lasts τ (bisection on the
  /// timing's own ṡ(s), which the cap leaves unchanged below it).
  bool capPeak(const TimingProfile& b, std::size_t p, std::size_t first, std::size_t last, double tau);

  /// The profile from the underlying timing: segments, their windows and integrals.
  void buildProfile(TimingProfile base);

  // The final check with exact third-order path jets, the stretch and the figures
  // (jerk_limited_check.cpp).
  /// The rates at base time tb of segment g (one-sided), with the path's jet given.
  static Rates6 rates(const PathJet3& j, const Jet<3>& s);

  /// The path's side at s within segment g (time side while moving; at its ends, inwards).
  Side pathSide(const JerkLimitedProfile::Segment& g, double s, Side side) const;

  /// The Taylor coefficients of the cubic p at h from those at 0: s(t) is a cubic polynomial on
  /// each piece, so the jet at its middle gives it exactly on the whole piece, ends included
  /// (one-sided by construction: no rounding of t − τ can pick a neighbouring piece).
  static Jet<3> shifted(const Jet<3>& p, double h);

  /// The path's jet at s within segment g: s clamped to the segment (the cubic of a piece
  /// evaluated at its end rounds to either side of a stop), from `side` inside, inwards at its ends.
  PathJet3 segmentPathJet(const JerkLimitedProfile::Segment& g, double s, Side side) const;

  /// The rates at the point of a piece whose cubic is `s` (inside the piece: no breakpoint).
  Rates6 ratesInside(const JerkLimitedProfile::Segment& g, const Jet<3>& s) const;

  /// The pieces of segment g in base time: the grid's times, shifted by τ, and the passages of the
  /// path's breakpoints; `crossing` holds the breakpoint passed at each time (NaN: none), where
  /// the path's C‴ jumps.
  void pieces(const JerkLimitedProfile::Segment& g, const std::vector<double>& path_breaks, std::vector<double>* times,
              std::vector<double>* crossing) const;

  /// The final check (file comment): the peaks of the six rates over every piece, the figures,
  /// and the stretch k they need. Returns k.
  double verify();

  /// A piece of the final check: its segment, times, cubic (at its middle) and the rates at its
  /// ends and middle; one the interior search may take (verify).
  struct CheckPiece
  {
    std::size_t segment;
    double lo, hi;
    Jet<3> middle;  ///< s at the middle: the piece's cubic
    Rates6 f0, fm, f1;
  };

  /// A part of a piece still to be checked: its times, cubic (at its middle), the path's jets and
  /// the rates at its ends, and how often it was halved.
  struct CheckPart
  {
    double lo, hi;
    Jet<3> middle;
    PathJet3 jr, jl;
    Rates6 f0, f1;
    int depth;
  };

  /// What the final check gathers over the pieces: the peaks, the energy, the pieces the interior
  /// search may take, and the stack of parts (reused from piece to piece).
  struct CheckTally
  {
    Rates6 peak{};
    std::array<double, 2> energy{};  ///< ∫|a|² dt per channel, Simpson's rule on every piece
    std::vector<CheckPiece> candidates;
    std::vector<CheckPart> parts;
  };

  /// Clears the motion's breakpoints and reserves room for them (about twice the grid's intervals
  /// beside the path's `path_breaks` breakpoints).
  void reserveMotionBreaks(std::size_t path_breaks);

  /// Checks one piece of segment k (verify): halved while the path varies across a part
  /// (pathVaries); each part's rates at its ends and middle into the peaks and the energy, and the
  /// parts the interior search may take into the candidates.
  void checkPiece(std::size_t k, const CheckPart& piece, CheckTally* tally) const;

  /// The interior maxima of the candidates where the parabola through their ends and middle peaks
  /// near the largest value, into *peak.
  void searchPieces(const std::vector<CheckPiece>& candidates, Rates6* peak) const;

  /// The stretch k the peaks need: the largest of 1 and each rate's ratio to its bound, to the
  /// power 1, 1/2, 1/3 for speed, acceleration and jerk.
  double stretchNeeded(const Rates6& peak) const;

  /// The floors of |C′|² below which a channel counts as still in pathVaries (time_optimal's
  /// kMoveTolerance of the largest at the grid's points).
  void splitFloor();

  /// Whether the path's jets at the ends and middle of a piece (a, m, b; d its length in s) vary
  /// too much for the parabola through the rates there to stand for the piece (verify halves it).
  bool pathVaries(const PathJet3& a, const PathJet3& m, const PathJet3& b, double d) const;

  /// Caps |s̈_T| where the path nearly stands still (file comment of jerk_limited_runs.cpp, at
  /// kStationaryGrowth) from the first run's times and segments (findSegments); returns whether
  /// any cap was set.
  bool capStationaryPoints(const TimingProfile& base);

  /// Runs the motion slower by k and sets the figures.
  void applyStretch(double k);

  const JerkPathModel& path_;
  RateBounds bounds_;
  JerkLimitedOptions options_;
  bool fixed_start_ = false;
  std::array<bool, 2> moves_{};
  RateBounds under_;                ///< the underlying timing's bounds of the current run
  double tau_ = 0.0;                ///< the window before the short segments' factor
  double lead_speed_ = 0.0;         ///< ṡ_T0
  std::vector<double> grid_;        ///< the underlying grid
  std::vector<double> factor_;      ///< its acceleration factor at each grid point
  std::vector<double> cap_;         ///< its cap on x at each grid point
  std::vector<double> u_cap_;       ///< its cap on |s̈_T| at each grid point (capStationaryPoints)
  bool cap_stationary_ = false;     ///< whether run() caps |s̈_T| where the path nearly stands still
  std::vector<double> jerk_s_;      ///< J_s at each grid point
  std::vector<PathJet3> jets_;      ///< the path's third-order jets at the grid points
  std::vector<double> path_caps_;   ///< pathSpeedCap at the grid points
  std::vector<double> seg_tau_;     ///< the window of each segment
  std::vector<double> seg_budget_;  ///< 1 − β: the window's share of the jerk in each segment
  std::vector<std::size_t> seg_first_, seg_last_;
  std::vector<double> seg_f_;  ///< the short-segment factor f of each segment
  Rates6 peak_{};
  std::array<double, 2> energy_{};       ///< ∫|a|² dt per channel before the stretch (verify)
  std::array<double, 2> split_floor_{};  ///< splitFloor
  JerkLimitedProfile profile_;
};

}  // namespace jerk_limited_detail
}  // namespace timing
}  // namespace se3_interpolation
