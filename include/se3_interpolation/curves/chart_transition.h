// curves/chart_transition.h: what the C² solve (interpolating_solver.h) needs of a geometry, as a
// trait instead of branches on the geometry's type: the derivatives D = dF(0), Q = d²F(0) of the
// transition map F(δ) = log_{x1}(exp_{x0}(L + δ)) between the charts at the ends of a segment (C3
// of c2_spline_system.h's file comment), their inverse, the leading coordinates Q acts in, and the steps a
// geometry refuses. ChartTransition<G> is the generic rule (identity frames and a fixed dimension:
// jets of F at compile-time size; otherwise chart_cubic.h's transitionDerivatives); the
// specialisations below say where a geometry knows more.
#pragma once

#include <Eigen/Dense>

#include <limits>
#include <sstream>
#include <string>

#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/geometry/geometry.h"

namespace se3_interpolation
{
namespace detail
{
/// c q for a constant unit quaternion c and a quaternion of jets q (Hamilton product, double ×
/// jet products only).
inline Quaternion<Jet<2>> constantTimes(const Quaternion<double>& c, const Quaternion<Jet<2>>& q)
{
  return Quaternion<Jet<2>>(c.w() * q.w() - c.x() * q.x() - c.y() * q.y() - c.z() * q.z(),
                            c.w() * q.x() + c.x() * q.w() + c.y() * q.z() - c.z() * q.y(),
                            c.w() * q.y() - c.x() * q.z() + c.y() * q.w() + c.z() * q.x(),
                            c.w() * q.z() + c.x() * q.y() - c.y() * q.x() + c.z() * q.w());
}

/// The transition map F(δ) = H::log(x1, H::exp(x0, δ)) on jets, for a geometry whose frames are
/// the identity.
template <class H>
struct TransitionMap
{
  const typename H::template Point<double>& x0;
  const typename H::template Point<double>& x1;
  typename H::template Tangent<Jet<2>> operator()(const typename H::template Tangent<Jet<2>>& delta) const
  {
    return H::log(H::template cast<Jet<2>>(x1), H::exp(H::template cast<Jet<2>>(x0), delta));
  }
};

/// On SO(3), x1⁻¹ (x0 Exp(δ)) = (x1⁻¹ x0) Exp(δ): one product of a constant with a jet.
template <>
struct TransitionMap<So3>
{
  const Quaternion<double>& x0;
  const Quaternion<double>& x1;
  Eigen::Matrix<Jet<2>, 3, 1> operator()(const Eigen::Matrix<Jet<2>, 3, 1>& delta) const
  {
    return so3Log(constantTimes(Quaternion<double>(x1.conjugate() * x0), so3Exp(delta)));
  }
};

/// D = dF(0) and Q = d²F(0) of the transition map of a geometry H whose frames are the identity,
/// at compile-time size N: Q(e_j, e_j) and D e_j from the jet of s ↦ F(s e_j), the mixed
/// Q(e_j, e_k) by polarisation from s ↦ F(s (e_j + e_k)) (as chart_cubic.h's
/// transitionDerivatives). `quadratic` holds the blocks Q(e_j, ·) side by side.
template <class H, int N>
void unitFrameTransition(const typename H::template Point<double>& x0, const typename H::template Point<double>& x1,
                         const typename H::template Tangent<double>& log, Eigen::Matrix<double, N, N>* jacobian,
                         Eigen::Matrix<double, N, N * N>* quadratic)
{
  using J2 = Jet<2>;
  const TransitionMap<H> map{ x0, x1 };
  // s ↦ F(s (e_j + e_k)) (e_j alone when j = k): velocity and acceleration.
  auto motion = [&](int j, int k, Eigen::Matrix<double, N, 1>* velocity, Eigen::Matrix<double, N, 1>* acceleration) {
    typename H::template Tangent<J2> delta;
    for (int m = 0; m < N; ++m)
      delta[m] = J2(log[m]);
    delta[j].coefficient(1) = 1.0;
    delta[k].coefficient(1) = 1.0;
    const typename H::template Tangent<J2> y = map(delta);
    for (int m = 0; m < N; ++m)
    {
      (*velocity)[m] = y[m].coefficient(1);
      (*acceleration)[m] = 2.0 * y[m].coefficient(2);
    }
  };
  Eigen::Matrix<double, N, 1> velocity, acceleration;
  for (int j = 0; j < N; ++j)
  {
    motion(j, j, &velocity, &acceleration);
    jacobian->col(j) = velocity;
    quadratic->col(j * N + j) = acceleration;
  }
  for (int j = 0; j < N; ++j)
    for (int k = j + 1; k < N; ++k)
    {
      motion(j, k, &velocity, &acceleration);
      const Eigen::Matrix<double, N, 1> mixed =
          (acceleration - quadratic->col(j * N + j) - quadratic->col(k * N + k)) / 2.0;
      quadratic->col(j * N + k) = mixed;
      quadratic->col(k * N + j) = mixed;
    }
}

inline std::string scientific(double x)
{
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

/// The C^2 solve on S^m refuses a waypoint step closer than this to pi (the sphere's first
/// conjugate point, where D_i is singular). Measured (natural splines on S^2 through x0, x1 at
/// pi - gap from x0 after h, and a third point; 60 random configurations per gap and h in
/// 1e-6 ... 1 s): the acceleration at x1 from its two sides, both evaluated from the ambient jet,
/// differs by up to 2e-8 of its size at a gap of 1e-8 rad, 1e-7 at 1e-7 rad (h = 1e-5 s),
/// 2e-6 at 1e-10 and 1e-11 rad (h = 1e-3 s), 0.15 at 1e-10 rad and 1 (the value itself) at
/// 1e-12 rad (h = 2.5e-6 s): the rounding of the segment's terms, which grow with the condition
/// of D_i, swamps the acceleration. verifyContinuity, on the scale of those terms, passes all of
/// these but the last. Below 1e-8 rad such steps are refused, naming the waypoints.
constexpr double kMinSphereConjugateGap = 1e-8;

/// The generic rule: D_i and Q_i from jets of F (fixed dimension, identity frames) or from
/// chart_cubic.h's transitionDerivatives in the frames b0, b1; D inverted by a rank-revealing LU;
/// every step accepted; Q acts in all coordinates.
template <class G>
struct GenericChartTransition
{
  /// The leading coordinates that Q_i depends on and acts in, for `dof` coordinates in all.
  static constexpr int curvedCoordinates(int dof) { return dof; }

  /// D_i and Q_i of the segment from x0 to x1 (log = log_{x0} x1); b0, b1 its tangent frames
  /// (nullptr: the identity), used only where the dimension is not fixed.
  template <class Mat, class Quad>
  static void derivatives(const typename G::template Point<double>& x0, const typename G::template Point<double>& x1,
                          const typename G::template Tangent<double>& log, const Eigen::MatrixXd* b0,
                          const Eigen::MatrixXd* b1, Mat* d, Quad* q)
  {
    constexpr int kDof = Mat::RowsAtCompileTime;
    if constexpr (kDof != Eigen::Dynamic)
    {
      unitFrameTransition<G, kDof>(x0, x1, log, d, q);
    }
    else
    {
      const Eigen::Index dof = log.size();
      const TransitionDerivatives t =
          transitionDerivatives<G>(x0, x1, log, b0 ? *b0 : Eigen::MatrixXd::Identity(dof, dof),
                                   b1 ? *b1 : Eigen::MatrixXd::Identity(dof, dof));
      *d = t.jacobian;
      *q = t.quadratic;
    }
  }

  /// E = D⁻¹ if D is invertible.
  template <class Mat>
  static bool invert(const Mat& d, Mat* e)
  {
    const Eigen::FullPivLU<Mat> lu(d);
    if (!lu.isInvertible())
      return false;
    *e = lu.inverse();
    return true;
  }

  /// Why the solve cannot take the step from waypoints[i], whose log is `log` ("" when it can:
  /// no allocation on the solve's path).
  static std::string refusedStep(const typename G::template Tangent<double>& /*log*/, std::size_t /*i*/)
  {
    return std::string();
  }
};

template <class G>
struct ChartTransition : GenericChartTransition<G>
{
};

/// R^n: the charts are one, D = I and Q = 0.
template <>
struct ChartTransition<Euclidean> : GenericChartTransition<Euclidean>
{
  template <class Mat, class Quad>
  static void derivatives(const Eigen::VectorXd& /*x0*/, const Eigen::VectorXd& /*x1*/, const Eigen::VectorXd& log,
                          const Eigen::MatrixXd* /*b0*/, const Eigen::MatrixXd* /*b1*/, Mat* d, Quad* q)
  {
    const Eigen::Index dof = log.size();
    *d = Mat::Identity(dof, dof);
    *q = Quad::Zero(dof, dof * dof);
  }
};

/// R⁻¹ of the rotation block of an SE(3) transition's D (a Jacobian of SO(3), inverted by
/// cofactors), refused (false) when |det R| ≤ ε · (max |R_ab|)³.
inline bool invertRotationBlock(const Eigen::Matrix3d& r, Eigen::Matrix3d* inverse)
{
  double det = 0.0;
  bool invertible = false;
  const double size = r.cwiseAbs().maxCoeff();
  r.computeInverseAndDetWithCheck(*inverse, det, invertible,
                                  std::numeric_limits<double>::epsilon() * size * size * size);
  return invertible && size > 0.0;
}

/// SO(3) × R³: only the rotation's 3 coordinates are curved; D's rotation block R is the right
/// Jacobian J_r(L) (det = 2 (1 − cos θ)/θ² ≥ 4/π² below half a turn), inverted by cofactors and
/// refused when |det R| ≤ ε · (max |R_ab|)³; the translation block is the identity.
template <>
struct ChartTransition<DoubleGeodesicSe3> : GenericChartTransition<DoubleGeodesicSe3>
{
  static constexpr int curvedCoordinates(int /*dof*/) { return 3; }
  template <class Mat, class Quad>
  static void derivatives(const DoubleGeodesicSe3::Point<double>& x0, const DoubleGeodesicSe3::Point<double>& x1,
                          const DoubleGeodesicSe3::Tangent<double>& log, const Eigen::MatrixXd* /*b0*/,
                          const Eigen::MatrixXd* /*b1*/, Mat* d, Quad* q)
  {
    Eigen::Matrix3d rd;
    Eigen::Matrix<double, 3, 9> rq;
    unitFrameTransition<So3, 3>(x0.q, x1.q, Eigen::Vector3d(log.template head<3>()), &rd, &rq);
    d->setIdentity();
    d->template topLeftCorner<3, 3>() = rd;
    *q = rq;
  }
  template <class Mat>
  static bool invert(const Mat& d, Mat* e)
  {
    Eigen::Matrix3d inverse;
    if (!invertRotationBlock(d.template topLeftCorner<3, 3>(), &inverse))
      return false;
    e->setIdentity();
    e->template topLeftCorner<3, 3>() = inverse;
    return true;
  }
};

/// SE(3) with the screw metric: D_i and Q_i in closed form from the right Jacobian of SE(3) and its
/// derivatives (detail::screwTransitionDerivatives), instead of 21 jet evaluations of the map.
/// D = J_r(L) = [[V, 0], [Q_l, V]] is block lower-triangular, so D⁻¹ = [[V⁻¹, 0], [−V⁻¹ Q_l V⁻¹, V⁻¹]]
/// from the rotation block's inverse (refused as the double geodesic's).
template <>
struct ChartTransition<ScrewSe3> : GenericChartTransition<ScrewSe3>
{
  template <class Mat, class Quad>
  static void derivatives(const ScrewSe3::Point<double>& /*x0*/, const ScrewSe3::Point<double>& /*x1*/,
                          const ScrewSe3::Tangent<double>& log, const Eigen::MatrixXd* /*b0*/,
                          const Eigen::MatrixXd* /*b1*/, Mat* d, Quad* q)
  {
    screwTransitionDerivatives(log, d, q);
  }
  template <class Mat>
  static bool invert(const Mat& d, Mat* e)
  {
    Eigen::Matrix3d inverse;
    if (!invertRotationBlock(d.template topLeftCorner<3, 3>(), &inverse))
      return false;
    e->template topLeftCorner<3, 3>() = inverse;
    e->template topRightCorner<3, 3>().setZero();
    e->template bottomRightCorner<3, 3>() = inverse;
    e->template bottomLeftCorner<3, 3>() = -inverse * d.template bottomLeftCorner<3, 3>() * inverse;
    return true;
  }
};

/// S^m: no step within kMinSphereConjugateGap of the antipode.
template <>
struct ChartTransition<Sphere> : GenericChartTransition<Sphere>
{
  static std::string refusedStep(const Eigen::VectorXd& log, std::size_t i)
  {
    const double gap = EIGEN_PI - log.norm();
    if (gap >= kMinSphereConjugateGap)
      return std::string();
    return "the step from " + indexedField("waypoints", i) + " to " + indexedField("waypoints", i + 1) + " is " +
           scientific(gap) + " rad from the antipode, closer than " + scientific(kMinSphereConjugateGap) +
           " rad (the sphere's conjugate point, where the spline's acceleration is lost to rounding); add a "
           "waypoint between them or use curve 'hermite'";
  }
};

}  // namespace detail
}  // namespace se3_interpolation
