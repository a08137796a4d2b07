// The solve of `interpolating` with end_condition natural / clamped: the velocities of the C²
// chart-cubic spline (equations (S0)–(S3) of curves/interpolating_spline.h, (C1)–(C3) of
// curves/chart_cubic.h). C2SplineSolver ties together its units:
//   - curves/c2_spline_system.h: the system (the rows, their weights and exact banded Jacobian
//     blocks, the segments' data) and its cost;
//   - curves/newton_continuation.h: the globally convergent Newton solve (continuation in the
//     curvature λ, Armijo backtracking, chord polishing, pseudo-arclength past turning points);
//   - curves/c2_verification.h: the check of the returned curve itself (verifyContinuity);
//   - curves/end_condition.h: the end conditions; curves/chart_transition.h: what the solve needs
//     of a geometry (the transition derivatives D_i, Q_i, E_i = D_i⁻¹).
//
// Cost. Instructions per waypoint (bench/instruction_counts.txt, *_solve_per_waypoint): double
// geodesic 47 k, screw 72 k. A typical solve is 3 factorisations (λ = 0, two Newton steps at
// λ = 1) and 2 chord polishing steps.
#pragma once

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/c2_spline_system.h"
#include "se3_interpolation/curves/c2_verification.h"
#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/curves/chart_transition.h"
#include "se3_interpolation/curves/end_condition.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/newton_continuation.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/geometry/tangent_space.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/banded_lu.h"

namespace se3_interpolation
{
namespace detail
{
/// Newton's method with continuation for the velocities of the natural / clamped spline.
template <class G>
class C2SplineSolver
{
public:
  using Point = typename G::template Point<double>;
  using Tangent = typename G::template Tangent<double>;

  /// `points`, `times` validated by the caller; end velocities used only when clamped.
  C2SplineSolver(const std::vector<Point>& points, const std::vector<double>& times, EndCondition condition,
                 const Tangent& start_velocity, const Tangent& end_velocity, const SplineSolverOptions& options)
    : system_(points, times, condition, start_velocity, end_velocity), newton_(system_, options)
  {
  }
  // newton_ refers to system_.
  C2SplineSolver(const C2SplineSolver&) = delete;
  C2SplineSolver& operator=(const C2SplineSolver&) = delete;

  /// The velocities z_i (frame coordinates). Throws ConvergenceError.
  Eigen::VectorXd solve() const { return newton_.solve(); }

  std::string prefix() const { return system_.prefix(); }

  /// The curve for solved frame coordinates z.
  std::shared_ptr<const ChartCubicSpline<G>> curve(const Eigen::VectorXd& z) const
  {
    const std::size_t n = system_.blockCount();
    std::vector<Tangent> start, end;
    start.reserve(n - 1);
    end.reserve(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      start.push_back(system_.startVelocity(z, i));
      end.push_back(system_.endVelocity(z, i));
    }
    const auto spline = std::make_shared<const ChartCubicSpline<G>>(system_.points(), system_.times(), system_.logs(),
                                                                    std::move(start), std::move(end));
    verifyContinuity(system_, *spline);
    return spline;
  }

  Eigen::Index dof() const { return system_.dof(); }

private:
  C2SplineSystem<G> system_;
  NewtonContinuation<C2SplineSystem<G>> newton_;
};

}  // namespace detail
}  // namespace se3_interpolation
