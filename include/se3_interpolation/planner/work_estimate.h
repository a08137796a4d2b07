// Bounded work per request: the cost of a request is estimated from its fields before anything
// is computed, and a request whose estimate exceeds PlannerLimits::max_work_seconds (node
// parameter ~max_work_seconds, CLI --max-work-seconds) is refused with a LimitExceededError naming
// the field that makes it expensive. The estimate may be wrong (a loaded machine, a path that
// makes the time-optimal grid refine): the long loops also check a deadline (deadline.h).
//
// Unit: one geodesic step of a curve evaluation on second-order jets (the value and its first
// two time derivatives), i.e. one exp/log pair of the geometry; converted to seconds by a factor
// calibrated per family, geometry and timing on one core of the development machine
// (secondsPerUnit, bench/bench_work_estimate.cpp). What depends on the family (its pieces, the
// cost of an evaluation, the calibration, the field a refusal names) is its descriptor's
// (planner/curve_family.h, planner/families/); the sums below are the same for every family.
//
// The planner evaluates the curve (analysis/figures.h, measureCurve) at
//   P (2 + 10 s) + 8 (2 + 60) points, s = max(4, 64 / P) Gauss-Legendre subintervals per piece
// (P analytic pieces, 8 nodes and 2 ends, golden-section searches of 2 + at most 60 evaluations,
// counted as two per peak rate; subintervals where the speed varies strongly are halved, see
// figures.h) under `stretch`; under a timing (which measures its own rates) only the lengths
// (measureLengths: 10 max(1, 64 / P) points per piece, counted 3.5 times for its halvings); then
// once per sample. An evaluation costs, in geodesic steps (the families' evaluationCost),
//   piecewise_geodesic 1; interpolating and hermite 6 (a cubic de Casteljau per piece);
//   blended 2 (its three-point curves are cheap closed forms, measured); bezier d (d + 1) / 2
//   with d = N - 1 (de Casteljau over all N points); bspline m (m + 1) / 2 (de Boor, degree m).
// Corner blends (blend_radius on piecewise_geodesic) make up to 2N - 3 pieces, legs and
// blends in turn, and an evaluation costs PiecewiseGeodesicFamily::kBlendEvaluationCost (measured).
// Timing adds (timing/time_optimal.h): time_optimal runs TOPP-RA on a grid of at most
// G = 17 P + 512 intervals, with 6 G + 4096 curve evaluations and 3 units of its own (the
// passes' bisections, the checks) per interval, all scaled by (G / 17 512)^0.1 (its time per unit
// grows with the grid, which outgrows the caches; 17 512 intervals are those of 1000 pieces);
// replanning (start_state) measures again on the curve joined to the start state: the figures
// twice more under stretch (before and after the stretch, P pieces), the lengths once more under
// a timing.
// Building the curve costs about 10 units per waypoint (times, logs, the
// C^2 solve's sweeps). The figures' effort is thus linear in the pieces; what grows as N^2 is
// the evaluation of one Bezier of degree N - 1, which the estimate charges (and refuses) up front.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
/// The estimate of one request: curve evaluations for the figures, per-evaluation cost,
/// samples, and their total in work units.
struct WorkEstimate
{
  double pieces = 0.0;
  double evaluation_cost = 0.0;     ///< geodesic steps per evaluation
  double figure_evaluations = 0.0;  ///< evaluations of measureCurve (every pass), or of measureLengths under a timing
  double timing_intervals = 0.0;    ///< time_optimal's grid intervals (0: stretch)
  double timing_evaluations = 0.0;  ///< evaluations of time_optimal
  double timing_units = 0.0;        ///< time_optimal's own work, and its evaluations
  double samples = 0.0;
  double construction_units = 0.0;  ///< building the curve (the family's constructionUnits)
  /// sample_tolerance's interval tests (execution/sample_refinement.h): kRefinementTestsPerSample per
  /// sample, each costing kRefinementTestSeconds whatever the family (0 without sample_tolerance)
  double refinement_tests = 0.0;
  double total = 0.0;  ///< work units
  /// total × the family's calibrated seconds per unit, plus the refinement's tests
  double seconds = 0.0;
};

/// What the estimate needs of a request, pose or sphere: the curve, its size, the sampling.
struct WorkShape
{
  CurveType curve = CurveType::kPiecewiseGeodesic;
  std::size_t waypoints = 0;
  int degree = 3;  ///< bspline degree
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = RequestDefaults::kSampleCount;
  bool corner_blends = false;  ///< blend_radius > 0
  Timing timing = RequestDefaults::kTiming;
  bool start_state = false;     ///< replanning from a given state (the figures are measured again)
  bool screw = false;           ///< the screw geometry (its steps cost more than the double geodesic's)
  bool jerk = false;            ///< a jerk bound (max_linear_jerk or max_angular_jerk > 0)
  double fit_intervals = 0.0;   ///< curve fit: the knot intervals M (fitting/bspline_fit.h)
  bool fit_smoothing = false;   ///< curve fit: smoothing > 0
  bool fit_huber = false;       ///< curve fit: loss huber
  bool refine_samples = false;  ///< sample_tolerance > 0 (samples inserted, execution/sample_refinement.h)
};

/// The refinement of sample_tolerance tests the interval before each sample and two more per sample
/// it inserts: counted as one insertion per sample asked for. A refinement that inserts more (a
/// tight tolerance, sparse samples) runs into the request's deadline (deadline.h), naming
/// sample_tolerance.
constexpr double kRefinementTestsPerSample = 3.0;
/// One interval test: a motion evaluation, the two-point goal and its bound-aware peak search
/// (GoalTrajectory::boundExcess). Measured 32 µs with bounds on the screw geometry (a jerk-limited
/// 30-waypoint interpolating motion, 64 samples refined to 802 by the CLI), doubled as the other
/// work estimates are (within 2× of measured).
constexpr double kRefinementTestSeconds = 6.4e-5;

/// Building the curve costs about this many work units per waypoint (times, logs, the C² solve's
/// sweeps); families that do more say so (CurveFamilyDefaults::constructionUnits).
constexpr double kConstructionUnitsPerWaypoint = 10.0;

/// The shape of a validated request of any space.
template <class Space>
WorkShape workShape(const BasicValidatedRequest<Space>& r)
{
  WorkShape w;
  w.curve = r.curve;
  w.waypoints = r.waypoints.size();
  w.degree = r.degree;
  w.sample_times = r.sampling.sample_times;
  w.sample_period = r.sampling.sample_period;
  w.sample_count = r.sampling.sample_count;
  w.corner_blends = r.blend_radius > 0.0;
  w.timing = r.timing;
  w.start_state = r.start_state.has_value();
  w.jerk = r.max_linear_jerk > 0.0 || r.max_angular_jerk > 0.0;
  w.refine_samples = r.sampling.sample_tolerance > 0.0;
  if constexpr (std::is_same_v<Space, PoseSpace>)
  {
    w.screw = r.geometry == GeometryType::kScrew;
    if (r.curve == CurveType::kFit && r.times.size() >= 2)
      w.fit_intervals = std::max(1.0, std::ceil((r.times.back() - r.times.front()) / r.control_period - 1e-9));
    w.fit_smoothing = r.smoothing > 0.0;
    w.fit_huber = r.loss == FitLoss::kHuber;
  }
  else
    w.screw = true;  // the sphere's steps cost about the screw's
  return w;
}

/// Geodesic steps of one evaluation of the curve `r` asks for.
double evaluationCost(const WorkShape& r);

/// The estimate for `r` with `samples` samples (the sample count as far as it is known).
WorkEstimate estimateWork(const WorkShape& r, double samples);

/// The samples `r` will take before any stretch: sample_times' size, sample_count, or the
/// periods within `span` (the waypoint times' span).
double expectedSamples(const WorkShape& r, double span);

/// Seconds per work unit of the request's family, geometry and timing on one core of the
/// development machine (calibrated by bench/bench_work_estimate.cpp).
double secondsPerUnit(const WorkShape& r);

/// Throws LimitExceededError naming the dominant field (the sampling field when samples
/// dominate, timing when time_optimal's share does, waypoints for bezier, degree for bspline,
/// else waypoints) if `w.seconds` exceeds limits.max_work_seconds.
void requireWorkWithin(const WorkEstimate& w, const WorkShape& r, const PlannerLimits& limits);

}  // namespace se3_interpolation
