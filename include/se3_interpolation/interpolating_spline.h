// `interpolating`: C² cubic splines through every waypoint at its time (SPEC, Curves), in any
// geometry G of geometry.h (ScrewSe3, DoubleGeodesicSe3, So3, Euclidean, Sphere).
//
// Form. On each segment [t_i, t_{i+1}], h_i = t_{i+1} − t_i, the curve is the generalised cubic
// (H1) of hermite.h — Crouch–Kun–Silva Leite (seed 001) Case 1 — through x_i and x_{i+1} with
// velocities v_i, v_{i+1} (T1, tangent_space.h). It passes every waypoint at its time exactly
// and is C¹ by construction; the velocities are chosen so that it is C²:
//
//   interior, i = 1 … N − 2:   A⁻_i = A⁺_i,                                                (S1)
//     A⁻_i the acceleration (T2) at t_i of segment i − 1 (a function of v_{i−1}, v_i) and
//     A⁺_i that of segment i (of v_i, v_{i+1}). Equal (T1) and (T2) on both sides mean the
//     two pieces agree to second order in the chart at x_i: C².
//   natural:  A⁺_0 = 0 and A⁻_{N−1} = 0                                                     (S2)
//     — the geodesic analogue of a zero second derivative: the acceleration (T2) is the one
//     that vanishes along the geodesics of G: d/dt of the body twist (Rᵀω̇, Rᵀ(p̈ − ω × ṗ)) for
//     the screw metric, (Rᵀω̇, p̈) for the double geodesic, p̈ in R^n, the covariant
//     acceleration on S^m.
//   clamped:  v_0 and v_{N−1} given.                                                        (S3)
//
// In R^n (and for rotations about one fixed axis, or pure translations) each segment is the
// cubic Hermite polynomial and (S1)–(S3) are the classical spline equations, so the curve is
// the classical natural / clamped cubic spline — the same curve as the cubic B-spline with
// knots at the waypoint times that the SPEC names. On a curved group that B-spline form would
// not do: the generalised de Boor algorithm (thesis Alg. 4.3.3) joins its pieces with equal
// velocities but not equal accelerations (for 0.5–1 rad between control points the one-sided
// accelerations at a knot differ by 1e-4…5e-3 relative; test GeodesicBSplineIsOnlyC1), so the
// C² requirement is met in the piecewise form, as Crouch et al. build splines from Case 1/2
// pieces.
//
// Solve (natural / clamped). Newton's method on the velocities, v_i = B_i z_i in the orthonormal
// frame B_i of T_{x_i} (TangentFrame; the identity except on S^m). Row i of the residual is
// (S1) scaled by h_{i−1} h_i, or (S2) by h², or (S3) by h — all lengths — in the frame at x_i;
// row i involves v_{i−1}, v_i, v_{i+1} only, so the Jacobian is block tridiagonal. Its blocks
// are forward differences (each moved velocity re-evaluates the end accelerations of its two
// segments — on the groups by Crouch Thm 2.9, groupStartAcceleration, elsewhere by the de Casteljau
// algorithm in Jet<2> arithmetic; ~1e-8 relative error, so a Newton step still gains about eight
// digits), factorised by a banded LU with partial pivoting (banded_lu.h) and kept while it
// contracts the residual tenfold per step (chord method), else rebuilt: O(N) work and memory
// per iteration. Steps are damped by backtracking until the residual decreases. The initial
// guess is the classical spline (its slope equations, one tridiagonal solve) through the
// "development" y_0 = 0, y_{i+1} = y_i + log(x_i, x_{i+1}) of the waypoints, its slopes taken as v_i: exact in
// R^n and for rotations about one fixed axis. The solve stops when every row is below
// tolerance · scale (scale = the largest of 1 + |coordinates| and the segment lengths); then the
// curve is built, and a velocity too large for its segment (a control point half a turn away,
// hermite.h) is rejected. Failure (iteration limit, no decrease, a non-finite value, a singular
// system, a wrapped control point) throws ConvergenceError: no curve is returned that is not C².
//
// start (Algorithm 7.4.1 of seed 000, Crouch Case 2): given v_0 and the acceleration a_0 at x_0,
// solved forward segment by segment: on [t_i, t_{i+1}] the generalised cubic (H1) from x_i with
// velocity v_i, where v_{i+1} is found by Newton's method (dense, dof × dof) so that the
// acceleration at t_i equals a_i (Crouch Thm 2.9: it depends on b_0, b_1, b_2 only; evaluated as
// for the natural / clamped solve); the velocity v_{i+1} and the acceleration at
// t_{i+1} carry to the next segment, so the curve is C² by construction. Like its Euclidean
// counterpart the forward recursion amplifies its data by up to 2 + √3 per segment; when a
// carried velocity grows too large for a segment it throws ConvergenceError, not wrap around.
#pragma once

#include <Eigen/LU>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "se3_interpolation/banded_lu.h"
#include "se3_interpolation/hermite.h"
#include "se3_interpolation/planner.h"
#include "se3_interpolation/tangent_space.h"

namespace se3_interpolation
{
/// Limits of the iterative solves.
struct SplineSolverOptions
{
  /// Newton iterations (natural / clamped: of the whole system; start: per segment).
  int max_iterations = 50;
  /// Bound on the C² defect h² |A⁻_i − A⁺_i| (and the end conditions' residuals) relative to
  /// the data's scale (the largest of 1 + |coordinates| and the segment lengths).
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

/// The scale of the data for absolute tolerances.
template <class G>
double dataScale(const std::vector<typename G::template Point<double>>& points,
                 const std::vector<typename G::template Tangent<double>>& logs)
{
  double scale = 1.0;
  for (const auto& x : points)
    scale = std::max(scale, pointMagnitude(x));
  for (const auto& l : logs)
    scale = std::max(scale, l.norm());
  return scale;
}

/// Geometries whose geodesics are one-parameter subgroups, x Exp(λ W) with W the body tangent
/// G::log(x, y) = Log(x⁻¹ y): SE(3) (screw), SO(3) × R³ (double geodesic), SO(3), R^n.
template <class G>
struct HasGroupGeodesics : std::false_type
{
};
template <>
struct HasGroupGeodesics<ScrewSe3> : std::true_type
{
};
template <>
struct HasGroupGeodesics<DoubleGeodesicSe3> : std::true_type
{
};
template <>
struct HasGroupGeodesics<So3> : std::true_type
{
};
template <>
struct HasGroupGeodesics<Euclidean> : std::true_type
{
};

/// The accelerations (T2) at both ends of the generalised cubic with control points b on
/// [0, h], by differentiating the de Casteljau algorithm in Jet<2> arithmetic (any geometry).
template <class G>
std::pair<typename G::template Tangent<double>, typename G::template Tangent<double>>
cubicEndAccelerationsByJets(const std::vector<typename G::template Point<double>>& b, double h)
{
  using Tangent = typename G::template Tangent<double>;
  const std::vector<Tangent> logs{ G::log(b[0], b[1]), G::log(b[1], b[2]), G::log(b[2], b[3]) };
  const Jet<2> rate(1.0 / h);
  return { tangentMotion<G>(deCasteljau<G>(b, logs, Jet<2>::variable(0.0) * rate)).acceleration,
           tangentMotion<G>(deCasteljau<G>(b, logs, Jet<2>::variable(h) * rate)).acceleration };
}

/// On a group (HasGroupGeodesics), the acceleration (T2) at b_0 of the cubic b_0 … b_3 on [0, h]:
///   (6/h²) J_r(W_0)⁻¹ (W_1 − W_0),   W_k = log(b_k, b_{k+1}),   J_r(W)⁻¹ u = d/dε Log(Exp(W) Exp(ε u)),
/// which is Crouch Thm 2.9 (n = 3: n(n − 1) Υ_0 (V_1^1 − V_0^1)) read through the inversion g ↦ g⁻¹:
/// it maps b_k Exp(λ W_k) to Exp(−λ W_k) b_k⁻¹ (their right-invariant form, V_k = −W_k, with
/// Υ_0 = (∫_0^1 exp(−u ad W_0) du)⁻¹ = J_r(W_0)⁻¹) and the body twist ξ to Ω = −ξ, whose rate is
/// (T2) (tangent_space.h). Only b_0, b_1, b_2 enter.
template <class G>
typename G::template Tangent<double> groupStartAcceleration(const typename G::template Point<double>& b0,
                                                            const typename G::template Point<double>& b1,
                                                            const typename G::template Point<double>& b2, double h)
{
  using J1 = Jet<1>;
  const typename G::template Tangent<double> u = G::log(b1, b2) - G::log(b0, b1);
  const typename G::template Tangent<J1> e(u.template cast<J1>() * J1::variable(0.0));
  const typename G::template Point<J1> moved = G::exp(G::template cast<J1>(b1), e);
  return jetCoefficients(G::log(G::template cast<J1>(b0), moved), 1) * (6.0 / (h * h));
}

/// The accelerations (T2) at both ends of the generalised cubic (H1) from x0 with velocity v0
/// to x1 with velocity v1 in time h (the end one as the start one of the reversed polygon).
/// Throws NonUniqueGeodesicError for antipodal control points.
template <class G>
std::pair<typename G::template Tangent<double>, typename G::template Tangent<double>>
cubicEndAccelerations(const typename G::template Point<double>& x0, const typename G::template Point<double>& x1,
                      const typename G::template Tangent<double>& v0, const typename G::template Tangent<double>& v1,
                      double h)
{
  using Tangent = typename G::template Tangent<double>;
  const std::vector<typename G::template Point<double>> b{ x0, G::exp(x0, Tangent(v0 * (h / 3.0))),
                                                          G::exp(x1, Tangent(v1 * (-h / 3.0))), x1 };
  if constexpr (HasGroupGeodesics<G>::value)
    return { groupStartAcceleration<G>(b[0], b[1], b[2], h), groupStartAcceleration<G>(b[3], b[2], b[1], h) };
  else
    return cubicEndAccelerationsByJets<G>(b, h);
}

/// Newton's method for the velocities of the natural / clamped spline (file comment).
template <class G>
class C2SplineSolver
{
public:
  using Point = typename G::template Point<double>;
  using Tangent = typename G::template Tangent<double>;

  /// `points`, `times` validated by the caller; end velocities used only when clamped.
  C2SplineSolver(const std::vector<Point>& points, const std::vector<double>& times, EndCondition condition,
                 const Tangent& start_velocity, const Tangent& end_velocity, const SplineSolverOptions& options)
    : x_(points)
    , t_(times)
    , n_(points.size())
    , condition_(condition)
    , start_velocity_(start_velocity)
    , end_velocity_(end_velocity)
    , options_(options)
  {
    const std::vector<Tangent> logs = polygonLogs<G>(x_, "waypoints");
    tolerance_ = options_.tolerance * dataScale<G>(x_, logs);
    for (const auto& x : x_)
      frames_.push_back(TangentFrame<G>::basis(x));
    dof_ = frames_[0].cols();
  }

  /// The velocities v_0 … v_{N−1}, from a guess. Throws ConvergenceError.
  std::vector<Tangent> solve(std::vector<Tangent> v) const
  {
    std::vector<Accelerations> a;
    Eigen::VectorXd r;
    if (!tryResidual(v, &a, &r))
      throw ConvergenceError(prefix() + "the initial guess is not finite or not defined (are the waypoints finite?)");
    const Eigen::Index size = static_cast<Eigen::Index>(n_) * dof_;
    // Chord method: the factorised Jacobian is kept while it still contracts the residual
    // tenfold per step (a reuse costs one residual instead of the 2·dof of a Jacobian), else rebuilt.
    std::optional<BandedLu> jacobian;
    bool refresh = true;
    int polish = 0;
    for (int iteration = 0;; ++iteration)
    {
      const std::pair<double, std::size_t> worst = worstRow(r);
      // Below tolerance, up to three more full chord steps polish towards rounding level while
      // they reduce the residual.
      const bool converged = worst.first <= tolerance_;
      if (converged && (polish == 3 || refresh || worst.first <= 1e-3 * tolerance_ ||
                        iteration >= options_.max_iterations))
        return v;
      if (converged)
        ++polish;
      if (iteration >= options_.max_iterations)
        throw ConvergenceError(prefix() + "the velocities did not converge in " +
                               std::to_string(options_.max_iterations) + " Newton iterations" + where(worst));
      const bool fresh = refresh || !jacobian;
      if (fresh)
      {
        jacobian.emplace(size, 2 * dof_ - 1, 2 * dof_ - 1);
        fillJacobian(v, a, r, &*jacobian);
        try
        {
          jacobian->factorize();
        }
        catch (const ConvergenceError& e)
        {
          throw ConvergenceError(prefix() + e.what() + where(worst));
        }
      }
      const Eigen::VectorXd dz = jacobian->solve(-r);
      if (!dz.allFinite())
        throw ConvergenceError(prefix() + "the Newton step is not finite" + where(worst));
      const double norm = r.norm();
      bool accepted = false;
      bool full_step = true;
      for (double step = 1.0; step > (converged ? 0.5 : 1e-9) && !accepted; step *= 0.5)
      {
        full_step = step == 1.0;
        std::vector<Tangent> trial = v;
        for (std::size_t j = 0; j < n_; ++j)
          trial[j] += Tangent(frames_[j] * (step * dz.segment(static_cast<Eigen::Index>(j) * dof_, dof_)));
        std::vector<Accelerations> at;
        Eigen::VectorXd rt;
        if (!tryResidual(trial, &at, &rt))
          continue;
        if (rt.norm() < (1.0 - 1e-4 * step) * norm || (!converged && worstRow(rt).first <= tolerance_))
        {
          v = std::move(trial);
          a = std::move(at);
          r = std::move(rt);
          accepted = true;
        }
      }
      if (!accepted && converged)
        return v;
      if (!accepted && fresh)
        throw ConvergenceError(prefix() + "the Newton iteration stalled after " + std::to_string(iteration) +
                               " iterations" + where(worst));
      refresh = !accepted || !full_step || r.norm() > 0.1 * norm;
    }
  }

private:
  /// A⁺ (start) and A⁻ (end) of one segment.
  using Accelerations = std::pair<Tangent, Tangent>;

  std::string prefix() const
  {
    return std::string("curve 'interpolating' (end_condition '") + endConditionName(condition_) + "'): ";
  }

  std::string where(const std::pair<double, std::size_t>& worst) const
  {
    std::string row;
    if (worst.second == 0)
      row = condition_ == EndCondition::kNatural ? "the zero start acceleration" : "start_velocity";
    else if (worst.second + 1 == n_)
      row = condition_ == EndCondition::kNatural ? "the zero end acceleration" : "end_velocity";
    else
      row = "the acceleration at " + indexedField("waypoints", worst.second);
    return " (largest residual " + scientific(worst.first) + " at " + row + ", tolerance " + scientific(tolerance_) +
           "); the waypoints are probably too far apart in rotation for a C^2 spline through them: add waypoints, "
           "or use curve 'hermite'";
  }

  double h(std::size_t i) const { return t_[i + 1] - t_[i]; }

  Accelerations segment(std::size_t i, const Tangent& vi, const Tangent& vi1) const
  {
    return cubicEndAccelerations<G>(x_[i], x_[i + 1], vi, vi1, h(i));
  }

  /// B_iᵀ r: a residual at x_i in the coordinates of T_{x_i}.
  Eigen::VectorXd project(std::size_t i, const Tangent& r) const
  {
    if (TangentFrame<G>::kIdentity)
      return Eigen::VectorXd(r);
    return frames_[i].transpose() * Eigen::VectorXd(r);
  }

  /// Row i from the velocities v(j) and the segments' accelerations a(j).
  template <class V, class A>
  Eigen::VectorXd row(std::size_t i, const V& v, const A& a) const
  {
    const bool natural = condition_ == EndCondition::kNatural;
    if (i == 0)
      return natural ? project(0, Tangent(a(0).first * (h(0) * h(0)))) :
                       project(0, Tangent((v(0) - start_velocity_) * h(0)));
    if (i + 1 == n_)
    {
      const double hl = h(n_ - 2);
      return natural ? project(i, Tangent(a(n_ - 2).second * (hl * hl))) :
                       project(i, Tangent((v(n_ - 1) - end_velocity_) * hl));
    }
    return project(i, Tangent((a(i - 1).second - a(i).first) * (h(i - 1) * h(i))));
  }

  bool tryResidual(const std::vector<Tangent>& v, std::vector<Accelerations>* a, Eigen::VectorXd* r) const
  {
    try
    {
      a->clear();
      for (std::size_t i = 0; i + 1 < n_; ++i)
        a->push_back(segment(i, v[i], v[i + 1]));
    }
    catch (const NonUniqueGeodesicError&)
    {
      return false;
    }
    r->resize(static_cast<Eigen::Index>(n_) * dof_);
    auto fetch_v = [&v](std::size_t j) -> const Tangent& { return v[j]; };
    auto fetch_a = [a](std::size_t j) -> const Accelerations& { return (*a)[j]; };
    for (std::size_t i = 0; i < n_; ++i)
      r->segment(static_cast<Eigen::Index>(i) * dof_, dof_) = row(i, fetch_v, fetch_a);
    return r->allFinite();
  }

  /// The largest row norm and its row.
  std::pair<double, std::size_t> worstRow(const Eigen::VectorXd& r) const
  {
    std::pair<double, std::size_t> worst{ 0.0, 0 };
    for (std::size_t i = 0; i < n_; ++i)
    {
      const double e = r.segment(static_cast<Eigen::Index>(i) * dof_, dof_).norm();
      if (e > worst.first)
        worst = { e, i };
    }
    return worst;
  }

  /// Forward differences: moving v_j changes segments j − 1 and j, hence rows j − 1 … j + 1.
  /// The step, √ε in the control points b = exp(x, ±h v/3), is √ε · 3/h̄ in the velocity.
  void fillJacobian(const std::vector<Tangent>& v, const std::vector<Accelerations>& a, const Eigen::VectorXd& r,
                    BandedLu* jacobian) const
  {
    constexpr double kStep = 1.5e-8;
    for (std::size_t j = 0; j < n_; ++j)
    {
      const double hj = j == 0 ? h(0) : (j + 1 == n_ ? h(n_ - 2) : 0.5 * (h(j - 1) + h(j)));
      const double step = 3.0 * kStep / hj;
      const std::size_t first_row = j == 0 ? 0 : j - 1;
      const std::size_t last_row = std::min(j + 1, n_ - 1);
      for (Eigen::Index k = 0; k < dof_; ++k)
      {
        const Tangent moved = v[j] + Tangent(frames_[j].col(k) * step);
        Accelerations before, after;
        try
        {
          if (j > 0)
            before = segment(j - 1, v[j - 1], moved);
          if (j + 1 < n_)
            after = segment(j, moved, v[j + 1]);
        }
        catch (const NonUniqueGeodesicError&)
        {
          throw ConvergenceError(prefix() + "a control point became antipodal to its neighbour while "
                                            "differentiating at " + indexedField("waypoints", j));
        }
        auto fetch_v = [&](std::size_t m) -> const Tangent& { return m == j ? moved : v[m]; };
        auto fetch_a = [&](std::size_t m) -> const Accelerations& {
          return m + 1 == j ? before : (m == j ? after : a[m]);
        };
        const Eigen::Index c = static_cast<Eigen::Index>(j) * dof_ + k;
        for (std::size_t i = first_row; i <= last_row; ++i)
        {
          const Eigen::VectorXd column =
              (row(i, fetch_v, fetch_a) - r.segment(static_cast<Eigen::Index>(i) * dof_, dof_)) / step;
          for (Eigen::Index rr = 0; rr < dof_; ++rr)
            (*jacobian)(static_cast<Eigen::Index>(i) * dof_ + rr, c) = column[rr];
        }
      }
    }
  }

  std::vector<Point> x_;
  std::vector<double> t_;
  std::size_t n_;
  EndCondition condition_;
  Tangent start_velocity_;
  Tangent end_velocity_;
  SplineSolverOptions options_;
  double tolerance_ = 0.0;
  Eigen::Index dof_ = 0;
  std::vector<Eigen::MatrixXd> frames_;
};

/// The slopes v_i of the classical C² cubic spline through y_i at t_i (Thomas algorithm on the
/// diagonally dominant slope equations, Δ_i = y_{i+1} − y_i):
///   v_{i−1}/h_{i−1} + 2 (1/h_{i−1} + 1/h_i) v_i + v_{i+1}/h_i = 3 (Δ_{i−1}/h_{i−1}² + Δ_i/h_i²),
///   natural: 2 v_0 + v_1 = 3 Δ_0/h_0,  v_{N−2} + 2 v_{N−1} = 3 Δ_{N−2}/h_{N−2};  clamped: v_0, v_{N−1} given.
inline std::vector<Eigen::VectorXd> classicalSlopes(const std::vector<Eigen::VectorXd>& y, const std::vector<double>& t,
                                                    EndCondition condition, const Eigen::VectorXd& start_velocity,
                                                    const Eigen::VectorXd& end_velocity)
{
  const std::size_t n = y.size();
  const bool natural = condition == EndCondition::kNatural;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 0.0);
  std::vector<Eigen::VectorXd> r(n);
  auto h = [&t](std::size_t i) { return t[i + 1] - t[i]; };
  b[0] = natural ? 2.0 : 1.0;
  c[0] = natural ? 1.0 : 0.0;
  r[0] = natural ? Eigen::VectorXd((y[1] - y[0]) * (3.0 / h(0))) : start_velocity;
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    a[i] = 1.0 / h(i - 1);
    c[i] = 1.0 / h(i);
    b[i] = 2.0 * (a[i] + c[i]);
    r[i] = (y[i] - y[i - 1]) * (3.0 * a[i] * a[i]) + (y[i + 1] - y[i]) * (3.0 * c[i] * c[i]);
  }
  a[n - 1] = natural ? 1.0 : 0.0;
  b[n - 1] = natural ? 2.0 : 1.0;
  r[n - 1] = natural ? Eigen::VectorXd((y[n - 1] - y[n - 2]) * (3.0 / h(n - 2))) : end_velocity;
  for (std::size_t i = 1; i < n; ++i)
  {
    const double w = a[i] / b[i - 1];
    b[i] -= w * c[i - 1];
    r[i] -= w * r[i - 1];
  }
  r[n - 1] /= b[n - 1];
  for (std::size_t i = n - 1; i-- > 0;)
    r[i] = (r[i] - c[i] * r[i + 1]) / b[i];
  return r;
}

/// The initial velocities: the classical spline's slopes through the development (file comment).
template <class G>
std::vector<typename G::template Tangent<double>> chartGuess(const std::vector<typename G::template Point<double>>& x,
                                                            const std::vector<double>& times, EndCondition condition,
                                                            const typename G::template Tangent<double>& start_velocity,
                                                            const typename G::template Tangent<double>& end_velocity)
{
  using Tangent = typename G::template Tangent<double>;
  const std::size_t n = x.size();
  std::vector<Eigen::VectorXd> y(n);
  y[0] = Eigen::VectorXd::Zero(tangentDimension<G>(x[0]));
  for (std::size_t i = 0; i + 1 < n; ++i)
    y[i + 1] = y[i] + Eigen::VectorXd(G::log(x[i], x[i + 1]));
  const std::vector<Eigen::VectorXd> slopes =
      classicalSlopes(y, times, condition, Eigen::VectorXd(start_velocity), Eigen::VectorXd(end_velocity));
  std::vector<Tangent> v;
  v.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    Eigen::VectorXd s = slopes[i];
    if (!TangentFrame<G>::kIdentity)
    {
      const Eigen::MatrixXd b = TangentFrame<G>::basis(x[i]);
      s = b * (b.transpose() * s);
    }
    v.push_back(Tangent(s));
  }
  return v;
}

/// The Hermite spline through `points` with velocities `v`; a velocity too large for its
/// segment (produced by a diverging solve) is a ConvergenceError, not bad input.
template <class G>
std::shared_ptr<const HermiteSpline<G>> solvedSpline(const std::vector<typename G::template Point<double>>& points,
                                                    const std::vector<double>& times,
                                                    std::vector<typename G::template Tangent<double>> v,
                                                    const std::string& prefix, const std::string& hint)
{
  try
  {
    return std::make_shared<const HermiteSpline<G>>(points, times, std::move(v), "the solved velocity at waypoints");
  }
  catch (const InvalidInputError& e)
  {
    throw ConvergenceError(prefix + e.what() + hint);
  }
}
}  // namespace detail

/// `interpolating` with end_condition natural or clamped (file comment). `start_velocity` and
/// `end_velocity` (G's representation, at the first / last point) are used only when clamped.
template <class G>
std::shared_ptr<const HermiteSpline<G>> solveC2Spline(const std::vector<typename G::template Point<double>>& points,
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
  return detail::solvedSpline<G>(points, times,
                                 solver.solve(detail::chartGuess<G>(points, times, condition, v0, v1)),
                                 std::string("curve 'interpolating' (end_condition '") +
                                     detail::endConditionName(condition) + "'): ",
                                 "; the waypoints are probably too far apart in rotation for a C^2 spline through "
                                 "them: add waypoints, or use curve 'hermite'");
}

/// `interpolating` with end_condition start (Algorithm 7.4.1 / Case 2, file comment): the C²
/// piecewise cubic from the velocity and acceleration (G's representation) at the first point.
template <class G>
std::shared_ptr<const HermiteSpline<G>> solveForwardSpline(
    const std::vector<typename G::template Point<double>>& points, const std::vector<double>& times,
    const typename G::template Tangent<double>& start_velocity,
    const typename G::template Tangent<double>& start_acceleration, const SplineSolverOptions& options = {})
{
  using Tangent = typename G::template Tangent<double>;
  const Eigen::Index dim = detail::requireSplineData<G>(points, times);
  detail::requireTangent<G>(points.front(), start_velocity, dim, "start_velocity");
  detail::requireTangent<G>(points.front(), start_acceleration, dim, "start_acceleration");
  const std::vector<Tangent> logs = polygonLogs<G>(points, "waypoints");
  const double tolerance = options.tolerance * detail::dataScale<G>(points, logs);
  const std::string prefix = "curve 'interpolating' (end_condition 'start'): ";
  const std::string growth =
      "; the forward construction (Algorithm 7.4.1) amplifies the start data along the spline (up to 2 + sqrt3 per "
      "segment): use end_condition 'natural' or 'clamped', fewer waypoints, or start data closer to the motion";
  const std::size_t n = points.size();
  std::vector<Tangent> v(n);
  v[0] = start_velocity;
  Tangent a = start_acceleration;
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    const double h = times[i + 1] - times[i];
    const std::string segment = "segment " + std::to_string(i) + " (" + detail::indexedField("waypoints", i) +
                                " -> " + detail::indexedField("waypoints", i + 1) + ")";
    const Eigen::MatrixXd b_in = TangentFrame<G>::basis(points[i]);
    const Eigen::MatrixXd b_out = TangentFrame<G>::basis(points[i + 1]);
    // Unknown: v_{i+1} = B z, in units of h/3 so that z moves the control point b_2 by ~|z|.
    const double scale = 3.0 / h;
    std::pair<Tangent, Tangent> ends;
    auto residual = [&](const Eigen::VectorXd& z, Eigen::VectorXd* f) {
      try
      {
        ends = detail::cubicEndAccelerations<G>(points[i], points[i + 1], v[i], Tangent(b_out * z * scale), h);
      }
      catch (const NonUniqueGeodesicError&)
      {
        return false;
      }
      *f = b_in.transpose() * Eigen::VectorXd((ends.first - a) * (h * h));
      return f->allFinite();
    };
    // Euclidean start: v_{i+1} = 3 (x_{i+1} − x_i)/h − 2 v_i − h a_i/2 (the classical continuation).
    const Tangent classical = G::log(points[i + 1], points[i]) * (-3.0 / h) - v[i] * 2.0 - a * (h / 2.0);
    Eigen::VectorXd z = b_out.transpose() * Eigen::VectorXd(classical) / scale;
    Eigen::VectorXd f;
    if (!residual(z, &f))
      throw ConvergenceError(prefix + segment + " is not defined" + growth);
    for (int iteration = 0; f.norm() > tolerance; ++iteration)
    {
      if (iteration >= options.max_iterations)
        throw ConvergenceError(prefix + segment + " did not converge (residual " + detail::scientific(f.norm()) + ")" +
                               growth);
      constexpr double kStep = 1e-6;
      Eigen::MatrixXd jac(f.size(), z.size());
      for (Eigen::Index k = 0; k < z.size(); ++k)
      {
        Eigen::VectorXd fp, fm;
        Eigen::VectorXd zp = z, zm = z;
        zp[k] += kStep;
        zm[k] -= kStep;
        if (!residual(zp, &fp) || !residual(zm, &fm))
          throw ConvergenceError(prefix + segment + " is not defined near its solution" + growth);
        jac.col(k) = (fp - fm) / (2.0 * kStep);
      }
      const Eigen::VectorXd dz = jac.fullPivLu().solve(-f);
      bool accepted = false;
      for (double step = 1.0; step > 1e-9 && !accepted; step *= 0.5)
      {
        Eigen::VectorXd ft;
        const Eigen::VectorXd zt = z + step * dz;
        if (residual(zt, &ft) && (ft.norm() < (1.0 - 1e-4 * step) * f.norm() || ft.norm() <= tolerance))
        {
          z = zt;
          f = ft;
          accepted = true;
        }
      }
      if (!accepted)
        throw ConvergenceError(prefix + segment + " stalled (residual " + detail::scientific(f.norm()) + ")" + growth);
    }
    v[i + 1] = Tangent(b_out * z * scale);
    residual(z, &f);  // the accelerations of the accepted segment
    a = ends.second;
  }
  return detail::solvedSpline<G>(points, times, std::move(v), prefix, growth);
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
