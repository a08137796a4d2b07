// The family `fit`: the least-squares geodesic B-spline through recorded poses
// (fitting/bspline_fit.h): degree `degree` (default 3), uniform clamped knots every
// `control_period` s over the waypoints' `times` (required), `smoothing`, `loss`, `loss_scale`.
// Poses only (either SE(3) geometry).
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/planner/curve_family.h"

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
      out.curve = std::make_shared<BSplineCurve<G>>(fit.control, fit.degree, fit.knots, "control poses");
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
  /// @return de Boor's m (m + 1) / 2 geodesic steps
  static double evaluationCost(const WorkShape& shape)
  {
    const double m = static_cast<double>(shape.degree);
    return std::max(1.0, m * (m + 1.0) / 2.0);
  }

  /// The fit's own work in units per waypoint (besides the curve's figures, timing and samples):
  /// the Levenberg–Marquardt steps' de Boor evaluations with Jacobians (a geodesic step's log,
  /// exp and three Jacobians, about 4 units each) and the trial evaluations, counted in
  /// test_work_estimate; Huber's reweighting passes and the smoothing's jerk Jacobians (per knot
  /// interval, 2·dof·(m + 1) third-order de Boor evaluations at each of 4 Gauss points) on top.
  static double constructionUnits(const WorkShape& shape)
  {
    const double m = static_cast<double>(shape.degree);
    const double steps = m * (m + 1.0) / 2.0;
    const double per_waypoint = kFitIterations * (kFitUnitsPerStep * steps) * (shape.fit_huber ? kFitHuberFactor : 1.0);
    const double dof = shape.screw ? 6.0 : 3.0;
    const double smoothing =
        shape.fit_smoothing ? kFitIterations * 4.0 * 2.0 * dof * (m + 1.0) * kJetUnits * steps * shape.fit_intervals : 0.0;
    return per_waypoint * static_cast<double>(shape.waypoints) + smoothing;
  }

  static SecondsPerUnit secondsPerUnit(const WorkShape& /*shape*/) { return { 5.65e-08, 1.03e-07, 1.69e-07, 2.56e-07 }; }

  /// @param shape the request's shape
  /// @param name the family's name
  /// @return the waypoints, with the control period's intervals
  static std::string costlyField(const WorkShape& shape, const char* name)
  {
    return "waypoints: " + std::to_string(shape.waypoints) + " waypoints for curve '" + name + "' (" +
           std::to_string(static_cast<long long>(shape.fit_intervals)) + " knot intervals)";
  }

private:
  /// Levenberg–Marquardt steps with their trials, as counted on noisy recordings (5–17).
  static constexpr double kFitIterations = 12.0;
  /// Units per geodesic step of a de Boor evaluation with the step's Jacobians (and its trial).
  static constexpr double kFitUnitsPerStep = 6.0;
  /// Huber's reweighting costs about this many times the squared loss's steps (measured).
  static constexpr double kFitHuberFactor = 4.0;
  /// A third-order jet's geodesic step, in units.
  static constexpr double kJetUnits = 3.0;
};

}  // namespace se3_interpolation
