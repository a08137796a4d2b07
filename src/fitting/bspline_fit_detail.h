// What the units of curve fit's least-squares B-spline (fitting/bspline_fit.h) share: the
// Levenberg–Marquardt constants, the two groups the fit works on, de Boor's triangle with its
// Jacobians, the problem (data, knots, weights) and the two parts of the unknowns (the group part
// and the double geodesic's translation). Private to src/fitting/, not installed. The units:
//   fit_groups.cpp       the Jacobians of the groups' exponentials (SO(3), SE(3));
//   fit_problem.cpp      the knot layout, the Euclidean basis, the jerk quadrature, the input's checks;
//   translation_fit.cpp  the translation's linear least squares (banded normal equations);
//   group_fit.cpp        the group part's start and its Levenberg–Marquardt steps;
//   bspline_fit.cpp      the passes (Huber's reweighting), the result, the entry points.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/math/lie_groups.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace fitting_detail
{
/// Levenberg–Marquardt: the trial steps at most (over all of Huber's passes), the damping's start
/// and bounds, and the step below which (max |δ|, rad or m) it has converged: far below any
/// recording's noise, above rounding.
constexpr int kMaxIterations = 500;
constexpr double kInitialDamping = 1e-6;
constexpr double kMaxDamping = 1e12;
constexpr double kConvergedStep = 1e-10;
/// A relative decrease of the objective at or below this is rounding: converged.
constexpr double kRoundingImprovement = 1e-14;
/// Slow convergence (Huber's weights chasing the steps on a few points): kStagnationSteps steps that
/// together lower the objective by less than kStagnation of it end the pass (the gradient is then
/// below 1e-6 of the objective's scale, as test_bspline_fit's stationarity test checks).
constexpr std::size_t kStagnationSteps = 10;
constexpr double kStagnation = 1e-12;

/// Huber's loss and its derivative (the IRLS weight) at s = d² for δ = scale.
inline double huberLoss(double s, double scale)
{
  return s <= scale * scale ? s : 2.0 * scale * std::sqrt(s) - scale * scale;
}
inline double huberWeight(double s, double scale)
{
  return s <= scale * scale ? 1.0 : scale / std::sqrt(s);
}

// ---- The two groups the fit works on: SO(3) (the double geodesic's rotation) and SE(3) (screw).

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;

/// The SO(3) right Jacobian J_r(w) = I − a W + b W² with W = [w]×, a = (1 − cos θ)/θ²,
/// b = (θ − sin θ)/θ³.
Mat<3> so3RightJacobian(const Vec<3>& w);

/// J_r⁻¹(w) = I + ½ W + c W², c = 1/θ² − (1 + cos θ)/(2θ sin θ).
Mat<3> so3RightJacobianInverse(const Vec<3>& w);

/// Barfoot's Q(ρ, φ) (Barfoot & Furgale, "Associating uncertainty with three-dimensional poses",
/// IEEE T-RO 2014, eq. 102): the off-diagonal block of SE(3)'s left Jacobian in the ordering
/// (translation, rotation).
Mat<3> barfootQ(const Vec<3>& rho, const Vec<3>& phi);

/// SO(3) (the double geodesic's rotation part): elements are unit quaternions, x ⊕ δ = x Exp(δ)
/// with δ the body rotation vector (the tangent of geometry/so3.h).
struct So3Group
{
  static constexpr int kDof = 3;
  using Element = Quaternion<double>;
  using Geometry = So3;

  static Vec<3> log(const Element& a, const Element& b) { return so3Log(Quaternion<double>(a.conjugate() * b)); }
  static Element exp(const Element& a, const Vec<3>& v) { return Element(a * so3Exp(v)); }
  static Mat<3> rightJacobian(const Vec<3>& w) { return so3RightJacobian(w); }
  static Mat<3> rightJacobianInverse(const Vec<3>& w) { return so3RightJacobianInverse(w); }
  /// Ad(Exp(−w)) = Exp(w)ᵀ.
  static Mat<3> adjointOfInverseExp(const Vec<3>& w) { return so3Exp(w).toRotationMatrix().transpose(); }

  static Element ofPose(const Pose<double>& x) { return x.q; }
  /// The chord residual ρ Log(R_Pᵀ R_C) (rad·m/rad) and its Jacobian in C's right perturbation.
  static Vec<3> residual(const Element& c, const Element& p, double rho, Mat<3>* jacobian)
  {
    const Vec<3> e = log(p, c);
    if (jacobian)
      *jacobian = rho * so3RightJacobianInverse(e);
    return rho * e;
  }
  /// The jerk residual ρ ω̈ of the third-order jet of the curve's rotation.
  static Vec<3> jerk(const Quaternion<Jet<3>>& x, double rho)
  {
    return rho * timing::kinematics3FromJet(Pose<Jet<3>>(x, Vector3<Jet<3>>::Zero())).jerk.angular;
  }
  static Quaternion<Jet<3>> castJet(const Element& x) { return So3::cast<Jet<3>>(x); }
};

/// SE(3) with the screw geometry: elements are poses, x ⊕ δ = x Exp(δ) with δ = (ω, v) the body
/// twist (the tangent of geometry/screw_se3.h).
struct Se3Group
{
  static constexpr int kDof = 6;
  using Element = Pose<double>;
  using Geometry = ScrewSe3;

  static Vec<6> log(const Element& a, const Element& b) { return se3Log(a.inverseTimes(b)); }
  static Element exp(const Element& a, const Vec<6>& v) { return a * se3Exp(Vec<6>(v)); }
  /// J_r(ω, v) = [[J_r(ω), 0], [Q(−v, −ω), J_r(ω)]] in the ordering (ω, v).
  static Mat<6> rightJacobian(const Vec<6>& xi)
  {
    const Vec<3> w = xi.head<3>();
    const Mat<3> j = so3RightJacobian(w);
    Mat<6> m = Mat<6>::Zero();
    m.topLeftCorner<3, 3>() = j;
    m.bottomRightCorner<3, 3>() = j;
    m.bottomLeftCorner<3, 3>() = barfootQ(-xi.tail<3>(), -w);
    return m;
  }
  static Mat<6> rightJacobianInverse(const Vec<6>& xi)
  {
    const Vec<3> w = xi.head<3>();
    const Mat<3> ji = so3RightJacobianInverse(w);
    Mat<6> m = Mat<6>::Zero();
    m.topLeftCorner<3, 3>() = ji;
    m.bottomRightCorner<3, 3>() = ji;
    m.bottomLeftCorner<3, 3>() = -ji * barfootQ(-xi.tail<3>(), -w) * ji;
    return m;
  }
  /// Ad(T⁻¹) for T = Exp(ξ) = (R, p): [[Rᵀ, 0], [[−Rᵀp]× Rᵀ, Rᵀ]].
  static Mat<6> adjointOfInverseExp(const Vec<6>& xi)
  {
    const Pose<double> inv = se3Exp(Vec<6>(xi)).inverse();
    const Mat<3> r = inv.q.toRotationMatrix();
    Mat<6> m = Mat<6>::Zero();
    m.topLeftCorner<3, 3>() = r;
    m.bottomRightCorner<3, 3>() = r;
    m.bottomLeftCorner<3, 3>() = hat(Vec<3>(inv.p)) * r;
    return m;
  }

  static Element ofPose(const Pose<double>& x) { return x; }
  /// The chord residual (ρ Log(R_Pᵀ R_C), p_C − p_P) and its Jacobian in C's body twist: the
  /// translation moves by R_C v to first order.
  static Vec<6> residual(const Element& c, const Element& p, double rho, Mat<6>* jacobian)
  {
    const Vec<3> e = so3Log(Quaternion<double>(p.q.conjugate() * c.q));
    if (jacobian)
    {
      jacobian->setZero();
      jacobian->topLeftCorner<3, 3>() = rho * so3RightJacobianInverse(e);
      jacobian->bottomRightCorner<3, 3>() = c.q.toRotationMatrix();
    }
    Vec<6> r;
    r << rho * e, c.p - p.p;
    return r;
  }
  /// The jerk residual (ρ ω̈, p⃛).
  static Vec<6> jerk(const Pose<Jet<3>>& x, double rho)
  {
    const timing::Kinematics3 k = timing::kinematics3FromJet(x);
    Vec<6> j;
    j << rho * k.jerk.angular, k.jerk.linear;
    return j;
  }
  static Pose<Jet<3>> castJet(const Element& x) { return ScrewSe3::cast<Jet<3>>(x); }
};

// ---- De Boor's triangle with the Jacobians of its point in the control points.

/// De Boor's algorithm (curves/bspline.h) in a group L, recording the Jacobians of every
/// geodesic step so that the point's Jacobian in each of the m + 1 control points of the span is
/// one backward pass through the triangle (the file comment of bspline_fit.h).
template <class L>
class DeBoorTriangle
{
public:
  static constexpr int D = L::kDof;
  using Element = typename L::Element;
  using Jacobians = std::array<Mat<D>, kMaxFitDegree + 1>;

  /// The point at t in span k of the B-spline with control points d, degree m, knots u; with
  /// `jacobians`, the steps' Jacobians are kept for pullBack.
  Element evaluate(const std::vector<Element>& d, const std::vector<double>& u, int m, std::size_t k, double t,
                   bool jacobians)
  {
    m_ = m;
    const std::size_t p = static_cast<std::size_t>(m);
    for (std::size_t j = 0; j <= p; ++j)
      node_[0][j] = d[k - p + j];
    for (std::size_t r = 1; r <= p; ++r)
      for (std::size_t j = r; j <= p; ++j)
      {
        const std::size_t i = k - p + j;
        const double alpha = (t - u[i]) / (u[i + p + 1 - r] - u[i]);
        const Element& a = node_[r - 1][j - 1];
        const Element& b = node_[r - 1][j];
        const Vec<D> v = L::log(a, b);
        const Vec<D> w = alpha * v;
        node_[r][j] = L::exp(a, w);
        if (jacobians)
        {
          const Mat<D> jw = L::rightJacobian(w);
          step_b_[r][j] = alpha * jw * L::rightJacobianInverse(v);
          step_a_[r][j] = L::adjointOfInverseExp(w) - alpha * jw * L::rightJacobianInverse(Vec<D>(-v));
        }
      }
    return node_[p][p];
  }

  /// out[j] = e · ∂x/∂d_{k−m+j} (j = 0 … m) for the last evaluate(…, true), e = ∂r/∂x.
  void pullBack(const Mat<D>& e, Jacobians* out)
  {
    const std::size_t p = static_cast<std::size_t>(m_);
    adjoint_[p][p] = e;
    for (std::size_t r = p; r >= 1; --r)
    {
      for (std::size_t j = r - 1; j <= p; ++j)
        adjoint_[r - 1][j].setZero();
      for (std::size_t j = r; j <= p; ++j)
      {
        adjoint_[r - 1][j - 1] += adjoint_[r][j] * step_a_[r][j];
        adjoint_[r - 1][j] += adjoint_[r][j] * step_b_[r][j];
      }
    }
    for (std::size_t j = 0; j <= p; ++j)
      (*out)[j] = adjoint_[0][j];
  }

private:
  static constexpr std::size_t kSize = kMaxFitDegree + 1;
  int m_ = 0;
  std::array<std::array<Element, kSize>, kSize> node_;
  std::array<std::array<Mat<D>, kSize>, kSize> step_a_, step_b_;
  std::array<std::array<Mat<D>, kSize>, kSize> adjoint_;
};

// ---- The problem: data, knots, weights, and the two parts of the unknowns.

/// The quadrature of the jerk term: Gauss–Legendre nodes per knot interval, exact for the
/// translation's polynomial jerk (degree m − 3) and accurate for the rotation's.
struct QuadraturePoint
{
  std::size_t span;
  double t;
  double weight;  ///< Gauss weight × half the interval
};

/// The data of a fit and what every part of it reads: the knots, each waypoint's knot span, the
/// quadrature nodes and the IRLS weights.
struct FitProblem
{
  const std::vector<Pose<double>>* poses;
  const std::vector<double>* times;
  FitOptions options;
  std::size_t n = 0;  ///< control points
  std::vector<double> knots;
  std::vector<std::size_t> spans;  ///< of each waypoint
  std::vector<QuadraturePoint> quadrature;
  std::vector<double> weights;  ///< IRLS weights (1 for squared loss)
  double inverse_count = 1.0;   ///< 1/N

  std::size_t size() const { return poses->size(); }
};

/// The B-spline basis functions of degree m nonzero on span k (N_{k−m} … N_k) and their
/// derivatives up to `order` at t: ders(r, j) = N^{(r)}_{k−m+j}(t) (Piegl & Tiller, "The NURBS
/// Book", Algorithm A2.3).
Eigen::MatrixXd basisDerivatives(const std::vector<double>& u, int m, std::size_t k, double t, int order);

/// t in seconds to 9 significant digits, for the messages that refuse an input.
std::string formatSeconds(double t);

/// The problem of the file comment of bspline_fit.h with unit weights: the input checked (the
/// times, every field of FitOptions, and the Schoenberg–Whitney condition when λ = 0), the
/// clamped uniform knots, each waypoint's knot span and the jerk term's quadrature nodes.
/// @throws InvalidInputError naming the field
FitProblem makeProblem(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                       const FitOptions& options);

/// Gauss–Newton's normal equations H δ = −g of one Levenberg–Marquardt step: H = Σ w JᵀJ and
/// g = Σ w Jᵀr over the weighted residuals r with Jacobians J in the control points' tangents.
/// A residual involves the m + 1 control points of one span, so H is banded (|row − column| ≤
/// band = D(m + 1) − 1) and kept by rows of 2·band + 1 entries.
struct BandedNormalEquations
{
  Eigen::Index dim = 0;   ///< the unknowns, D per control point
  Eigen::Index band = 0;  ///< H's half bandwidth
  std::vector<double> h;  ///< H's band, row by row
  Eigen::VectorXd g;

  /// H(r, c) for |r − c| ≤ band.
  double& entry(Eigen::Index r, Eigen::Index c)
  {
    return h[static_cast<std::size_t>(r * (2 * band + 1) + (c - r + band))];
  }
};

/// The group part of the unknowns, fitted by Levenberg–Marquardt: the rotations of the double
/// geodesic (L = So3Group, with the translation's squared distances `other` added to each
/// waypoint's chord distance for the loss), or the poses of the screw geometry (L = Se3Group).
template <class L>
class GroupFit
{
public:
  static constexpr int D = L::kDof;
  using Element = typename L::Element;

  GroupFit(const FitProblem& problem, std::vector<Element> control) : pb_(problem), control_(std::move(control)) {}

  const std::vector<Element>& control() const { return control_; }
  int iterations() const { return iterations_; }

  /// The squared chord-distance part of each waypoint at the current control points.
  std::vector<double> squaredDistances(const std::vector<Element>& control);

  /// λ ∫ |jerk residual|² dt by the quadrature.
  double jerkTerm(const std::vector<Element>& control) const;

  /// The objective: (1/N) Σ loss(other_i + s_i) + λ ∫ jerk², for the translation's part `other`.
  /// ∞ where the control points make a half-turn geodesic step (a rejected trial).
  double objective(const std::vector<Element>& control, const std::vector<double>& other);

  double loss(double s) const { return pb_.options.loss == FitLoss::kHuber ? huberLoss(s, pb_.options.loss_scale) : s; }

  /// One Levenberg–Marquardt step of the weighted problem (weights pb_.weights, from the current
  /// state) whose acceptance is judged on the true objective with the translation's part `other`.
  /// @return the largest component of the accepted step (0 if none improves)
  double step(const std::vector<double>& other, double* objective_value);

private:
  /// The normal equations of the weighted problem (weights pb_.weights) at the current control
  /// points: the waypoints' chord residuals, then (λ > 0) the jerk residuals at the quadrature nodes.
  BandedNormalEquations normalEquations();

  /// The Jacobian of the jerk residual in the control points of span q.span, by central
  /// differences of the exact jerk (kJerkDifferenceStep).
  void jerkJacobian(const QuadraturePoint& q, typename DeBoorTriangle<L>::Jacobians* jac);

  const FitProblem& pb_;
  std::vector<Element> control_;
  DeBoorTriangle<L> tri_;
  double damping_ = kInitialDamping;
  int iterations_ = 0;
};

extern template class GroupFit<So3Group>;
extern template class GroupFit<Se3Group>;

/// The recording interpolated (along L's geodesics) at each control point's Greville abscissa.
template <class L>
std::vector<typename L::Element> grevilleStart(const FitProblem& pb);

/// The translation of the double geodesic: the weighted linear least-squares spline with the
/// jerk penalty, solved from its banded normal equations (three right-hand sides).
class TranslationFit
{
public:
  explicit TranslationFit(const FitProblem& problem) : pb_(problem)
  {
    const int m = pb_.options.degree;
    basis_.resize(pb_.size());
    for (std::size_t i = 0; i < pb_.size(); ++i)
      basis_[i] = basisDerivatives(pb_.knots, m, pb_.spans[i], (*pb_.times)[i], 0).row(0);
    for (const QuadraturePoint& q : pb_.quadrature)
      jerk_basis_.push_back(basisDerivatives(pb_.knots, m, q.span, q.t, 3).row(3));
  }

  /// The control positions minimising (1/N) Σ wᵢ |p(tᵢ) − pᵢ|² + λ ∫ |p⃛|² dt.
  std::vector<Vector3<double>> solve() const;

  /// |p(tᵢ) − pᵢ|² of each waypoint.
  std::vector<double> squaredDistances(const std::vector<Vector3<double>>& control) const;

  /// λ ∫ |p⃛|² dt (exact: the quadrature integrates the polynomial jerk exactly).
  double jerkTerm(const std::vector<Vector3<double>>& control) const;

private:
  const FitProblem& pb_;
  std::vector<Eigen::RowVectorXd> basis_;
  std::vector<Eigen::RowVectorXd> jerk_basis_;
};

}  // namespace fitting_detail
}  // namespace se3_interpolation
