// math/: numbers and closed forms, no geometry policy: jet.h (truncated Taylor arithmetic, exact
// derivatives), lie_groups.h (this header: Pose, SO(3)/SE(3) Exp/Log and slerp with their jets;
// lie_coefficients.h the scalar coefficients of their closed forms),
// banded_lu.h (the banded LU of the C² systems), quadrature.h (Gauss–Legendre, golden section).
//
// Closed-form exponential and logarithm maps of SO(3) (unit quaternions) and SE(3).
//
// Conventions (as Sophus):
//  - A rotation is a unit quaternion q = (w, x, y, z); q and −q are the same rotation.
//    A rotation vector ω ∈ R³ (rad) has angle θ = |ω| and Exp(ω) = (cos θ/2, sin(θ/2) ω/θ).
//  - A pose world_T_body = (q, p): x_world = R(q) x_body + p.
//  - A twist ξ = (ω, v) ∈ R⁶, rotation first; Exp(ξ) = (Exp(ω), V(ω) v) with
//    V(ω) = I + (1 − cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×² (thesis ch. 5, screw motion).
//
// Accuracy: every coefficient that cancels for small θ (A, B, C: lie_coefficients.h) switches to its
// Taylor series in θ² for θ < 0.2, with enough terms that the truncation is below one
// ulp; above 0.2 the direct formulas lose at most ~1e-14 relative. The logarithm works
// with atan2 on the quaternion, so it stays accurate up to θ = π − 1e-9 and beyond.
// All functions are templates over the scalar (double or Jet<K>), so derivatives of
// any order flow through them exactly.
#pragma once

#include <algorithm>
#include <cmath>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/jet.h"
#include "se3_interpolation/math/lie_coefficients.h"

namespace se3_interpolation
{
template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Vector6 = Eigen::Matrix<S, 6, 1>;
template <class S>
using Quaternion = Eigen::Quaternion<S, Eigen::DontAlign>;

/// |w| of a normalised relative quaternion at or below this is "exactly π"
/// (angle within 2e-15 rad of π: indistinguishable from π in double precision).
constexpr double kAntipodalTolerance = 1e-15;

/// Exp: R³ → SO(3) as a unit quaternion.
template <class S>
Quaternion<S> so3Exp(const Vector3<S>& omega)
{
  const S theta2 = omega.squaredNorm();
  S k, c;
  detail::halfAngle(theta2, &k, &c);
  return Quaternion<S>(c, k * omega.x(), k * omega.y(), k * omega.z());
}

/// Log: SO(3) → R³, the rotation vector of angle in [0, π]. The quaternion must be
/// unit; its sign does not matter. Throws NonUniqueGeodesicError at angle π.
template <class S>
Vector3<S> so3Log(const Quaternion<S>& q)
{
  S w = q.w();
  Vector3<S> v = q.vec();
  if (valueOf(w) < 0.0)
  {
    w = -w;
    v = -v;
  }
  if (valueOf(w) <= kAntipodalTolerance)
    throw NonUniqueGeodesicError("the rotation angle is pi: the shortest rotation is not unique");
  return v * detail::logFactor(S(v.squaredNorm()), w);
}

/// Below this |sin φ| (φ half the relative angle) the slerp weights are λ and 1 − λ: the
/// neglected terms are O(φ²) < 1e-300, and sin(λφ) is kept away from subnormals.
constexpr double kSlerpTinySine = 1e-150;

/// The SO(3) geodesic step q_a Exp(λ Log(q_a* q_b)) in slerp form, without the Log → Exp round
/// trip: with cos φ = ⟨q_a, q_b⟩ (q_b's sign chosen so that it is ≥ 0) and sin φ = |q_b − cos φ q_a|
/// (φ = θ/2, θ the relative rotation angle),
///   q(λ) = (cos λφ − cos φ · s) q_a + s q_b,   s = sin(λφ)/sin φ
/// (Shoemake's slerp, rewritten so that only sin(λφ) and cos(λφ) are needed: one atan and one
/// sincos, neither of which has an errno wrapper in glibc). φ = atan(sin φ / cos φ) is accurate
/// at both ends: near 0 both terms are exact to rounding (so s → λ with relative error of
/// order ε), near θ = π the quotient is large and atan flat. sin φ carries the same cancellation
/// as the quaternion product q_a* q_b of the Log path (absolute error of order ε; none when q_a
/// is the identity). Defined for every real λ (extrapolation). Throws NonUniqueGeodesicError at
/// θ = π (as so3Log).
inline Quaternion<double> so3Slerp(const Quaternion<double>& qa, const Quaternion<double>& qb, double lambda)
{
  double w = qa.coeffs().dot(qb.coeffs());
  Eigen::Vector4d b = qb.coeffs();
  if (w < 0.0)
  {
    w = -w;
    b = -b;
  }
  if (w <= kAntipodalTolerance)
    throw NonUniqueGeodesicError("the rotation angle is pi: the shortest rotation is not unique");
  const Eigen::Vector4d a = qa.coeffs();
  const double n = (b - w * a).norm();  // sin φ
  double s = lambda;
  double c = 1.0;
  if (n >= kSlerpTinySine)
  {
    const double phi = std::atan(n / w);
    double sl;
    sincos(lambda * phi, &sl, &c);
    s = sl / n;
  }
  Quaternion<double> r;
  r.coeffs() = (c - w * s) * a + s * b;
  return r;
}

/// At or above this sin²φ (sin φ ≥ 0.025, θ ≥ 0.05 rad) so3SlerpJet computes the slerp weights
/// in closed form. The derivatives of sin φ = |q_b − cos φ q_a| and of s = sin(λφ)/sin φ amplify
/// rounding by about 1/sin φ (measured: disagreement with the Log → Exp jet path 1e-15/θ, 7e-14
/// at θ = 0.05), so below it the weights come from their series in φ² (detail::sinSqrtRatio),
/// which involve neither sin φ nor its square root.
constexpr double kSlerpJetMinSine2 = 6.25e-4;

/// The largest argument z = ν²φ² at which the weights' series are summed (ν ∈ {λ, 1 − λ, 2λ − 1}).
/// Their seven terms leave out z⁷/15! < 1e-21 there; in a jet of order K ≤ 3 the omitted term's
/// k-th coefficient is of order C(7, k) z^{7−k} ż^k/15!, below 2e-16 of the series' own (of order
/// ż^k). Fewer terms would not do: four leave ~1e-8 of it at z = 1e-3. Every λ of the de Casteljau
/// and de Boor recursions (λ ∈ [0, 1], ν² ≤ 1) qualifies up to φ² = 0.05, beyond every caller's
/// closed-form threshold (sin²φ ≤ 1e-2, φ² < 0.0101); far extrapolation (ν² φ² > 0.05 with a small
/// φ) takes the caller's Log → Exp path.
constexpr double kSlerpSeriesMaxArgument = 0.05;

namespace detail
{
/// sin(√z)/√z = Σ_k (−1)^k z^k/(2k+1)! for 0 ≤ z ≤ kSlerpSeriesMaxArgument (seven terms).
template <class S>
S sinSqrtRatio(const S& z)
{
  static constexpr double k[] = {
    1.0, -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0, 1.0 / 6227020800.0
  };
  return horner(z, k);
}

/// sin(νφ)/sin φ from ν, x = φ² and 1/sinSqrtRatio(x) = φ/sin φ: ν sinSqrtRatio(ν² x) φ/sin φ (a
/// slerp weight, and even in φ, so a function of φ² without the removable singularity at φ = 0).
template <class S>
S sinRatioSeries(const S& nu, const S& x, const S& phi_over_sin)
{
  return nu * sinSqrtRatio(S(nu * nu * x)) * phi_over_sin;
}
}  // namespace detail

/// The slerp weights of so3Slerp in jet arithmetic: with φ the half angle between q_a and
/// sign · q_b (sign making cos φ = w ≥ 0), slerp is ka q_a + kb sign q_b with
/// ka = sin((1 − λ)φ)/sin φ = cos λφ − w kb and kb = sin(λφ)/sin φ. From sin²φ ≥ the closed-form
/// threshold: c = cos λφ from atan2 and sincos; below it: x = φ² and the series in it.
template <int K>
struct SlerpJetWeights
{
  Jet<K> ka, kb;        ///< the weights of q_a and sign q_b
  Jet<K> w;             ///< cos φ
  Jet<K> n2;            ///< sin² φ
  Jet<K> c;             ///< cos λφ (closed form only)
  Jet<K> x;             ///< φ² (series only)
  Jet<K> phi_over_sin;  ///< φ/sin φ = 1/sinSqrtRatio(x) (series only)
  bool series = false;
  double sign = 1.0;
};

/// The slerp weights of q_a, q_b at λ (SlerpJetWeights): in closed form from sin²φ ≥ min_sine2,
/// else from the series when every ν² φ² ≤ kSlerpSeriesMaxArgument. Returns false, leaving *out
/// unspecified, otherwise (a far extrapolation at a small angle). Throws NonUniqueGeodesicError
/// at θ = π.
template <int K>
SE3_JET_INLINE bool slerpJetWeights(const Quaternion<Jet<K>>& qa, const Quaternion<Jet<K>>& qb, const Jet<K>& lambda,
                                    SlerpJetWeights<K>* out, double min_sine2 = kSlerpJetMinSine2)
{
  using J = Jet<K>;
  J w = qa.w() * qb.w() + qa.x() * qb.x() + qa.y() * qb.y() + qa.z() * qb.z();
  const double sign = w.value() < 0.0 ? -1.0 : 1.0;
  w = w * sign;
  if (w.value() <= kAntipodalTolerance)
    throw NonUniqueGeodesicError("the rotation angle is pi: the shortest rotation is not unique");
  const J dw = qb.w() * sign - w * qa.w();
  const J dx = qb.x() * sign - w * qa.x();
  const J dy = qb.y() * sign - w * qa.y();
  const J dz = qb.z() * sign - w * qa.z();
  out->n2 = dw * dw + dx * dx + dy * dy + dz * dz;  // sin² φ
  out->w = w;
  out->sign = sign;
  if (out->n2.value() >= min_sine2)
  {
    const J n = sqrt(out->n2);
    J sl;
    sincos(J(lambda * atan2(n, w)), &sl, &out->c);
    out->kb = sl / n;
    out->ka = out->c - w * out->kb;
    out->series = false;
    return true;
  }
  // φ = atan2(n, w) and φ/n = logFactor/2, so φ² = sin²φ (logFactor/2)², free of the square root.
  const J half_factor = detail::logFactor(out->n2, w) * 0.5;
  out->x = out->n2 * half_factor * half_factor;
  const double l = lambda.value();
  const double reach = std::max({ l * l, (1.0 - l) * (1.0 - l), (2.0 * l - 1.0) * (2.0 * l - 1.0) });
  if (!(reach * out->x.value() <= kSlerpSeriesMaxArgument))
    return false;
  out->phi_over_sin = J(1.0) / detail::sinSqrtRatio(out->x);
  out->kb = detail::sinRatioSeries(lambda, out->x, out->phi_over_sin);
  out->ka = detail::sinRatioSeries(J(J(1.0) - lambda), out->x, out->phi_over_sin);
  out->series = true;
  return true;
}

/// ka q_a + kb sign q_b: the slerp of q_a, q_b from its weights.
template <int K>
SE3_JET_INLINE Quaternion<Jet<K>> slerpFromWeights(const Quaternion<Jet<K>>& qa, const Quaternion<Jet<K>>& qb,
                                                   const SlerpJetWeights<K>& weights)
{
  using J = Jet<K>;
  const J& ka = weights.ka;
  const J kb = weights.kb * weights.sign;
  return Quaternion<J>(ka * qa.w() + kb * qb.w(), ka * qa.x() + kb * qb.x(), ka * qa.y() + kb * qb.y(),
                       ka * qa.z() + kb * qb.z());
}

/// so3Slerp at quaternions and parameter given as jets (the levels ≥ 2 of de Casteljau / de Boor
/// when derivatives are sampled): the same weights in jet arithmetic, without the two
/// quaternion products of the Log → Exp path. Returns false, leaving *out unchanged, where
/// slerpJetWeights does (a far extrapolation at a small angle). Throws NonUniqueGeodesicError at
/// θ = π.
template <int K>
SE3_JET_INLINE bool so3SlerpJet(const Quaternion<Jet<K>>& qa, const Quaternion<Jet<K>>& qb, const Jet<K>& lambda,
                                Quaternion<Jet<K>>* out)
{
  SlerpJetWeights<K> weights;
  if (!slerpJetWeights(qa, qb, lambda, &weights))
    return false;
  *out = slerpFromWeights(qa, qb, weights);
  return true;
}

/// Rotation angle θ ∈ [0, π] of a unit quaternion (sign-independent).
inline double rotationAngle(const Quaternion<double>& q)
{
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

/// A rigid transformation world_T_body = (q, p). Composition a * b = (q_a q_b, R_a p_b + p_a).
template <class S>
struct Pose
{
  Quaternion<S> q = Quaternion<S>::Identity();
  Vector3<S> p = Vector3<S>::Zero();

  Pose() = default;
  Pose(const Quaternion<S>& rotation, const Vector3<S>& translation) : q(rotation), p(translation) {}

  static Pose Identity() { return Pose(); }

  Pose operator*(const Pose& o) const { return Pose(q * o.q, q * o.p + p); }
  /// this⁻¹ · o without forming the inverse: (q* q_o, q* (p_o − p)).
  Pose inverseTimes(const Pose& o) const
  {
    const Quaternion<S> qi = q.conjugate();
    return Pose(qi * o.q, qi * Vector3<S>(o.p - p));
  }
  Pose inverse() const
  {
    const Quaternion<S> qi = q.conjugate();
    return Pose(qi, -(qi * p));
  }
  template <class T>
  Pose<T> cast() const
  {
    return Pose<T>(Quaternion<T>(T(q.w()), T(q.x()), T(q.y()), T(q.z())), Vector3<T>(T(p.x()), T(p.y()), T(p.z())));
  }
};

/// The chord distance √(|p_b − p_a|² + (ρ θ)²) between two poses (m): θ the angle of the relative
/// rotation q_a* q_b, ρ = rotation_scale (m per rad). The distance of the chord parameterization
/// (docs/timing.md) and of sample_tolerance (execution/sample_refinement.h).
inline double chordDistance(const Pose<double>& a, const Pose<double>& b, double rotation_scale)
{
  const double rho_theta = rotation_scale * rotationAngle(Quaternion<double>(a.q.conjugate() * b.q));
  return std::sqrt((b.p - a.p).squaredNorm() + rho_theta * rho_theta);
}

/// a · b for a constant pose a and a jet pose b: (q_a q_b, R_a p_b + p_a) with products of a double
/// and a jet only (a jet × jet product costs twice as much).
template <int K>
Pose<Jet<K>> constantTimes(const Pose<double>& a, const Pose<Jet<K>>& b)
{
  const Quaternion<double>& q = a.q;
  const Quaternion<Jet<K>>& r = b.q;
  const Quaternion<Jet<K>> product(r.w() * q.w() - r.x() * q.x() - r.y() * q.y() - r.z() * q.z(),
                                   r.x() * q.w() + r.w() * q.x() + r.z() * q.y() - r.y() * q.z(),
                                   r.y() * q.w() - r.z() * q.x() + r.w() * q.y() + r.x() * q.z(),
                                   r.z() * q.w() + r.y() * q.x() - r.x() * q.y() + r.w() * q.z());
  const Eigen::Matrix3d rotation = q.toRotationMatrix();
  Vector3<Jet<K>> p;
  for (int i = 0; i < 3; ++i)
    p[i] = b.p[0] * rotation(i, 0) + b.p[1] * rotation(i, 1) + b.p[2] * rotation(i, 2) + a.p[i];
  return Pose<Jet<K>>(product, p);
}

/// V(ω) v (left Jacobian of SO(3) applied to v).
template <class S>
Vector3<S> screwV(const Vector3<S>& omega, const Vector3<S>& v)
{
  const S theta2 = omega.squaredNorm();
  S k, c;
  detail::halfAngle(theta2, &k, &c);
  const S a = 2.0 * k * k;  // (1 − cos θ)/θ²
  const S b = detail::screwB(theta2, k, c);
  const Vector3<S> wv = omega.cross(v);
  return v + a * wv + b * omega.cross(wv);
}

/// Exp: se(3) → SE(3), twist ξ = (ω, v).
template <class S>
Pose<S> se3Exp(const Vector6<S>& xi)
{
  const Vector3<S> omega = xi.template head<3>();
  const Vector3<S> v = xi.template tail<3>();
  const S theta2 = omega.squaredNorm();
  S k, c;
  detail::halfAngle(theta2, &k, &c);
  const S a = 2.0 * k * k;
  const S b = detail::screwB(theta2, k, c);
  const Vector3<S> wv = omega.cross(v);
  return Pose<S>(Quaternion<S>(c, k * omega.x(), k * omega.y(), k * omega.z()), v + a * wv + b * omega.cross(wv));
}

/// Log: SE(3) → se(3), twist (ω, v) with |ω| ≤ π. Throws at rotation angle π.
/// V(ω)⁻¹'s coefficient C(θ) reuses the quaternion: (θ/2) cot(θ/2) = (θ/2) w/|vec(q)|.
template <class S>
Vector6<S> se3Log(const Pose<S>& g)
{
  S w = g.q.w();
  Vector3<S> v = g.q.vec();
  if (valueOf(w) < 0.0)
  {
    w = -w;
    v = -v;
  }
  if (valueOf(w) <= kAntipodalTolerance)
    throw NonUniqueGeodesicError("the rotation angle is pi: the shortest rotation is not unique");
  const S f = detail::logFactor(S(v.squaredNorm()), w);  // θ/|vec(q)|
  const Vector3<S> omega = v * f;
  const S theta2 = omega.squaredNorm();
  const S c = valueOf(theta2) < kSeriesThetaSquared ? detail::screwC(theta2) : S((1.0 - 0.5 * f * w) / theta2);
  const Vector3<S> wp = omega.cross(g.p);
  Vector6<S> xi;
  xi.template head<3>() = omega;
  xi.template tail<3>() = g.p - 0.5 * wp + c * omega.cross(wp);
  return xi;
}

/// [ω]× as a matrix (for tests and Jacobians).
template <class S>
Eigen::Matrix<S, 3, 3> hat(const Vector3<S>& w)
{
  Eigen::Matrix<S, 3, 3> m;
  m << S(0), -w.z(), w.y(), w.z(), S(0), -w.x(), -w.y(), w.x(), S(0);
  return m;
}

// Jets along one-parameter subgroups (the first de Casteljau / de Boor level x·Exp(α(t) L)
// with x, L constant and α a jet of time: closed forms, no jet × jet products).
namespace detail
{
/// The jet of f(α(t)) from f, f' and f'' at α_0 = α(t_0) (Faà di Bruno at order 2:
/// c_1 = α_1 f', c_2 = α_2 f' + α_1² f''/2, with α = (α_0, α_1, α_2) the jet's coefficients; a
/// first-order jet keeps c_0 and c_1).
template <int K>
Jet<K> composeJet(double f, double d1, double d2, const Jet<K>& alpha)
{
  static_assert(K == 1 || K == 2, "jets along a subgroup are written to second order");
  Jet<K> r{ typename Jet<K>::NoInit{} };
  const double a1 = alpha.coefficient(1);
  r.coefficient(0) = f;
  r.coefficient(1) = a1 * d1;
  if constexpr (K == 2)
    r.coefficient(2) = alpha.coefficient(2) * d1 + 0.5 * a1 * a1 * d2;
  return r;
}

/// The jet of a rotation q(α(t)) = q_a Exp(α ω) with constant q_a and ω: along a one-parameter
/// subgroup dq/dα = q (0, ω/2) and d²q/dα² = q (0, ω/2)² = −(|ω|²/4) q, so the jet needs one
/// double evaluation of q and one quaternion product of doubles (no jet × jet products).
template <int K>
Quaternion<Jet<K>> rotationLineJet(const Quaternion<double>& q, const Vector3<double>& omega, const Jet<K>& alpha)
{
  const Quaternion<double> d1 = q * Quaternion<double>(0.0, 0.5 * omega.x(), 0.5 * omega.y(), 0.5 * omega.z());
  const double k2 = -0.25 * omega.squaredNorm();
  return Quaternion<Jet<K>>(composeJet(q.w(), d1.w(), k2 * q.w(), alpha), composeJet(q.x(), d1.x(), k2 * q.x(), alpha),
                            composeJet(q.y(), d1.y(), k2 * q.y(), alpha), composeJet(q.z(), d1.z(), k2 * q.z(), alpha));
}

/// The jet of a vector p(α(t)) from p, dp/dα and d²p/dα² at α_0.
template <int K>
Vector3<Jet<K>> vectorJet(const Vector3<double>& p, const Vector3<double>& d1, const Vector3<double>& d2,
                          const Jet<K>& alpha)
{
  return Vector3<Jet<K>>(composeJet(p.x(), d1.x(), d2.x(), alpha), composeJet(p.y(), d1.y(), d2.y(), alpha),
                         composeJet(p.z(), d1.z(), d2.z(), alpha));
}
}  // namespace detail

}  // namespace se3_interpolation
