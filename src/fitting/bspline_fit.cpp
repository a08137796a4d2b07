// The entry points of curve fit (fitting/bspline_fit.h's fitBSpline): the passes of each geometry
// (the double geodesic's translation and rotation, the screw's poses), Huber's loss by reweighting
// between them, their convergence and the result. The units they call are listed in
// bspline_fit_detail.h.
#include "se3_interpolation/fitting/bspline_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "bspline_fit_detail.h"
#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace fitting_detail
{
namespace
{
/// The IRLS passes of Huber's loss at most (each a majorisation step; squared loss needs one).
constexpr int kMaxReweightings = 100;
/// The passes stop when no weight changes by more than this.
constexpr double kWeightTolerance = 1e-10;

/// Updates the IRLS weights from the squared chord distances; returns the largest change.
double reweight(FitProblem* pb, const std::vector<double>& s)
{
  double change = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    const double w = huberWeight(s[i], pb->options.loss_scale);
    change = std::max(change, std::abs(w - pb->weights[i]));
    pb->weights[i] = w;
  }
  return change;
}

/// The RMS residuals of `linear2` (m²) and `angular2` (rad²), the objective and the steps into `out`.
/// @throws ConvergenceError if the objective is not finite
void finish(const std::vector<double>& linear2, const std::vector<double>& angular2, double objective, int iterations,
            BSplineFitResult* out)
{
  double sl = 0.0, sa = 0.0;
  for (std::size_t i = 0; i < linear2.size(); ++i)
  {
    sl += linear2[i];
    sa += angular2[i];
  }
  const double n = static_cast<double>(linear2.size());
  out->residual_linear = std::sqrt(sl / n);
  out->residual_angular = std::sqrt(sa / n);
  out->objective = objective;
  out->iterations = iterations;
  if (!std::isfinite(objective))
    throw ConvergenceError("fit: the least-squares problem has no finite solution");
}

/// Levenberg–Marquardt on the group part until its step is below kConvergedStep; with Huber's
/// loss, the weights follow each accepted step (and the translation, if any, each pass).
template <class L, class Other>
void solveGroup(FitProblem* pb, GroupFit<L>* fit, const Other& other_part, double* objective)
{
  std::vector<double> history;  // the objective after each step of this pass
  while (fit->iterations() < kMaxIterations)
  {
    const std::vector<double> other = other_part();
    const double step = fit->step(other, objective);
    history.push_back(*objective);
    // Stagnation: ten steps that together lower the objective by less than kStagnation of it.
    if (history.size() > kStagnationSteps &&
        history[history.size() - 1 - kStagnationSteps] - *objective <= kStagnation * *objective)
      return;
    bool reweighted = false;
    if (pb->options.loss == FitLoss::kHuber)
    {
      const std::vector<double> s = fit->squaredDistances(fit->control());
      std::vector<double> total(s.size());
      for (std::size_t i = 0; i < s.size(); ++i)
        total[i] = s[i] + other[i];
      reweighted = reweight(pb, total) > kWeightTolerance;
    }
    // No step improves the objective beyond its rounding: converged, whatever the weights do.
    if (step == 0.0 || (step < kConvergedStep && !reweighted))
      return;
  }
}

/// The refusal of a recording whose fit would need a half-turn geodesic step between two control
/// points (or between the start's control points): its knots are too far apart for its turns.
[[noreturn]] void refuseHalfTurn(const FitOptions& options)
{
  throw InvalidInputError("control_period: the waypoints turn by about half a turn within " +
                          formatSeconds(options.control_period) +
                          " s, so neighbouring control poses of the fit would be half a turn apart (no unique "
                          "geodesic between them); a shorter control_period");
}

BSplineFitResult fitDoubleGeodesic(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                                   const FitOptions& options)
{
  FitProblem pb = makeProblem(poses, times, options);
  TranslationFit translation(pb);
  std::vector<Vector3<double>> positions = translation.solve();
  GroupFit<So3Group> rotation(pb, grevilleStart<So3Group>(pb));
  std::vector<double> linear2 = translation.squaredDistances(positions);
  double rotation_objective = rotation.objective(rotation.control(), linear2);
  if (!std::isfinite(rotation_objective))
    refuseHalfTurn(options);
  double last_pass = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < kMaxReweightings; ++pass)
  {
    solveGroup(
        &pb, &rotation, [&]() { return linear2; }, &rotation_objective);
    if (pb.options.loss == FitLoss::kSquared)
      break;
    // Each pass is a majorisation step of Huber's objective: one that lowers it by no more than
    // its rounding (kRoundingImprovement) has converged.
    if (!(rotation_objective < last_pass * (1.0 - kRoundingImprovement)))
      break;
    last_pass = rotation_objective;
    // The translation with the weights of the current rotation, then the weights again.
    positions = translation.solve();
    linear2 = translation.squaredDistances(positions);
    const std::vector<double> angular2 = rotation.squaredDistances(rotation.control());
    std::vector<double> total(linear2.size());
    for (std::size_t i = 0; i < total.size(); ++i)
      total[i] = linear2[i] + angular2[i];
    rotation_objective = rotation.objective(rotation.control(), linear2);
    if (reweight(&pb, total) <= kWeightTolerance && pass > 0)
      break;
  }
  BSplineFitResult out;
  out.degree = options.degree;
  out.knots = pb.knots;
  out.control.resize(pb.n);
  for (std::size_t j = 0; j < pb.n; ++j)
    out.control[j] = Pose<double>(rotation.control()[j], positions[j]);
  const double rho2 = options.rotation_scale * options.rotation_scale;
  std::vector<double> angular2 = rotation.squaredDistances(rotation.control());
  for (double& a : angular2)
    a /= rho2;
  finish(linear2, angular2, rotation.objective(rotation.control(), linear2) + translation.jerkTerm(positions),
         rotation.iterations(), &out);
  return out;
}

BSplineFitResult fitScrew(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                          const FitOptions& options)
{
  FitProblem pb = makeProblem(poses, times, options);
  GroupFit<Se3Group> fit(pb, grevilleStart<Se3Group>(pb));
  const std::vector<double> none(poses.size(), 0.0);
  double objective = fit.objective(fit.control(), none);
  if (!std::isfinite(objective))
    refuseHalfTurn(options);
  if (pb.options.loss == FitLoss::kHuber)
    reweight(&pb, fit.squaredDistances(fit.control()));
  solveGroup(
      &pb, &fit, [&]() { return none; }, &objective);
  BSplineFitResult out;
  out.degree = options.degree;
  out.knots = pb.knots;
  out.control = fit.control();
  std::vector<double> linear2(poses.size()), angular2(poses.size());
  DeBoorTriangle<Se3Group> tri;
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    const Pose<double> c = tri.evaluate(out.control, pb.knots, options.degree, pb.spans[i], times[i], false);
    linear2[i] = (c.p - poses[i].p).squaredNorm();
    const double theta = so3Log(Quaternion<double>(poses[i].q.conjugate() * c.q)).norm();
    angular2[i] = theta * theta;
  }
  finish(linear2, angular2, fit.objective(fit.control(), none), fit.iterations(), &out);
  return out;
}

}  // namespace
}  // namespace fitting_detail

template <>
BSplineFitResult fitBSpline<DoubleGeodesicSe3>(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                                               const FitOptions& options)
{
  try
  {
    return fitting_detail::fitDoubleGeodesic(poses, times, options);
  }
  catch (const NonUniqueGeodesicError&)
  {
    fitting_detail::refuseHalfTurn(options);
  }
}

template <>
BSplineFitResult fitBSpline<ScrewSe3>(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                                      const FitOptions& options)
{
  try
  {
    return fitting_detail::fitScrew(poses, times, options);
  }
  catch (const NonUniqueGeodesicError&)
  {
    fitting_detail::refuseHalfTurn(options);
  }
}

}  // namespace se3_interpolation
