// The least-squares B-spline fit of fitting/bspline_fit.h (the method is described there).
#include "se3_interpolation/fitting/bspline_fit.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/math/banded_lu.h"
#include "se3_interpolation/math/lie_groups.h"
#include "se3_interpolation/math/quadrature.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace
{
/// Below this θ² the Jacobians' coefficients are their Taylor series (to θ⁴; the next term is
/// below 1e-15 relative there), above it their closed forms (whose cancellation costs at most
/// about 1e-10 relative at θ = 0.1).
constexpr double kJacobianSeriesThetaSquared = 1e-2;

/// The step of the central difference of the exact angular jerk in a control pose's tangent
/// (rad, m): truncation ~h² ≈ 1e-12 and rounding ~1e-16/h ≈ 1e-10 relative to the jerk.
constexpr double kJerkDifferenceStep = 1e-6;

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
double huberLoss(double s, double scale)
{
  return s <= scale * scale ? s : 2.0 * scale * std::sqrt(s) - scale * scale;
}
double huberWeight(double s, double scale)
{
  return s <= scale * scale ? 1.0 : scale / std::sqrt(s);
}

// ---- The two groups the fit works on: SO(3) (the double geodesic's rotation) and SE(3) (screw).

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;

/// The SO(3) right Jacobian's coefficients: J_r(w) = I − a W + b W² with W = [w]×,
/// a = (1 − cos θ)/θ², b = (θ − sin θ)/θ³.
void so3JacobianCoefficients(double theta2, double* a, double* b)
{
  if (theta2 < kJacobianSeriesThetaSquared)
  {
    *a = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0;
    *b = 1.0 / 6.0 - theta2 / 120.0 + theta2 * theta2 / 5040.0;
    return;
  }
  const double theta = std::sqrt(theta2);
  const double s = std::sin(0.5 * theta);
  *a = 2.0 * s * s / theta2;
  *b = (theta - std::sin(theta)) / (theta2 * theta);
}

Mat<3> so3RightJacobian(const Vec<3>& w)
{
  double a, b;
  so3JacobianCoefficients(w.squaredNorm(), &a, &b);
  const Mat<3> h = hat(w);
  return Mat<3>::Identity() - a * h + b * h * h;
}

/// J_r⁻¹(w) = I + ½ W + c W², c = 1/θ² − (1 + cos θ)/(2θ sin θ).
Mat<3> so3RightJacobianInverse(const Vec<3>& w)
{
  const double theta2 = w.squaredNorm();
  double c;
  if (theta2 < kJacobianSeriesThetaSquared)
    c = 1.0 / 12.0 + theta2 / 720.0 + theta2 * theta2 / 30240.0;
  else
  {
    const double theta = std::sqrt(theta2);
    c = 1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  const Mat<3> h = hat(w);
  return Mat<3>::Identity() + 0.5 * h + c * h * h;
}

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

/// Barfoot's Q(ρ, φ) (Barfoot & Furgale, "Associating uncertainty with three-dimensional poses",
/// IEEE T-RO 2014, eq. 102): the off-diagonal block of SE(3)'s left Jacobian in the ordering
/// (translation, rotation).
Mat<3> barfootQ(const Vec<3>& rho, const Vec<3>& phi)
{
  const double theta2 = phi.squaredNorm();
  double c1, c2, c3;
  if (theta2 < kJacobianSeriesThetaSquared)
  {
    c1 = 1.0 / 6.0 - theta2 / 120.0 + theta2 * theta2 / 5040.0;
    c2 = 1.0 / 24.0 - theta2 / 720.0 + theta2 * theta2 / 40320.0;
    c3 = 1.0 / 120.0 - theta2 / 2520.0 + theta2 * theta2 / 120960.0;
  }
  else
  {
    const double theta = std::sqrt(theta2);
    const double s = std::sin(theta);
    const double c = std::cos(theta);
    c1 = (theta - s) / (theta2 * theta);
    c2 = (theta2 + 2.0 * c - 2.0) / (2.0 * theta2 * theta2);
    c3 = (2.0 * theta - 3.0 * s + theta * c) / (2.0 * theta2 * theta2 * theta);
  }
  const Mat<3> p = hat(phi);
  const Mat<3> r = hat(rho);
  const Mat<3> pr = p * r;
  const Mat<3> prp = pr * p;
  return 0.5 * r + c1 * (pr + r * p + prp) + c2 * (p * pr + r * p * p - 3.0 * prp) + c3 * (prp * p + p * prp);
}

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

// ---- The knot vector and the Euclidean basis.

/// The B-spline basis functions of degree m nonzero on span k (N_{k−m} … N_k) and their
/// derivatives up to `order` at t: ders(r, j) = N^{(r)}_{k−m+j}(t) (Piegl & Tiller, "The NURBS
/// Book", Algorithm A2.3).
Eigen::MatrixXd basisDerivatives(const std::vector<double>& u, int m, std::size_t k, double t, int order)
{
  const std::size_t p = static_cast<std::size_t>(m);
  Eigen::MatrixXd ndu(p + 1, p + 1);
  std::vector<double> left(p + 1), right(p + 1);
  ndu(0, 0) = 1.0;
  for (std::size_t j = 1; j <= p; ++j)
  {
    left[j] = t - u[k + 1 - j];
    right[j] = u[k + j] - t;
    double saved = 0.0;
    for (std::size_t r = 0; r < j; ++r)
    {
      ndu(j, r) = right[r + 1] + left[j - r];  // lower triangle: knot differences
      const double temp = ndu(r, j - 1) / ndu(j, r);
      ndu(r, j) = saved + right[r + 1] * temp;  // upper triangle: basis functions
      saved = left[j - r] * temp;
    }
    ndu(j, j) = saved;
  }
  const int n = std::min(order, m);
  Eigen::MatrixXd ders = Eigen::MatrixXd::Zero(order + 1, m + 1);
  for (std::size_t j = 0; j <= p; ++j)
    ders(0, static_cast<Eigen::Index>(j)) = ndu(j, p);
  Eigen::MatrixXd a(2, p + 1);
  for (int r = 0; r <= m; ++r)
  {
    int s1 = 0, s2 = 1;
    a(0, 0) = 1.0;
    for (int kk = 1; kk <= n; ++kk)
    {
      double d = 0.0;
      const int rk = r - kk, pk = m - kk;
      if (r >= kk)
      {
        a(s2, 0) = a(s1, 0) / ndu(pk + 1, rk);
        d = a(s2, 0) * ndu(rk, pk);
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? kk - 1 : m - r;
      for (int j = j1; j <= j2; ++j)
      {
        a(s2, j) = (a(s1, j) - a(s1, j - 1)) / ndu(pk + 1, rk + j);
        d += a(s2, j) * ndu(rk + j, pk);
      }
      if (r <= pk)
      {
        a(s2, kk) = -a(s1, kk - 1) / ndu(pk + 1, r);
        d += a(s2, kk) * ndu(r, pk);
      }
      ders(kk, r) = d;
      std::swap(s1, s2);
    }
  }
  double factor = m;
  for (int kk = 1; kk <= n; ++kk)
  {
    ders.row(kk) *= factor;
    factor *= (m - kk);
  }
  return ders;
}

std::string formatSeconds(double t)
{
  std::ostringstream s;
  s.precision(9);
  s << t;
  return s.str();
}

/// The Schoenberg–Whitney condition for the least-squares system of n control points to be
/// nonsingular without smoothing: increasing waypoints i_0 < … < i_{n−1} with t_{i_j} inside the
/// support (u_j, u_{j+m+1}) of N_j (closed at the domain's ends). Matched greedily; the first
/// control point without a waypoint names the gap.
void checkSchoenbergWhitney(const std::vector<double>& times, const std::vector<double>& u, std::size_t n, int m)
{
  const std::size_t p = static_cast<std::size_t>(m);
  const double t0 = u[p], t1 = u[n];
  std::size_t i = 0;
  for (std::size_t j = 0; j < n; ++j)
  {
    const double lo = u[j], hi = u[j + p + 1];
    while (i < times.size() && !(times[i] > lo || (lo == t0 && times[i] >= lo)))
      ++i;
    if (i == times.size() || !(times[i] < hi || (hi == t1 && times[i] <= hi)))
    {
      // The knot interval of the support with the fewest waypoints is the gap.
      double gap_lo = lo, gap_hi = hi;
      for (std::size_t s = j; s <= j + p && s + 1 < u.size(); ++s)
      {
        if (!(u[s] < u[s + 1]))
          continue;
        const auto first = std::lower_bound(times.begin(), times.end(), u[s]);
        if (first == times.end() || *first > u[s + 1])
        {
          gap_lo = u[s];
          gap_hi = u[s + 1];
          break;
        }
      }
      throw InvalidInputError("control_period: the waypoints leave control pose " + std::to_string(j) +
                              " of the fit undetermined: too few waypoints between t = " + formatSeconds(gap_lo) +
                              " and t = " + formatSeconds(gap_hi) +
                              " s (a gap in the recording); a longer control_period, or smoothing > 0");
    }
    ++i;
  }
}

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

/// The third-order jet of the B-spline in L's geometry at t in span k (de Boor in Jet<3>).
template <class L>
auto deBoorJet(const std::vector<typename L::Element>& d, const std::vector<double>& u, int m, std::size_t k,
               double t)
{
  using G = typename L::Geometry;
  using JetPoint = decltype(L::castJet(d[0]));
  const std::size_t p = static_cast<std::size_t>(m);
  std::array<JetPoint, kMaxFitDegree + 1> node;
  for (std::size_t j = 0; j <= p; ++j)
    node[j] = L::castJet(d[k - p + j]);
  const Jet<3> tj = Jet<3>::variable(t);
  for (std::size_t r = 1; r <= p; ++r)
    for (std::size_t j = p; j >= r; --j)
    {
      const std::size_t i = k - p + j;
      const Jet<3> alpha = (tj - Jet<3>(u[i])) * Jet<3>(1.0 / (u[i + p + 1 - r] - u[i]));
      node[j] = geodesic<G>(node[j - 1], node[j], alpha);
    }
  return node[p];
}

// ---- The problem: data, knots, weights, and the two parts of the unknowns.

/// The quadrature of the jerk term: Gauss–Legendre nodes per knot interval, exact for the
/// translation's polynomial jerk (degree m − 3) and accurate for the rotation's.
struct QuadraturePoint
{
  std::size_t span;
  double t;
  double weight;  ///< Gauss weight × half the interval
};

struct FitProblem
{
  const std::vector<Pose<double>>* poses;
  const std::vector<double>* times;
  FitOptions options;
  std::size_t n = 0;                     ///< control points
  std::vector<double> knots;
  std::vector<std::size_t> spans;        ///< of each waypoint
  std::vector<QuadraturePoint> quadrature;
  std::vector<double> weights;           ///< IRLS weights (1 for squared loss)
  double inverse_count = 1.0;            ///< 1/N

  std::size_t size() const { return poses->size(); }
};

std::vector<QuadraturePoint> jerkQuadrature(const std::vector<double>& u, std::size_t n, int m)
{
  std::vector<QuadraturePoint> q;
  if (m < 3)
    return q;
  for (std::size_t k = static_cast<std::size_t>(m); k < n; ++k)
  {
    const double a = u[k], b = u[k + 1];
    if (!(a < b))
      continue;
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (std::size_t g = 0; g < kGauss4Nodes.size(); ++g)
      q.push_back({ k, mid + half * kGauss4Nodes[g], half * kGauss4Weights[g] });
  }
  return q;
}

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
  std::vector<double> squaredDistances(const std::vector<Element>& control)
  {
    std::vector<double> s(pb_.size());
    for (std::size_t i = 0; i < s.size(); ++i)
    {
      checkDeadlineEvery(i, 4096, "fit");
      const Element c = tri_.evaluate(control, pb_.knots, pb_.options.degree, pb_.spans[i], (*pb_.times)[i], false);
      s[i] = L::residual(c, L::ofPose((*pb_.poses)[i]), pb_.options.rotation_scale, nullptr).squaredNorm();
    }
    return s;
  }

  /// λ ∫ |jerk residual|² dt by the quadrature.
  double jerkTerm(const std::vector<Element>& control) const
  {
    if (pb_.options.smoothing == 0.0)
      return 0.0;
    double sum = 0.0;
    for (const QuadraturePoint& q : pb_.quadrature)
      sum += q.weight * L::jerk(deBoorJet<L>(control, pb_.knots, pb_.options.degree, q.span, q.t),
                                pb_.options.rotation_scale)
                            .squaredNorm();
    return pb_.options.smoothing * sum;
  }

  /// The objective: (1/N) Σ loss(other_i + s_i) + λ ∫ jerk², for the translation's part `other`.
  /// ∞ where the control points make a half-turn geodesic step (a rejected trial).
  double objective(const std::vector<Element>& control, const std::vector<double>& other)
  {
    std::vector<double> s;
    try
    {
      s = squaredDistances(control);
    }
    catch (const NonUniqueGeodesicError&)
    {
      return std::numeric_limits<double>::infinity();
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < s.size(); ++i)
      sum += loss(other[i] + s[i]);
    return pb_.inverse_count * sum + jerkTerm(control);
  }

  double loss(double s) const
  {
    return pb_.options.loss == FitLoss::kHuber ? huberLoss(s, pb_.options.loss_scale) : s;
  }

  /// One Levenberg–Marquardt step of the weighted problem (weights pb_.weights, from the current
  /// state) whose acceptance is judged on the true objective with the translation's part `other`.
  /// @return the largest component of the accepted step (0 if none improves)
  double step(const std::vector<double>& other, double* objective_value)
  {
    const int m = pb_.options.degree;
    const Eigen::Index dim = static_cast<Eigen::Index>(pb_.n) * D;
    const Eigen::Index band = D * (m + 1) - 1;
    std::vector<double> h((static_cast<std::size_t>(dim)) * static_cast<std::size_t>(2 * band + 1), 0.0);
    auto normal_entry = [&](Eigen::Index r, Eigen::Index c) -> double& {
      return h[static_cast<std::size_t>(r * (2 * band + 1) + (c - r + band))];
    };
    Eigen::VectorXd g = Eigen::VectorXd::Zero(dim);
    typename DeBoorTriangle<L>::Jacobians jac;
    const std::size_t p = static_cast<std::size_t>(m);
    auto accumulate = [&](std::size_t k, const Vec<D>& r, double w) {
      const Eigen::Index first = static_cast<Eigen::Index>(k - p) * D;
      for (std::size_t a = 0; a <= p; ++a)
      {
        const Mat<D>& ja = jac[a];
        g.template segment<D>(first + static_cast<Eigen::Index>(a) * D) += w * ja.transpose() * r;
        for (std::size_t b = a; b <= p; ++b)
        {
          const Mat<D> block = w * ja.transpose() * jac[b];
          const Eigen::Index r0 = first + static_cast<Eigen::Index>(a) * D;
          const Eigen::Index c0 = first + static_cast<Eigen::Index>(b) * D;
          for (int x = 0; x < D; ++x)
            for (int y = 0; y < D; ++y)
            {
              normal_entry(r0 + x, c0 + y) += block(x, y);
              if (b != a)
                normal_entry(c0 + y, r0 + x) += block(x, y);
            }
        }
      }
    };
    for (std::size_t i = 0; i < pb_.size(); ++i)
    {
      checkDeadlineEvery(i, 2048, "fit");
      const std::size_t k = pb_.spans[i];
      const Element c = tri_.evaluate(control_, pb_.knots, m, k, (*pb_.times)[i], true);
      Mat<D> e;
      const Vec<D> r = L::residual(c, L::ofPose((*pb_.poses)[i]), pb_.options.rotation_scale, &e);
      tri_.pullBack(e, &jac);
      accumulate(k, r, pb_.inverse_count * pb_.weights[i]);
    }
    if (pb_.options.smoothing > 0.0)
      for (const QuadraturePoint& q : pb_.quadrature)
      {
        checkDeadline("fit");
        jerkJacobian(q, &jac);
        const Vec<D> r = L::jerk(deBoorJet<L>(control_, pb_.knots, m, q.span, q.t), pb_.options.rotation_scale);
        accumulate(q.span, r, pb_.options.smoothing * q.weight);
      }
    const double current = *objective_value;
    for (;;)
    {
      BandedLu lu(dim, band, band);
      for (Eigen::Index r = 0; r < dim; ++r)
        for (Eigen::Index c = std::max<Eigen::Index>(0, r - band); c <= std::min(dim - 1, r + band); ++c)
          lu(r, c) = normal_entry(r, c) + (r == c ? damping_ * (normal_entry(r, r) + 1e-12) : 0.0);
      Eigen::VectorXd delta = -g;
      if (lu.tryFactorize() == dim)
      {
        lu.solveInPlace(&delta);
        std::vector<Element> trial(control_.size());
        for (std::size_t j = 0; j < control_.size(); ++j)
          trial[j] = L::exp(control_[j], Vec<D>(delta.template segment<D>(static_cast<Eigen::Index>(j) * D)));
        ++iterations_;
        const double value = objective(trial, other);
        const double size = delta.lpNorm<Eigen::Infinity>();
        if (std::isfinite(value) && value <= current)
        {
          control_ = std::move(trial);
          *objective_value = value;
          damping_ = std::max(damping_ / 3.0, kInitialDamping * 1e-6);
          // An improvement at the objective's rounding is convergence, whatever the step.
          return current - value <= kRoundingImprovement * current ? 0.0 : size;
        }
        // A step this small that does not improve: the objective is at its rounding floor.
        if (size < kConvergedStep)
          return 0.0;
      }
      damping_ *= 4.0;
      if (damping_ > kMaxDamping)
        return 0.0;
    }
  }

private:
  /// The Jacobian of the jerk residual in the control points of span q.span, by central
  /// differences of the exact jerk (kJerkDifferenceStep).
  void jerkJacobian(const QuadraturePoint& q, typename DeBoorTriangle<L>::Jacobians* jac)
  {
    const std::size_t p = static_cast<std::size_t>(pb_.options.degree);
    std::vector<Element>& work = control_;
    for (std::size_t a = 0; a <= p; ++a)
    {
      const std::size_t j = q.span - p + a;
      const Element saved = work[j];
      for (int x = 0; x < D; ++x)
      {
        Vec<D> h = Vec<D>::Zero();
        h[x] = kJerkDifferenceStep;
        work[j] = L::exp(saved, h);
        const Vec<D> plus = L::jerk(deBoorJet<L>(work, pb_.knots, pb_.options.degree, q.span, q.t),
                                    pb_.options.rotation_scale);
        work[j] = L::exp(saved, Vec<D>(-h));
        const Vec<D> minus = L::jerk(deBoorJet<L>(work, pb_.knots, pb_.options.degree, q.span, q.t),
                                     pb_.options.rotation_scale);
        work[j] = saved;
        (*jac)[a].col(x) = (plus - minus) / (2.0 * kJerkDifferenceStep);
      }
    }
  }

  const FitProblem& pb_;
  std::vector<Element> control_;
  DeBoorTriangle<L> tri_;
  double damping_ = kInitialDamping;
  int iterations_ = 0;
};

/// The recording interpolated (along L's geodesics) at each control point's Greville abscissa.
template <class L>
std::vector<typename L::Element> grevilleStart(const FitProblem& pb)
{
  const std::vector<double>& t = *pb.times;
  const std::size_t p = static_cast<std::size_t>(pb.options.degree);
  std::vector<typename L::Element> d(pb.n);
  for (std::size_t j = 0; j < pb.n; ++j)
  {
    double tau = 0.0;
    for (std::size_t s = 1; s <= p; ++s)
      tau += pb.knots[j + s];
    tau = p == 0 ? pb.knots[j] : tau / static_cast<double>(p);
    const std::size_t i = static_cast<std::size_t>(
        std::max<std::ptrdiff_t>(0, (std::upper_bound(t.begin(), t.end(), tau) - t.begin()) - 1));
    const typename L::Element a = L::ofPose((*pb.poses)[i]);
    if (i + 1 >= t.size())
    {
      d[j] = a;
      continue;
    }
    const typename L::Element b = L::ofPose((*pb.poses)[i + 1]);
    const double alpha = std::clamp((tau - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0);
    try
    {
      d[j] = L::exp(a, Vec<L::kDof>(alpha * L::log(a, b)));
    }
    catch (const NonUniqueGeodesicError&)
    {
      d[j] = alpha < 0.5 ? a : b;
    }
  }
  return d;
}

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
  std::vector<Vector3<double>> solve() const
  {
    const int m = pb_.options.degree;
    const std::size_t p = static_cast<std::size_t>(m);
    const Eigen::Index n = static_cast<Eigen::Index>(pb_.n);
    BandedLu lu(n, m, m);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
    for (std::size_t i = 0; i < pb_.size(); ++i)
    {
      const double w = pb_.inverse_count * pb_.weights[i];
      const Eigen::Index first = static_cast<Eigen::Index>(pb_.spans[i] - p);
      for (Eigen::Index a = 0; a <= m; ++a)
      {
        rhs.row(first + a) += w * basis_[i][a] * (*pb_.poses)[i].p.transpose();
        for (Eigen::Index b = 0; b <= m; ++b)
          lu(first + a, first + b) += w * basis_[i][a] * basis_[i][b];
      }
    }
    if (pb_.options.smoothing > 0.0)
      for (std::size_t q = 0; q < pb_.quadrature.size(); ++q)
      {
        const double w = pb_.options.smoothing * pb_.quadrature[q].weight;
        const Eigen::Index first = static_cast<Eigen::Index>(pb_.quadrature[q].span - p);
        for (Eigen::Index a = 0; a <= m; ++a)
          for (Eigen::Index b = 0; b <= m; ++b)
            lu(first + a, first + b) += w * jerk_basis_[q][a] * jerk_basis_[q][b];
      }
    lu.factorize();
    std::vector<Vector3<double>> out(pb_.n);
    for (int c = 0; c < 3; ++c)
    {
      Eigen::VectorXd x = rhs.col(c);
      lu.solveInPlace(&x);
      for (Eigen::Index j = 0; j < n; ++j)
        out[static_cast<std::size_t>(j)][c] = x[j];
    }
    return out;
  }

  /// |p(tᵢ) − pᵢ|² of each waypoint.
  std::vector<double> squaredDistances(const std::vector<Vector3<double>>& control) const
  {
    const std::size_t p = static_cast<std::size_t>(pb_.options.degree);
    std::vector<double> s(pb_.size());
    for (std::size_t i = 0; i < s.size(); ++i)
    {
      Vector3<double> x = Vector3<double>::Zero();
      for (std::size_t a = 0; a <= p; ++a)
        x += basis_[i][static_cast<Eigen::Index>(a)] * control[pb_.spans[i] - p + a];
      s[i] = (x - (*pb_.poses)[i].p).squaredNorm();
    }
    return s;
  }

  /// λ ∫ |p⃛|² dt (exact: the quadrature integrates the polynomial jerk exactly).
  double jerkTerm(const std::vector<Vector3<double>>& control) const
  {
    const std::size_t p = static_cast<std::size_t>(pb_.options.degree);
    double sum = 0.0;
    for (std::size_t q = 0; q < pb_.quadrature.size(); ++q)
    {
      Vector3<double> j = Vector3<double>::Zero();
      for (std::size_t a = 0; a <= p; ++a)
        j += jerk_basis_[q][static_cast<Eigen::Index>(a)] * control[pb_.quadrature[q].span - p + a];
      sum += pb_.quadrature[q].weight * j.squaredNorm();
    }
    return pb_.options.smoothing * sum;
  }

private:
  const FitProblem& pb_;
  std::vector<Eigen::RowVectorXd> basis_;
  std::vector<Eigen::RowVectorXd> jerk_basis_;
};

void validateOptions(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                     const FitOptions& o)
{
  if (times.size() != poses.size())
    throw InvalidInputError("times: curve 'fit' needs one time per waypoint (" + std::to_string(times.size()) +
                            " times for " + std::to_string(poses.size()) + " waypoints)");
  if (poses.size() < 2)
    throw InvalidInputError("waypoints: curve 'fit' needs at least 2 waypoints");
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!std::isfinite(times[i]) || (i > 0 && !(times[i] > times[i - 1])))
      throw InvalidInputError(indexedField("times", i) + ": times must be finite and strictly increasing");
  if (o.degree < 1 || o.degree > kMaxFitDegree)
    throw InvalidInputError("degree: " + std::to_string(o.degree) + " for curve 'fit'; expected 1 … " +
                            std::to_string(kMaxFitDegree));
  if (!std::isfinite(o.smoothing) || o.smoothing < 0.0)
    throw InvalidInputError("smoothing: must be a finite number ≥ 0");
  if (o.smoothing > 0.0 && o.degree < 3)
    throw InvalidInputError("smoothing: penalises the jerk, which a B-spline of degree " + std::to_string(o.degree) +
                            " does not have between its knots; use degree 3 or more");
  if (o.loss == FitLoss::kHuber && !(std::isfinite(o.loss_scale) && o.loss_scale > 0.0))
    throw InvalidInputError("loss_scale: loss 'huber' needs a positive loss_scale (m of chord distance)");
  if (!(std::isfinite(o.rotation_scale) && o.rotation_scale > 0.0))
    throw InvalidInputError("rotation_scale: must be positive");
}

FitProblem makeProblem(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                       const FitOptions& options)
{
  validateOptions(poses, times, options);
  FitProblem pb;
  pb.poses = &poses;
  pb.times = &times;
  pb.options = options;
  const std::size_t intervals =
      fitIntervals(times.front(), times.back(), options.control_period, options.degree, poses.size());
  pb.n = intervals + static_cast<std::size_t>(options.degree);
  pb.knots = clampedUniformKnots(pb.n, options.degree, times.front(), times.back());
  pb.spans.resize(times.size());
  for (std::size_t i = 0; i < times.size(); ++i)
    pb.spans[i] = knotSpan(pb.knots, pb.n, options.degree, times[i], Side::kRight);
  if (options.smoothing == 0.0)
    checkSchoenbergWhitney(times, pb.knots, pb.n, options.degree);
  pb.quadrature = jerkQuadrature(pb.knots, pb.n, options.degree);
  pb.weights.assign(times.size(), 1.0);
  pb.inverse_count = 1.0 / static_cast<double>(times.size());
  return pb;
}

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

void finish(const std::vector<double>& linear2, const std::vector<double>& angular2, double objective,
            int iterations, BSplineFitResult* out)
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

}  // namespace

std::size_t fitIntervals(double t0, double t1, double control_period, int degree, std::size_t max_control)
{
  if (!(std::isfinite(control_period) && control_period > 0.0))
    throw InvalidInputError("control_period: must be a positive number of seconds (0 takes the default " +
                            formatSeconds(kDefaultControlPeriod) + " s)");
  const double ratio = (t1 - t0) / control_period;
  const double intervals = std::max(1.0, std::ceil(ratio - 1e-9));
  if (!(intervals + degree <= static_cast<double>(max_control)))
    throw InvalidInputError("control_period: " + formatSeconds(control_period) + " s over the waypoints' " +
                            formatSeconds(t1 - t0) + " s makes " + formatSeconds(intervals + degree) +
                            " control poses of degree " + std::to_string(degree) + " for " +
                            std::to_string(max_control) + " waypoints (at most one per waypoint): a longer "
                            "control_period or more waypoints");
  return static_cast<std::size_t>(intervals);
}

namespace
{
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
    solveGroup(&pb, &rotation, [&]() { return linear2; }, &rotation_objective);
    if (pb.options.loss == FitLoss::kSquared)
      break;
    // Each pass is a majorisation step of Huber's objective: one that no longer lowers it has
    // converged.
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
  solveGroup(&pb, &fit, [&]() { return none; }, &objective);
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

template <>
BSplineFitResult fitBSpline<DoubleGeodesicSe3>(const std::vector<Pose<double>>& poses,
                                               const std::vector<double>& times, const FitOptions& options)
{
  try
  {
    return fitDoubleGeodesic(poses, times, options);
  }
  catch (const NonUniqueGeodesicError&)
  {
    refuseHalfTurn(options);
  }
}

template <>
BSplineFitResult fitBSpline<ScrewSe3>(const std::vector<Pose<double>>& poses, const std::vector<double>& times,
                                      const FitOptions& options)
{
  try
  {
    return fitScrew(poses, times, options);
  }
  catch (const NonUniqueGeodesicError&)
  {
    refuseHalfTurn(options);
  }
}

}  // namespace se3_interpolation
