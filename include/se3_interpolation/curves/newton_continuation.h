// curves/newton_continuation.h: the globally convergent Newton solve of the C² spline's system
// (curves/interpolating_solver.h ties it together), generic over the system it solves: a
// residual R_λ(z) with the sizes of its rows' terms, a convergence test, and a factorised
// Jacobian, as curves/c2_spline_system.h assembles them. The solved curve is checked by
// curves/c2_verification.h.
//
// Solve: globally convergent Newton.
//   - continuation in the curvature: R_λ(z) = M z − b + λ q(z), λ from 0 to 1. At λ = 0 the system
//     is linear (the "linearised spline": the classical spline equations carried between the
//     waypoints' tangent spaces by D_i, E_i; exactly the classical spline in the abelian cases),
//     solved by one Newton step; then λ = 1 is tried from there (the common case: a few Newton
//     steps, no continuation), and otherwise λ is advanced from the last solution, the step
//     doubled after a success and quartered after a failure;
//   - at each λ, Newton's method with a backtracking line search on |R_λ| (Armijo: accept the
//     longest step 2⁻ᵏ that decreases |R_λ| by the fraction 10⁻⁴ of it);
//   - once below tolerance, up to two polishing steps towards rounding level, kept while they
//     reduce |R_λ|, with the last factorised Jacobian (chord steps: the Jacobian changes by the
//     order of the last step, already below tolerance, so a new factorisation would not help);
//   - if λ's step falls below 10⁻⁶ the branch of solutions has a turning point in λ: it is then
//     followed by pseudo-arclength continuation (Keller; predictor along the branch's tangent,
//     Newton corrector on R_λ = 0 plus the arclength condition, by block elimination) past it to λ = 1;
//   - every linear system is banded (block tridiagonal, bandwidth 2·dof − 1) and factorised by
//     math/banded_lu.h: O(N) work and memory per iteration.
// The iteration's buffers (residuals, trial point, step) are allocated once in the constructor,
// so Newton's iterations do not allocate (the arclength continuation, rarely needed, does).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "se3_interpolation/curves/chart_transition.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
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
/// Polishing steps below tolerance at λ = 1 (file comment).
constexpr int kPolishSteps = 2;

/// R(z) and, per row, the size of the terms it is made of (for the tolerance).
struct Residual
{
  Eigen::VectorXd r;
  Eigen::VectorXd scale;
};

/// Newton's method with continuation in λ (file comment) on a system that provides
///   - size(): the unknowns; blockCount(): the rows' blocks (the entries of Residual::scale);
///   - residual(z, λ, Residual*): R_λ(z) and its rows' sizes, false if not finite;
///   - converged(Residual, tolerance): whether every row is within tolerance of its size;
///   - factorized(λ): the Jacobian at the z of the last residual() factorised, false if singular;
///     solveInPlace(VectorXd*): a solve with those factors;
///   - prefix(): the start of its error messages; phase(): the phase its deadline names.
template <class System>
class NewtonContinuation
{
public:
  NewtonContinuation(const System& system, const SplineSolverOptions& options) : system_(system), options_(options)
  {
    for (Residual* r : { &current_, &trial_ })
    {
      r->r.resize(system_.size());
      r->scale.resize(static_cast<Eigen::Index>(system_.blockCount()));
    }
    trial_z_.resize(system_.size());
    step_.resize(system_.size());
  }

  /// The solution z of R_1(z) = 0. Throws ConvergenceError.
  Eigen::VectorXd solve() const
  {
    int budget = options_.max_iterations;
    // λ = 0: the linear system (one Newton step from 0; it only starts λ = 1, no polishing).
    Eigen::VectorXd z = Eigen::VectorXd::Zero(system_.size());
    Outcome outcome = newton(&z, 0.0, options_.tolerance, kIterationsPerStep, 0, &budget);
    if (outcome == Outcome::kNotFinite)
      throw ConvergenceError(system_.prefix() + "the linearised system is not finite (are the waypoints finite?)");
    if (outcome == Outcome::kSingular)
      throw ConvergenceError(system_.prefix() + "the linearised C^2 system is singular");
    if (outcome == Outcome::kBudget)
      throw budgetError(0.0);
    double lambda = 0.0;
    double step = 1.0;
    Eigen::VectorXd trial(z.size());
    while (true)
    {
      const double target = std::min(1.0, lambda + step);
      trial = z;
      const bool last = target >= 1.0;
      outcome = newton(&trial, target, last ? options_.tolerance : kPathTolerance, kIterationsPerStep,
                       last ? kPolishSteps : 0, &budget);
      if (outcome == Outcome::kConverged)
      {
        z.swap(trial);
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
        throw ConvergenceError(system_.prefix() +
                               "no C^2 spline of this form continues from the linearised one to these "
                               "waypoints: the continuation stalls at curvature " +
                               scientific(lambda) + " of the geometry's (" + why +
                               "); add waypoints between the largest rotations or use curve 'hermite'");
      }
    }
  }

private:
  enum class Outcome
  {
    kConverged,
    kSingular,
    kStalled,
    kNotFinite,
    kBudget
  };

  /// Damped Newton on R at curvature λ from *z (file comment), to `tolerance`, at most
  /// `iterations` steps, then `polish_steps` below tolerance. No allocation: current_, trial_,
  /// trial_z_ and step_ are reused.
  Outcome newton(Eigen::VectorXd* z, double lambda, double tolerance, int iterations, int polish_steps,
                 int* budget) const
  {
    if (!system_.residual(*z, lambda, &current_))
      return Outcome::kNotFinite;
    int polish = 0;
    bool have_factors = false;
    for (int iteration = 0;; ++iteration)
    {
      checkDeadline(system_.phase());
      const bool done = system_.converged(current_, tolerance);
      if (done && polish == polish_steps)
        return Outcome::kConverged;
      if (iteration >= iterations)
        return done ? Outcome::kConverged : Outcome::kStalled;
      if (*budget <= 0)
        return done ? Outcome::kConverged : Outcome::kBudget;
      --*budget;
      // Polishing reuses the factors of the previous step (chord steps, file comment).
      if (!(done && have_factors))
      {
        if (!system_.factorized(lambda))
          return done ? Outcome::kConverged : Outcome::kSingular;
        have_factors = true;
      }
      step_ = -current_.r;
      system_.solveInPlace(&step_);
      if (!step_.allFinite())
        return done ? Outcome::kConverged : Outcome::kSingular;
      const double norm = current_.r.norm();
      bool accepted = false;
      for (double alpha = 1.0; alpha >= (done ? 1.0 : kShortestLineStep) && !accepted; alpha *= 0.5)
      {
        trial_z_ = *z + alpha * step_;
        if (!system_.residual(trial_z_, lambda, &trial_))
          continue;
        if (trial_.r.norm() < (1.0 - kArmijo * alpha) * norm || (!done && system_.converged(trial_, tolerance)))
        {
          z->swap(trial_z_);
          std::swap(current_.r, trial_.r);
          std::swap(current_.scale, trial_.scale);
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
    return ConvergenceError(system_.prefix() + "the velocities did not converge in " +
                            std::to_string(options_.max_iterations) + " Newton iterations (continuation at " +
                            scientific(lambda) + " of the way from the classical spline)");
  }

  /// dR/dλ at z: the quadratic terms' rows (R is affine in λ). Leaves w_i, G_i at z.
  bool lambdaDerivative(const Eigen::VectorXd& z, Eigen::VectorXd* q) const
  {
    Residual one = current_, zero = current_;
    if (!system_.residual(z, 0.0, &zero) || !system_.residual(z, 1.0, &one))
      return false;
    *q = one.r - zero.r;
    return true;
  }

  /// The unit tangent (dz, dλ) of the branch R(z, λ) = 0 at (z, λ): J dz + (dR/dλ) dλ = 0, in the
  /// inner product ⟨(a, α), (b, β)⟩ = aᵀb/σ² + αβ, oriented along (pz, pl).
  bool pathTangent(const Eigen::VectorXd& z, double lambda, double sigma2, const Eigen::VectorXd& pz, double pl,
                   Eigen::VectorXd* tz, double* tl) const
  {
    Eigen::VectorXd b;
    if (!lambdaDerivative(z, &b) || !system_.factorized(lambda))
      return false;
    system_.solveInPlace(&b);
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

  /// The corrector of one predictor step of followPath from (z, λ) along the unit tangent (tz, tl)
  /// by ds: Newton on R(z_c, λ_c) = 0 and ⟨tangent, (z_c − z, λ_c − λ)⟩ = ds (the norm weighted by
  /// σ²) by block elimination, from the predicted (*zc, *lc), at most kIterationsPerStep iterations
  /// (*used counts them). Whether it converged to kPathTolerance; false where an iteration fails
  /// or wanders farther than ds.
  bool correct(const Eigen::VectorXd& z, double lambda, const Eigen::VectorXd& tz, double tl, double ds, double sigma2,
               Eigen::VectorXd* zc, double* lc, int* used, int* budget, Residual* r) const
  {
    for (; (*used < kIterationsPerStep) && (*budget > 0); ++*used)
    {
      if (!system_.residual(*zc, *lc, r))
        return false;
      if (system_.converged(*r, kPathTolerance))
        return true;
      --*budget;
      Eigen::VectorXd b;
      // lambdaDerivative ends with residual(zc, 1): w_i, G_i at zc for the Jacobian.
      if (!lambdaDerivative(*zc, &b) || !system_.factorized(*lc))
        return false;
      Eigen::VectorXd a = -r->r;
      system_.solveInPlace(&a);
      system_.solveInPlace(&b);
      const double g = tz.dot(*zc - z) / sigma2 + tl * (*lc - lambda) - ds;
      const double denominator = tl - tz.dot(b) / sigma2;
      if (!a.allFinite() || !b.allFinite() || denominator == 0.0)
        return false;
      const double dl = (-g - tz.dot(a) / sigma2) / denominator;
      const Eigen::VectorXd dz = a - b * dl;
      if (std::sqrt(dz.squaredNorm() / sigma2 + dl * dl) > ds)
        return false;  // the corrector wanders off: a shorter step
      *zc += dz;
      *lc += dl;
    }
    return false;
  }

  /// Pseudo-arclength continuation (Keller) of R(z, λ) = 0 from a solution (*z, λ) to λ = 1:
  /// predictor along the unit tangent, Newton corrector on R = 0 and ⟨tangent, Δ⟩ = step by block
  /// elimination with the banded LU; past λ = 1, Newton's method from the secant's point there.
  bool followPath(Eigen::VectorXd* solution, double lambda, int* budget, std::string* why) const
  {
    Eigen::VectorXd z = *solution;
    const double sigma2 = std::max(1.0, z.squaredNorm() / static_cast<double>(system_.blockCount()));
    Eigen::VectorXd tz;
    double tl = 0.0;
    if (!pathTangent(z, lambda, sigma2, Eigen::VectorXd::Zero(z.size()), 1.0, &tz, &tl))
    {
      *why = "the Jacobian of the C^2 conditions is singular there";
      return false;
    }
    double ds = kInitialPathStep;
    Residual r = current_;
    while (ds >= kMinContinuationStep)
    {
      checkDeadline(system_.phase());
      if (*budget <= 0)
      {
        *why = "the iteration budget of " + std::to_string(options_.max_iterations) + " is spent";
        return false;
      }
      --*budget;  // each step costs a tangent at least
      Eigen::VectorXd zc = z + ds * tz;
      double lc = lambda + ds * tl;
      int used = 0;
      if (!correct(z, lambda, tz, tl, ds, sigma2, &zc, &lc, &used, budget, &r))
      {
        ds *= 0.5;
        continue;
      }
      if (lc >= 1.0)
      {
        Eigen::VectorXd zs = z + (zc - z) * ((1.0 - lambda) / (lc - lambda));
        if (newton(&zs, 1.0, options_.tolerance, kIterationsPerStep, kPolishSteps, budget) == Outcome::kConverged)
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

  const System& system_;
  SplineSolverOptions options_;
  // Buffers of the iteration (allocated once; solve() is const, the buffers are scratch).
  mutable Residual current_;
  mutable Residual trial_;
  mutable Eigen::VectorXd trial_z_;
  mutable Eigen::VectorXd step_;
};

}  // namespace detail
}  // namespace se3_interpolation
