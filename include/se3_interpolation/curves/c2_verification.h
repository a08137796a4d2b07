// curves/c2_verification.h: the check of the C² solve's curve (curves/interpolating_solver.h
// ties the solve together; its system is curves/c2_spline_system.h, its Newton solve
// curves/newton_continuation.h).
//
// The returned curve is checked itself (verifyContinuity: its one-sided chart jets at the
// interior waypoints, through exp and log rather than D_i, E_i, Q_i): near a conjugate point of
// the geometry the rows' rounding is amplified by the condition of D_i, and such data end in a
// ConvergenceError naming the waypoints instead of a "converged" curve that is not C².
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <vector>

#include "se3_interpolation/curves/c2_spline_system.h"
#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/curves/chart_transition.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/jet.h"

namespace se3_interpolation
{
namespace detail
{
/// The relative continuity that verifyContinuity asks of the solved curve: a thousand times the
/// default row tolerance (SplineSolverOptions::tolerance), for the rounding of evaluating the
/// curve through exp and log; a solution of the rows whose D_i, Q_i describe the curve meets it
/// with margin (rounding level, about 1e-15, in the unit tests' configurations).
constexpr double kContinuityTolerance = 1e-9;
/// The continuity a user sees, which verifyContinuity asks too: the jump of the state
/// (velocity and acceleration, stacked) at an interior waypoint at most this fraction of
/// 1 + the size of both sides' states (SI units: a floor of 1e-7 m/s, rad/s, m/s², rad/s²).
/// kContinuityTolerance, relative to the terms, is not enough where the terms are far larger than
/// the value: near the sphere's conjugate point the terms' rounding is amplified by the condition
/// of D_i (1/gap) and a short step makes the terms 6|L|/h² dwarf the acceleration (fuzz_c2
/// findings: π − 1e-6 rad in 2.5e-6 s, terms 3e12 and an acceleration of 6e6 that jumped by 43,
/// 7e-6 of the state, passed it). fuzz_c2 checks 1e-6 of the same, through the ambient
/// kinematics: ten times this, for the rounding of the other evaluation path.
constexpr double kStateContinuityTolerance = 1e-7;

/// The curve's chart velocity and acceleration in T_{x_i} (log_{x_i} of its second-order jet)
/// at t_i from `side`, stacked.
template <class G>
Eigen::VectorXd chartState(const ChartCubicSpline<G>& curve, const typename G::template Point<double>& x, double t,
                           Side side)
{
  using J2 = Jet<2>;
  const typename G::template Tangent<J2> y = G::log(G::template cast<J2>(x), curve.jet(J2::variable(t), side));
  const Eigen::Index m = static_cast<Eigen::Index>(y.size());
  Eigen::VectorXd s(2 * m);
  for (Eigen::Index k = 0; k < m; ++k)
  {
    s[k] = y[k].coefficient(1);
    s[m + k] = 2.0 * y[k].coefficient(2);
  }
  return s;
}

/// The C^2 conditions checked on the curve itself: at every interior waypoint its one-sided
/// chart velocities and accelerations (chartState, evaluated through the geometry's exp and
/// log, not through D_i, E_i, Q_i) must agree to kContinuityTolerance of the size of the terms
/// they are made of (|L|/h and 6 |L|/h^2 of both segments, and the two sides themselves), and
/// to kStateContinuityTolerance of the state itself (the continuity a user measures).
/// The solve meets its rows with the transition derivatives D_i, Q_i; near a conjugate point
/// of the geometry (a step within ~1e-6 of pi on S^m, where D_i is singular) their rounding is
/// amplified by the condition of D_i and the converged rows no longer describe the curve
/// (the fuzz_c2 finding: an acceleration jump of 4.5e4 on terms of 3e12, 1.5e-8 of them,
/// with rows converged to 1e-12). Such data are refused rather than returned as a C^2 curve.
/// `system`: the solved system (the waypoints, their times and steps, the messages' prefix).
template <class G>
void verifyContinuity(const C2SplineSystem<G>& system, const ChartCubicSpline<G>& curve)
{
  const auto& x = system.points();
  const std::vector<double>& t = system.times();
  const auto& logs = system.logs();
  const Eigen::Index m = static_cast<Eigen::Index>(logs[0].size());
  for (std::size_t i = 1; i + 1 < system.blockCount(); ++i)
  {
    checkDeadlineEvery(i, kSegmentsPerDeadlineCheck, kSolvePhase);
    const Eigen::VectorXd left = chartState(curve, x[i], t[i], Side::kLeft);
    const Eigen::VectorXd right = chartState(curve, x[i], t[i], Side::kRight);
    const double h0 = system.step(i - 1), h1 = system.step(i);
    const double l0 = logs[i - 1].norm(), l1 = logs[i].norm();
    const double velocity_size = l0 / h0 + l1 / h1 + left.head(m).norm() + right.head(m).norm();
    const double acceleration_size =
        6.0 * l0 / (h0 * h0) + 6.0 * l1 / (h1 * h1) + left.tail(m).norm() + right.tail(m).norm();
    const double velocity_jump = (left.head(m) - right.head(m)).norm();
    const double acceleration_jump = (left.tail(m) - right.tail(m)).norm();
    const double state_size = 1.0 + left.norm() + right.norm();
    const double state_jump = (left - right).norm();
    if (!(velocity_jump <= kContinuityTolerance * velocity_size) ||
        !(acceleration_jump <= kContinuityTolerance * acceleration_size) ||
        !(state_jump <= kStateContinuityTolerance * state_size))
      throw ConvergenceError(
          system.prefix() + "the solved spline is not C^2 at " + indexedField("waypoints", i) +
          " to the accuracy of double precision (velocity jump " + scientific(velocity_jump) + ", acceleration jump " +
          scientific(acceleration_jump) + ", " + scientific(state_jump / state_size) + " of the state and " +
          scientific(std::max(velocity_jump / velocity_size, acceleration_jump / acceleration_size)) +
          " of the terms): the steps from " + indexedField("waypoints", i - 1) + " to " +
          indexedField("waypoints", i + 1) +
          " are too close to a conjugate point of the geometry (nearly antipodal points) for their "
          "time steps; add waypoints between them or use curve 'hermite'");
  }
}

}  // namespace detail
}  // namespace se3_interpolation
