// timing/: geodesic_timing.h (this header): the time-optimal timing of a chain of geodesic
// segments in closed form.
//
// Along a geodesic segment of the double geodesic, x(λ) = (R_A Exp(λ Ω), (1 − λ) p_A + λ p_B),
// the path derivatives are constant: p′ = (p_B − p_A) λ′, ω_s = R_A Ω λ′ (a fixed spatial
// direction), p″ = p‴ = 0, ω′_s = ω″_s = 0. By the chain rule (time_optimal.h eq. 1,
// jerk_limited.h eq. 1) every channel c then moves at one rate r_c = |C′_c| times the path's:
//   |v_c| = r_c ṡ,   |a_c| = r_c |s̈|,   |j_c| = r_c |s⃛|,
// so the six norm bounds are the scalar bounds ṡ ≤ V, |s̈| ≤ A, |s⃛| ≤ J with V = min_c v_c / r_c
// (and A, J alike) over the channels that move, and the fastest rest-to-rest timing of the segment
// is the 1-DOF one: the trapezoidal velocity profile without a jerk bound, the "double S" with one
// (L. Biagiotti, C. Melchiorri, "Trajectory Planning for Automatic Machines and Robots", Springer
// 2008, §3.2.2 and §3.4; restToRestProfile). On the screw geometry the spatial angular velocity is
// constant too, but p″ = ω_s × p′ (the centripetal term) vanishes only where the twist's rotation
// and translation are parallel (a pure rotation about an axis through the body's origin, a pure
// translation, or a screw along such an axis): such segments are accepted, others are not.
// Acceptance is tested on the path's own exact third-order jets at each piece's middle (constant
// along a geodesic of either geometry): |C″_c| Δ ≤ ε (|C′_c| + δ) and |C‴_c| Δ² ≤ ε (|C′_c| + δ),
// Δ the piece's path-time length, ε = kGeodesicStraightness, δ = kMoveTolerance times the largest
// |C′|. On the double S, ṡ² ≤ A L and ṡ s̈ ≤ J L / 2, ṡ³ ≤ J L² / 4 (L = Δ), so the path terms
// C″ ṡ², 3 C″ ṡ s̈, C‴ ṡ³ that the scalar profile leaves out are at most 3ε of a bound.
//
// Which paths (geodesicChain): `piecewise_geodesic` without blends (PiecewiseGeodesic) and the
// Bézier curve of two control points (BezierCurve, a geodesic at constant rate). The general timing
// stops at velocity corners (breakpoints where C′ jumps, velocityJumps); consecutive pieces without
// a corner between them (collinear waypoints at the rate of the chord parameterisation) are one
// run, timed as one profile over their joint length at the larger of their rates. Each run is
// timed from rest to rest, so the motion stops at every corner, as the general timing's does.
// A piece that does not move (a dwell), a channel that moves without the bounds the general timing
// needs, or a bound that is not finite: no closed form (the general timing serves or refuses it).
//
// The result is exact to rounding: the time-optimal motion itself, where the general timings
// (time_optimal.h, jerk_limited.h) approximate it on a grid and correct by a uniform stretch. Its
// figures (peaks, energy ∫|a|² dt, lengths) are closed forms too.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace timing
{
/// ε of the file comment: the largest share of a bound the path's own curvature terms may take.
constexpr double kGeodesicStraightness = 1e-12;

/// A rest-to-rest 1-DOF motion over `distance` under ṡ ≤ V, |s̈| ≤ A, |s⃛| ≤ J (Biagiotti &
/// Melchiorri §3.4): acceleration phase [0, t_a] (jerk phases of t_j at its ends, the plateau
/// between at ±peak_acceleration), cruise of t_v at peak_speed, and the mirror image of the
/// acceleration phase; t_j = 0 without a jerk bound (the trapezoid).
struct RestToRestProfile
{
  double distance = 0.0;
  double jerk = 0.0;  ///< J (+∞ without a jerk bound)
  double t_j = 0.0;
  double t_a = 0.0;
  double t_v = 0.0;
  double peak_speed = 0.0;
  double peak_acceleration = 0.0;

  double duration() const { return 2.0 * t_a + t_v; }
  /// ∫ s̈² dt over the motion: 2 a² (t_a − 4 t_j / 3) (each jerk phase a² t_j / 3).
  double accelerationEnergy() const { return 2.0 * peak_acceleration * peak_acceleration * (t_a - 4.0 * t_j / 3.0); }
  /// The largest |s⃛|: J with jerk phases, +∞ where the acceleration steps (the trapezoid), 0 at rest.
  double peakJerk() const
  {
    return t_j > 0.0 ? jerk : (peak_acceleration > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  }

  /// s(τ) from the start (a double or a jet of τ), at rest before 0 and after the duration; at a
  /// switch time the phase on `side`. The second half is the first mirrored, s(τ) = L − s(T − τ),
  /// so that s(T) is exactly L; its phase is chosen on τ against the switch times T − t_a,
  /// T − t_a + t_j, T − t_j (a mirrored time T − τ may round across a switch).
  template <class S>
  S position(const S& tau, Side side) const
  {
    const double tv = valueOf(tau);
    const double total = duration();
    const bool left = side == Side::kLeft;
    const auto before = [tv, left](double switch_time) { return tv < switch_time || (tv == switch_time && left); };
    if (before(0.0))
      return S(0.0);
    if (!before(total))
      return S(distance);
    if (before(0.5 * total))
      return phaseValue(before(t_j) ? 1 : before(t_a - t_j) ? 2 : before(t_a) ? 3 : 4, tau);
    const int phase = before(total - t_a) ? 4 : before(total - t_a + t_j) ? 3 : before(total - t_j) ? 2 : 1;
    return S(distance) - phaseValue(phase, S(total) - tau);
  }

  /// The time at which s(τ) = s for 0 ≤ s ≤ distance (bisection to rounding; the ends exactly).
  double timeAt(double s) const;

private:
  /// s on the first half [0, T/2] in phase 1 (jerk J), 2 (acceleration a), 3 (jerk −J) or 4 (cruise).
  template <class S>
  S phaseValue(int phase, const S& tau) const
  {
    const double a = peak_acceleration;
    const double end_of_acceleration = 0.5 * peak_speed * t_a;
    if (phase == 1 && t_j > 0.0)
      return (jerk / 6.0) * (tau * tau * tau);
    if (phase <= 2 || (phase == 3 && !(t_j > 0.0)))
    {
      const S h = tau - S(t_j);
      return S(a * t_j * t_j / 6.0) + (0.5 * a * t_j) * h + (0.5 * a) * (h * h);
    }
    if (phase == 3)
    {
      const S sigma = S(t_a) - tau;
      return S(end_of_acceleration) - peak_speed * sigma + (jerk / 6.0) * (sigma * sigma * sigma);
    }
    return S(end_of_acceleration) + peak_speed * (tau - S(t_a));
  }
};

/// The fastest rest-to-rest motion over distance > 0 under the scalar bounds (+∞ = unbounded).
/// Needs a finite A, or with a finite J a finite V (then the acceleration √(V J) is reached).
/// @return nullopt where the bounds do not determine a finite motion
std::optional<RestToRestProfile> restToRestProfile(double distance, double velocity, double acceleration, double jerk);

/// A run of geodesic pieces between two stops: path parameters [s_begin, s_end], each channel's
/// rate |C′_c| (the largest over its pieces) and whether it moves there.
struct GeodesicRun
{
  double s_begin = 0.0;
  double s_end = 0.0;
  std::array<double, 2> rate{};
  std::array<bool, 2> moves{};
};

/// The path's runs, and the pieces' breakpoints (the waypoints' path times).
struct GeodesicChain
{
  std::vector<GeodesicRun> runs;
  /// Each channel's length ∫|C′_c| ds (translation in m, rotation in rad).
  std::array<double, 2> length{};
  /// Each channel's largest rate |C′_c|: the path's peak speed on its own clock (its acceleration
  /// and jerk are 0 between the waypoints).
  std::array<double, 2> max_rate{};
};

/// The timing of a geodesic chain: one rest-to-rest profile per run, run after run.
struct GeodesicChainProfile
{
  std::vector<GeodesicRun> runs;
  std::vector<RestToRestProfile> profiles;
  std::vector<double> start;  ///< the motion time at which each run starts (start[0]: the path's start)
  std::array<double, 2> max_speed{};
  std::array<double, 2> max_acceleration{};
  std::array<double, 2> max_jerk{};             ///< +∞ where the acceleration steps (no jerk bound)
  std::array<double, 2> acceleration_energy{};  ///< ∫|a_c|² dt per channel

  double startTime() const { return start.front(); }
  double endTime() const { return start.back() + profiles.back().duration(); }
  double duration() const { return endTime() - startTime(); }
  /// The index of the run that motion time t falls in (at a stop, the one on `side`).
  std::size_t runAt(double t, Side side) const;
  /// s(t) (a double or a jet of time), at rest before the start and after the end. A run's end is
  /// its next one's start (exactly: t − start[i] may round off the run's duration).
  template <class S>
  S pathParameter(const S& t, Side side) const
  {
    const double tv = valueOf(t);
    const std::size_t i = runAt(tv, side);
    const double end = i + 1 < start.size() ? start[i + 1] : endTime();
    if (tv > end || (tv == end && side == Side::kRight))
      return S(runs[i].s_end);
    return S(runs[i].s_begin) + profiles[i].position(t - S(start[i]), side);
  }
  /// The motion time at which the path parameter s is passed (at a stop, the arrival); s⁻¹.
  double timeAt(double s) const;
  /// The motion times at which s⃛ may jump (every run's phase switches), sorted, ends included.
  std::vector<double> breakpoints() const;
};

/// The runs of `path` when it is a chain of geodesic pieces with proportional rates (file comment).
/// @return nullopt for any other path
template <class G>
std::optional<GeodesicChain> geodesicChain(const Curve<G>& path);

/// The time-optimal timing of `chain` under `bounds` (their jerk bounds with jerk: pass them as 0
/// for the acceleration-only timing). @return nullopt where a run lacks the bounds that determine it
/// (a moving channel that the general timing refuses without an acceleration bound, all bounds 0).
std::optional<GeodesicChainProfile> geodesicChainProfile(const GeodesicChain& chain, const RateBounds& bounds);

/// The timed motion t ↦ C(s(t)) of a geodesic chain, with jets through the chain rule (as
/// TimeOptimalCurve), third-order ones too.
template <class G>
class GeodesicTimedCurve final : public RetimedCurve<G>, public ThirdOrderJets<G>
{
public:
  using typename ThirdOrderJets<G>::Jet3Point;

  /// @param path the path, its time axis the path parameter s
  /// @param profile the timing along it
  GeodesicTimedCurve(std::shared_ptr<const Curve<G>> path, GeodesicChainProfile profile)
    : RetimedCurve<G>(std::move(path)), profile_(std::move(profile)), snap_(this->base().breakpoints())
  {
  }

  Jet3Point jet3(const Jet<3>& t, Side side) const override
  {
    const Jet<3> s = snap_.snap(profile_.pathParameter(t, side));
    return jet3Of(this->base(), s, pathSide(t.value(), s.value(), side));
  }
  double startTime() const override { return profile_.startTime(); }
  double endTime() const override { return profile_.endTime(); }
  std::vector<double> breakpoints() const override { return profile_.breakpoints(); }

  const GeodesicChainProfile& profile() const { return profile_; }

private:
  double baseTime(double t) const override { return profile_.pathParameter(t, Side::kRight); }
  Jet<2> baseTime(const Jet<2>& t, Side side, Side* path_side) const override
  {
    const Jet<2> s = snap_.snap(profile_.pathParameter(t, side));
    *path_side = pathSide(t.value(), s.value(), side);
    return s;
  }
  /// At a run's ends the path is evaluated inside the run (a stop is a corner of the path).
  Side pathSide(double t, double s, Side side) const
  {
    const GeodesicRun& run = profile_.runs[profile_.runAt(t, side)];
    if (s >= run.s_end)
      return Side::kLeft;
    if (s <= run.s_begin)
      return Side::kRight;
    return side;
  }

  GeodesicChainProfile profile_;
  BreakpointSnap snap_;
};

/// The closed-form time-optimal motion along `path` under `bounds`, or null where the path is not
/// a geodesic chain or the bounds do not determine it (the caller then uses the general timing).
template <class G>
std::shared_ptr<const GeodesicTimedCurve<G>> makeGeodesicTimedCurve(std::shared_ptr<const Curve<G>> path,
                                                                    const RateBounds& bounds)
{
  const std::optional<GeodesicChain> chain = geodesicChain(*path);
  if (!chain)
    return nullptr;
  std::optional<GeodesicChainProfile> profile = geodesicChainProfile(*chain, bounds);
  if (!profile)
    return nullptr;
  return std::make_shared<GeodesicTimedCurve<G>>(std::move(path), std::move(*profile));
}

namespace geodesic_detail
{
/// One piece's rates |C′_c| and whether its curvature terms are within ε (file comment), from its
/// third-order path jet at the middle; `delta` is the piece's path-time length.
struct PieceRates
{
  std::array<double, 2> rate{};
  std::array<double, 2> curvature{};  ///< max(|C″_c| Δ, |C‴_c| Δ²)
};

inline PieceRates pieceRates(const PathJet3& j, double delta)
{
  PieceRates p;
  for (int c = 0; c < 2; ++c)
  {
    p.rate[c] = std::sqrt(j[c].bb);
    p.curvature[c] = std::max(std::sqrt(j[c].aa) * delta, std::sqrt(j[c].cc) * delta * delta);
  }
  return p;
}

/// The chain from the pieces between `b` (sorted breakpoints) and which of them are corners.
std::optional<GeodesicChain> chainOf(const std::vector<double>& b, const std::vector<PieceRates>& pieces,
                                     const std::vector<bool>& corner);

/// Whether `path` is one of the curves made of geodesic pieces at constant rate.
template <class G>
bool madeOfGeodesics(const Curve<G>& path)
{
  if (dynamic_cast<const PiecewiseGeodesic<G>*>(&path) != nullptr)
    return true;
  const auto* bezier = dynamic_cast<const BezierCurve<G>*>(&path);
  return bezier != nullptr && bezier->controlPoints().size() == 2;
}
}  // namespace geodesic_detail

template <class G>
std::optional<GeodesicChain> geodesicChain(const Curve<G>& path)
{
  if (!geodesic_detail::madeOfGeodesics(path))
    return std::nullopt;
  const std::vector<double> b = path.breakpoints();
  std::vector<geodesic_detail::PieceRates> pieces;
  std::vector<bool> corner(b.size(), true);
  pieces.reserve(b.size() - 1);
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
  {
    const double mid = 0.5 * (b[i] + b[i + 1]);
    pieces.push_back(geodesic_detail::pieceRates(pathJet3At(path, mid, Side::kRight), b[i + 1] - b[i]));
    if (i > 0)
      corner[i] = velocityJumps(path, b[i]);
  }
  return geodesic_detail::chainOf(b, pieces, corner);
}

}  // namespace timing
}  // namespace se3_interpolation
