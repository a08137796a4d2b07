// The family `fit`: the least-squares geodesic B-spline through recorded poses
// (fitting/bspline_fit.h): degree `degree` (default 3), uniform clamped knots every
// `control_period` s over the waypoints' `times` (required), `smoothing`, `loss`, `loss_scale`.
// Poses only (either SE(3) geometry).
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/planner/curve_family.h"
#include "se3_interpolation/planner/families/bspline.h"

namespace se3_interpolation
{
/// `fit` (planner/curve_family.h): takes degree, times (required) and the fit's fields.
struct FitFamily : CurveFamilyDefaults
{
  static constexpr CurveType kType = CurveType::kFit;
  static constexpr const char* kName = "fit";
  static constexpr unsigned kFields = kDegreeField | kFitField;
  static constexpr bool kRequiresTimes = true;

  /// @param r a validated pose request of the family (its control_period resolved)
  /// @param times the waypoints' times (s), its `times`
  /// @return the fitted B-spline, with the fit's residuals and knots
  template <class G, class Space>
  static FamilyCurve<G> make(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
  {
    if constexpr (std::is_same_v<Space, PoseSpace>)
    {
      FitOptions options;
      options.degree = r.degree;
      options.control_period = r.control_period;
      options.smoothing = r.smoothing;
      options.loss = r.loss;
      options.loss_scale = r.loss_scale;
      options.rotation_scale = r.rotation_scale;
      BSplineFitResult fit = fitBSpline<G>(r.waypoints, times, options);
      FamilyCurve<G> out;
      try
      {
        out.curve = std::make_shared<BSplineCurve<G>>(fit.control, fit.degree, fit.knots, "control poses");
      }
      catch (const NonUniqueGeodesicError&)
      {
        throw InvalidInputError(
            "control_period: two neighbouring control poses of the fit are half a turn apart "
            "(no unique geodesic between them); a shorter control_period");
      }
      out.fit = FitSummary{ fit.residual_linear, fit.residual_angular, std::move(fit.knots) };
      return out;
    }
    else
    {
      throw InvalidInputError("curve: 'fit' fits poses; it is not available on the sphere");
    }
  }

  /// @param shape the request's shape
  /// @return the knot intervals M of the fitted B-spline
  static double pieces(const WorkShape& shape) { return std::max(1.0, shape.fit_intervals); }

  /// @param shape the request's shape
  /// @return de Boor's geodesic steps: the fitted curve is a `bspline`
  static double evaluationCost(const WorkShape& shape) { return BsplineFamily::evaluationCost(shape); }

  /// The fit's own work (besides the curve's figures, timing and samples), in work units:
  /// per waypoint, Levenberg–Marquardt's de Boor evaluations with their Jacobians and trials
  /// (kFitUnitsPerStep per geodesic step of de Boor, the screw's dearer by kFitScrewFactor, Huber's
  /// reweighting kFitHuberFactor times as much); per knot interval with smoothing, the jerk's
  /// Jacobians (kFitSmoothingUnits per tangent direction and geodesic step). Calibrated against
  /// bench_fit on a noisy 100 Hz recording with knots every 0.25 s (bench/recording.h): measured
  /// 5.4 µs (double geodesic) and 30 µs (screw) per pose, ×10.5 and ×3.2 with Huber's loss, and
  /// 0.65 ms and 2.5 ms per knot interval of smoothing.
  static double constructionUnits(const WorkShape& shape)
  {
    const double m = static_cast<double>(shape.degree);
    const double steps = std::max(1.0, m * (m + 1.0) / 2.0);
    const double per_waypoint =
        kFitUnitsPerStep * steps * (shape.screw ? kFitScrewFactor : 1.0) * (shape.fit_huber ? kFitHuberFactor : 1.0);
    const double dof = shape.screw ? 6.0 : 3.0;
    const double per_interval = shape.fit_smoothing ? kFitSmoothingUnits * dof * steps : 0.0;
    return per_waypoint * static_cast<double>(shape.waypoints) + per_interval * shape.fit_intervals;
  }

  /// @param shape the request's shape
  /// @return the `bspline` family's calibration under `stretch` (the fitted curve is one, and the
  ///         fit's own work, constructionUnits, is counted in its units); under `time_optimal` its
  ///         own: the fitted B-spline has a knot every 25 poses, its few pieces make the timing's
  ///         fixed costs (the grid's 512 intervals, the searches) most of the estimate, which the
  ///         bspline's calibration at 1000 waypoints would put at 2.3–2.9 times the measured time
  static SecondsPerUnit secondsPerUnit(const WorkShape& shape)
  {
    SecondsPerUnit row = BsplineFamily::secondsPerUnit(shape);
    row[1] = kTimeOptimalSecondsPerUnit[0];
    row[3] = kTimeOptimalSecondsPerUnit[1];
    return row;
  }

  /// @param shape the request's shape
  /// @param name the family's name
  /// @return the waypoints, with the control period's intervals
  static std::string costlyField(const WorkShape& shape, const char* name)
  {
    return "waypoints: " + std::to_string(shape.waypoints) + " waypoints for curve '" + name + "' (" +
           std::to_string(static_cast<long long>(shape.fit_intervals)) + " knot intervals)";
  }

private:
  /// Seconds per unit under `time_optimal` (double geodesic, screw): bench_work_estimate, 10³ … 10⁵
  /// recorded poses, estimate / measured 1.5 … 1.6 (double geodesic) and 1.2 … 1.8 (screw); lowered by
  /// 0.8 when the timings measured only the path's lengths (1.9–2.1 and 1.4–2.0 before).
  static constexpr std::array<double, 2> kTimeOptimalSecondsPerUnit{ 6.8e-08, 1.25e-07 };
  /// Work units per waypoint and geodesic step of de Boor (bench_fit: 16 × 6 × 5.65e-8 s = 5.4 µs
  /// per pose in the double geodesic).
  static constexpr double kFitUnitsPerStep = 16.0;
  /// The screw geometry's SE(3) Jacobians, per unit (its units already cost 3× the double
  /// geodesic's: secondsPerUnit).
  static constexpr double kFitScrewFactor = 1.7;
  /// Huber's reweighting passes (measured ×10.5 in the double geodesic, ×3.2 in the screw).
  static constexpr double kFitHuberFactor = 10.0;
  /// Smoothing's jerk Jacobians per knot interval, tangent direction and geodesic step.
  static constexpr double kFitSmoothingUnits = 520.0;
};

}  // namespace se3_interpolation
