// Piecewise cubics in the tangent space of their first waypoint: the segments of `interpolating`
// (interpolating_spline.h), in the manner of Park & Ravani's C² rotation splines (a cubic in the
// rotation vector per segment) written once over the geometry G (geometry.h).
//
// Form. On [t_i, t_{i+1}], h = t_{i+1} − t_i, u = (t − t_i)/h,
//   c(t) = G::exp(x_i, P_i(t − t_i)),                                                      (C1)
//   P_i(s) = H10(u) h v_i + H01(u) L_i + H11(u) h w_i,     L_i = G::log(x_i, x_{i+1}),
// with the cubic Hermite basis H10 = u(1 − u)², H01 = u²(3 − 2u), H11 = u²(u − 1): the cubic in
// T_{x_i} with P(0) = 0, P'(0) = v_i, P(h) = L_i, P'(h) = w_i. Only L_i is a logarithm; the rates
// v_i, w_i are arbitrary tangents (G::exp is defined on the whole tangent space), so a segment may
// turn any number of times: there is no half-turn limit on the rates, only the waypoints' own
// steps must have a unique geodesic (a rotation below π). At u = 1 the basis is exactly
// (0, 1, 0), so c(t_{i+1}⁻) = G::exp(x_i, L_i) = x_{i+1} up to rounding, whatever the rates.
//
// Kinematics at the ends, in the chart of tangent_space.h (T1)/(T2):
//   at t_i:      log(x_i, c(t_i + s)) = P_i(s), so velocity v_i and acceleration
//                P_i''(0) = (6 L_i − 4 h v_i − 2 h w_i)/h²;                                 (C2)
//   at t_{i+1}:  log(x_{i+1}, c(t_{i+1} + s)) = F_i(P_i(h + s) − L_i) with the transition map
//                F_i(δ) = G::log(x_{i+1}, G::exp(x_i, L_i + δ)), F_i(0) = 0, so
//                velocity      D_i w_i,                                                    (C3)
//                acceleration  D_i P_i''(h) + Q_i(w_i),  P_i''(h) = (−6 L_i + 2 h v_i + 4 h w_i)/h²,
//                D_i = dF_i(0) (on the groups the right Jacobian J_r(L_i) of Exp, as in the
//                inverse-right-Jacobian relation ω = J_r(φ) φ̇ between rotation-vector rates
//                and angular velocity) and Q_i(w) = d²F_i(0)[w, w], a quadratic form.
// D_i and Q_i are computed once per segment from jets (jet.h) of F_i: D_i column by column in
// Jet<2> with Q_i's diagonal, the rest by polarisation, Q(a, b) = (Q(a + b) − Q(a) − Q(b))/2, of
// Q(w) = 2 · the second Taylor coefficient of s ↦ F_i(s w). D_i is invertible while |L_i| < π on SO(3)
// (J_r is singular only at 2π) and on S^m (the first conjugate point is at π).
// In R^n (and when all steps and rates share one rotation axis, or for pure translations) F_i is
// the identity up to a translation, D_i = I, Q_i = 0, and (C1) is the classical cubic Hermite
// polynomial; for the double geodesic the translation part is the classical one exactly.
//
// Values and derivatives are analytic: (C1) is written over a scalar S, and jets of t give its
// exact first and second time derivatives.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/geometry/tangent_space.h"

namespace se3_interpolation
{
/// The transition map F(δ) = G::log(x1, G::exp(x0, L + δ)) of (C3), in any scalar.
template <class G, class S>
typename G::template Tangent<S> transitionMap(const typename G::template Point<double>& x0,
                                              const typename G::template Point<double>& x1,
                                              const typename G::template Tangent<double>& log,
                                              const typename G::template Tangent<S>& delta)
{
  using Tangent = typename G::template Tangent<S>;
  return G::log(G::template cast<S>(x1), G::exp(G::template cast<S>(x0), Tangent(log.template cast<S>() + delta)));
}

/// (C3): velocity D w and acceleration D b + Q(w) at x1 of the motion s ↦ G::exp(x0, L + w s + b s²/2).
template <class G>
TangentMotion<G> transitionMotion(const typename G::template Point<double>& x0,
                                  const typename G::template Point<double>& x1,
                                  const typename G::template Tangent<double>& log,
                                  const typename G::template Tangent<double>& w,
                                  const typename G::template Tangent<double>& b)
{
  using J2 = Jet<2>;
  typename G::template Tangent<J2> delta(w.size());
  for (Eigen::Index k = 0; k < w.size(); ++k)
  {
    delta[k] = J2(0.0);
    delta[k].coefficient(1) = w[k];
    delta[k].coefficient(2) = b[k] / 2.0;
  }
  const typename G::template Tangent<J2> y = transitionMap<G, J2>(x0, x1, log, delta);
  TangentMotion<G> m;
  m.velocity = jetCoefficients(y, 1);
  m.acceleration = 2.0 * jetCoefficients(y, 2);
  return m;
}

/// D = dF(0) and the quadratic form Q = d²F(0) of one segment's transition map (C3), in the
/// orthonormal frames B0 of T_{x0} (inputs) and B1 of T_{x1} (outputs) of TangentFrame.
/// Q is stored as dof × dof² columns: Q(ζ) = Σ_jk quadratic.col(j·dof + k) ζ_j ζ_k.
struct TransitionDerivatives
{
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd quadratic;

  /// Q(ζ) in the output frame.
  Eigen::VectorXd quadraticForm(const Eigen::VectorXd& z) const
  {
    const Eigen::Index n = z.size();
    Eigen::VectorXd q = Eigen::VectorXd::Zero(quadratic.rows());
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index k = 0; k < n; ++k)
        q += quadratic.col(j * n + k) * (z[j] * z[k]);
    return q;
  }
  /// dQ(ζ)/dζ = 2 Q(ζ, ·).
  Eigen::MatrixXd quadraticJacobian(const Eigen::VectorXd& z) const
  {
    const Eigen::Index n = z.size();
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(quadratic.rows(), n);
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index k = 0; k < n; ++k)
        d.col(j) += quadratic.col(j * n + k) * (2.0 * z[k]);
    return d;
  }
};

template <class G>
TransitionDerivatives transitionDerivatives(const typename G::template Point<double>& x0,
                                            const typename G::template Point<double>& x1,
                                            const typename G::template Tangent<double>& log, const Eigen::MatrixXd& b0,
                                            const Eigen::MatrixXd& b1)
{
  using J2 = Jet<2>;
  using TangentJ = typename G::template Tangent<J2>;
  const Eigen::Index dof = b0.cols();
  const typename G::template Point<J2> x0j = G::template cast<J2>(x0);
  const typename G::template Point<J2> x1j = G::template cast<J2>(x1);
  // s ↦ F(s w): its velocity D w and acceleration Q(w) (C3), in the output frame.
  auto motion = [&](const Eigen::VectorXd& w, Eigen::VectorXd* velocity, Eigen::VectorXd* acceleration) {
    TangentJ delta(w.size());
    for (Eigen::Index k = 0; k < w.size(); ++k)
    {
      delta[k] = J2(log[k]);
      delta[k].coefficient(1) = w[k];
    }
    const TangentJ y = G::log(x1j, G::exp(x0j, delta));
    *velocity = b1.transpose() * Eigen::VectorXd(jetCoefficients(y, 1));
    *acceleration = b1.transpose() * Eigen::VectorXd(2.0 * jetCoefficients(y, 2));
  };
  TransitionDerivatives d;
  d.jacobian.resize(b1.cols(), dof);
  d.quadratic.resize(b1.cols(), dof * dof);
  Eigen::VectorXd velocity, acceleration;
  for (Eigen::Index j = 0; j < dof; ++j)
  {
    motion(b0.col(j), &velocity, &acceleration);
    d.jacobian.col(j) = velocity;
    d.quadratic.col(j * dof + j) = acceleration;
  }
  // Polarisation: Q(a, b) = (Q(a + b) − Q(a) − Q(b))/2.
  for (Eigen::Index j = 0; j < dof; ++j)
    for (Eigen::Index k = j + 1; k < dof; ++k)
    {
      motion(b0.col(j) + b0.col(k), &velocity, &acceleration);
      const Eigen::VectorXd mixed = (acceleration - d.quadratic.col(j * dof + j) - d.quadratic.col(k * dof + k)) / 2.0;
      d.quadratic.col(j * dof + k) = mixed;
      d.quadratic.col(k * dof + j) = mixed;
    }
  return d;
}

/// (C1): the piecewise chart cubic through x_i at t_i with rates v_i = P_i'(0) and w_i = P_i'(h)
/// (both in T_{x_i}, G's representation). C¹ and C² are properties of the rates (the solves of
/// interpolating_spline.h choose them so); this class only evaluates.
template <class G>
class ChartCubicSpline final : public CurveBase<G, ChartCubicSpline<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;
  using Tangent = typename G::template Tangent<double>;

  /// `logs[i]` = G::log(points[i], points[i + 1]); one start and one end rate per segment.
  ChartCubicSpline(std::vector<Point> points, std::vector<double> times, std::vector<Tangent> logs,
                   std::vector<Tangent> start_rates, std::vector<Tangent> end_rates)
    : points_(std::move(points))
    , times_(std::move(times))
    , logs_(std::move(logs))
    , start_rates_(std::move(start_rates))
    , end_rates_(std::move(end_rates))
  {
    if (points_.size() < 2 || times_.size() != points_.size() || logs_.size() + 1 != points_.size() ||
        start_rates_.size() != logs_.size() || end_rates_.size() != logs_.size())
      throw InvalidInputError("ChartCubicSpline: one time per point and one log, start and end rate per segment");
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const std::size_t i = findInterval(times_, valueOf(t), side);
    const double h = times_[i + 1] - times_[i];
    // A division, not a product with 1/h: u is exactly 1 at t_{i+1}.
    const S u = (t - S(times_[i])) / S(h);
    const S one_minus = S(1.0) - u;
    const S h10 = u * one_minus * one_minus;
    const S h01 = u * u * (S(3.0) - S(2.0) * u);
    const S h11 = u * u * (u - S(1.0));
    using TangentS = typename G::template Tangent<S>;
    const TangentS p(Tangent(start_rates_[i] * h) * h10 + logs_[i] * h01 + Tangent(end_rates_[i] * h) * h11);
    return G::exp(G::template cast<S>(points_[i]), p);
  }

  /// The kinematics at t in closed form, where the geometry gives them for its exp (G::expKinematics):
  /// the cubic's tangent and its two time derivatives (the Hermite basis differentiated, d/dt =
  /// (1/h) d/du) mapped through them. Equal to kinematicsFromJet(jet(t)) to rounding (tested).
  Kinematics kinematics(double t, Side side) const
  {
    const TangentJet j = tangentJet(t, side);
    return G::expKinematics(points_[j.segment], j.v, j.dv, j.ddv);
  }

  /// The velocity and acceleration at t without the pose (G::expRates, in the frames it names):
  /// kinematics()'s rates up to a rotation of each part.
  MotionRates rates(double t, Side side) const
  {
    const TangentJet j = tangentJet(t, side);
    return G::expRates(j.v, j.dv, j.ddv);
  }

  /// rates() with the jerk (G::expRates3): the cubic's third time derivative is constant on its
  /// segment, 6 (v_i + w_i)/h² − 12 L_i/h³ (the Hermite basis's third u-derivatives 6, −12, 6).
  MotionRates3 rates3(double t, Side side) const
  {
    const TangentJet j = tangentJet(t, side);
    const double inv_h = 1.0 / (times_[j.segment + 1] - times_[j.segment]);
    const Tangent dddv = (start_rates_[j.segment] + end_rates_[j.segment]) * (6.0 * inv_h * inv_h) -
                         logs_[j.segment] * (12.0 * inv_h * inv_h * inv_h);
    return G::expRates3(j.v, j.dv, j.ddv, dddv);
  }

  double startTime() const override { return times_.front(); }
  double endTime() const override { return times_.back(); }
  std::vector<double> breakpoints() const override { return times_; }
  /// For display, x_0, b_1, b_2, x_1, b_1', … (3N − 2 points): b_1 = exp(x_i, h v_i/3),
  /// b_2 = exp(x_i, L_i − h w_i/3), the images of the cubic's Bézier control points in T_{x_i}
  /// (the classical Bézier polygon of the segment in R^n).
  std::vector<Point> controlPoints() const override
  {
    std::vector<Point> c{ points_.front() };
    for (std::size_t i = 0; i + 1 < points_.size(); ++i)
    {
      const double h = times_[i + 1] - times_[i];
      c.push_back(G::exp(points_[i], Tangent(start_rates_[i] * (h / 3.0))));
      c.push_back(G::exp(points_[i], Tangent(logs_[i] - end_rates_[i] * (h / 3.0))));
      c.push_back(points_[i + 1]);
    }
    return c;
  }
  /// v_i = P_i'(0), the velocity (T1) at x_i, and w_i = P_i'(h) (in T_{x_i}), per segment.
  const std::vector<Tangent>& startRates() const { return start_rates_; }
  const std::vector<Tangent>& endRates() const { return end_rates_; }
  const std::vector<Tangent>& logs() const { return logs_; }

private:
  /// The cubic of a segment in the tangent space at its start: its value and two time derivatives.
  struct TangentJet
  {
    std::size_t segment;
    Tangent v, dv, ddv;
  };

  TangentJet tangentJet(double t, Side side) const
  {
    const std::size_t i = findInterval(times_, t, side);
    const double h = times_[i + 1] - times_[i];
    const double inv_h = 1.0 / h;
    const double u = (t - times_[i]) / h;  // (exactly 1 at the segment's end)
    const Tangent& v0 = start_rates_[i];
    const Tangent& v1 = end_rates_[i];
    const Tangent& l = logs_[i];
    const double one_minus = 1.0 - u;
    // The Hermite basis in u with the rates scaled by h, its u-derivatives divided by h and h²: the
    // powers of h folded into the scalar weights.
    return { i, v0 * (h * u * one_minus * one_minus) + l * (u * u * (3.0 - 2.0 * u)) + v1 * (h * u * u * (u - 1.0)),
             v0 * (1.0 - 4.0 * u + 3.0 * u * u) + l * (6.0 * u * one_minus * inv_h) + v1 * (u * (3.0 * u - 2.0)),
             v0 * ((6.0 * u - 4.0) * inv_h) + l * ((6.0 - 12.0 * u) * inv_h * inv_h) + v1 * ((6.0 * u - 2.0) * inv_h) };
  }

  std::vector<Point> points_;
  std::vector<double> times_;
  std::vector<Tangent> logs_;
  std::vector<Tangent> start_rates_;
  std::vector<Tangent> end_rates_;
};

}  // namespace se3_interpolation
