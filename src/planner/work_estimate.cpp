#include "se3_interpolation/planner/work_estimate.h"

#include <algorithm>
#include <cmath>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
/// measureCurve's effort (analysis/figures.h): its Gauss-Legendre nodes and the two ends of each of
/// subintervalsPerPiece subintervals (more where it halves them: a speed that varies by more than
/// kFigureSpeedRatio inside one), and one golden-section search per peak rate of 2 + at most
/// kGoldenMaxIterations evaluations.
constexpr double kNodesPerSubinterval = static_cast<double>(kGaussNodes.size()) + 2.0;
constexpr double kGoldenEvaluations = 4.0 * (2.0 + kGoldenMaxIterations);

double analyticPieces(const WorkShape& r)
{
  const double n = static_cast<double>(r.waypoints);
  switch (r.curve)
  {
    case CurveType::kBezier:
      return 1.0;
    case CurveType::kBspline:
      return std::max(1.0, n - static_cast<double>(r.degree));
    case CurveType::kPiecewiseGeodesic:
      if (r.corner_blends)
        return std::max(1.0, 2.0 * n - 3.0);  // legs and blends in turn
      [[fallthrough]];
    default:
      return std::max(1.0, n - 1.0);
  }
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
  switch (r.curve)
  {
    case CurveType::kPiecewiseGeodesic:
      return r.corner_blends ? kCornerBlendEvaluationCost : 1.0;
    case CurveType::kBezier:
    {
      const double d = static_cast<double>(r.waypoints) - 1.0;
      return std::max(1.0, d * (d + 1.0) / 2.0);
    }
    case CurveType::kBspline:
    {
      const double m = static_cast<double>(r.degree);
      return std::max(1.0, m * (m + 1.0) / 2.0);
    }
    case CurveType::kInterpolating:
    case CurveType::kHermite:
      return 6.0;
    case CurveType::kBlended:
      return 2.0;
  }
  return 1.0;
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

WorkEstimate estimateWork(const WorkShape& r, double samples)
{
  WorkEstimate w;
  w.pieces = analyticPieces(r);
  w.evaluation_cost = evaluationCost(r);
  w.figure_evaluations = figureEvaluations(w.pieces);
  if (r.timing == Timing::kTimeOptimal)
  {
    w.timing_intervals = kTimeOptimalIntervalsPerPiece * w.pieces + kTimeOptimalMinIntervals;
    w.timing_evaluations = kTimeOptimalEvaluationsPerInterval * w.timing_intervals + kTimeOptimalSearchEvaluations;
    if (r.start_state)
      w.figure_evaluations += figureEvaluations(w.timing_intervals);
  }
  else if (r.start_state)
  {
    // measured again on the joined curve, and once more if the bounds stretch it
    w.figure_evaluations *= 3.0;
  }
  w.timing_units = w.timing_evaluations * w.evaluation_cost + kTimeOptimalUnitsPerInterval * w.timing_intervals;
  w.samples = samples;
  w.total = (w.figure_evaluations + w.samples) * w.evaluation_cost + w.timing_units +
            kConstructionUnitsPerWaypoint * static_cast<double>(r.waypoints);
  w.seconds = w.total * secondsPerUnit(r);
  return w;
}

/// Seconds per work unit, per family, geometry and timing: the CPU time of generate() over the
/// estimate's units at N = 1000 waypoints (a bezier 100) on one core of the development machine,
/// measured by bench/bench_work_estimate.cpp; from 100 to 10⁴ waypoints (a bezier 20 to 400) the
/// estimate is then within 0.67 … 1.6 of the measured time (re-measured after each change of the
/// estimate's model, `bench_work_estimate --middle`). Rows: the curve families in the
/// order of CurveType, then piecewise_geodesic with corner blends; columns: double geodesic
/// (stretch, time_optimal), screw (stretch, time_optimal). The sphere uses the screw's.
constexpr double kCalibratedSecondsPerUnit[7][4] = {
  { 5.6e-08, 8.53e-08, 7.74e-08, 1.41e-07 },  // piecewise_geodesic
  { 8.24e-08, 8.13e-08, 2.99e-07, 3.07e-07 },  // bezier
  { 5.65e-08, 1.03e-07, 1.69e-07, 2.56e-07 },  // bspline
  { 3.46e-08, 6.11e-08, 6.79e-08, 7.55e-08 },  // interpolating
  { 5.97e-08, 8.23e-08, 1.85e-07, 2.04e-07 },  // hermite
  { 2.14e-07, 3.04e-07, 3.28e-07, 4.29e-07 },  // blended
  { 1.54e-07, 2.03e-07, 3.54e-07, 3.97e-07 },  // piecewise_geodesic with blend_radius
};

double secondsPerUnit(const WorkShape& r)
{
  const std::size_t row = r.curve == CurveType::kPiecewiseGeodesic && r.corner_blends ? 6 : static_cast<std::size_t>(r.curve);
  const std::size_t column = (r.screw ? 2 : 0) + (r.timing == Timing::kTimeOptimal ? 1 : 0);
  return kCalibratedSecondsPerUnit[row][column];
}

void requireWorkWithin(const WorkEstimate& w, const WorkShape& r, const PlannerLimits& limits)
{
  if (w.seconds <= limits.max_work_seconds)
    return;
  const std::string n = std::to_string(r.waypoints);
  std::string what;
  if (w.samples > w.figure_evaluations && w.samples * w.evaluation_cost > w.timing_units)
    what = samplingField(r) + ": " + formatNumber(w.samples) + " samples";
  else if (w.timing_units > w.figure_evaluations * w.evaluation_cost)
    what = "timing: 'time_optimal' over " + formatNumber(w.timing_intervals) + " grid intervals of " + n +
           " waypoints of curve '" + toString(r.curve) + "'";
  else if (r.curve == CurveType::kBezier)
    what = "waypoints: " + n + " waypoints make a bezier of degree " + std::to_string(r.waypoints - 1);
  else if (r.curve == CurveType::kBspline)
    what = "degree: " + std::to_string(r.degree) + " for curve 'bspline' with " + n + " waypoints";
  else
    what = "waypoints: " + n + " waypoints for curve '" + toString(r.curve) + "'";
  throw LimitExceededError(what + " would take about " + formatNumber(w.seconds) + " s (" +
                           formatNumber(w.figure_evaluations + w.samples + w.timing_evaluations) +
                           " curve evaluations of " + formatNumber(w.evaluation_cost) +
                           " geodesic steps each); the limit (max_work_seconds) is " +
                           formatNumber(limits.max_work_seconds) + " s");
}

}  // namespace se3_interpolation
