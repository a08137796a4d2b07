// SE(3) with its Ad-invariant (screw) metric: everything the geometry ScrewSe3 provides.
//
// Points: poses (pose.h). Tangent: the body twist (ω, v) of a⁻¹b, rotation first (se(3),
// thesis ch. 5); exp/log through se3Exp/se3Log (math/lie_groups.h). Geodesics are screw
// motions a · Exp(λ Log(a⁻¹ b)). Twist conversion (tangent = body twist (ω_b, v_b) of x⁻¹ y):
//   velocity      (ω_b, v_b) = (Rᵀω, Rᵀṗ)                            (V1)
//     since d/ds x Exp(s ξ) = x ξ^, whose rotation part is Ṙ = R [ω_b]× = [R ω_b]× R and
//     whose translation part is R v_b;
//   acceleration  d/dt (Rᵀω, Rᵀṗ) = (Rᵀω̇, Rᵀ(p̈ − ω × ṗ))            (A1)
//     using Ṙᵀ = −Rᵀ[ω]×, so d/dt(Rᵀω) = Rᵀω̇ − Rᵀ(ω × ω) and d/dt(Rᵀṗ) = Rᵀ(p̈ − ω × ṗ);
//   the inverse map needs the velocity: p̈ = R a_v + ω × ṗ.
// The three-point curve of blended splines is the generic one (curves/blended_spline.h).
#pragma once

#include <array>
#include <type_traits>

#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
/// SE(3) with its Ad-invariant (screw) metric: a · Exp(λ Log(a⁻¹ b)). Bi-invariant.
struct ScrewSe3 : PoseGeometryTypes
{
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
  /// exp(e, v) from the identity, without the product with it.
  template <class S>
  static Point<S> expFromIdentity(const Tangent<S>& v)
  {
    return se3Exp(v);
  }
  /// exp(a, α v) at a jet α of time (first or second order), constant a and v, in closed form:
  /// g(α) = a Exp(α ξ) is a one-parameter subgroup through a, dg/dα = g ξ^ and d²g/dα² = g ξ^ ξ^,
  /// i.e. (quaternion, translation) derivatives (q (0, ω/2), R v) and (−|ω|²/4 q, R (ω × v)).
  template <int K>
  static Point<Jet<K>> expLine(const Point<double>& a, const Tangent<double>& v, const Jet<K>& alpha)
  {
    const Point<double> g = a * se3Exp(Tangent<double>(v * alpha.value()));
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> lin = v.template tail<3>();
    return Point<Jet<K>>(detail::rotationLineJet(g.q, omega, alpha),
                         detail::vectorJet(g.p, g.q * lin, g.q * Vector3<double>(omega.cross(lin)), alpha));
  }
  /// kinematicsFromJet(expLine(a, v, α)) in closed form, without the quaternion jets: with g = a Exp(α ξ),
  /// ξ = (ω, v), the body twist is α̇ ξ, so the spatial angular velocity is α̇ R_g ω = α̇ R_a ω (the
  /// rotation turns about a fixed axis) and its derivative α̈ R_a ω; ṗ = α̇ R_g v and
  /// p̈ = α̇² R_g (ω × v) + α̈ R_g v (expLine's d²g/dα²). Tested to rounding against the jets.
  static Kinematics expLineKinematics(const Point<double>& a, const Tangent<double>& v, const Jet<2>& alpha)
  {
    const Vector3<double> omega = v.template head<3>();
    const Vector3<double> lin = v.template tail<3>();
    const double rate = alpha.coefficient(1);
    const double acceleration = 2.0 * alpha.coefficient(2);
    Kinematics out;
    out.pose = a * se3Exp(Tangent<double>(v * alpha.value()));
    const Vector3<double> axis = out.pose.q * omega;
    const Vector3<double> along = out.pose.q * lin;
    out.velocity.angular = rate * axis;
    out.velocity.linear = rate * along;
    out.acceleration.angular = acceleration * axis;
    out.acceleration.linear = acceleration * along + (rate * rate) * axis.cross(along);
    return out;
  }
};

template <>
struct Se3TangentConversion<ScrewSe3>
{
  /// (V1)
  static Vector6<double> velocity(const Pose<double>& x, const Twist& v)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Vector6<double> xi;
    xi << r.transpose() * v.angular, r.transpose() * v.linear;
    return xi;
  }
  static Twist twist(const Pose<double>& x, const Vector6<double>& xi)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Twist v;
    v.angular = r * xi.head<3>();
    v.linear = r * xi.tail<3>();
    return v;
  }
  /// (A1)
  static Vector6<double> acceleration(const Pose<double>& x, const Twist& v, const Twist& a)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Vector6<double> alpha;
    alpha << r.transpose() * a.angular, r.transpose() * (a.linear - v.angular.cross(v.linear));
    return alpha;
  }
  static Twist twistAcceleration(const Pose<double>& x, const Twist& v, const Vector6<double>& alpha)
  {
    const Eigen::Matrix3d r = x.q.toRotationMatrix();
    Twist a;
    a.angular = r * alpha.head<3>();
    a.linear = r * alpha.tail<3>() + v.angular.cross(v.linear);
    return a;
  }
};

namespace detail
{
/// The smallest sin²φ at which screwSlerpJet takes its weights in closed form at jets of order K:
/// so3SlerpJet's at second order; at third order 0.01 (θ ≥ 0.2 rad), since the 1/sin²φ of B
/// amplifies the rounding of the last coefficient by about 1/sin³φ (measured against the
/// Log → Exp jet path: up to 7e-12 of the coefficients' size at θ = 0.05, within 1e-12 from
/// θ = 0.2). Below it the weights come from their series in φ² (slerpJetWeights, screwTranslationSeriesB).
template <int K>
constexpr double kScrewSlerpJetMinSine2 = K <= 2 ? kSlerpJetMinSine2 : 1e-2;

/// B = (μ sin φ − sin μφ)/(2 sin³φ) (screwSlerpJet's translation weight, μ = 2λ − 1) from x = φ²:
/// μ sin φ − sin μφ = φ³ Σ_{k≥1} (−1)^k μ (1 − μ^{2k}) x^{k−1}/(2k+1)! and sin φ = φ sinSqrtRatio(x)
/// (phi_over_sin = 1/sinSqrtRatio(x)),
/// with 1 − μ^{2k} = (1 − μ²)(1 + μ² + … + μ^{2(k−1)}) summed without cancellation. Seven terms:
/// the first left out is below 1e-19 for μ²x ≤ kSlerpSeriesMaxArgument.
template <int K>
Jet<K> screwTranslationSeriesB(const Jet<K>& mu, const Jet<K>& x, const Jet<K>& phi_over_sin)
{
  using J = Jet<K>;
  static constexpr double kInverseOddFactorial[] = {
    1.0 / 6.0, 1.0 / 120.0, 1.0 / 5040.0, 1.0 / 362880.0, 1.0 / 39916800.0, 1.0 / 6227020800.0, 1.0 / 1307674368000.0
  };
  constexpr std::size_t kTerms = sizeof(kInverseOddFactorial) / sizeof(kInverseOddFactorial[0]);
  const J m = mu * mu;
  // g_k = 1 + m + … + m^{k−1}; the sum Σ_k (−1)^k g_k x^{k−1}/(2k+1)! by Horner from the last term.
  std::array<J, kTerms> g;
  g[0] = J(1.0);
  for (std::size_t k = 1; k < kTerms; ++k)
    g[k] = J(1.0) + m * g[k - 1];
  J sum(0.0);
  for (std::size_t k = kTerms; k-- > 0;)
  {
    const double sign = k % 2 == 0 ? -1.0 : 1.0;
    sum = sum * x + g[k] * (sign * kInverseOddFactorial[k]);
  }
  return mu * (J(1.0) - m) * sum * (phi_over_sin * phi_over_sin * phi_over_sin * 0.5);
}

/// The screw step between jet poses in slerp form (the jet specialisations of geodesic below). A screw
/// motion's rotation is the slerp of the two rotations. Its translation: with the relative
/// rotation q_b q_a* = (cos φ, u), u = sin φ n (half angle φ, world axis n), and Δ = p_b − p_a,
/// the motion slides λ (Δ·n) along n and turns the rest of Δ about the screw axis, where
/// (I − Rot(λ 2φ)) (I − Rot(2φ))⁻¹ = (sin(λφ)/sin φ) Rot((λ − 1)φ) in the plane normal to n; so
///   p(λ) = p_a + A Δ + B (Δ·u) u + C u × Δ,
///   A = sin(λφ) cos((λ − 1)φ)/sin φ = (1 + sin(μφ)/sin φ)/2,
///   B = (λ − A)/sin² φ = (μ sin φ − sin μφ)/(2 sin³φ),
///   C = sin(λφ) sin((λ − 1)φ)/sin² φ = −ka kb   (μ = 2λ − 1; ka, kb the slerp weights)
/// (p(0) = p_a, p(1) = p_b). A and B in closed form from sin²φ ≥ kScrewSlerpJetMinSine2, else from
/// their series in φ². Returns false, leaving *out unchanged, where slerpJetWeights does (a far
/// extrapolation at a small angle): the caller takes the Log → Exp path with its series.
template <int K>
bool screwSlerpJet(const Pose<Jet<K>>& a, const Pose<Jet<K>>& b, const Jet<K>& lambda, Pose<Jet<K>>* out)
{
  using J = Jet<K>;
  SlerpJetWeights<K> k;
  if (!slerpJetWeights(a.q, b.q, lambda, &k, kScrewSlerpJetMinSine2<K>))
    return false;
  // u = sign vec(q_b q_a*) = sign (w_a v_b − w_b v_a + v_a × v_b).
  const Vector3<J> va = a.q.vec();
  const Vector3<J> vb = b.q.vec();
  const Vector3<J> u = (a.q.w() * vb - b.q.w() * va + va.cross(vb)) * k.sign;
  const Vector3<J> delta = b.p - a.p;
  J coefficient_a;
  J coefficient_b;
  if (k.series)
  {
    const J mu = lambda * 2.0 - 1.0;
    coefficient_a = (detail::sinRatioSeries(mu, k.x, k.phi_over_sin) + 1.0) * 0.5;
    coefficient_b = screwTranslationSeriesB(mu, k.x, k.phi_over_sin);
  }
  else
  {
    coefficient_a = k.kb * (k.c * k.w + k.kb * k.n2);
    coefficient_b = (lambda - coefficient_a) / k.n2;
  }
  const J coefficient_c = -(k.ka * k.kb);
  out->q = slerpFromWeights(a.q, b.q, k);
  out->p = a.p + delta * coefficient_a + u * (coefficient_b * delta.dot(u)) + u.cross(delta) * coefficient_c;
  return true;
}

/// dV(Ω)[e_k] w = 2A'Ω_k Ω × w + A e_k × w + 2B'Ω_k Ω × (Ω × w) + B (e_k × (Ω × w) + Ω × (e_k × w)),
/// the derivative of V(Ω) w along e_k, given u = Ω × w, in the scalar S (double, or a first-order
/// jet along Ω), from A, B and A', B' at |Ω|² (screwTransitionDerivatives).
template <class Om, class S, class W, class U>
auto screwLeftDV(const Om& om, const S& a, const S& b, const S& da, const S& db, int k, const W& w, const U& u)
{
  using Vec = std::decay_t<U>;
  const Vec y = Vec::Unit(k);
  const auto yw = y.cross(w).eval();
  const auto dx = 2.0 * om[k];  // 2 Ω·e_k
  return (u * (da * dx) + yw * a + om.cross(u) * (db * dx) + (y.cross(u) + om.cross(yw)) * b).eval();
}

/// V(Ω) e_k, and Q_l(Ω, n) e_k = dV(Ω)[e_k] n − (V(Ω) e_k) × (V(Ω) n) with n = −v, for k < 3, as the
/// columns of *v_columns and *q_columns (screwTransitionDerivatives).
template <class Om, class S, class N, class Columns>
void screwLeftJacobianColumns(const Om& om, const S& a, const S& b, const S& da, const S& db, const N& n,
                              Columns* v_columns, Columns* q_columns)
{
  const auto un = om.cross(n).eval();
  const auto vn = (n + un * a + om.cross(un) * b).eval();
  for (int k = 0; k < 3; ++k)
  {
    using Vec = std::decay_t<decltype(un)>;
    const Vec y = Vec::Unit(k);
    const auto uy = om.cross(y).eval();
    const auto vy = (y + uy * a + om.cross(uy) * b).eval();
    v_columns->col(k) = vy;
    q_columns->col(k) = screwLeftDV(om, a, b, da, db, k, n, un) - vy.cross(vn);
  }
}

/// The derivatives D = dF(0) and Q = d²F(0) of the chart transition F(δ) = Log(Exp(−L) Exp(L + δ))
/// (the C² solve's map between the charts at a segment's ends, chart_transition.h), in closed
/// form. With g(s) = Exp(−L) Exp(L + s d), g⁻¹ ġ = J_r(L + s d) d = J_r(F) Ḟ (J_r the right
/// Jacobian of SE(3)), so Ḟ(0) = J_r(L) d and F̈(0) = dJ_r(L)[d] d (the term of J_r(F)⁻¹ is
/// ½ ad_Ḟ Ḟ = 0): D = J_r(L) and Q(e_a, e_b) = ½ (dJ_r(L)[e_a] e_b + dJ_r(L)[e_b] e_a).
/// J_r(ξ) = J_l(−ξ), and the left Jacobian of ξ = (ω, v) is
///   J_l(ξ) η = (V(ω) η_ω, Q_l(ω, v) η_ω + V(ω) η_v),  Q_l(ω, v) y = dV(ω)[y] v − (V(ω) y) × (V(ω) v)
/// (the translation part of d/dε Exp(ξ + ε η) Exp(ξ)⁻¹ with Exp(ξ) = (Exp(ω), V(ω) v); V the left
/// Jacobian of SO(3), V(ω) w = w + A ω × w + B ω × (ω × w), screwCoefficients). J_r depends on v
/// linearly and only through Q_l, so its derivatives along the rotation coordinates come from
/// first-order jets of ω and along the translation coordinates from doubles. Tested against the
/// second-order jets of F itself (unitFrameTransition).
inline void screwTransitionDerivatives(const Vector6<double>& log, Eigen::Matrix<double, 6, 6>* d,
                                       Eigen::Matrix<double, 6, 36>* q)
{
  using J1 = Jet<1>;
  const Vector3<double> omega = -log.head<3>();  // J_r(L) = J_l(−L)
  const Vector3<double> lin = -log.tail<3>();
  const double x = omega.squaredNorm();
  const ScrewCoefficients c = screwCoefficients(x);
  const ScrewSecondDerivatives c2 = screwSecondDerivatives(x, c);
  // dJ_r(L)[e_j], j < 3: along the rotation, Ω(s) = −(ω_L + s e_j), from first-order jets.
  std::array<Eigen::Matrix<double, 6, 6>, 3> rotation_derivative;
  for (int j = 0; j < 3; ++j)
  {
    Vector3<J1> om = omega.cast<J1>();
    om[j].coefficient(1) = -1.0;
    const double dx = -2.0 * omega[j];
    J1 ja(c.a), jb(c.b), jda(c.da), jdb(c.db);
    ja.coefficient(1) = c.da * dx;
    jb.coefficient(1) = c.db * dx;
    jda.coefficient(1) = c2.dda * dx;
    jdb.coefficient(1) = c2.ddb * dx;
    Eigen::Matrix<J1, 3, 3> v_columns, q_columns;
    screwLeftJacobianColumns(om, ja, jb, jda, jdb, Vector3<J1>(lin.cast<J1>()), &v_columns, &q_columns);
    rotation_derivative[j].setZero();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
      {
        if (j == 0)
        {
          (*d)(r, k) = v_columns(r, k).value();
          (*d)(3 + r, 3 + k) = v_columns(r, k).value();
          (*d)(3 + r, k) = q_columns(r, k).value();
          (*d)(r, 3 + k) = 0.0;
        }
        rotation_derivative[j](r, k) = v_columns(r, k).coefficient(1);
        rotation_derivative[j](3 + r, 3 + k) = v_columns(r, k).coefficient(1);
        rotation_derivative[j](3 + r, k) = q_columns(r, k).coefficient(1);
      }
  }
  // dJ_r(L)[e_{3+b}] e_a = (0, ∂Q_l/∂v_b e_a) = (0, −dV(Ω)[e_a] e_b + V(Ω) e_a × V(Ω) e_b) for a < 3
  // (N = −v, Q_l linear in it), and 0 on the translation coordinates.
  auto translationDerivative = [&](int a_index, int b_index) {
    const Vector3<double> w = Vector3<double>::Unit(b_index);
    return Vector3<double>(-screwLeftDV(omega, c.a, c.b, c.da, c.db, a_index, w, Vector3<double>(omega.cross(w))) +
                           d->block<3, 1>(0, a_index).cross(d->block<3, 1>(0, b_index)));
  };
  q->setZero();
  for (int a = 0; a < 3; ++a)
  {
    for (int b = 0; b < 3; ++b)
      q->col(6 * a + b) = 0.5 * (rotation_derivative[a].col(b) + rotation_derivative[b].col(a));
    for (int b = 0; b < 3; ++b)
    {
      Vector6<double> mixed = 0.5 * rotation_derivative[a].col(3 + b);
      mixed.tail<3>() += 0.5 * translationDerivative(a, b);
      q->col(6 * a + 3 + b) = mixed;
      q->col(6 * (3 + b) + a) = mixed;
    }
  }
}

/// The screw step between jet poses: screwSlerpJet, else (a far extrapolation at a small angle)
/// the SE(3) Log → Exp in jets.
template <int K>
Pose<Jet<K>> screwGeodesicJet(const Pose<Jet<K>>& a, const Pose<Jet<K>>& b, const Jet<K>& lambda)
{
  Pose<Jet<K>> out;
  if (!screwSlerpJet(a, b, lambda, &out))
    out = ScrewSe3::exp(a, Vector6<Jet<K>>(ScrewSe3::log(a, b) * lambda));
  return out;
}
}  // namespace detail

/// The screw step between jet poses (levels ≥ 2 of the recursions when derivatives are sampled;
/// detail::screwGeodesicJet).
template <>
inline Pose<Jet<2>> geodesic<ScrewSe3, Jet<2>>(const Pose<Jet<2>>& a, const Pose<Jet<2>>& b, const Jet<2>& lambda)
{
  return detail::screwGeodesicJet(a, b, lambda);
}

/// The screw step between first-order jet poses (the speeds of the path's length, analysis/figures.h).
template <>
inline Pose<Jet<1>> geodesic<ScrewSe3, Jet<1>>(const Pose<Jet<1>>& a, const Pose<Jet<1>>& b, const Jet<1>& lambda)
{
  return detail::screwGeodesicJet(a, b, lambda);
}

/// The screw step between third-order jet poses (the jerk-limited timing's path jets).
template <>
inline Pose<Jet<3>> geodesic<ScrewSe3, Jet<3>>(const Pose<Jet<3>>& a, const Pose<Jet<3>>& b, const Jet<3>& lambda)
{
  return detail::screwGeodesicJet(a, b, lambda);
}

}  // namespace se3_interpolation
