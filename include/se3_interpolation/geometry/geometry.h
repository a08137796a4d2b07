// The geometries a curve can live in, as policies for the generic algorithms.
//
// Every geometry G provides
//   template <class S> using Point;     // a point of the manifold, scalar S
//   template <class S> using Tangent;   // a tangent vector (representation below)
//   log(a, b) -> Tangent                // the initial velocity of the geodesic a → b at λ = 0
//   exp(a, v) -> Point                  // the geodesic from a with initial velocity v, at λ = 1
//   cast<T>(Point<double>) -> Point<T>
// so that the geodesic interpolation of thesis eq. (4.1) is
//   interp_λ(a, b) = exp(a, λ log(a, b)),
// defined for every real λ (λ outside [0, 1] extrapolates along the geodesic).
// log throws NonUniqueGeodesicError when a and b are antipodal (the minimising
// geodesic is not unique).
//
// Tangent representations:
//   ScrewSe3:          body twist (ω, v) of a⁻¹b, rotation first (se(3), thesis ch. 5)
//   DoubleGeodesicSe3: (ω, Δp): ω the body rotation vector of R_aᵀ R_b, Δp = p_b − p_a in
//                      the world frame (product metric SO(3) × R³)
//   So3:               body rotation vector ω of q_a⁻¹ q_b
//   Euclidean:         b − a in R^n
//   Sphere:            the ambient vector in T_a S^m ⊂ R^{m+1} (Crouch et al., eq. 17/18)
#pragma once

#include <Eigen/Core>

#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
template <class S>
using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

namespace detail
{
/// The second-order jet of f(α(t)) from f, f' and f'' at α_0 = α(t_0) (Faà di Bruno at order 2:
/// c_1 = α_1 f', c_2 = α_2 f' + α_1² f''/2, with α = (α_0, α_1, α_2) the jet's coefficients).
inline Jet<2> composeJet(double f, double d1, double d2, const Jet<2>& alpha)
{
  Jet<2> r{ Jet<2>::NoInit{} };
  const double a1 = alpha.coefficient(1);
  r.coefficient(0) = f;
  r.coefficient(1) = a1 * d1;
  r.coefficient(2) = alpha.coefficient(2) * d1 + 0.5 * a1 * a1 * d2;
  return r;
}

/// The jet of a rotation q(α(t)) = q_a Exp(α ω) with constant q_a and ω: along a one-parameter
/// subgroup dq/dα = q (0, ω/2) and d²q/dα² = q (0, ω/2)² = −(|ω|²/4) q, so the jet needs one
/// double evaluation of q and one quaternion product of doubles (no jet × jet products).
inline Quaternion<Jet<2>> rotationLineJet(const Quaternion<double>& q, const Vector3<double>& omega,
                                          const Jet<2>& alpha)
{
  const Quaternion<double> d1 = q * Quaternion<double>(0.0, 0.5 * omega.x(), 0.5 * omega.y(), 0.5 * omega.z());
  const double k2 = -0.25 * omega.squaredNorm();
  return Quaternion<Jet<2>>(composeJet(q.w(), d1.w(), k2 * q.w(), alpha), composeJet(q.x(), d1.x(), k2 * q.x(), alpha),
                            composeJet(q.y(), d1.y(), k2 * q.y(), alpha), composeJet(q.z(), d1.z(), k2 * q.z(), alpha));
}

/// The jet of a vector p(α(t)) from p, dp/dα and d²p/dα² at α_0.
inline Vector3<Jet<2>> vectorJet(const Vector3<double>& p, const Vector3<double>& d1, const Vector3<double>& d2,
                                 const Jet<2>& alpha)
{
  return Vector3<Jet<2>>(composeJet(p.x(), d1.x(), d2.x(), alpha), composeJet(p.y(), d1.y(), d2.y(), alpha),
                         composeJet(p.z(), d1.z(), d2.z(), alpha));
}
}  // namespace detail

/// SE(3) with its Ad-invariant (screw) metric: a · Exp(λ Log(a⁻¹ b)). Bi-invariant.
struct ScrewSe3
{
  template <class S>
  using Point = Pose<S>;
  template <class S>
  using Tangent = Vector6<S>;

  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    return se3Log(a.inverseTimes(b));
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return a * se3Exp(v);
  }
  /// exp(a, α v) at a second-order jet α of time, constant a and v, in closed form: g(α) =
  /// a Exp(α ξ) is a one-parameter subgroup through a, dg/dα = g ξ^ and d²g/dα² = g ξ^ ξ^, i.e.
  /// (quaternion, translation) derivatives (q (0, ω/2), R v) and (−|ω|²/4 q, R (ω × v)).
  static Point<Jet<2>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    const Point<double> g = a * se3Exp(Tangent<double>(v * alpha.value()));
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> lin = v.template tail<3>();
    return Point<Jet<2>>(detail::rotationLineJet(g.q, omega, alpha),
                         detail::vectorJet(g.p, g.q * lin, g.q * Vector3<double>(omega.cross(lin)), alpha));
  }
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return a.template cast<T>();
  }
};

/// SE(3) as SO(3) × R³: rotation along its geodesic, translation on a straight line.
/// Left-invariant, not right-invariant. What tf2 and KDL do between two poses.
struct DoubleGeodesicSe3
{
  template <class S>
  using Point = Pose<S>;
  template <class S>
  using Tangent = Vector6<S>;

  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    Tangent<S> v;
    v.template head<3>() = so3Log(Quaternion<S>(a.q.conjugate() * b.q));
    v.template tail<3>() = b.p - a.p;
    return v;
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return Point<S>(a.q * so3Exp(Vector3<S>(v.template head<3>())), a.p + v.template tail<3>());
  }
  /// exp(a, α v) at a second-order jet α of time, constant a and v, in closed form: the rotation
  /// is a one-parameter subgroup through q_a (detail::rotationLineJet), the translation
  /// p_a + α Δp has derivatives Δp and 0.
  static Point<Jet<2>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> dp = v.template tail<3>();
    const Quaternion<double> q = a.q * so3Exp(Vector3<double>(omega * alpha.value()));
    return Point<Jet<2>>(detail::rotationLineJet(q, omega, alpha),
                         detail::vectorJet(Vector3<double>(a.p + alpha.value() * dp), dp, Vector3<double>::Zero(), alpha));
  }
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return a.template cast<T>();
  }
};

/// SO(3) with its bi-invariant metric (unit quaternions).
struct So3
{
  template <class S>
  using Point = Quaternion<S>;
  template <class S>
  using Tangent = Vector3<S>;

  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    return so3Log(Quaternion<S>(a.conjugate() * b));
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return a * so3Exp(v);
  }
  /// exp(a, α v) at a second-order jet α, constant a and v (detail::rotationLineJet).
  static Point<Jet<2>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    return detail::rotationLineJet(Quaternion<double>(a * so3Exp(Vector3<double>(v * alpha.value()))), v, alpha);
  }
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return Point<T>(T(a.w()), T(a.x()), T(a.y()), T(a.z()));
  }
};

/// R^n: the abelian case, where every construction reduces to its classical form.
struct Euclidean
{
  template <class S>
  using Point = VectorX<S>;
  template <class S>
  using Tangent = VectorX<S>;

  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    return b - a;
  }
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    return a + v;
  }
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return a.template cast<T>();
  }
};

/// The unit sphere S^m ⊂ R^{m+1} with its round metric (great circles).
struct Sphere
{
  template <class S>
  using Point = VectorX<S>;
  template <class S>
  using Tangent = VectorX<S>;

  /// θ (b − cos θ a)/sin θ, θ = ∠(a, b); throws when b = −a.
  template <class S>
  static Tangent<S> log(const Point<S>& a, const Point<S>& b)
  {
    const S c = a.dot(b);
    const Tangent<S> w = b - c * a;
    const S n2 = w.squaredNorm();
    if (valueOf(c) < 0.0 && valueOf(n2) <= 4.0 * kAntipodalTolerance * kAntipodalTolerance)
      throw NonUniqueGeodesicError("the points are antipodal: the great circle between them is not unique");
    // atan2(|w|, c)/|w|, the quaternion log factor halved (same series near 0).
    if (valueOf(c) > 0.0)
      return w * (detail::logFactor(n2, c) / 2.0);
    using std::atan2;
    using std::sqrt;
    const S n = sqrt(n2);
    return w * (atan2(n, c) / n);
  }
  /// cos|v| a + sin|v| v/|v|.
  template <class S>
  static Point<S> exp(const Point<S>& a, const Tangent<S>& v)
  {
    const S theta2 = v.squaredNorm();
    S k, c;
    // sin(θ/2)/θ and cos(θ/2) at 2θ give sin θ/(2θ) and cos θ.
    detail::halfAngle(S(4.0 * theta2), &k, &c);
    return c * a + S(2.0) * k * v;
  }
  template <class T>
  static Point<T> cast(const Point<double>& a)
  {
    return a.template cast<T>();
  }
};

/// Geodesic interpolation interp_λ(a, b) = exp(a, λ log(a, b)) (thesis eq. 4.1).
template <class G, class S>
typename G::template Point<S> geodesic(const typename G::template Point<S>& a, const typename G::template Point<S>& b,
                                       const S& lambda)
{
  return G::exp(a, typename G::template Tangent<S>(G::log(a, b) * lambda));
}

/// The double-geodesic step between two poses in double precision: the rotation in slerp form
/// (so3Slerp, no Log → Exp round trip), the translation on its line. Equal to the generic
/// exp(a, λ log(a, b)) to rounding; tested against it and a long double reference.
template <>
inline Pose<double> geodesic<DoubleGeodesicSe3, double>(const Pose<double>& a, const Pose<double>& b,
                                                        const double& lambda)
{
  return Pose<double>(so3Slerp(a.q, b.q, lambda), a.p + lambda * (b.p - a.p));
}

/// The SO(3) step between two rotations in double precision, in slerp form (so3Slerp).
template <>
inline Quaternion<double> geodesic<So3, double>(const Quaternion<double>& a, const Quaternion<double>& b,
                                                const double& lambda)
{
  return so3Slerp(a, b, lambda);
}

/// The double-geodesic step between jet poses (levels ≥ 2 of the recursions when derivatives
/// are sampled): the rotation by so3SlerpJet where its weights are accurate, else by the
/// Log → Exp jet path; the translation on its line.
template <>
inline Pose<Jet<2>> geodesic<DoubleGeodesicSe3, Jet<2>>(const Pose<Jet<2>>& a, const Pose<Jet<2>>& b,
                                                        const Jet<2>& lambda)
{
  Quaternion<Jet<2>> q;
  if (!so3SlerpJet(a.q, b.q, lambda, &q))
    q = a.q * so3Exp(Vector3<Jet<2>>(so3Log(Quaternion<Jet<2>>(a.q.conjugate() * b.q)) * lambda));
  return Pose<Jet<2>>(q, a.p + lambda * (b.p - a.p));
}

/// The SO(3) step between jet rotations (as geodesic<DoubleGeodesicSe3, Jet<2>>).
template <>
inline Quaternion<Jet<2>> geodesic<So3, Jet<2>>(const Quaternion<Jet<2>>& a, const Quaternion<Jet<2>>& b,
                                                const Jet<2>& lambda)
{
  Quaternion<Jet<2>> q;
  if (!so3SlerpJet(a, b, lambda, &q))
    q = a * so3Exp(Vector3<Jet<2>>(so3Log(Quaternion<Jet<2>>(a.conjugate() * b)) * lambda));
  return q;
}

}  // namespace se3_interpolation
