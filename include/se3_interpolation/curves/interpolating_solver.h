// The solve of `interpolating` with end_condition natural / clamped: the velocities of the C²
// chart-cubic spline (equations (S0)–(S3) of curves/interpolating_spline.h, (C1)–(C3) of
// curves/chart_cubic.h).
//
// System. Unknowns v_i = B_i z_i in the orthonormal frame B_i of T_{x_i} (TangentFrame; the
// identity except on S^m, and then not stored). Row i is (S1) scaled by
// ρ_i = h_{i−1} h_i/(4 (h_{i−1} + h_i)), (S2) by h/4, (S3) by 1: velocities, with unit diagonal in
// the classical system, so the scaling does not depend on the time steps' ratios. With
// w_i = E_i z_{i+1} (S0), segment i contributes −ρ_i A⁺_i to row i and ρ_{i+1} A⁻_{i+1} to row i + 1:
//   A⁺_i = 6 L_i/h_i² − (4/h_i) z_i − (2/h_i) w_i                                          (C2)
//   A⁻_{i+1} = −D_i 6 L_i/h_i² + (2/h_i) D_i z_i + (4/h_i) D_i E_i z_{i+1} + λ Q_i(w_i)    (C3)
// and the exact Jacobian blocks (Q_i symmetric, so dQ_i(w)/dw = 2 Q_i(w, ·)):
//   −dA⁺_i:      (4/h_i) I at column i,  (2/h_i) E_i at column i + 1;
//   dA⁻_{i+1}:   (2/h_i) D_i at column i,  (4/h_i) D_i E_i + 2 λ Q_i(w_i, ·) E_i at column i + 1.
// Q_i is stored as the dof × dof blocks Q_i^(j) = Q_i(e_j, ·) side by side, so that the one
// matrix G_i = [Q_i^(0) w_i … Q_i^(dof−1) w_i] gives both Q_i(w_i) = G_i w_i and 2 Q_i(w_i, ·) = 2 G_i.
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
// Converged when every row is below tolerance · (the size of the terms that make it up).
// The returned curve is then checked itself (verifyContinuity: its one-sided chart jets at the
// interior waypoints, through exp and log rather than D_i, E_i, Q_i): near a conjugate point of
// the geometry the rows' rounding is amplified by the condition of D_i, and such data end in a
// ConvergenceError naming the waypoints instead of a "converged" curve that is not C².
//
// Cost. D_i and Q_i come from second-order jets of the transition map (curves/chart_cubic.h),
// once per segment: dof + dof(dof − 1)/2 jet evaluations in general; for the double geodesic only the
// rotation's 3 + 3 (its translation part of F_i is δ ↦ δ + const: D = I, Q = 0 there, and the
// rotation part does not depend on the translation), none in R^n (D = I, Q = 0). Vectors and
// matrices have the geometry's size at compile time when its frame is the identity (SE(3), SO(3));
// for the double geodesic Q_i and G_i are kept on the rotation's 3 coordinates only (a segment's
// data, which every iteration streams through, is then ≈ 1.3 kB); every buffer of the iteration
// (residuals, trial point, step, banded matrix) is allocated once in the constructor, so
// Newton's iterations do not allocate (the arclength continuation, rarely needed, does).
// Instructions per waypoint (bench/instruction_counts.txt, *_solve_per_waypoint): double
// geodesic 276 k before this form → 41 k, screw 365 k → 146 k (its 21 SE(3) jet evaluations
// per segment are most of it). A typical solve is 3 factorisations (λ = 0, two Newton steps at
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
#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/curves/chart_transition.h"
#include "se3_interpolation/curves/end_condition.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/geometry/tangent_space.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/banded_lu.h"

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

/// Newton's method with continuation for the velocities of the natural / clamped spline.
/// The phase a deadline (deadline.h) names when the solve runs past it, and the segments handled
/// between two checks inside one sweep (a sweep of 2·10⁵ waypoints takes longer than a deadline).
constexpr const char* kSolvePhase = "curve 'interpolating': the C^2 solve";
constexpr std::size_t kSegmentsPerDeadlineCheck = 2048;

template <class G>
class C2SplineSolver
{
public:
  using Point = typename G::template Point<double>;
  using Tangent = typename G::template Tangent<double>;
  static constexpr bool kIdentityFrame = TangentFrame<G>::kIdentity;
  /// dof at compile time when the frames are the identity and G's tangents have a fixed size.
  static constexpr int kDof = kIdentityFrame ? Tangent::RowsAtCompileTime : Eigen::Dynamic;
  using Vec = Eigen::Matrix<double, kDof, 1>;
  using Mat = Eigen::Matrix<double, kDof, kDof>;
  /// The leading coordinates that Q_i depends on and acts in: the rotation's 3 for the double
  /// geodesic (file comment, Cost), all of them otherwise.
  static constexpr int kCurved = ChartTransition<G>::curvedCoordinates(kDof);
  using CurvedVec = Eigen::Matrix<double, kCurved, 1>;
  using CurvedMat = Eigen::Matrix<double, kCurved, kCurved>;
  using Quad = Eigen::Matrix<double, kCurved, kCurved == Eigen::Dynamic ? Eigen::Dynamic : kCurved * kCurved>;
  using CurvedRows = Eigen::Matrix<double, kCurved, kDof>;

  /// `points`, `times` validated by the caller; end velocities used only when clamped.
  C2SplineSolver(const std::vector<Point>& points, const std::vector<double>& times, EndCondition condition,
                 const Tangent& start_velocity, const Tangent& end_velocity, const SplineSolverOptions& options)
    : x_(points), t_(times), n_(points.size()), condition_(condition), options_(options)
  {
    logs_ = polygonLogs<G>(x_, "waypoints");
    if (!kIdentityFrame)
      for (const auto& x : x_)
        frames_.push_back(TangentFrame<G>::basis(x));
    dof_ = kIdentityFrame ? tangentDimension<G>(x_[0]) : frames_[0].cols();
    curved_ = kCurved == Eigen::Dynamic ? dof_ : kCurved;
    start_ = toFrame(0, start_velocity);
    end_ = toFrame(n_ - 1, end_velocity);
    segments_.resize(n_ - 1);
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      checkDeadlineEvery(i, kSegmentsPerDeadlineCheck, kSolvePhase);
      Segment& s = segments_[i];
      s.h = t_[i + 1] - t_[i];
      const std::string refused = ChartTransition<G>::refusedStep(logs_[i], i);
      if (!refused.empty())
        throw ConvergenceError(prefix() + refused);
      s.log = toFrame(i, logs_[i]);
      transition(i, &s.d, &s.q);
      if (!s.d.allFinite() || !s.q.allFinite())
        throw ConvergenceError(prefix() + "segment " + std::to_string(i) + " is not finite (are " +
                               indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1) +
                               " finite?)");
      if (!invert(s.d, &s.e))
        throw ConvergenceError(prefix() + "the transition map of segment " + std::to_string(i) +
                               " is singular (its step is at a conjugate point of the geometry)");
      const double h = s.h;
      s.dlog6 = (6.0 / (h * h)) * (s.d * s.log);
      s.de = s.d * s.e;
      s.log_size = 6.0 * s.log.norm() / (h * h);
      s.g = CurvedMat::Zero(curved_, curved_);
      s.w = Vec::Zero(dof_);
    }
    const Eigen::Index size = static_cast<Eigen::Index>(n_) * dof_;
    jacobian_ = std::make_unique<BandedLu>(size, 2 * dof_ - 1, 2 * dof_ - 1);
    for (Residual* r : { &current_, &trial_ })
    {
      r->r.resize(size);
      r->scale.resize(static_cast<Eigen::Index>(n_));
    }
    z_norms_.resize(n_);
    trial_z_.resize(size);
    step_.resize(size);
    row_start_ = Vec::Zero(dof_);
    row_end_ = Vec::Zero(dof_);
    quadratic_ = CurvedVec::Zero(curved_);
    quadratic_block_ = CurvedRows::Zero(curved_, dof_);
  }

  /// The velocities z_i (frame coordinates). Throws ConvergenceError.
  Eigen::VectorXd solve() const
  {
    int budget = options_.max_iterations;
    // λ = 0: the linear system (one Newton step from 0; it only starts λ = 1, no polishing).
    Eigen::VectorXd z = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n_) * dof_);
    Outcome outcome = newton(&z, 0.0, options_.tolerance, kIterationsPerStep, 0, &budget);
    if (outcome == Outcome::kNotFinite)
      throw ConvergenceError(prefix() + "the linearised system is not finite (are the waypoints finite?)");
    if (outcome == Outcome::kSingular)
      throw ConvergenceError(prefix() + "the linearised C^2 system is singular");
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
        throw ConvergenceError(prefix() + "no C^2 spline of this form continues from the linearised one to these "
                                          "waypoints: the continuation stalls at curvature " +
                               scientific(lambda) + " of the geometry's (" + why +
                               "); add waypoints between the largest rotations or use curve 'hermite'");
      }
    }
  }

  std::string prefix() const
  {
    return std::string("curve 'interpolating' (end_condition '") + toString(condition_) + "'): ";
  }

  /// The curve for solved frame coordinates z.
  std::shared_ptr<const ChartCubicSpline<G>> curve(const Eigen::VectorXd& z) const
  {
    std::vector<Tangent> start, end;
    start.reserve(n_ - 1);
    end.reserve(n_ - 1);
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      const Vec w = segments_[i].e * block(z, i + 1);
      start.push_back(fromFrame(i, block(z, i)));
      end.push_back(fromFrame(i, w));
    }
    const auto spline = std::make_shared<const ChartCubicSpline<G>>(x_, t_, logs_, std::move(start), std::move(end));
    verifyContinuity(*spline);
    return spline;
  }

  Eigen::Index dof() const { return dof_; }

private:
  /// The curve's chart velocity and acceleration in T_{x_i} (log_{x_i} of its second-order jet)
  /// at t_i from `side`, stacked.
  Eigen::VectorXd chartState(const ChartCubicSpline<G>& curve, std::size_t i, Side side) const
  {
    using J2 = Jet<2>;
    const typename G::template Tangent<J2> y =
        G::log(G::template cast<J2>(x_[i]), curve.jet(J2::variable(t_[i]), side));
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
  void verifyContinuity(const ChartCubicSpline<G>& curve) const
  {
    const Eigen::Index m = static_cast<Eigen::Index>(logs_[0].size());
    for (std::size_t i = 1; i + 1 < n_; ++i)
    {
      checkDeadlineEvery(i, kSegmentsPerDeadlineCheck, kSolvePhase);
      const Eigen::VectorXd left = chartState(curve, i, Side::kLeft);
      const Eigen::VectorXd right = chartState(curve, i, Side::kRight);
      const double h0 = segments_[i - 1].h, h1 = segments_[i].h;
      const double l0 = logs_[i - 1].norm(), l1 = logs_[i].norm();
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
            prefix() + "the solved spline is not C^2 at " + indexedField("waypoints", i) +
            " to the accuracy of double precision (velocity jump " + scientific(velocity_jump) +
            ", acceleration jump " + scientific(acceleration_jump) + ", " +
            scientific(state_jump / state_size) + " of the state and " +
            scientific(std::max(velocity_jump / velocity_size, acceleration_jump / acceleration_size)) +
            " of the terms): the steps from " +
            indexedField("waypoints", i - 1) + " to " + indexedField("waypoints", i + 1) +
            " are too close to a conjugate point of the geometry (nearly antipodal points) for their "
            "time steps; add waypoints between them or use curve 'hermite'");
    }
  }

  enum class Outcome
  {
    kConverged,
    kSingular,
    kStalled,
    kNotFinite,
    kBudget
  };

  /// One segment of the C² system: the data of (C2), (C3) in the frames at its ends, with the
  /// products the rows and blocks of the file comment use; w and G of the last evaluation.
  /// Kept small (every iteration streams through all segments): Q_i and G_i only on the
  /// coordinates Q_i acts in, the h factors applied on the fly.
  struct Segment
  {
    double h = 1.0;
    Vec log;    ///< L_i in the frame at x_i
    Mat d;      ///< D_i (frame i → frame i + 1)
    Quad q;     ///< the blocks Q_i(e_j, ·), j < kCurved
    Mat e;      ///< E_i = D_i⁻¹
    Mat de;     ///< D_i E_i (the identity up to rounding)
    Vec dlog6;  ///< D_i 6 L_i/h²
    double log_size = 0.0;
    Vec w;        ///< E_i z_{i+1}
    CurvedMat g;  ///< G_i (file comment)
  };

  /// R(z) and, per row, the size of the terms it is made of (for the tolerance).
  struct Residual
  {
    Eigen::VectorXd r;
    Eigen::VectorXd scale;
  };

  /// A tangent of G's representation in the frame at x_i, and back.
  Vec toFrame(std::size_t i, const Tangent& v) const
  {
    if constexpr (kIdentityFrame)
      return Vec(v);
    else
      return frames_[i].transpose() * Eigen::VectorXd(v);
  }
  Tangent fromFrame(std::size_t i, const Vec& z) const
  {
    if constexpr (kIdentityFrame)
      return Tangent(z);
    else
      return Tangent(frames_[i] * z);
  }

  /// D_i and Q_i of segment i (file comment, Cost).
  void transition(std::size_t i, Mat* d, Quad* q) const
  {
    ChartTransition<G>::template derivatives<Mat, Quad>(x_[i], x_[i + 1], logs_[i], kIdentityFrame ? nullptr : &frames_[i],
                                                        kIdentityFrame ? nullptr : &frames_[i + 1], d, q);
  }

  /// E = D⁻¹ if D is invertible (ChartTransition<G>).
  static bool invert(const Mat& d, Mat* e) { return ChartTransition<G>::invert(d, e); }

  auto block(const Eigen::VectorXd& z, std::size_t i) const
  {
    if constexpr (kDof == Eigen::Dynamic)
      return z.segment(static_cast<Eigen::Index>(i) * dof_, dof_);
    else
      return z.template segment<kDof>(static_cast<Eigen::Index>(i) * kDof);
  }
  auto block(Eigen::VectorXd& z, std::size_t i) const
  {
    if constexpr (kDof == Eigen::Dynamic)
      return z.segment(static_cast<Eigen::Index>(i) * dof_, dof_);
    else
      return z.template segment<kDof>(static_cast<Eigen::Index>(i) * kDof);
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

  /// w_i and (for λ ≠ 0) G_i of segment i at z.
  void updateSegment(const Eigen::VectorXd& z, std::size_t i, double lambda) const
  {
    Segment& s = segments_[i];
    s.w.noalias() = s.e * block(z, i + 1);
    if (lambda == 0.0)
      return;  // G_i enters R and its Jacobian only with the factor λ
    for (Eigen::Index j = 0; j < curved_; ++j)
    {
      if constexpr (kCurved == Eigen::Dynamic)
        s.g.col(j).noalias() = s.q.middleCols(j * curved_, curved_) * s.w.head(curved_);
      else
        s.g.col(j).noalias() = s.q.template middleCols<kCurved>(j * kCurved) * s.w.template head<kCurved>();
    }
  }

  /// R at curvature λ (the quadratic terms Q scaled by λ, file comment) into *out; w_i and G_i
  /// of every segment updated to z.
  bool residual(const Eigen::VectorXd& z, double lambda, Residual* out) const
  {
    const bool natural = condition_ == EndCondition::kNatural;
    for (std::size_t i = 0; i < n_; ++i)
      z_norms_[i] = block(z, i).norm();
    out->r.setZero();
    out->scale.setZero();
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      checkDeadlineEvery(i, kSegmentsPerDeadlineCheck, kSolvePhase);
      Segment& s = segments_[i];
      updateSegment(z, i, lambda);
      const double h = s.h;
      // A⁺_i and A⁻_{i+1} (file comment) with the sizes of their terms.
      row_start_ = (6.0 / (h * h)) * s.log - (4.0 / h) * block(z, i) - (2.0 / h) * s.w;
      row_end_ = -s.dlog6;
      row_end_.noalias() += (2.0 / h) * (s.d * block(z, i));
      row_end_.noalias() += (4.0 / h) * (s.de * block(z, i + 1));
      if (lambda == 0.0)
      {
        quadratic_.setZero();
      }
      else
      {
        if constexpr (kCurved == Eigen::Dynamic)
          quadratic_.noalias() = lambda * (s.g * s.w.head(curved_));
        else
          quadratic_.noalias() = lambda * (s.g * s.w.template head<kCurved>());
        row_end_.head(curved_) += quadratic_;
      }
      const double start_size = s.log_size + (4.0 * z_norms_[i] + 2.0 * s.w.norm()) / h;
      const double end_size = s.log_size + (2.0 * z_norms_[i] + 4.0 * z_norms_[i + 1]) / h + quadratic_.norm();
      if (i > 0 || natural)
      {
        const double rho = weight(i);
        block(out->r, i) -= rho * row_start_;
        out->scale[static_cast<Eigen::Index>(i)] += rho * start_size;
      }
      if (i + 2 < n_ || natural)
      {
        const double rho = weight(i + 1);
        block(out->r, i + 1) += rho * row_end_;
        out->scale[static_cast<Eigen::Index>(i + 1)] += rho * end_size;
      }
    }
    if (!natural)
    {
      block(out->r, 0) = block(z, 0) - start_;
      out->scale[0] = z_norms_[0] + start_.norm();
      block(out->r, n_ - 1) = block(z, n_ - 1) - end_;
      out->scale[static_cast<Eigen::Index>(n_ - 1)] = z_norms_[n_ - 1] + end_.norm();
    }
    return out->r.allFinite() && out->scale.allFinite();
  }

  /// Whether every row is within tolerance of the size of its terms.
  bool converged(const Residual& r, double tolerance) const
  {
    for (std::size_t i = 0; i < n_; ++i)
      if (block(r.r, i).norm() > tolerance * r.scale[static_cast<Eigen::Index>(i)])
        return false;
    return true;
  }

  /// m · factor added to block (row, column) of the banded matrix.
  template <class M>
  void addBlock(std::size_t row, std::size_t column, const M& m, double factor) const
  {
    BandedLu& j = *jacobian_;
    for (Eigen::Index a = 0; a < m.rows(); ++a)
    {
      double* entry = &j(static_cast<Eigen::Index>(row) * dof_ + a, static_cast<Eigen::Index>(column) * dof_);
      for (Eigen::Index b = 0; b < m.cols(); ++b)
        entry[b] += factor * m(a, b);
    }
  }
  void addIdentity(std::size_t row, double factor) const
  {
    for (Eigen::Index a = 0; a < dof_; ++a)
      (*jacobian_)(static_cast<Eigen::Index>(row) * dof_ + a, static_cast<Eigen::Index>(row) * dof_ + a) += factor;
  }

  /// The exact Jacobian dR/dz (file comment), block tridiagonal, into jacobian_, at the z of
  /// the last residual() (its w_i, G_i).
  void fillJacobian(double lambda) const
  {
    const bool natural = condition_ == EndCondition::kNatural;
    jacobian_->setZero();
    if (!natural)
    {
      addIdentity(0, 1.0);
      addIdentity(n_ - 1, 1.0);
    }
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      checkDeadlineEvery(i, kSegmentsPerDeadlineCheck, kSolvePhase);
      const Segment& s = segments_[i];
      if (i > 0 || natural)
      {
        // −d A⁺_i/dz_i, /dz_{i+1} in row i.
        const double rho = weight(i);
        addIdentity(i, rho * (4.0 / s.h));
        addBlock(i, i + 1, s.e, rho * (2.0 / s.h));
      }
      if (i + 2 < n_ || natural)
      {
        // d A⁻_{i+1}/dz_i, /dz_{i+1} in row i + 1.
        const double rho = weight(i + 1);
        addBlock(i + 1, i, s.d, rho * (2.0 / s.h));
        addBlock(i + 1, i + 1, s.de, rho * (4.0 / s.h));
        if (lambda != 0.0)
        {
          if constexpr (kCurved == Eigen::Dynamic)
            quadratic_block_.noalias() = s.g * s.e.topRows(curved_);
          else
            quadratic_block_.noalias() = s.g * s.e.template topRows<kCurved>();
          addBlock(i + 1, i + 1, quadratic_block_, 2.0 * lambda * rho);
        }
      }
    }
  }

  /// The Jacobian at the z of the last residual(), factorised; false if singular.
  bool factorized(double lambda) const
  {
    fillJacobian(lambda);
    return jacobian_->tryFactorize() == jacobian_->size();
  }

  /// Damped Newton on R at curvature λ from *z (file comment), to `tolerance`, at most
  /// `iterations` steps, then `polish_steps` below tolerance. No allocation: current_, trial_,
  /// trial_z_ and step_ are reused.
  Outcome newton(Eigen::VectorXd* z, double lambda, double tolerance, int iterations, int polish_steps,
                 int* budget) const
  {
    if (!residual(*z, lambda, &current_))
      return Outcome::kNotFinite;
    int polish = 0;
    bool have_factors = false;
    for (int iteration = 0;; ++iteration)
    {
      checkDeadline(kSolvePhase);
      const bool done = converged(current_, tolerance);
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
        if (!factorized(lambda))
          return done ? Outcome::kConverged : Outcome::kSingular;
        have_factors = true;
      }
      step_ = -current_.r;
      jacobian_->solveInPlace(&step_);
      if (!step_.allFinite())
        return done ? Outcome::kConverged : Outcome::kSingular;
      const double norm = current_.r.norm();
      bool accepted = false;
      for (double alpha = 1.0; alpha >= (done ? 1.0 : kShortestLineStep) && !accepted; alpha *= 0.5)
      {
        trial_z_ = *z + alpha * step_;
        if (!residual(trial_z_, lambda, &trial_))
          continue;
        if (trial_.r.norm() < (1.0 - kArmijo * alpha) * norm || (!done && converged(trial_, tolerance)))
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
    return ConvergenceError(prefix() + "the velocities did not converge in " + std::to_string(options_.max_iterations) +
                            " Newton iterations (continuation at " + scientific(lambda) +
                            " of the way from the classical spline)");
  }

  /// dR/dλ at z: the quadratic terms' rows (R is affine in λ). Leaves w_i, G_i at z.
  bool lambdaDerivative(const Eigen::VectorXd& z, Eigen::VectorXd* q) const
  {
    Residual one = current_, zero = current_;
    if (!residual(z, 0.0, &zero) || !residual(z, 1.0, &one))
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
    if (!lambdaDerivative(z, &b) || !factorized(lambda))
      return false;
    jacobian_->solveInPlace(&b);
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
    Residual r = current_;
    while (ds >= kMinContinuationStep)
    {
      checkDeadline(kSolvePhase);
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
        if (!residual(zc, lc, &r))
          break;
        if (converged(r, kPathTolerance))
        {
          ok = true;
          break;
        }
        --*budget;
        Eigen::VectorXd b;
        // lambdaDerivative ends with residual(zc, 1): w_i, G_i at zc for the Jacobian.
        if (!lambdaDerivative(zc, &b) || !factorized(lc))
          break;
        Eigen::VectorXd a = -r.r;
        jacobian_->solveInPlace(&a);
        jacobian_->solveInPlace(&b);
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

  std::vector<Point> x_;
  std::vector<double> t_;
  std::size_t n_;
  EndCondition condition_;
  SplineSolverOptions options_;
  Eigen::Index dof_ = 0;
  Eigen::Index curved_ = 0;
  std::vector<Tangent> logs_;
  std::vector<Eigen::MatrixXd> frames_;  ///< only when the frames are not the identity
  Vec start_;
  Vec end_;
  // Buffers of the iteration (allocated once; solve() is const, the buffers are scratch).
  mutable std::vector<Segment> segments_;
  mutable std::unique_ptr<BandedLu> jacobian_;
  mutable Residual current_;
  mutable Residual trial_;
  mutable std::vector<double> z_norms_;
  mutable Eigen::VectorXd trial_z_;
  mutable Eigen::VectorXd step_;
  mutable Vec row_start_;
  mutable Vec row_end_;
  mutable CurvedVec quadratic_;
  mutable CurvedRows quadratic_block_;
};

}  // namespace detail
}  // namespace se3_interpolation
