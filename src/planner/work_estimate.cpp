#include "se3_interpolation/planner/work_estimate.h"

#include <algorithm>
#include <cmath>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/names.h"

namespace se3_interpolation
{
namespace
{
/// measureCurve's effort (analysis/figures.h): its Gauss-Legendre nodes and the two ends of each of
/// subintervalsPerPiece subintervals (more where it halves them: a speed that varies by more than
/// kFigureSpeedRatio inside one), and golden-section searches of 2 + at most kGoldenMaxIterations
/// evaluations, kPeakSearchesPerRate per peak rate.
constexpr double kNodesPerSubinterval = static_cast<double>(kGaussNodes.size()) + 2.0;
constexpr double kGoldenEvaluations = 4.0 * static_cast<double>(kPeakSearchesPerRate) * (2.0 + kGoldenMaxIterations);
/// TOPP-RA's grid (TimeOptimalOptions: max(16, ⌈512 ℓ/T⌉) intervals on a piece of length ℓ
/// of T): at most 17 per piece plus 512.
constexpr double kTimeOptimalIntervalsPerPiece = 17.0;
constexpr double kTimeOptimalMinIntervals = 512.0;
/// time_optimal's curve evaluations: per grid interval (its ends' and middle's path jets, the
/// corner checks, the checks' and the figures' searches where the rates peak, the refinement of
/// intervals where the path's rates vary), and the searches that
/// concentrate on few pieces (counted: 2.2 (piecewise_geodesic) ... 2.6 (hermite) per interval
/// on 2000 waypoints, up to 3871 in all on the 513 intervals of a two-piece curve).
constexpr double kTimeOptimalEvaluationsPerInterval = 6.0;
constexpr double kTimeOptimalSearchEvaluations = 4096.0;
/// time_optimal's work per grid interval besides the evaluations (bisections of the controllable
/// sets, the forward pass, the checks' parabolas), in work units: measured 2.6 us per interval on
/// the loaded development machine (piecewise_geodesic, whose evaluations take 0.08 us).
constexpr double kTimeOptimalUnitsPerInterval = 3.0;

/// time_optimal's time per unit grows with its grid: the passes stream the grid's per-interval data
/// (controllable sets, path jets), which outgrows the caches. bench_work_estimate measured the time
/// per estimated unit at 100 waypoints 0.7 times, at 10⁴ 1.1 to 2.5 times that at 10³ (every family,
/// both geometries, on a loaded machine); on an idle one, after the path jets became cheaper, the
/// time of 10⁴ waypoints was 9.4 to 13.3 times that of 10³. The units of the timing are scaled by
/// (G / G₁₀₀₀)^0.1, G its grid intervals and G₁₀₀₀ those of a curve of 1000 pieces (the
/// calibration's size): 1.26 at 10⁴ waypoints.
constexpr double kTimeOptimalGridExponent = 0.1;
constexpr double kTimeOptimalReferenceIntervals = kTimeOptimalIntervalsPerPiece * 1000.0 + kTimeOptimalMinIntervals;

/// The jerk-limited timing (timing/jerk_limited.h): up to three runs of the acceleration-only
/// timing on one grid and a check of about twice its intervals with third-order jets (measured 1.8
/// times its cost at 1000 waypoints, 2.1 at 3000: bench_time_optimal, docs/performance.md);
/// counted as three times its work, which the cache misses of long paths use up: the estimate for
/// 10⁴ waypoints of bench_time_optimal's spline is 0.78 s, and its generate() took 0.97 s of CPU
/// (the timing alone 0.67 s) on the 2-vCPU EPYC VM of that measurement.
constexpr double kJerkLimitedTimingFactor = 3.0;
/// The constant-speed timing (timing/constant_speed.h), per interval of time_optimal's grid: its
/// table of S(σ) has two intervals there (or more where it is refined), each a jet at its end, 4
/// Gauss–Legendre nodes and two checks of its slope; the check's three points over the cruise (twice
/// where the ramps grow) and the ramps, and the searches where a rate comes near its bound or its
/// peak, which concentrate on few pieces. Counted (test_work_estimate.cpp): 14–20 per grid
/// interval on 40 waypoints of every family, up to 20 361 in all on the 529 intervals of a two-piece
/// curve; with a jerk bound the check's jets are third-order ones, about twice as dear. Counted as
/// 40: it shares time_optimal's seconds per unit (secondsPerUnit), which fell by 0.85 when the
/// timings measured only the path's lengths (measureLengths), while its own work did not (its
/// 10⁴-waypoint splines, measured at 1.6 s and more, stay refused by the default limit).
constexpr double kConstantSpeedEvaluationsPerInterval = 40.0;
constexpr double kConstantSpeedSearchEvaluations = 8192.0;
/// The peak jerk under `stretch` (timing/jerk_peaks.h): ends and middle of each figure
/// subinterval plus the searches, in third-order jets of about twice an evaluation's cost.
constexpr double kJerkPeakEvaluationsPerSubinterval = 2.0 * (3.0 + 2.0);

double analyticPieces(const WorkShape& r)
{
  return visitFamily(r.curve, [&r](auto family) { return decltype(family)::pieces(r); });
}

std::string samplingField(const WorkShape& r)
{
  if (!r.sample_times.empty())
    return "sample_times";
  return r.sample_period > 0.0 ? "sample_period" : "sample_count";
}
}  // namespace

double evaluationCost(const WorkShape& r)
{
  return visitFamily(r.curve, [&r](auto family) { return decltype(family)::evaluationCost(r); });
}

double expectedSamples(const WorkShape& r, double span)
{
  if (!r.sample_times.empty())
    return static_cast<double>(r.sample_times.size());
  if (r.sample_period > 0.0)
    return std::floor(span / r.sample_period) + 2.0;
  return static_cast<double>(r.sample_count);
}

/// measureCurve's evaluations on a curve of `pieces` analytic pieces.
/// The subintervals measureCurve halves where a speed varies by more than kFigureSpeedRatio: up to
/// 15 % more evaluations, counted on random polygons of every family (test_work_estimate.cpp).
constexpr double kFigureRefinementAllowance = 1.25;

double figureEvaluations(double pieces)
{
  const double sub = static_cast<double>(subintervalsPerPiece(static_cast<std::size_t>(pieces)));
  return pieces * (2.0 + kFigureRefinementAllowance * kNodesPerSubinterval * sub) + kGoldenEvaluations;
}

/// measureLengths' halvings: one Gauss rule per piece is halved where a speed varies by more than
/// kFigureSpeedRatio across the piece, which on random polygons is most pieces (counted 1.8–3.2
/// times the unhalved evaluations at 40 waypoints of every family, test_work_estimate.cpp).
constexpr double kLengthRefinementAllowance = 3.5;

/// measureLengths' evaluations (analysis/figures.h), the timings' measure of the path: the nodes and
/// ends of lengthSubintervalsPerPiece subintervals per piece, more where it halves them.
double lengthEvaluations(double pieces)
{
  const double sub = static_cast<double>(lengthSubintervalsPerPiece(static_cast<std::size_t>(pieces)));
  return pieces * kLengthRefinementAllowance * kNodesPerSubinterval * sub;
}

WorkEstimate estimateWork(const WorkShape& r, double samples)
{
  WorkEstimate w;
  w.pieces = analyticPieces(r);
  w.evaluation_cost = evaluationCost(r);
  // A timing measures only the curve's lengths, and from a start state those of the joined path too.
  w.figure_evaluations = r.timing == Timing::kStretch ? figureEvaluations(w.pieces) :
                                                        (r.start_state ? 2.0 : 1.0) * lengthEvaluations(w.pieces);
  if (r.timing == Timing::kTimeOptimal)
  {
    w.timing_intervals = kTimeOptimalIntervalsPerPiece * w.pieces + kTimeOptimalMinIntervals;
    w.timing_evaluations = kTimeOptimalEvaluationsPerInterval * w.timing_intervals + kTimeOptimalSearchEvaluations;
    if (r.jerk)
      w.timing_evaluations *= kJerkLimitedTimingFactor;
  }
  else if (r.timing == Timing::kConstantSpeed)
  {
    w.timing_intervals = kTimeOptimalIntervalsPerPiece * w.pieces + kTimeOptimalMinIntervals;
    w.timing_evaluations =
        (kConstantSpeedEvaluationsPerInterval * w.timing_intervals + kConstantSpeedSearchEvaluations) *
        (r.jerk ? 2.0 : 1.0);
  }
  else
  {
    // measured again on the joined curve, and once more if the bounds stretch it
    if (r.start_state)
      w.figure_evaluations *= 3.0;
    if (r.jerk)
      w.figure_evaluations += kJerkPeakEvaluationsPerSubinterval * w.pieces *
                              static_cast<double>(subintervalsPerPiece(static_cast<std::size_t>(w.pieces)));
  }
  w.timing_units = w.timing_evaluations * w.evaluation_cost;
  if (r.timing == Timing::kTimeOptimal)
  {
    w.timing_units += kTimeOptimalUnitsPerInterval * w.timing_intervals * (r.jerk ? kJerkLimitedTimingFactor : 1.0);
    w.timing_units *= std::pow(w.timing_intervals / kTimeOptimalReferenceIntervals, kTimeOptimalGridExponent);
  }
  w.samples = samples;
  w.construction_units = visitFamily(r.curve, [&r](auto family) { return decltype(family)::constructionUnits(r); });
  w.total = (w.figure_evaluations + w.samples) * w.evaluation_cost + w.timing_units + w.construction_units;
  w.refinement_tests = r.refine_samples ? kRefinementTestsPerSample * samples : 0.0;
  w.seconds = w.total * secondsPerUnit(r) + w.refinement_tests * kRefinementTestSeconds;
  return w;
}

double secondsPerUnit(const WorkShape& r)
{
  const SecondsPerUnit row = visitFamily(r.curve, [&r](auto family) { return decltype(family)::secondsPerUnit(r); });
  // (constant_speed's work is that of a timing too: path jets over a grid)
  return row[(r.screw ? 2 : 0) + (r.timing == Timing::kStretch ? 0 : 1)];
}

void requireWorkWithin(const WorkEstimate& w, const WorkShape& r, const PlannerLimits& limits)
{
  if (w.seconds <= limits.max_work_seconds)
    return;
  const std::string n = std::to_string(r.waypoints);
  std::string what;
  if (w.refinement_tests * kRefinementTestSeconds > 0.5 * w.seconds)
    what = "sample_tolerance: about " + formatNumber(w.refinement_tests) + " interval tests of " +
           formatNumber(w.samples) + " samples";
  else if (w.samples > w.figure_evaluations && w.samples * w.evaluation_cost > w.timing_units)
    what = samplingField(r) + ": " + formatNumber(w.samples) + " samples";
  else if (w.timing_units > w.figure_evaluations * w.evaluation_cost)
    what = std::string("timing: '") + toString(r.timing) + "' over " + formatNumber(w.timing_intervals) +
           " grid intervals of " + n + " waypoints of curve '" + toString(r.curve) + "'";
  else
    what =
        visitFamily(r.curve, [&r](auto family) { return decltype(family)::costlyField(r, decltype(family)::kName); });
  throw LimitExceededError(what + " would take about " + formatNumber(w.seconds) + " s (" +
                           formatNumber(w.figure_evaluations + w.samples + w.timing_evaluations) +
                           " curve evaluations of " + formatNumber(w.evaluation_cost) +
                           " geodesic steps each); the limit (max_work_seconds) is " +
                           formatNumber(limits.max_work_seconds) + " s");
}

}  // namespace se3_interpolation
