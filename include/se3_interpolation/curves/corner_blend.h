// Corner blending for waypoint paths: `piecewise_geodesic` with `blend_radius`.
//
// The polyline of geodesics x_{i−1} → x_i (piecewise_geodesic, bezier.h) stops
// dead or jumps in velocity at every interior waypoint. With a blend radius r each interior
// corner x_i is replaced by a blend that
//   * leaves the incoming geodesic at the point a_i whose chord distance
//     D(x, y) = sqrt(|p_x − p_y|² + (ρ θ(R_xᵀ R_y))²)   (ρ = rotation_scale, docs/timing.md)
//     from x_i is r_i = min(r, D(x_{i−1}, x_i)/2, D(x_i, x_{i+1})/2), and joins the outgoing
//     geodesic at the point b_i at distance r_i;
//   * starts at the time t_i − τ_in and ends at t_i + τ_out at which the polyline itself is
//     at a_i and b_i, so outside [t_i − τ_in, t_i + τ_out] path and timing are exactly the
//     polyline's (same poses at the same times);
//   * is C² with the constant-rate geodesic legs at both ends (pose, velocity, acceleration).
// The interior waypoints are no longer passed through; the first and last are.
//
// Construction (written once over the geometry G), relative to the corner: both geometries are
// invariant under left multiplication by a pose (Prop. 4.2.1), so β(t) = x_i · B(λ(t)).
//   Path. With L_in = Log(e, x_i⁻¹ a_i) and L_out = Log(e, x_i⁻¹ b_i) (the legs from the corner
//   are the one-parameter subgroups α ↦ exp(e, α L), so L_in = s_in Log(e, x_i⁻¹ x_{i−1}) for the
//   leg parameter s_in of a_i, likewise L_out), the blend is the quartic Bézier curve in the
//   exponential chart at the corner with the control points a_i, the midpoint of a_i x_i, x_i,
//   the midpoint of x_i b_i and b_i, whose logs are L_in, L_in/2, 0, L_out/2, L_out:
//     B(λ) = exp(e, w_in(λ) L_in + w_out(λ) L_out),   w_in = B₀ + B₁/2 = (1 − λ)³(1 + λ),
//                                                     w_out = B₃/2 + B₄ = λ³(2 − λ) = w_in(1 − λ)
//   (B_k the quartic Bernstein polynomials). w_in = 1 − 2λ + 2λ³ − λ⁴ and w_out = O(λ³), so at λ = 0
//   the curve has the 2-jet of λ ↦ exp(e, (1 − 2λ) L_in), the incoming leg from a_i at constant
//   rate 2 L_in with zero geodesic acceleration (exp of a perturbation O(λ³) changes only the
//   third and higher derivatives); by the symmetry w_out(λ) = w_in(1 − λ), at λ = 1 the outgoing leg's
//   2-jet, exp(e, (2λ − 1) L_out). A collinear corner at one speed (L_out = −L_in) gives
//   exp(e, (1 − 2λ) L_in): the leg itself. One exp per point, in closed form in every geometry,
//   and bi-invariant for screw (Ad commutes with the linear combination).
//   Timing. The legs move at constant rate: Log(a_i, x_i) in τ_in, Log(x_i, b_i) in τ_out.
//   So dλ/dt must be 1/(2τ_in) at the start and 1/(2τ_out) at the end, with d²λ/dt² = 0 at
//   both ends. With t = ψ(λ) = t_i − τ_in + 2τ_in λ + 2(τ_out − τ_in)(λ³ − λ⁴/2):
//     ψ(0) = t_i − τ_in, ψ(1) = t_i + τ_out, ψ'(λ) = 2τ_in + 2(τ_out − τ_in)(3λ² − 2λ³)
//   (between 2τ_in and 2τ_out: strictly increasing), ψ''(0) = ψ''(1) = 0; λ(t) = ψ⁻¹(t).
//   When τ_in = τ_out (the default chord parameterisation moves at one chord speed) ψ is
//   affine. λ is found by safeguarded Newton in double, then two Newton steps in the jet
//   arithmetic give its exact first and second derivatives (each step doubles the number
//   of correct Taylor coefficients; implicit function theorem), so derivatives stay
//   analytic.
//   The classical construction in Rⁿ (pure translations): the chart is Rⁿ itself, so this is
//   the Euclidean quartic Bézier curve with the control points above, at λ = ψ⁻¹(t); when
//   τ_in = τ_out it is the quintic Hermite interpolant with zero end accelerations (its degree
//   elevation has the quintic's control points a, a + 2v τ/5, a + 4v τ/5, …). Rotations about
//   one axis likewise give the Euclidean quartic in the angle.
//   Within the ball. w_in, w_out ≥ 0 and w_in + w_out ≤ 1. For double_geodesic
//   exp(e, w_in L_in + w_out L_out) turns by at most w_in θ_in + w_out θ_out and translates by
//   w_in Δp_in + w_out Δp_out, so by the triangle inequality in R⁴ its chord distance
//   sqrt(|Δp|² + (ρθ)²) from the corner is at most (w_in + w_out) r_i ≤ r_i.
//   For screw (whose exp turns the translation, V(ω) v) this is checked by the tests, not proven.
// Numerics. Differences of nearby absolute poses never enter (the chart is at the corner and its
// logs are exact multiples of the legs' logs from the corner), so a blend of radius 1e−12 m keeps
// full relative precision.
//
// Requirements on G: Point = Pose<S>, invariant under left multiplication, tangents such
// that Log(e, exp(e, s v)) = s v for the legs' parameters s ≤ 1/2 (ScrewSe3, DoubleGeodesicSe3),
// and G::expFromIdentity.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/deadline.h"

namespace se3_interpolation
{
namespace detail
{
/// The chord distance of a pose from the identity: sqrt(|p|² + (ρ θ)²).
inline double chordFromIdentity(const Pose<double>& x, double rotation_scale)
{
  return chordDistance(Pose<double>::Identity(), x, rotation_scale);
}

/// The parameter s ∈ [0, 1/2] at which exp(e, s v) is at chord distance r from e, given
/// that the whole leg (s = 1) is at distance d ≥ 2r. The rotation angle along the leg is
/// s θ (both geometries rotate at a constant rate); the translation is s Δp for
/// double_geodesic (so s = r/d) and a helix for screw, whose chord grows monotonically
/// while the angle s θ < π. Safeguarded Newton on D(s)² − r² from the straight-line value r/d.
template <class G>
double legParameterAtDistance(const typename G::template Tangent<double>& v, double d, double r, double rotation_scale)
{
  using J = Jet<1>;
  const double rho_theta = rotation_scale * v.template head<3>().norm();
  auto f = [&](double s, double* df) {
    const J js = J::variable(s);
    const Pose<J> x = G::exp(Pose<J>(), typename G::template Tangent<J>(v.template cast<J>() * js));
    const J rt = js * rho_theta;
    const J g = x.p.squaredNorm() + rt * rt - r * r;
    *df = g.coefficient(1);
    return g.value();
  };
  double lo = 0.0;
  double hi = 0.5;
  double s = std::min(hi, r / d);
  for (int it = 0; it < 100; ++it)
  {
    double df = 0.0;
    const double g = f(s, &df);
    if (g == 0.0)
      return s;
    (g < 0.0 ? lo : hi) = s;
    double next = df > 0.0 ? s - g / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi))
      next = 0.5 * (lo + hi);
    if (std::abs(next - s) <= 4.0 * std::numeric_limits<double>::epsilon() * s)
      return next;
    s = next;
  }
  return s;
}
}  // namespace detail

/// Corners built between two checks of the request's deadline (deadline.h).
constexpr std::size_t kCornersPerDeadlineCheck = 1024;

/// One blended corner: the waypoint, its radius r_i and the blend's time interval.
struct CornerBlendZone
{
  std::size_t corner = 0;   ///< index i of the interior waypoint
  double radius = 0.0;      ///< r_i, m (chord distance)
  double start_time = 0.0;  ///< t_i − τ_in
  double end_time = 0.0;    ///< t_i + τ_out
};

/// `piecewise_geodesic` with `blend_radius` > 0: the polyline with each interior corner
/// replaced by the C² blend described above. With blend_radius = 0 it is the polyline.
template <class G>
class CornerBlendedGeodesic final : public CurveBase<G, CornerBlendedGeodesic<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;
  using Tangent = typename G::template Tangent<double>;

  /// @param points the polyline's vertices x_0 … x_{N−1} (N ≥ 2)
  /// @param times strictly increasing t_0 … t_{N−1}, the polyline's times (s)
  /// @param blend_radius r ≥ 0 (m, chord distance); each corner's own radius is r_i (see above)
  /// @param rotation_scale ρ (m per rad) of the chord distance
  /// @param label the points' name in error messages (`label[i]`)
  /// @throws NonUniqueGeodesicError if two consecutive points are antipodal
  CornerBlendedGeodesic(std::vector<Point> points, std::vector<double> times, double blend_radius,
                        double rotation_scale, const std::string& label = "waypoints")
    : points_(std::move(points)), times_(std::move(times)), logs_(polygonLogs<G>(points_, label))
  {
    const std::size_t n = points_.size();
    std::vector<double> chord(n - 1);
    for (std::size_t j = 0; j + 1 < n; ++j)
      chord[j] = detail::chordFromIdentity(points_[j].inverseTimes(points_[j + 1]), rotation_scale);
    for (std::size_t i = 1; i + 1 < n; ++i)
    {
      checkDeadlineEvery(i, kCornersPerDeadlineCheck, "blend_radius: the corner blends");
      const double r = std::min({ blend_radius, 0.5 * chord[i - 1], 0.5 * chord[i] });
      if (!(r > 0.0))
        continue;
      Blend b;
      b.zone.corner = i;
      b.zone.radius = r;
      const Point e = Point::Identity();
      // Logs from the corner back along the incoming leg and on along the outgoing one.
      const Tangent m_in = G::log(e, points_[i].inverseTimes(points_[i - 1]));
      const Tangent m_out = G::log(e, points_[i].inverseTimes(points_[i + 1]));
      const double s_in = detail::legParameterAtDistance<G>(m_in, chord[i - 1], r, rotation_scale);
      const double s_out = detail::legParameterAtDistance<G>(m_out, chord[i], r, rotation_scale);
      // τ from s (not from the rounded start and end times: for a tiny radius those differences
      // would lose the relative precision of the blend's rate).
      b.tau_in = s_in * (times_[i] - times_[i - 1]);
      b.tau_out = s_out * (times_[i + 1] - times_[i]);
      b.zone.start_time = times_[i] - b.tau_in;
      b.zone.end_time = times_[i] + b.tau_out;
      b.corner_point = points_[i];
      // A radius too small to move the blend's ends off t_i in floating point: a sharp corner.
      if (!(b.zone.start_time < times_[i] && times_[i] < b.zone.end_time))
        continue;
      b.leg_in = m_in * s_in;
      b.leg_out = m_out * s_out;
      blends_.push_back(std::move(b));
    }
    // Two blends sharing a leg meet at its middle at most (r_i ≤ half of each leg); rounding
    // may let them overlap by an ulp: then they meet at the mean of the two times.
    for (std::size_t k = 0; k + 1 < blends_.size(); ++k)
    {
      CornerBlendZone& a = blends_[k].zone;
      CornerBlendZone& b = blends_[k + 1].zone;
      const std::size_t j = a.corner;
      if (b.corner != j + 1)
        continue;
      const double gap = b.start_time - a.end_time;
      if (gap <= 1e-12 * (times_[j + 1] - times_[j]))
      {
        a.end_time = b.start_time = 0.5 * (a.end_time + b.start_time);
        blends_[k].tau_out = a.end_time - times_[j];
        blends_[k + 1].tau_in = times_[j + 1] - b.start_time;
      }
    }
    buildPieces();
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const Piece& piece = pieces_[findInterval(breaks_, valueOf(t), side)];
    if (piece.blend < 0)
    {
      const std::size_t j = piece.segment;
      const S lambda = (t - S(times_[j])) * S(1.0 / (times_[j + 1] - times_[j]));
      return geodesicFromLog<G>(points_[j], logs_[j], lambda);
    }
    const Blend& b = blends_[static_cast<std::size_t>(piece.blend)];
    // Time into the blend, measured from its nearer end so that both ends map exactly to
    // λ = 0 and 1 however short the blend is next to the magnitude of t.
    const S u = valueOf(t) < times_[b.zone.corner] ? S(t - S(b.zone.start_time)) :
                                                     S(S(t - S(b.zone.end_time)) + S(b.tau_in + b.tau_out));
    const PointT<S> relative = blendFromCorner(b, blendParameter(b, u));
    if constexpr (std::is_same<S, double>::value)
      return b.corner_point * relative;
    else
      return constantTimes(b.corner_point, relative);
  }

  double startTime() const override { return times_.front(); }
  double endTime() const override { return times_.back(); }
  std::vector<double> breakpoints() const override { return breaks_; }
  std::vector<Point> controlPoints() const override { return points_; }

  /// The blended corners, in order (corners with r_i = 0 are not listed).
  std::vector<CornerBlendZone> zones() const
  {
    std::vector<CornerBlendZone> z;
    for (const Blend& b : blends_)
      z.push_back(b.zone);
    return z;
  }
  /// r_i per waypoint (0 at the ends and at corners left sharp).
  std::vector<double> radii() const
  {
    std::vector<double> r(points_.size(), 0.0);
    for (const Blend& b : blends_)
      r[b.zone.corner] = b.zone.radius;
    return r;
  }

private:
  struct Blend
  {
    CornerBlendZone zone;
    Point corner_point;
    double tau_in = 0.0;
    double tau_out = 0.0;
    Tangent leg_in;   ///< L_in = s_in m_in = Log(e, x_i⁻¹ a_i), the blend's start from the corner
    Tangent leg_out;  ///< L_out = s_out m_out = Log(e, x_i⁻¹ b_i), its end
  };
  /// A piece between consecutive breakpoints: a part of leg `segment` or blend `blend`.
  struct Piece
  {
    std::size_t segment = 0;
    int blend = -1;
  };

  void buildPieces()
  {
    breaks_.assign(1, times_.front());
    std::size_t next_blend = 0;
    for (std::size_t j = 0; j + 1 < times_.size(); ++j)
    {
      const double leg_end = next_blend < blends_.size() && blends_[next_blend].zone.corner == j + 1 ?
                                 blends_[next_blend].zone.start_time :
                                 times_[j + 1];
      if (leg_end > breaks_.back() || j == 0)
      {
        breaks_.push_back(leg_end);
        pieces_.push_back(Piece{ j, -1 });
      }
      if (next_blend < blends_.size() && blends_[next_blend].zone.corner == j + 1)
      {
        breaks_.push_back(blends_[next_blend].zone.end_time);
        pieces_.push_back(Piece{ j + 1, static_cast<int>(next_blend) });
        ++next_blend;
      }
    }
  }

  /// B(λ) = x_i⁻¹ β = exp(e, w_in(λ) L_in + w_out(λ) L_out) (see "Construction" above).
  template <class S>
  static PointT<S> blendFromCorner(const Blend& b, const S& lambda)
  {
    const S rest = S(1.0) - lambda;
    const S in_weight = rest * rest * rest * (S(1.0) + lambda);         // w_in = (1 − λ)³(1 + λ)
    const S out_weight = lambda * lambda * lambda * (S(2.0) - lambda);  // w_out = λ³(2 − λ)
    typename G::template Tangent<S> log;
    for (int k = 0; k < 6; ++k)
      log[k] = in_weight * b.leg_in[k] + out_weight * b.leg_out[k];
    return G::expFromIdentity(log);
  }

  /// λ = ψ⁻¹(t) for u = t − (t_i − τ_in): Newton in double, then two Newton steps in S.
  template <class S>
  static S blendParameter(const Blend& b, const S& u)
  {
    const double a = 2.0 * b.tau_in;
    const double c = 2.0 * (b.tau_out - b.tau_in);
    auto psi = [a, c](const auto& l) { return a * l + c * (l * l * l) * (1.0 - 0.5 * l); };
    auto dpsi = [a, c](const auto& l) { return a + c * (l * l) * (3.0 - 2.0 * l); };
    const double target = valueOf(u);
    const double total = b.tau_in + b.tau_out;
    double lo = 0.0;
    double hi = 1.0;
    double l = std::min(1.0, std::max(0.0, target / total));
    for (int it = 0; it < 60; ++it)
    {
      const double g = psi(l) - target;
      if (g == 0.0)
        break;
      (g < 0.0 ? lo : hi) = l;
      double next = l - g / dpsi(l);
      if (!(next >= lo && next <= hi))
        next = 0.5 * (lo + hi);
      const bool done = std::abs(next - l) <= 2.0 * std::numeric_limits<double>::epsilon();
      l = next;
      if (done)
        break;
    }
    S lambda(l);
    for (int step = 0; step < 2; ++step)
      lambda = lambda - (psi(lambda) - u) / dpsi(lambda);
    return lambda;
  }

  std::vector<Point> points_;
  std::vector<double> times_;
  std::vector<Tangent> logs_;
  std::vector<Blend> blends_;
  std::vector<double> breaks_;
  std::vector<Piece> pieces_;
};

}  // namespace se3_interpolation
