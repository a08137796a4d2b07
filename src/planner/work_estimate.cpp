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
/// measureCurve's effort (analysis/figures.h): its Gauss-Legendre nodes on subintervalsPerPiece
/// subintervals, and one golden-section search per peak rate of 2 + at most kGoldenMaxIterations
/// evaluations.
constexpr double kNodesPerSubinterval = static_cast<double>(kGaussNodes.size());
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
double figureEvaluations(double pieces)
{
  const double sub = static_cast<double>(subintervalsPerPiece(static_cast<std::size_t>(pieces)));
  return pieces * (2.0 + kNodesPerSubinterval * sub) + kGoldenEvaluations;
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
  return w;
}

void requireWorkWithin(const WorkEstimate& w, const WorkShape& r, const PlannerLimits& limits)
{
  if (w.total <= limits.max_work)
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
  throw LimitExceededError(what + " cost about " + formatNumber(std::round(w.total)) + " units of work (" +
                           formatNumber(w.figure_evaluations + w.samples + w.timing_evaluations) +
                           " curve evaluations of " + formatNumber(w.evaluation_cost) +
                           " geodesic steps each); the limit (~max_work) is " + formatNumber(limits.max_work));
}

}  // namespace se3_interpolation
