// curves/c2_spline_system.h: the system of the C² solve (curves/interpolating_solver.h ties it
// together): the per-segment data of the rows, the residual rows and their exact banded
// Jacobian. curves/newton_continuation.h solves it; curves/c2_verification.h checks the curve.
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
// Converged when every row is below tolerance · (the size of the terms that make it up).
//
// Cost. D_i and Q_i come from second-order jets of the transition map (curves/chart_cubic.h),
// once per segment: dof + dof(dof − 1)/2 jet evaluations in general; for the double geodesic only the
// rotation's 3 + 3 (its translation part of F_i is δ ↦ δ + const: D = I, Q = 0 there, and the
// rotation part does not depend on the translation), none in R^n (D = I, Q = 0). Vectors and
// matrices have the geometry's size at compile time when its frame is the identity (SE(3), SO(3));
// for the double geodesic Q_i and G_i are kept on the rotation's 3 coordinates only (a segment's
// data, which every iteration streams through, is then ≈ 1.3 kB); every buffer of the iteration
// (here the segments and the banded matrix; the residuals, trial point and step in
// NewtonContinuation) is allocated once in the constructor, so Newton's iterations do not allocate.
#pragma once

#include <Eigen/LU>
#include <memory>
#include <string>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/chart_transition.h"
#include "se3_interpolation/curves/end_condition.h"
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
/// The phase a deadline (deadline.h) names when the solve runs past it, and the segments handled
/// between two checks inside one sweep (a sweep of 2·10⁵ waypoints takes longer than a deadline).
constexpr const char* kSolvePhase = "curve 'interpolating': the C^2 solve";
constexpr std::size_t kSegmentsPerDeadlineCheck = 2048;

/// The C² system of the natural / clamped spline (file comment): its segments' data, R at
/// curvature λ and its banded Jacobian, in the form NewtonContinuation solves.
template <class G>
class C2SplineSystem
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
  C2SplineSystem(const std::vector<Point>& points, const std::vector<double>& times, EndCondition condition,
                 const Tangent& start_velocity, const Tangent& end_velocity)
    : x_(points), t_(times), n_(points.size()), condition_(condition)
  {
    logs_ = polygonLogs<G>(x_, "waypoints");
    if (!kIdentityFrame)
      for (const auto& x : x_)
        frames_.push_back(TangentFrame<G>::basis(x));
    dof_ = kIdentityFrame ? tangentDimension<G>(x_[0]) : frames_[0].cols();
    curved_ = kCurved == Eigen::Dynamic ? dof_ : kCurved;
    start_ = toFrame(0, start_velocity);
    end_ = toFrame(n_ - 1, end_velocity);
    // Reserved, then built one by one under the deadline: the segments of 10⁵ waypoints are over
    // 100 MB, whose zero-filling at once took most of a second before the first check.
    segments_.reserve(n_ - 1);
    for (std::size_t i = 0; i + 1 < n_; ++i)
    {
      checkDeadlineEvery(i, kSegmentsPerDeadlineCheck, kSolvePhase);
      Segment& s = segments_.emplace_back();
      s.h = t_[i + 1] - t_[i];
      const std::string refused = ChartTransition<G>::refusedStep(logs_[i], i);
      if (!refused.empty())
        throw ConvergenceError(prefix() + refused);
      s.log = toFrame(i, logs_[i]);
      transition(i, &s.d, &s.q);
      if (!s.d.allFinite() || !s.q.allFinite())
        throw ConvergenceError(prefix() + "segment " + std::to_string(i) + " is not finite (are " +
                               indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1) + " finite?)");
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
    z_norms_.resize(n_);
    row_start_ = Vec::Zero(dof_);
    row_end_ = Vec::Zero(dof_);
    quadratic_ = CurvedVec::Zero(curved_);
    quadratic_block_ = CurvedRows::Zero(curved_, dof_);
  }

  std::string prefix() const
  {
    return std::string("curve 'interpolating' (end_condition '") + toString(condition_) + "'): ";
  }
  const char* phase() const { return kSolvePhase; }

  Eigen::Index dof() const { return dof_; }
  /// The unknowns (n · dof) and the rows' blocks (n, one per waypoint).
  Eigen::Index size() const { return static_cast<Eigen::Index>(n_) * dof_; }
  std::size_t blockCount() const { return n_; }
  const std::vector<Point>& points() const { return x_; }
  const std::vector<double>& times() const { return t_; }
  const std::vector<Tangent>& logs() const { return logs_; }
  /// The time step h_i of segment i.
  double step(std::size_t i) const { return segments_[i].h; }

  /// The start and end velocities of segment i (G's representation) for solved frame
  /// coordinates z: z_i and w_i = E_i z_{i+1}.
  Tangent startVelocity(const Eigen::VectorXd& z, std::size_t i) const { return fromFrame(i, block(z, i)); }
  Tangent endVelocity(const Eigen::VectorXd& z, std::size_t i) const
  {
    const Vec w = segments_[i].e * block(z, i + 1);
    return fromFrame(i, w);
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

  /// The Jacobian at the z of the last residual(), factorised; false if singular.
  bool factorized(double lambda) const
  {
    fillJacobian(lambda);
    return jacobian_->tryFactorize() == jacobian_->size();
  }

  /// *v ← J⁻¹ *v with the factors of the last factorized().
  void solveInPlace(Eigen::VectorXd* v) const { jacobian_->solveInPlace(v); }

private:
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
    ChartTransition<G>::template derivatives<Mat, Quad>(x_[i], x_[i + 1], logs_[i],
                                                        kIdentityFrame ? nullptr : &frames_[i],
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

  std::vector<Point> x_;
  std::vector<double> t_;
  std::size_t n_;
  EndCondition condition_;
  Eigen::Index dof_ = 0;
  Eigen::Index curved_ = 0;
  std::vector<Tangent> logs_;
  std::vector<Eigen::MatrixXd> frames_;  ///< only when the frames are not the identity
  Vec start_;
  Vec end_;
  // Buffers of the iteration (allocated once; the solve is const, the buffers are scratch).
  mutable std::vector<Segment> segments_;
  mutable std::unique_ptr<BandedLu> jacobian_;
  mutable std::vector<double> z_norms_;
  mutable Vec row_start_;
  mutable Vec row_end_;
  mutable CurvedVec quadratic_;
  mutable CurvedRows quadratic_block_;
};

}  // namespace detail
}  // namespace se3_interpolation
