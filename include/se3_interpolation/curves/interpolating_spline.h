// `interpolating`: C² cubic splines through every waypoint at its time (SPEC, Curves), in any
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
// B-spline with knots at the waypoint times that the SPEC names. For the double geodesic the
// translation rows are that classical system exactly. On a curved group the geodesic B-spline
// would not do: the generalised de Boor algorithm (thesis Alg. 4.3.3) joins its pieces with equal
// velocities but not equal accelerations (test GeodesicBSplineIsOnlyC1).
//
// Solve (natural / clamped). Unknowns v_i = B_i z_i in the orthonormal frame B_i of T_{x_i}
// (TangentFrame; the identity except on S^m). Row i is (S1) scaled by h_{i−1} h_i/(4 (h_{i−1} + h_i)),
// (S2) by h/4, (S3) by 1: velocities, with unit diagonal in the classical system, so the
// scaling does not depend on the time steps' ratios. Globally convergent Newton:
//   - continuation in the curvature: R_λ(z) = M z − b + λ q(z), λ from 0 to 1. At λ = 0 the system
//     is linear (the "linearised spline": the classical spline equations carried between the
//     waypoints' tangent spaces by D_i, E_i; exactly the classical spline in the abelian cases),
//     solved by one Newton step; then λ = 1 is tried from there (the common case: a few Newton
//     steps), and otherwise λ is advanced from the last solution, the step doubled after a
//     success and quartered after a failure;
//   - at each λ, Newton's method with a backtracking line search on |R_λ| (Armijo: accept the
//     longest step 2⁻ᵏ that decreases |R_λ| by the fraction 10⁻⁴ of it);
//   - if λ's step falls below 10⁻⁶ the branch of solutions has a turning point in λ: it is then
//     followed by pseudo-arclength continuation (Keller; predictor along the branch's tangent,
//     Newton corrector on R_λ = 0 plus the arclength condition, by block elimination) past it to λ = 1;
//   - every linear system is banded (block tridiagonal, bandwidth 2·dof − 1) and factorised by
//     banded_lu.h: O(N) work and memory per iteration.
// Converged when every row is below tolerance · (the size of the terms that make it up).
// Before this construction and solve, 20–98 % of the requests of issue 12's table (time steps
// differing 5–100× between neighbours, 1.5–3 rad rotation steps) were refused; now none are
// (test_interpolating_stress.cpp). A failure throws ConvergenceError and says which: the
// iteration budget spent; the branch from the linearised spline ending at a singular Jacobian
// (no C² spline of this form continues to the data; the curvature fraction reached is named); a
// transition map D_i not invertible (a waypoint step at a conjugate point, which valid steps,
// below half a turn, never reach); or a non-finite value (non-finite or overflowing data). No
// curve is returned that is not C².
//
// start (Algorithm 7.4.1 of seed 000, Crouch Case 2): given v_0 and the acceleration a_0 at x_0,
// explicit, segment by segment: P_i(s) = v_i s + a_i s²/2 + c s³ with P_i(h) = L_i, i.e.
//   w_i = 3 L_i/h − 2 v_i − h a_i/2,   P_i''(h) = (−6 L_i + 2 h v_i + 4 h w_i)/h²,
// and (v_{i+1}, a_{i+1}) = (C3) of segment i, carried to the next one: C² by construction, no
// iteration. This C² spline is unique, and, like its Euclidean counterpart (the classical forward
// spline, which it equals in the abelian cases), it amplifies its data from segment to segment —
// by up to 2 + √3 in R^n, and faster on a curved group, where Q_i adds the square of the
// velocity to the carried acceleration. Only an overflow to a non-finite velocity is refused.
#pragma once

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/math/banded_lu.h"
#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/geometry/tangent_space.h"

namespace se3_interpolation
{
/// The end conditions of the C² spline (request field `end_condition`).
enum class EndCondition
{
  kNatural,  ///< "natural": zero acceleration at both ends
  kClamped,  ///< "clamped": the given start and end velocities
  kStart     ///< "start": the given start velocity and acceleration (Crouch Case 2)
};

/// Limits of the iterative solve (natural / clamped).
struct SplineSolverOptions
{
  /// Newton iterations in all, over every step of the continuation.
  int max_iterations = 400;
  /// Bound on every row of the C² system relative to the size of the terms that make it up.
  double tolerance = 1e-12;
};

namespace detail
{
inline const char* endConditionName(EndCondition c)
{
  switch (c)
  {
    case EndCondition::kNatural:
      return "natural";
    case EndCondition::kClamped:
      return "clamped";
    case EndCondition::kStart:
      return "start";
  }
  return "";
}

inline std::string scientific(double x)
{
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

/// Newton iterations per continuation step before the step is retried shorter.
constexpr int kIterationsPerStep = 16;
/// The smallest continuation step in λ before the solve gives up, and the relative tolerance of
/// the intermediate solutions (they only start the next step; λ = 1 is solved to the
/// solver's tolerance).
constexpr double kMinContinuationStep = 1e-6;
constexpr double kPathTolerance = 1e-8;
/// The first arclength step of followPath (weighted norm of pathTangent).
constexpr double kInitialPathStep = 0.01;
constexpr double kMaxPathStep = 0.25;
/// Armijo's sufficient-decrease fraction and the shortest backtracked step 2⁻¹⁰.
constexpr double kArmijo = 1e-4;
constexpr double kShortestLineStep = 1.0 / 1024.0;

/// One segment of the C² system: the data of (C2), (C3) in the frames at its ends.
struct SplineSegment
{
  double h = 1.0;
  Eigen::VectorXd log;        ///< L_i in the frame at x_i
  TransitionDerivatives map;  ///< D_i (frame i → frame i + 1) and Q_i
  Eigen::MatrixXd inverse;    ///< E_i = D_i⁻¹
  Eigen::MatrixXd identity;   ///< D_i E_i (the identity up to rounding)
};

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
    : x_(points), t_(times), n_(points.size()), condition_(condition), options_(options)
  {
    logs_ = polygonLogs<G>(x_, "waypoints");
    for (const auto& x : x_)
      frames_.push_back(TangentFrame<G>::basis(x));
    dof_ = frames_[0].cols();
    start_ = frames_.front().transpose() * Eigen::VectorXd(start_velocity);
    end_ = frames_.back().transpose() * Eigen::VectorXd(end_velocity);
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      SplineSegment s;
      s.h = t_[i + 1] - t_[i];
      s.log = frames_[i].transpose() * Eigen::VectorXd(logs_[i]);
      s.map = transitionDerivatives<G>(x_[i], x_[i + 1], logs_[i], frames_[i], frames_[i + 1]);
      if (!s.map.jacobian.allFinite() || !s.map.quadratic.allFinite())
        throw ConvergenceError(prefix() + "segment " + std::to_string(i) + " is not finite (are " +
                               indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1) +
                               " finite?)");
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(s.map.jacobian);
      if (!lu.isInvertible())
        throw ConvergenceError(prefix() + "the transition map of segment " + std::to_string(i) +
                               " is singular (its step is at a conjugate point of the geometry)");
      s.inverse = lu.inverse();
      s.identity = s.map.jacobian * s.inverse;
      segments_.push_back(std::move(s));
    }
  }

  /// The velocities z_i (frame coordinates). Throws ConvergenceError.
  Eigen::VectorXd solve() const
  {
    int budget = options_.max_iterations;
    // λ = 0: the linear system (one Newton step from 0, polished).
    Eigen::VectorXd z = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n_) * dof_);
    Outcome outcome = newton(&z, 0.0, options_.tolerance, kIterationsPerStep, &budget);
    if (outcome == Outcome::kNotFinite)
      throw ConvergenceError(prefix() + "the linearised system is not finite (are the waypoints finite?)");
    if (outcome == Outcome::kSingular)
      throw ConvergenceError(prefix() + "the linearised C^2 system is singular");
    if (outcome == Outcome::kBudget)
      throw budgetError(0.0);
    double lambda = 0.0;
    double step = 1.0;
    while (true)
    {
      const double target = std::min(1.0, lambda + step);
      Eigen::VectorXd trial = z;
      outcome = newton(&trial, target, target >= 1.0 ? options_.tolerance : kPathTolerance, kIterationsPerStep,
                       &budget);
      if (outcome == Outcome::kConverged)
      {
        z = trial;
        lambda = target;
        if (lambda >= 1.0)
          return z;
        step = std::min(2.0 * step, 1.0 - lambda);
        continue;
      }
      if (outcome == Outcome::kBudget)
        throw budgetError(lambda);
      step *= 0.25;
      if (step < kMinContinuationStep)
      {
        // A turning point of λ (the branch folds back): follow it by arclength instead.
        std::string why;
        if (followPath(&z, lambda, &budget, &why))
          return z;
        throw ConvergenceError(prefix() + "no C^2 spline of this form continues from the linearised one to these "
                                          "waypoints: the continuation stalls at curvature " +
                               scientific(lambda) + " of the geometry's (" + why +
                               "); add waypoints between the largest rotations or use curve 'hermite'");
      }
    }
  }

  std::string prefix() const
  {
    return std::string("curve 'interpolating' (end_condition '") + endConditionName(condition_) + "'): ";
  }

  /// The curve for solved frame coordinates z.
  std::shared_ptr<const ChartCubicSpline<G>> curve(const Eigen::VectorXd& z) const
  {
    std::vector<Tangent> start, end;
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      start.push_back(Tangent(frames_[i] * block(z, i)));
      end.push_back(Tangent(frames_[i] * (segments_[i].inverse * block(z, i + 1))));
    }
    return std::make_shared<const ChartCubicSpline<G>>(x_, t_, logs_, std::move(start), std::move(end));
  }

  Eigen::Index dof() const { return dof_; }
  const Eigen::MatrixXd& frame(std::size_t i) const { return frames_[i]; }

private:
  enum class Outcome
  {
    kConverged,
    kSingular,
    kStalled,
    kNotFinite,
    kBudget
  };

  /// R(z) and, per row, the size of the terms it is made of (for the tolerance).
  struct Residual
  {
    Eigen::VectorXd r;
    Eigen::VectorXd scale;
  };

  Eigen::VectorXd block(const Eigen::VectorXd& z, std::size_t i) const
  {
    return z.segment(static_cast<Eigen::Index>(i) * dof_, dof_);
  }

  /// Row weight ρ_i (file comment).
  double weight(std::size_t i) const
  {
    if (i == 0)
      return segments_[0].h / 4.0;
    if (i + 1 == n_)
      return segments_[n_ - 2].h / 4.0;
    const double a = segments_[i - 1].h, b = segments_[i].h;
    return a * b / (4.0 * (a + b));
  }

  /// R at curvature λ: the quadratic terms Q scaled by λ (file comment).
  bool residual(const Eigen::VectorXd& z, double lambda, Residual* out) const
  {
    out->r.resize(z.size());
    out->scale.resize(static_cast<Eigen::Index>(n_));
    // A⁺_i (start of segment i) and A⁻_{i+1} (its end) with the sizes of their terms.
    std::vector<Eigen::VectorXd> start(n_ - 1), end(n_ - 1);
    std::vector<double> start_size(n_ - 1), end_size(n_ - 1);
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      const SplineSegment& s = segments_[i];
      const Eigen::VectorXd zi = block(z, i), zj = block(z, i + 1);
      const Eigen::VectorXd w = s.inverse * zj;
      const double h = s.h;
      start[i] = (6.0 * s.log - 4.0 * h * zi - 2.0 * h * w) / (h * h);
      const Eigen::VectorXd q = lambda * s.map.quadraticForm(w);
      end[i] = s.map.jacobian * ((-6.0 * s.log + 2.0 * h * zi) / (h * h)) + (4.0 / h) * (s.identity * zj) + q;
      start_size[i] = (6.0 * s.log.norm() / h + 4.0 * zi.norm() + 2.0 * w.norm()) / h;
      end_size[i] = (6.0 * s.log.norm() / h + 2.0 * zi.norm() + 4.0 * zj.norm()) / h + q.norm();
    }
    const bool natural = condition_ == EndCondition::kNatural;
    for (std::size_t i = 0; i < n_; ++i)
    {
      Eigen::VectorXd row;
      double size;
      const double rho = weight(i);
      if (i == 0)
      {
        row = natural ? Eigen::VectorXd(-rho * start[0]) : Eigen::VectorXd(block(z, 0) - start_);
        size = natural ? rho * start_size[0] : block(z, 0).norm() + start_.norm();
      }
      else if (i + 1 == n_)
      {
        row = natural ? Eigen::VectorXd(rho * end[n_ - 2]) : Eigen::VectorXd(block(z, i) - end_);
        size = natural ? rho * end_size[n_ - 2] : block(z, i).norm() + end_.norm();
      }
      else
      {
        row = rho * (end[i - 1] - start[i]);
        size = rho * (end_size[i - 1] + start_size[i]);
      }
      out->r.segment(static_cast<Eigen::Index>(i) * dof_, dof_) = row;
      out->scale[static_cast<Eigen::Index>(i)] = size;
    }
    return out->r.allFinite() && out->scale.allFinite();
  }

  /// Whether every row is within tolerance of the size of its terms.
  bool converged(const Residual& r, double tolerance) const
  {
    for (std::size_t i = 0; i < n_; ++i)
    {
      const Eigen::Index k = static_cast<Eigen::Index>(i) * dof_;
      if (r.r.segment(k, dof_).norm() > tolerance * r.scale[static_cast<Eigen::Index>(i)])
        return false;
    }
    return true;
  }

  /// The exact Jacobian dR/dz (file comment), block tridiagonal.
  void fillJacobian(const Eigen::VectorXd& z, double lambda, BandedLu* j) const
  {
    const bool natural = condition_ == EndCondition::kNatural;
    auto put = [&](std::size_t row, std::size_t column, const Eigen::MatrixXd& m) {
      for (Eigen::Index a = 0; a < dof_; ++a)
        for (Eigen::Index b = 0; b < dof_; ++b)
          (*j)(static_cast<Eigen::Index>(row) * dof_ + a, static_cast<Eigen::Index>(column) * dof_ + b) += m(a, b);
    };
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(dof_, dof_);
    for (std::size_t i = 0; i < n_; ++i)
    {
      const double rho = weight(i);
      // d(end of segment i − 1)/dz_{i−1}, /dz_i
      auto end_blocks = [&](std::size_t row, double factor) {
        const SplineSegment& s = segments_[i - 1];
        put(row, i - 1, factor * (2.0 / s.h) * s.map.jacobian);
        const Eigen::VectorXd w = s.inverse * block(z, i);
        put(row, i, factor * ((4.0 / s.h) * s.identity + lambda * s.map.quadraticJacobian(w) * s.inverse));
      };
      // −d(start of segment i)/dz_i, /dz_{i+1}
      auto start_blocks = [&](std::size_t row, double factor) {
        const SplineSegment& s = segments_[i];
        put(row, i, factor * (4.0 / s.h) * identity);
        put(row, i + 1, factor * (2.0 / s.h) * s.inverse);
      };
      if (i == 0)
      {
        if (natural)
          start_blocks(0, rho);
        else
          put(0, 0, identity);
      }
      else if (i + 1 == n_)
      {
        if (natural)
          end_blocks(i, rho);
        else
          put(i, i, identity);
      }
      else
      {
        end_blocks(i, rho);
        start_blocks(i, rho);
      }
    }
  }

  /// Damped Newton on R at curvature λ from *z (file comment), to `tolerance`, at most
  /// `iterations` steps.
  Outcome newton(Eigen::VectorXd* z, double lambda, double tolerance, int iterations, int* budget) const
  {
    Residual r;
    if (!residual(*z, lambda, &r))
      return Outcome::kNotFinite;
    Eigen::VectorXd h = r.r;
    int polish = 0;
    for (int iteration = 0;; ++iteration)
    {
      const bool done = converged(r, tolerance);
      // Below tolerance, up to two more full steps polish towards rounding level while they
      // reduce the residual.
      if (done && polish == 2)
        return Outcome::kConverged;
      if (iteration >= iterations)
        return done ? Outcome::kConverged : Outcome::kStalled;
      if (*budget <= 0)
        return done ? Outcome::kConverged : Outcome::kBudget;
      --*budget;
      BandedLu jacobian(z->size(), 2 * dof_ - 1, 2 * dof_ - 1);
      fillJacobian(*z, lambda, &jacobian);
      try
      {
        jacobian.factorize();
      }
      catch (const ConvergenceError&)
      {
        return done ? Outcome::kConverged : Outcome::kSingular;
      }
      const Eigen::VectorXd dz = jacobian.solve(-h);
      if (!dz.allFinite())
        return done ? Outcome::kConverged : Outcome::kSingular;
      const double norm = h.norm();
      bool accepted = false;
      for (double alpha = 1.0; alpha >= (done ? 1.0 : kShortestLineStep) && !accepted; alpha *= 0.5)
      {
        const Eigen::VectorXd trial = *z + alpha * dz;
        Residual rt;
        if (!residual(trial, lambda, &rt))
          continue;
        const Eigen::VectorXd ht = rt.r;
        if (ht.norm() < (1.0 - kArmijo * alpha) * norm || (!done && converged(rt, tolerance)))
        {
          *z = trial;
          r = rt;
          h = ht;
          accepted = true;
        }
      }
      if (done)
      {
        if (!accepted)
          return Outcome::kConverged;
        ++polish;
      }
      else if (!accepted)
        return Outcome::kStalled;
    }
  }

  ConvergenceError budgetError(double lambda) const
  {
    return ConvergenceError(prefix() + "the velocities did not converge in " + std::to_string(options_.max_iterations) +
                            " Newton iterations (continuation at " + scientific(lambda) +
                            " of the way from the classical spline)");
  }

  /// dR/dλ at z: the quadratic terms' rows (R is affine in λ).
  bool lambdaDerivative(const Eigen::VectorXd& z, Eigen::VectorXd* q) const
  {
    Residual one, zero;
    if (!residual(z, 1.0, &one) || !residual(z, 0.0, &zero))
      return false;
    *q = one.r - zero.r;
    return true;
  }

  /// The unit tangent (dz, dλ) of the branch R(z, λ) = 0 at (z, λ): J dz + (dR/dλ) dλ = 0, in the
  /// inner product ⟨(a, α), (b, β)⟩ = aᵀb/σ² + αβ, oriented along (pz, pl).
  bool pathTangent(const Eigen::VectorXd& z, double lambda, double sigma2, const Eigen::VectorXd& pz, double pl,
                   Eigen::VectorXd* tz, double* tl) const
  {
    Eigen::VectorXd q;
    BandedLu j(z.size(), 2 * dof_ - 1, 2 * dof_ - 1);
    if (!lambdaDerivative(z, &q) || !factorized(z, lambda, &j))
      return false;
    const Eigen::VectorXd b = j.solve(q);
    if (!b.allFinite())
      return false;
    const double norm = std::sqrt(b.squaredNorm() / sigma2 + 1.0);
    *tz = -b / norm;
    *tl = 1.0 / norm;
    if (tz->dot(pz) / sigma2 + *tl * pl < 0.0)
    {
      *tz = -*tz;
      *tl = -*tl;
    }
    return true;
  }

  bool factorized(const Eigen::VectorXd& z, double lambda, BandedLu* j) const
  {
    fillJacobian(z, lambda, j);
    try
    {
      j->factorize();
    }
    catch (const ConvergenceError&)
    {
      return false;
    }
    return true;
  }

  /// Pseudo-arclength continuation (Keller) of R(z, λ) = 0 from a solution (*z, λ) to λ = 1:
  /// predictor along the unit tangent, Newton corrector on R = 0 and ⟨tangent, Δ⟩ = step by block
  /// elimination with the banded LU; past λ = 1, Newton's method from the secant's point there.
  bool followPath(Eigen::VectorXd* solution, double lambda, int* budget, std::string* why) const
  {
    Eigen::VectorXd z = *solution;
    const double sigma2 = std::max(1.0, z.squaredNorm() / static_cast<double>(n_));
    Eigen::VectorXd tz;
    double tl = 0.0;
    if (!pathTangent(z, lambda, sigma2, Eigen::VectorXd::Zero(z.size()), 1.0, &tz, &tl))
    {
      *why = "the Jacobian of the C^2 conditions is singular there";
      return false;
    }
    double ds = kInitialPathStep;
    while (ds >= kMinContinuationStep)
    {
      if (*budget <= 0)
      {
        *why = "the iteration budget of " + std::to_string(options_.max_iterations) + " is spent";
        return false;
      }
      --*budget;  // each step costs a tangent at least
      Eigen::VectorXd zc = z + ds * tz;
      double lc = lambda + ds * tl;
      bool ok = false;
      int used = 0;
      for (; used < kIterationsPerStep && *budget > 0; ++used)
      {
        Residual r;
        if (!residual(zc, lc, &r))
          break;
        if (converged(r, kPathTolerance))
        {
          ok = true;
          break;
        }
        --*budget;
        Eigen::VectorXd q;
        BandedLu j(z.size(), 2 * dof_ - 1, 2 * dof_ - 1);
        if (!lambdaDerivative(zc, &q) || !factorized(zc, lc, &j))
          break;
        const Eigen::VectorXd a = j.solve(-r.r);
        const Eigen::VectorXd b = j.solve(q);
        const double g = tz.dot(zc - z) / sigma2 + tl * (lc - lambda) - ds;
        const double denominator = tl - tz.dot(b) / sigma2;
        if (!a.allFinite() || !b.allFinite() || denominator == 0.0)
          break;
        const double dl = (-g - tz.dot(a) / sigma2) / denominator;
        const Eigen::VectorXd dz = a - b * dl;
        if (std::sqrt(dz.squaredNorm() / sigma2 + dl * dl) > ds)
          break;  // the corrector wanders off: a shorter step
        zc += dz;
        lc += dl;
      }
      if (!ok)
      {
        ds *= 0.5;
        continue;
      }
      if (lc >= 1.0)
      {
        Eigen::VectorXd zs = z + (zc - z) * ((1.0 - lambda) / (lc - lambda));
        if (newton(&zs, 1.0, options_.tolerance, kIterationsPerStep, budget) == Outcome::kConverged)
        {
          *solution = zs;
          return true;
        }
        ds *= 0.5;
        continue;
      }
      Eigen::VectorXd nz;
      double nl = 0.0;
      if (!pathTangent(zc, lc, sigma2, tz, tl, &nz, &nl))
      {
        ds *= 0.5;
        continue;
      }
      z = zc;
      lambda = lc;
      tz = nz;
      tl = nl;
      if (used <= 3)
        ds = std::min(2.0 * ds, kMaxPathStep);
    }
    *why = "the branch of solutions cannot be followed further: its Jacobian is singular there";
    return false;
  }

  std::vector<Point> x_;
  std::vector<double> t_;
  std::size_t n_;
  EndCondition condition_;
  SplineSolverOptions options_;
  Eigen::Index dof_ = 0;
  std::vector<Tangent> logs_;
  std::vector<Eigen::MatrixXd> frames_;
  std::vector<SplineSegment> segments_;
  Eigen::VectorXd start_;
  Eigen::VectorXd end_;
};

}  // namespace detail

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
    if (!end[i].allFinite() || !v.allFinite() || !a.allFinite())
      throw ConvergenceError("curve 'interpolating' (end_condition 'start'): the velocity carried to " +
                             indexedField("waypoints", i + 1) +
                             " is not finite: the C^2 spline with these start data exists but its velocities leave "
                             "double range (the forward construction, Algorithm 7.4.1, amplifies the start data "
                             "from segment to segment: by 2 + sqrt3 in the abelian case, quadratically in the "
                             "velocity on a curved group), or the data are not finite; use end_condition "
                             "'natural' or 'clamped', or fewer waypoints");
  }
  return std::make_shared<const ChartCubicSpline<G>>(points, times, logs, std::move(start), std::move(end));
}

/// The `interpolating` curve for an end condition (SPEC, Curves). Tangents are in G's
/// representation at the first / last point (se3_velocity.h converts request twists); unused
/// ones are ignored. Throws InvalidInputError (bad input, naming the field) or ConvergenceError.
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
