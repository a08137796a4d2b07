// `interpolating`: C² cubic splines through every waypoint at its time (docs/curves.md), in any
// geometry G of geometry.h (ScrewSe3, DoubleGeodesicSe3, So3, Euclidean, Sphere).
//
// Form. On each segment [t_i, t_{i+1}], h_i = t_{i+1} − t_i, the curve is the chart cubic (C1) of
// chart_cubic.h: c(t) = G::exp(x_i, P_i(t − t_i)), P_i the cubic in T_{x_i} with P_i(0) = 0,
// P_i'(0) = v_i, P_i(h_i) = L_i = log(x_i, x_{i+1}), P_i'(h_i) = w_i. It passes every waypoint
// at its time whatever the rates, and no rate is limited (a leg may turn any number of times);
// the rates are chosen so that the curve is C¹ and C²:
//
//   C¹ at x_{i+1}:  D_i w_i = v_{i+1},  i.e.  w_i = E_i v_{i+1},  E_i = D_i⁻¹,                   (S0)
//   C² at x_i, i = 1 … N − 2:   A⁻_i = A⁺_i,                                                   (S1)
//     A⁺_i = (6 L_i − 4 h_i v_i − 2 h_i w_i)/h_i²                       (C2, segment i),
//     A⁻_i = D_{i−1} (−6 L_{i−1} + 2 h_{i−1} v_{i−1} + 4 h_{i−1} w_{i−1})/h_{i−1}² + Q_{i−1}(w_{i−1})
//                                                                       (C3, segment i − 1):
//     equal velocity (T1) and acceleration (T2) on both sides: the pieces agree to second order
//     in the chart at x_i, i.e. C².
//   natural:  A⁺_0 = 0 and A⁻_{N−1} = 0                                                      (S2)
//     — the acceleration that vanishes along the geodesics of G: d/dt of the body twist
//     (Rᵀω̇, Rᵀ(p̈ − ω × ṗ)) for the screw metric, (Rᵀω̇, p̈) for the double geodesic, p̈ in R^n,
//     the covariant acceleration on S^m (tangent_space.h).
//   clamped:  v_0 and v_{N−1} given.                                                          (S3)
//
// With (S0) substituted, (S1)–(S3) are, in the velocities v_i alone, a block tridiagonal system
//   R(v) = M v − b + q(v) = 0,
// M and b constant (they hold D_i, E_i, L_i and the h_i), and q block diagonal: row i's
// Q_{i−1}(E_{i−1} v_i) depends on v_i only. So its Jacobian is exact and analytic (M plus the
// derivatives 2 Q_{i−1}(E_{i−1} v_i, E_{i−1} ·)), no finite differences. In R^n, for rotations
// about one fixed axis and for pure translations D_i = E_i = I (on the data's subspace) and q = 0:
// R = 0 is twice the classical spline's slope system
//   v_{i−1}/h_{i−1} + 2 (1/h_{i−1} + 1/h_i) v_i + v_{i+1}/h_i = 3 (Δ_{i−1}/h_{i−1}² + Δ_i/h_i²),
// so the curve is the classical natural / clamped cubic spline — the same curve as the cubic
// B-spline with knots at the waypoint times. For the double geodesic the
// translation rows are that classical system exactly. On a curved group the geodesic B-spline
// would not do: the generalised de Boor algorithm (thesis Alg. 4.3.3) joins its pieces with equal
// velocities but not equal accelerations (test GeodesicBSplineIsOnlyC1).
//
// Solve (natural / clamped): a globally convergent Newton's method on the velocities in the
// frames of the tangent spaces — continuation in the curvature from the linearised spline (the
// classical spline equations carried between the tangent spaces), backtracking line search,
// pseudo-arclength past turning points, banded LU: curves/interpolating_solver.h.
// It serves every request of the stress table (time steps differing 5–100× between neighbours,
// 1.5–3 rad rotation steps; test_interpolating_stress.cpp). A failure throws ConvergenceError and says which: the
// iteration budget spent; the branch from the linearised spline ending at a singular Jacobian
// (no C² spline of this form continues to the data; the curvature fraction reached is named); a
// transition map D_i not invertible (a waypoint step at a conjugate point, which valid steps,
// below half a turn, never reach); or a non-finite value (non-finite or overflowing data). No
// curve is returned that is not C².
//
// start (Algorithm 7.4.1 of Richardson's thesis, Crouch Case 2): given v_0 and the acceleration a_0 at x_0,
// explicit, segment by segment: P_i(s) = v_i s + a_i s²/2 + c s³ with P_i(h) = L_i, i.e.
//   w_i = 3 L_i/h − 2 v_i − h a_i/2,   P_i''(h) = (−6 L_i + 2 h v_i + 4 h w_i)/h²,
// and (v_{i+1}, a_{i+1}) = (C3) of segment i, carried to the next one: C² by construction, no
// iteration. This C² spline is unique, and, like its Euclidean counterpart (the classical forward
// spline, which it equals in the abelian cases), it amplifies its data from segment to segment —
// by up to 2 + √3 in R^n, and faster on a curved group, where Q_i adds the square of the
// velocity to the carried acceleration. Only an overflow to a non-finite velocity is refused.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_solver.h"
#include "se3_interpolation/geometry/tangent_space.h"

namespace se3_interpolation
{
/// The largest chart excursion h·max(|P'(0)|, |P'(h)|) (max norm, rad or m) of a segment of the
/// start spline: its cubic terms (|ω|²|v| in se3Exp) and their second-order jets (÷ h² ≤ 1e18,
/// h ≥ 1 ns) then stay far inside double range ((1e60)³ · 1e18 = 1e198 < 1.8e308). The forward
/// construction amplifies the start data from segment to segment; finite data beyond this bound
/// evaluated to NaN (fuzz_curves finding: chart velocities of 1e149 on the screw geometry).
constexpr double kMaxStartChartExcursion = 1e60;

/// `interpolating` with end_condition natural or clamped (file comment). `start_velocity` and
/// `end_velocity` (G's representation, at the first / last point) are used only when clamped.
template <class G>
std::shared_ptr<const ChartCubicSpline<G>> solveC2Spline(const std::vector<typename G::template Point<double>>& points,
                                                         const std::vector<double>& times, EndCondition condition,
                                                         const typename G::template Tangent<double>& start_velocity,
                                                         const typename G::template Tangent<double>& end_velocity,
                                                         const SplineSolverOptions& options = {})
{
  using Tangent = typename G::template Tangent<double>;
  if (condition == EndCondition::kStart)
    throw InvalidInputError("end_condition: 'start' is solved forward (solveForwardSpline)");
  const Eigen::Index dim = detail::requireSplineData<G>(points, times);
  Tangent v0 = G::log(points.front(), points.front()) * 0.0;
  Tangent v1 = v0;
  if (condition == EndCondition::kClamped)
  {
    detail::requireTangent<G>(points.front(), start_velocity, dim, "start_velocity");
    detail::requireTangent<G>(points.back(), end_velocity, dim, "end_velocity");
    v0 = start_velocity;
    v1 = end_velocity;
  }
  const detail::C2SplineSolver<G> solver(points, times, condition, v0, v1, options);
  return solver.curve(solver.solve());
}

/// `interpolating` with end_condition start (Algorithm 7.4.1 / Case 2, file comment): the C²
/// piecewise chart cubic from the velocity and acceleration (G's representation) at the first point.
template <class G>
std::shared_ptr<const ChartCubicSpline<G>> solveForwardSpline(
    const std::vector<typename G::template Point<double>>& points, const std::vector<double>& times,
    const typename G::template Tangent<double>& start_velocity,
    const typename G::template Tangent<double>& start_acceleration, const SplineSolverOptions& /*options*/ = {})
{
  using Tangent = typename G::template Tangent<double>;
  const Eigen::Index dim = detail::requireSplineData<G>(points, times);
  detail::requireTangent<G>(points.front(), start_velocity, dim, "start_velocity");
  detail::requireTangent<G>(points.front(), start_acceleration, dim, "start_acceleration");
  const std::vector<Tangent> logs = polygonLogs<G>(points, "waypoints");
  const std::size_t n = points.size();
  std::vector<Tangent> start(n - 1), end(n - 1);
  Tangent v = start_velocity;
  Tangent a = start_acceleration;
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    const double h = times[i + 1] - times[i];
    start[i] = v;
    end[i] = logs[i] * (3.0 / h) - v * 2.0 - a * (h / 2.0);
    const Tangent second = (logs[i] * (-6.0) + v * (2.0 * h) + end[i] * (4.0 * h)) / (h * h);
    const TangentMotion<G> m = transitionMotion<G>(points[i], points[i + 1], logs[i], end[i], second);
    v = m.velocity;
    a = m.acceleration;
    if (!TangentFrame<G>::kIdentity)
    {
      // Rounding leaves a normal component of order ε; T_{x_{i+1}} is exact for the next segment.
      const Eigen::MatrixXd b = TangentFrame<G>::basis(points[i + 1]);
      v = Tangent(b * (b.transpose() * Eigen::VectorXd(v)));
      a = Tangent(b * (b.transpose() * Eigen::VectorXd(a)));
    }
    const double excursion =
        h * std::max(start[i].template lpNorm<Eigen::Infinity>(), end[i].template lpNorm<Eigen::Infinity>());
    if (!(excursion <= kMaxStartChartExcursion) || !v.allFinite() || !a.allFinite())
      throw ConvergenceError("curve 'interpolating' (end_condition 'start'): the velocity carried to " +
                             indexedField("waypoints", i + 1) +
                             " is beyond the range where the curve can be evaluated: the C^2 spline with these start "
                             "data exists but its velocities leave "
                             "double range (the forward construction, Algorithm 7.4.1, amplifies the start data "
                             "from segment to segment: by 2 + sqrt3 in the abelian case, quadratically in the "
                             "velocity on a curved group), or the data are not finite; use end_condition "
                             "'natural' or 'clamped', or fewer waypoints");
  }
  return std::make_shared<const ChartCubicSpline<G>>(points, times, logs, std::move(start), std::move(end));
}

/// The `interpolating` curve for an end condition (docs/curves.md, "Splines through the
/// waypoints"). Tangents are in G's representation at the first / last point (geometry/pose.h
/// converts request twists); unused ones are ignored.
/// @param points the waypoints (N ≥ 2), passed at their times
/// @param times strictly increasing, one per waypoint (s)
/// @param condition natural, clamped (start_velocity, end_velocity) or start (start_velocity,
///        start_acceleration)
/// @param start_velocity the velocity at points.front() (clamped, start)
/// @param end_velocity the velocity at points.back() (clamped)
/// @param start_acceleration the acceleration at points.front() (start)
/// @param options the C² solve's iteration budget and tolerance
/// @return the C² spline through every waypoint at its time
/// @throws InvalidInputError for bad input, naming the field
/// @throws ConvergenceError if the C² solve cannot continue to the data, or the forward (start)
///         construction leaves double range
template <class G>
std::shared_ptr<const Curve<G>> makeInterpolatingSpline(const std::vector<typename G::template Point<double>>& points,
                                                        const std::vector<double>& times, EndCondition condition,
                                                        const typename G::template Tangent<double>& start_velocity,
                                                        const typename G::template Tangent<double>& end_velocity,
                                                        const typename G::template Tangent<double>& start_acceleration,
                                                        const SplineSolverOptions& options = {})
{
  if (condition == EndCondition::kStart)
    return solveForwardSpline<G>(points, times, start_velocity, start_acceleration, options);
  return solveC2Spline<G>(points, times, condition, start_velocity, end_velocity, options);
}

}  // namespace se3_interpolation
