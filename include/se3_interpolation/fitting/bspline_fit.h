// `curve: fit`: a least-squares geodesic B-spline through recorded, noisy poses.
//
// The fitted curve is the `bspline` family's curve (curves/bspline.h: the generalised de Boor
// algorithm of Richardson, "Designing Smooth Motions of Rigid Objects", Alg. 4.3.3 with the
// geodesic interpolation of eq. 4.1) of degree m on a clamped knot vector whose
//   M = max(1, ⌈(t_N − t_0)/control_period − 1e-9⌉)
// intervals are uniform on [t_0, t_N]; its M + m control poses d_j minimise
//   E(d) = (1/N) Σᵢ loss(d(C(tᵢ), Pᵢ)²) + λ ∫ (|p⃛|² + ρ²|ω̈|²) dt,
// with d(A, B)² = |p_A − p_B|² + ρ²θ(R_Aᵀ R_B)² the chord distance (ρ = rotation_scale, m/rad),
// λ = smoothing, p⃛ the linear jerk and ω̈ the (world-frame) angular jerk of the curve, and
// loss(s) = s (`squared`) or Huber's loss(s) = s for s ≤ δ², 2δ√s − δ² beyond (`huber`, δ = loss_scale).
// The mean (1/N) makes λ independent of the recording rate.
//
// How it is solved (src/fitting/, whose units src/fitting/bspline_fit_detail.h lists):
//   - double geodesic: the translation is the Euclidean B-spline Σ B_j(t) p_j, so its part of E
//     is linear least squares, solved exactly (banded normal equations; with λ = 0 the classical
//     least-squares spline on the same knots); the rotation part is a B-spline on SO(3), fitted by
//     Levenberg–Marquardt on the group (control poses updated as d_j Exp(δ_j));
//   - screw: the whole pose on SE(3), likewise.
//   The data residual's Jacobian is analytic: the chain rule through de Boor's triangle of
//   geodesic steps x = a Exp(α Log(a⁻¹b)), whose right-perturbation Jacobians are
//     ∂x/∂b = α J_r(αu) J_r⁻¹(u),  ∂x/∂a = Ad(Exp(−αu)) − α J_r(αu) J_l⁻¹(u),  u = Log(a⁻¹b)
//   (J_r, J_l the right and left Jacobians of the group's exponential). The rotation jerk term is
//   integrated by Gauss–Legendre quadrature of the exact ω̈ (third-order jets); its Jacobian is a
//   central difference of that exact ω̈ in each control pose's tangent (step kJerkDifferenceStep).
//   Huber's loss is minimised by iteratively reweighted least squares (each pass a
//   majorisation, so E never increases). The normal equations are banded: the cost is linear in
//   the number of poses. The start: each control pose is the recording interpolated at its
//   Greville abscissa (the mean of its m inner knots).
// Quaternion signs do not matter: residuals use the rotation angle of R_Aᵀ R_B.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
/// The loss applied to each waypoint's squared chord distance.
enum class FitLoss
{
  kSquared,  ///< loss(s) = s: least squares
  kHuber,    ///< loss(s) = s for s ≤ δ², 2δ√s − δ² beyond (δ = loss_scale): robust to outliers
};

/// The default knot interval of a fit, s (`control_period` 0): four control poses a second, the
/// scale of the quality targets (a motion below 0.1 Hz, a 10 s recording at 100 Hz).
constexpr double kDefaultControlPeriod = 0.25;

/// The highest degree of a fitted B-spline (the smoothing term needs at least 3).
constexpr int kMaxFitDegree = 5;

/// What shapes a fit (file comment); validated by fitBSpline.
struct FitOptions
{
  int degree = 3;                                 ///< m, 1 … kMaxFitDegree
  double control_period = kDefaultControlPeriod;  ///< s between knots (> 0)
  double smoothing = 0.0;                         ///< λ ≥ 0
  FitLoss loss = FitLoss::kSquared;
  double loss_scale = 0.0;      ///< δ, m of chord distance (> 0 for kHuber)
  double rotation_scale = 1.0;  ///< ρ, m/rad (> 0)
};

/// A fitted B-spline (the `bspline` family's curve: BSplineCurve<G>(control, degree, knots)).
struct BSplineFitResult
{
  std::vector<Pose<double>> control;  ///< d_0 … d_{M+m−1}
  std::vector<double> knots;          ///< clamped, uniform on [t_0, t_N]
  int degree = 3;
  double residual_linear = 0.0;   ///< RMS of |p(tᵢ) − pᵢ| over the waypoints, m
  double residual_angular = 0.0;  ///< RMS of θ(R(tᵢ)ᵀ Rᵢ) over the waypoints, rad
  double objective = 0.0;         ///< E(d) of the file comment at the fitted control poses
  int iterations = 0;             ///< Levenberg–Marquardt steps taken (all passes)
};

/// M of the file comment: the number of knot intervals.
/// @throws InvalidInputError naming `control_period` if it is not positive and finite, or if it
///         makes more control poses than `max_control` (a finer control period than the recording
///         can determine)
std::size_t fitIntervals(double t0, double t1, double control_period, int degree, std::size_t max_control);

/// The fit of the file comment in geometry G (DoubleGeodesicSe3 or ScrewSe3).
/// @param poses the recorded poses Pᵢ (unit quaternions; either sign)
/// @param times their times tᵢ, strictly increasing, as many as poses (≥ 2)
/// @param options degree, control period, smoothing, loss
/// @return the control poses, knots and residuals
/// @throws InvalidInputError naming the field: `degree`, `control_period` (also for a gap in the
///         recording that leaves a control pose undetermined when λ = 0: the Schoenberg–Whitney
///         condition, naming the gap's times; and for a recording that turns by half a turn within
///         a knot interval), `smoothing`, `loss_scale`, `times`
/// @throws ConvergenceError if Levenberg–Marquardt cannot reach a stationary point
template <class G>
BSplineFitResult fitBSpline(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                            const FitOptions& options);

}  // namespace se3_interpolation
