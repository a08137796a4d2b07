// src/timing/time_optimal_solver.h: the internal declarations of the time-optimal timing
// (include/se3_interpolation/timing/time_optimal.h, whose file comment describes the method):
// the solver class, its grid data and the constants its units share. Not installed. The solver's
// members are defined in three units:
//   - time_optimal.cpp: the grid (uniform, then refined), its jets and the solve's loop of passes,
//     and the public functions (timeOptimalProfile, TimingProfile::timeAt);
//   - time_optimal_passes.cpp: the backward pass (the controllable sets, by bisection on the exact
//     constraints) and the greedy forward pass with the recovery from a start outside them;
//   - time_optimal_check.cpp: the final dense check (the peaks of every interval), the local
//     tightening, the uniform stretch or the fixed start's check, and the figures.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace timing
{
namespace time_optimal_detail
{
constexpr double kInf = std::numeric_limits<double>::infinity();
/// Local passes: where an interval's middle exceeds a bound by more than kLocalTolerance, the
/// bound is tightened at its ends by the excess and the passes are rerun (at most kLocalPasses
/// times), so that the final uniform stretch only absorbs what is left (typically < 1e-3).
constexpr int kLocalPasses = 4;
constexpr double kLocalTolerance = 1e-4;
/// A motion that starts moving (which no stretch may correct) is also checked at the quarters of
/// every interval where a need at its ends or middle comes within this fraction of its bound: on
/// the request-space grid's moving and over-the-bound starts, rates rose above a bound between the
/// three points and fell back before the middle by up to 3 % (a rate at its bound at a grid point,
/// rising into the interval: the parabola through its ends and middle then peaks at the end). Not
/// from rest: there the two jets more per interval would cost a third of the timing's time
/// (bench_time_optimal, N = 1000: 81 → 107 ms), and the uniform stretch absorbs what is found.
constexpr double kQuarterFloor = 0.9;
/// A motion that starts moving cannot be stretched uniformly (that would change its start
/// velocity): its local passes continue, at most kFixedStartPasses in all, until every checked rate
/// is within kFixedStartTolerance of its bound; from the fifth pass on each tightening carries a
/// margin of kFixedStartMargin, so that the passes converge from above.
constexpr int kFixedStartPasses = 16;
constexpr double kFixedStartTolerance = 1e-8;
constexpr double kFixedStartMargin = 1e-3;
/// x_i above the controllable set by this relative amount is rounding, not a start to recover from.
constexpr double kRoundingExcess = 1e-9;
/// Grid points handled between two checks of the request's deadline (deadline.h).
constexpr std::size_t kPointsPerDeadlineCheck = 256;
/// Intervals between two deadline checks in the peak searches, checks and figures, which search
/// inside each interval (each costs about 16 grid points' work).
constexpr std::size_t kIntervalsPerSearchDeadlineCheck = kPointsPerDeadlineCheck / 16;
constexpr const char* kPhase = "timing: 'time_optimal'";

/// The grid's refinement rule, which the jerk-limited timing's final check applies to its pieces
/// too: Δ |C″| > kRefineTolerance |C′| over an interval (the direction or the speed of C′ turns by
/// more than ~0.25 across it) or |C′| at its ends and middle differing by more than the factor
/// 1 + kRefineTolerance.
constexpr double kRefineTolerance = 0.25;

/// Whether one channel's jets at the ends and middle of an interval d long in s (a, m, b: any jet
/// with the inner products bb = |C′|², aa = |C″|²) vary too much across it (kRefineTolerance) for
/// the values at those three points to stand for its interior; |C′|² below `floor` counts as still.
template <class ChannelJetType>
bool channelVaries(const ChannelJetType& a, const ChannelJetType& m, const ChannelJetType& b, double d, double floor)
{
  const double fastest = std::max({ a.bb, m.bb, b.bb, floor });
  const double slowest = std::max({ std::min({ a.bb, m.bb, b.bb }), floor });
  const double curvature = std::sqrt(std::max({ a.aa, m.aa, b.aa }));
  const double least_curvature = std::sqrt(std::min({ a.aa, m.aa, b.aa }));
  return d * curvature > kRefineTolerance * std::sqrt(fastest) ||
         d * (curvature - least_curvature) > kRefineTolerance * kRefineTolerance * std::sqrt(fastest) ||
         fastest > (1.0 + kRefineTolerance) * (1.0 + kRefineTolerance) * slowest;
}

struct Interval
{
  double lo = -kInf;
  double hi = kInf;
  bool empty = false;
  bool isEmpty() const { return empty || !(lo <= hi); }
};

/// One side of one grid point, as the constraints see it.
struct PointData
{
  PathJet jet;          ///< for the constraints (floored at stationary points)
  PathJet raw;          ///< the path's own, for the checks
  double x_max = kInf;  ///< from (2) and the extents of the ellipses (3), with the local factors
  /// Per channel, what the extent of the ellipse (3) takes from the jet (prepare): √(|C′|²/cross)
  /// (x ≤ a_max · it), or where C′ = 0, √|C″|² (x ≤ a_max / it); 0 where neither applies.
  std::array<double, 2> extent{};
};

/// The four rates: linear / angular velocity (0, 1), linear / angular acceleration (2, 3).
using Rates = std::array<double, 4>;

/// The time-optimal timing of one path under one set of bounds (time_optimal.h's file comment).
class TimeOptimalSolver
{
public:
  /// @param reusable keep the grid for firstPassAgain() (a copy of its path parameters)
  TimeOptimalSolver(const PathModel& path, const RateBounds& bounds, const TimeOptimalOptions& options,
                    bool reusable = false);

  /// The passes, the final check and the stretch or the fixed start's corrections (time_optimal.cpp):
  /// firstPass(), then finish().
  TimingProfile solve();

  /// The first pass only (the controllable sets, the greedy forward pass): the timing before the
  /// local passes and the final check, which may exceed a bound between grid points. For a caller
  /// that reads a timing only to decide how to solve again (the jerk-limited timing's runs, whose
  /// result is checked by their own final check): finish() of the last one gives exactly what
  /// solve() would have returned, and the runs it replaces skip their checks.
  const TimingProfile& firstPass();

  /// What solve() does after firstPass(): localPasses(), then the final check and the stretch or
  /// the fixed start's corrections. Once after each firstPass().
  TimingProfile finish();

  /// At most `passes` local passes after firstPass() (where the middle of an interval exceeds a
  /// bound, that bound tightened at its ends by the excess and the passes rerun; for a fixed start,
  /// until the whole check holds), without the final check and stretch: for a caller whose own
  /// final check holds the motion to the bounds (the jerk-limited timing). Once after each
  /// firstPass(), instead of finish().
  const TimingProfile& localPasses(int passes);

  /// After a pass of a reusable solver: the first pass again on the same grid and jets, with the
  /// local limits and start speed of `options` (its grid options and hold_start must be those of
  /// the construction: they made the grid); finish() completes it. Its finish() is exactly what a
  /// new solver with these options would return from solve(), without rebuilding the grid and
  /// evaluating the path's jets again (the jerk-limited timing's reruns).
  const TimingProfile& firstPassAgain(const TimeOptimalOptions& options);

private:
  /// Everything the passes and checks change, as the constructor leaves it, with the local limits
  /// and start speed of `options` (firstPassAgain).
  void reset(const TimeOptimalOptions& options);

  // The grid (time_optimal.cpp).
  bool bounded(int c) const { return bounds_.velocity[c] > 0.0 || bounds_.acceleration[c] > 0.0; }

  /// The largest |C′| of each channel over some jets.
  static void growLargest(const PathJet& j, std::array<double, 2>* largest);

  /// Whether the constraints at the ends of [s_a, s_b] (length d) cannot stand for its interior.
  bool needsSplit(const PathJet& a, const PathJet& m, const PathJet& b, double d) const;

  /// Adds the grid points strictly inside (s_a, s_b) and the jets at the middles of the intervals
  /// they make, halving where needsSplit says so.
  void refine(double sa, const PathJet& ja, double sb, const PathJet& jb, int depth);

  /// Appends grid point s with its right side's jet and its left side's where that differs (`left`
  /// null: the same; only the pieces' inner ends have one).
  void addPoint(double s, const PathJet& right, const PathJet* left, bool corner);

  /// The grid: max(intervals_per_piece, the piece's share of min_intervals) uniform intervals on
  /// every analytic piece, refined where the path's rates vary (refine), with the jets the passes
  /// and checks read: right- and left-sided at each point, and at the middle of each interval.
  void buildGrid(const TimeOptimalOptions& options);

  /// The uniform grid buildGrid refines: its points, the right-sided jets there, the left-sided
  /// ones at the pieces' inner ends (index and jet) and which of those are corners.
  struct UniformGrid
  {
    std::vector<double> s;
    std::vector<PathJet> right;
    std::vector<std::pair<std::size_t, PathJet>> left;
    std::vector<bool> corner;
  };

  /// The path's breakpoints, sorted and distinct; a path with a non-finite time or of no positive
  /// duration is refused.
  std::vector<double> gridBreakpoints() const;

  /// The uniform grid on the breakpoints b: max(intervals_per_piece, the piece's share of
  /// min_intervals) intervals per piece; sets the refinement's floors of |C′|² and its limit on
  /// the grid's size.
  UniformGrid uniformGrid(const std::vector<double>& b, const TimeOptimalOptions& options);

  /// The grid points, refined between the uniform grid's points (refine), with their jets.
  void refineGrid(const UniformGrid& uniform);

  /// Inserts the held first interval [s_0, s_0 + ε] (TimeOptimalOptions::hold_start): a new point
  /// after s_0, and new middles on both sides.
  void holdStart();

  void evaluateGrid(const TimeOptimalOptions& options);

  /// Checks that the motion at this point is bounded and floors stationary points.
  void prepare(PointData* p, double s) const;

  // The passes (time_optimal_passes.cpp).
  double velocityBound(std::size_t i, int c) const { return bounds_.velocity[c] * factor_[i][c]; }
  double accelerationBound(std::size_t i, int c) const { return bounds_.acceleration[c] * factor_[i][2 + c]; }

  /// x_max of both sides of every point with the current local factors (after the first pass: of
  /// the points whose factors changed).
  void updateCaps();

  double delta(std::size_t i) const { return profile_.s[i + 1] - profile_.s[i]; }

  /// Upper end of x_{i+1}: the controllable set and the velocity bound seen from the left.
  double nextLimit(std::size_t i) const { return std::min(k_[i + 1], left(i + 1).x_max); }

  /// The admissible controls u_i for x_i = x with x_{i+1} ∈ [0, next] (its lower and upper ends
  /// are meaningful only when it is not empty).
  Interval controls(std::size_t i, double x, double next) const;

  /// What controls(i, ·, next) computes that does not depend on x, computed once for the backward
  /// pass's bisection, which varies x only: 1/(2Δ)'s divisor, next, and the ellipses of the
  /// bounded channels (α, β, |a|², cross, A²), at s_i and s_{i+1} for each.
  struct ControlConstants
  {
    double two_delta = 0.0;
    double next = 0.0;
    double u_cap = kInf;  ///< the caller's cap on |u| on the interval (LocalLimit::path_acceleration_cap)
    int ellipses = 0;
    /// [0, ellipses) are set: two per bounded channel, two per component of the box constraint
    /// with an acceleration limit (cross = 0).
    std::array<std::array<double, 5>, 4 + 2 * kMaxBoxComponents> ellipse;
  };

  ControlConstants controlConstants(std::size_t i, double next) const;

  /// The admissible controls at x from the constants, the ellipses intersected in order; stops as
  /// soon as the interval is empty (it only shrinks).
  static Interval controlInterval(const ControlConstants& k, double x);

  /// The largest x from which braking at each acceleration ellipse's lowest control still reaches
  /// x_{i+1} ≤ next (the smallest over the ellipses; ∞ where none limits): where the acceleration
  /// bounds decide the controllable set's upper end, that end. An estimate the caller verifies.
  static double brakingLimit(const ControlConstants& k);

  /// Whether controls(i, x, next) is non-empty, from its constants.
  static bool admissible(const ControlConstants& k, double x);

  void backward();

  /// The greedy forward pass (Pham & Pham, eq. 12) from x_0 = start_x_ (held for the first interval
  /// with hold_start_). A start outside the controllable sets (faster than the bounds allow, or too
  /// fast to brake for what lies ahead) is brought into them by the hardest braking the acceleration
  /// bounds allow: the recovery, which ends at the grid point recovery_end_. A start that cannot be
  /// brought to rest before a velocity corner or the end of the path is an error.
  void forward();

  /// The recovery's control on interval i from x (forward): the hardest braking the acceleration
  /// bounds allow towards the next set (`next`), with the margin kRecoveryMargin on those bounds at
  /// both ends of the interval; where no braking keeps within them, the least acceleration, whose
  /// excess goes into the profile's recovery_excess.
  double recoveryControl(std::size_t i, double x, double next, double d);

  /// The first interval the checks hold to the bounds: after the recovery from a start that
  /// exceeds a bound; else all of them (a start within the bounds that must brake for what lies
  /// ahead brakes within them).
  std::size_t checkedFrom() const { return start_exceeds_ ? recovery_end_ : 0; }

  /// Where no control keeps the acceleration within a bound at x (the path bends too sharply for
  /// that speed): the control of least acceleration that does not speed up, and at most stops.
  double leastAccelerationControl(std::size_t i, double x, double d) const;

  // The final dense check, the tightening and the figures (time_optimal_check.cpp).
  /// The stretch each bounded rate would need at a point: |v|/v_max, √(|a|/a_max) (its level);
  /// 0 for the unbounded.
  Rates needs(const PathJet& j, double x, double u) const;

  Rates needsAtMiddle(std::size_t i) const;

  /// The path's jet at λ = ¼ (k = 0) or ¾ (k = 1) of interval i, evaluated on first use and kept
  /// (the grid does not change; the reruns of a reusable solver share them).
  const PathJet& quarterJet(std::size_t i, int k) const;

  /// The needs at λ = ¼ (k = 0) or ¾ (k = 1) of interval i.
  Rates needsAtQuarter(std::size_t i, int k) const;

  /// Tightens quantity q at both ends of interval i so that its need r (> 1) would come down to
  /// 1 − margin: velocities scale with the bound, accelerations' needs with its square root.
  void tighten(std::size_t i, int q, double r, double margin);

  /// Where the middle of an interval exceeds a bound (the ends satisfy them by construction),
  /// tightens that bound at both ends by the excess. Returns whether anything was tightened. The
  /// recovery from a start the bounds cannot hold is left as it is.
  bool tightenWhereTheMiddlesExceed();

  /// The largest need of each rate inside interval i that tightenWhereTheMiddlesExceed reads: at
  /// its middle, and at its quarters where intervalNeeds reads them.
  Rates needsInside(std::size_t i) const;

  /// The needs of one interval at λ = 0, ¼, ½, ¾, 1 (at the quarters only where `quarters`).
  struct IntervalNeeds
  {
    std::array<Rates, 5> at{};
    bool quarters = false;
  };

  /// The needs of interval i at its ends and middle, and, for a motion that starts moving
  /// (check_quarters_), at its quarters where one of those comes within kQuarterFloor of its bound
  /// (a rate near its bound may rise above it between the three points and fall back before the
  /// middle: the parabola through them cannot see that).
  IntervalNeeds intervalNeeds(std::size_t i) const;

  /// The peak of need q on interval i: the largest of its checked points, or, where a parabola
  /// through them (or through either half's three, with the quarters) peaks inside at or above
  /// `threshold`, the maximum found by detail::localMaxOfChecked on the exact rates.
  double peak(const IntervalNeeds& f, std::size_t i, int q, double threshold, bool* searched) const;

  /// A rate's level: its need (needs()) where it is bounded, its magnitude (magnitudes()) where
  /// not; monotone in the rate, so that one search of a level finds the rate's peak for both the
  /// check and the figures.
  Rates levels(const PathJet& j, double x, double u) const;

  /// The levels at s_i + λ Δ_i, from the path's jet there (x is linear in s on the interval, u
  /// constant): what the peak searches evaluate.
  Rates levelsAt(std::size_t i, double lambda) const;

  /// The magnitude (|v| or |a|, q as magnitudes()) whose level is `level`.
  double magnitudeOfLevel(int q, double level) const;

  /// The final check of a motion from rest: the peak level of every rate on every interval, then
  /// the uniform stretch k ≥ 1 that brings the worst need within its bound; the peaks, scaled by
  /// the stretch, are the figures' maxima.
  void verifyAndStretch();
  /// The uniform stretch t → t0 + k (t − t0), ṡ² and s̈ divided by k² (k ≥ 1; k = 1 leaves the
  /// profile as it is), recorded as profile_.stretch.
  void stretchUniformly(double k);

  /// The peaks of the intervals after the recovery, searched where they come within
  /// kRefineMargin of a bound; with `tighten_margin` ≥ 0 the bounds are tightened where a peak
  /// exceeds its bound by more than kFixedStartTolerance. Returns the worst need and whether
  /// anything was tightened.
  std::pair<double, bool> checkAfterRecovery(double tighten_margin, Rates* searched);

  bool tightenWhereTheCheckExceeds(double margin);

  /// The final check of a motion whose start is fixed (no stretch can correct it: the start
  /// velocity would change): every interval after the recovery within its bounds.
  void verifyFixedStart();

  /// |v| and |a| of both channels at a point with (x, u).
  static std::array<double, 4> magnitudes(const PathJet& j, double x, double u);

  // The box constraint (4), (5) (time_optimal_boxes.cpp): its jets at every grid point's sides and
  // interval's middle (2m values each: w, then a), its local factors, and its checks.
  /// Evaluates the jets once per grid (the constructor).
  void evaluateBoxJets();
  /// Whether every component of the box constraint has an acceleration limit: then the motion is
  /// bounded whatever the norm bounds.
  bool boxesBoundTheMotion() const;
  /// The jet of grid point i's right side, or of its left side (`left`: its own where it has one).
  const double* boxJet(std::size_t i, bool left) const;
  /// The cap (4) and the extent of (5) where w_k = 0 on x at point i, with the local factors.
  double boxCap(const double* jet, std::size_t i) const;
  /// Appends the bands (5) at both ends of interval i to k's ellipses.
  void addBoxBands(std::size_t i, ControlConstants* k) const;
  /// The control in [lo, 0] of the least largest band ratio |w u + a x| / A at point i
  /// (leastAccelerationControl).
  double boxLeastControl(std::size_t i, double x, double lo) const;
  /// The largest level of any component at a point: |w|√x / V, √(|w u + a x| / A); with `per`,
  /// each component's velocity level into per[k] and acceleration level into per[m + k].
  double boxLevel(const double* jet, double x, double u, double* per = nullptr) const;
  /// The level at s_i + λ Δ_i, from the constraint's jet there.
  double boxLevelAt(std::size_t i, double lambda) const;
  /// The largest level on interval i: its ends and middle, searched where a parabola through them
  /// peaks inside at or above `threshold`.
  double boxPeak(std::size_t i, double threshold) const;
  /// Tightens the components whose level at an interval's middle exceeds 1 + kLocalTolerance at
  /// both its ends (the local passes).
  bool tightenBoxesWhereTheMiddlesExceed();
  /// The largest level after the recovery, with the search of peaks; with `tighten_margin` ≥ 0 the
  /// components exceeding 1 + kFixedStartTolerance at an interval's middle or searched peak are
  /// tightened at its ends. Returns the worst level and whether anything was tightened.
  std::pair<double, bool> checkBoxes(double tighten_margin);
  /// Whether the start (x = start speed², u = 0) exceeds a box: its velocities, and with
  /// hold_start its accelerations (as start_exceeds_ for the norm bounds).
  bool startExceedsBoxes() const;
  /// TimingProfile::boxes and box_peaks of the final profile (after the stretch).
  void boxFigures();
  /// Raises the peaks of component k on interval i from its values at the ends and middle (and a
  /// search where their parabola peaks inside near the peak so far).
  void raiseBoxPeaks(std::size_t i, std::size_t k, const std::array<const double*, 3>& jets);

  /// Each channel's acceleration energy ∫|a|² dt (TimingProfile::acceleration_energy).
  using Energy = std::array<double, 2>;

  /// The timed motion's figures (TimingProfile::max_speed, …) from the cached jets; `searched`:
  /// the largest levels (levels()) found inside intervals, before the stretch k. With `energy`
  /// (verifyAndStretch): `searched` are every rate's peaks on the whole motion, which no further
  /// search raises, and `energy` the acceleration energy before the stretch.
  void figures(const Rates& searched, double k, const std::optional<Energy>& energy);

  /// The weights of interval i's acceleration energy in `p` at its ends and middle: the integral
  /// over the interval's time of the quadratic through the values at times 0, τ_m (the middle in
  /// s) and h.
  std::array<double, 3> energyWeights(const TimingProfile& p, std::size_t i) const;

  /// One channel's energy on an interval with weights `w` and |a| = a, m, b at its ends and middle.
  static double energyOfInterval(const std::array<double, 3>& w, double a, double m, double b);

  /// Largest |v| or |a| (q, as magnitudes()) on interval i of profile `p`, from its values at the
  /// ends and middle (and the quarters, where quarterJet has them), searched where a parabola
  /// through them peaks inside at or above `threshold`.
  double magnitudePeak(const TimingProfile& p, std::size_t i, int q, const std::array<double, 5>& at, bool quarters,
                       double threshold) const;

  const PathModel& path_;
  RateBounds bounds_;
  double start_x_;               ///< the requested ṡ² at s_0 (0: from rest)
  bool hold_start_;              ///< s̈ = 0 on the first interval
  bool check_quarters_ = false;  ///< the checks read the quarters too (intervalNeeds)
  std::array<bool, 2> moves_{};
  std::array<double, 2> floor_{};
  std::array<double, 2> refine_floor_{};  ///< |C′|² below which a channel counts as still (refinement)
  std::size_t grid_limit_ = 0;            ///< most grid points refinement may make
  std::size_t recovery_end_ = 0;          ///< the grid point at which the recovery (forward) ends
  bool start_exceeds_ = false;            ///< the start itself exceeds a bound
  TimingProfile profile_;
  std::vector<double> grid_;  ///< the grid's path parameters, kept for firstPassAgain() (reusable only)
  /// Grid point i from the right, and from the left: right_[i] itself where left_of_[i] is
  /// kSameAsRight (all but the pieces' inner ends), else distinct_left_[left_of_[i]] (a few entries
  /// instead of a second copy of the largest array of a long grid).
  const PointData& left(std::size_t i) const
  {
    return left_of_[i] == kSameAsRight ? right_[i] : distinct_left_[static_cast<std::size_t>(left_of_[i])];
  }
  /// Grid point i's own left side, or null where it is right_[i].
  PointData* distinctLeft(std::size_t i)
  {
    return left_of_[i] == kSameAsRight ? nullptr : &distinct_left_[static_cast<std::size_t>(left_of_[i])];
  }
  static constexpr std::int64_t kSameAsRight = -1;
  std::vector<PointData> right_;
  std::vector<std::int64_t> left_of_;
  std::vector<PointData> distinct_left_;
  std::vector<PathJet> middle_;  ///< at the middle of each interval (in s)
  /// At λ = ¼ and ¾ of interval i (entries 2i, 2i + 1), where has_quarter_[i] (quarterJet).
  mutable std::vector<PathJet> quarter_;
  mutable std::vector<bool> has_quarter_;
  std::vector<bool> corner_;
  std::vector<Rates> factor_;                   ///< local tightening of the four bounds at each grid point
  std::shared_ptr<const BoxConstraint> boxes_;  ///< null: none
  std::size_t box_count_ = 0;                   ///< m
  std::vector<double> box_right_;               ///< 2m per grid point: its right side's (the last point's left)
  std::vector<double> box_left_;                ///< 2m per distinct left side (indexed as distinct_left_)
  std::vector<double> box_middle_;              ///< 2m per interval, at its middle
  std::vector<double> box_factor_;              ///< 2m per grid point: the local factors of V_k, then of A_k
  std::vector<double> speed_cap_;               ///< the caller's cap on x at each grid point (empty: none)
  std::vector<double> u_cap_;                   ///< the caller's cap on |u| at each grid point (empty: none)
  std::vector<double> k_;                       ///< upper ends of the controllable sets
  /// The passes after the first recompute only what a tightening changed: the points whose local
  /// factors changed since the last backward pass (tighten, the recovery), the first point whose
  /// controllable set or factors changed in it, and the forward pass's first recomputed step (the
  /// steps before it are the previous pass's).
  std::vector<char> changed_;
  std::size_t first_change_ = 0;
  std::size_t first_step_ = 0;
};

}  // namespace time_optimal_detail
}  // namespace timing
}  // namespace se3_interpolation
