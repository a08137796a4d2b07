// timing/: path_jet3.h (this header): the third-order jets of a path, which the jerk-limited
// timing (jerk_limited.h) and the peak jerk of a curve (jerk_peaks.h) read; in a header of their
// own because they depend on the curves and their kinematics only, not on any timing.
//
// Along a path C(s) the rates of one channel under a timing s(t) are, by the chain rule
//   v = C′ ṡ,   a = C″ ṡ² + C′ s̈,   j = C‴ ṡ³ + 3 C″ ṡ s̈ + C′ s⃛                      (1)
// (jerk_limited.h's eq. 1), so their norms need only the inner products of C′, C″ and C‴
// (ChannelJet3). Those come exactly from the curve's third-order jet in s (curve.h, jet3Of): of a
// pose curve (p′, p″, p‴) and the spatial (ω_s, ω′_s, ω″_s) (kinematics3FromJet), of a sphere
// curve the covariant derivatives (sphereKinematics3FromJet). accelerationJumps tells where C″
// jumps at a breakpoint (a C¹ joint, where a motion that moves on has an unbounded jerk).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/curve.h"

namespace se3_interpolation
{
namespace timing
{
/// The inner products of one channel's path derivatives b = C′, a = C″, c = C‴ that the rates of
/// eq. 1 need (their Gram matrix).
struct ChannelJet3
{
  double bb = 0.0, ab = 0.0, aa = 0.0, bc = 0.0, ac = 0.0, cc = 0.0;

  /// |C′ ṡ|.
  double speed(double sd) const { return std::sqrt(bb) * sd; }
  /// |C″ ṡ² + C′ s̈|.
  double acceleration(double sd, double sdd) const
  {
    const double x = sd * sd;
    return std::sqrt(std::max(0.0, aa * x * x + 2.0 * ab * x * sdd + bb * sdd * sdd));
  }
  /// |C′ s⃛ + 3 C″ ṡ s̈ + C‴ ṡ³|.
  double jerk(double sd, double sdd, double sddd) const
  {
    const double y0 = sddd, y1 = 3.0 * sd * sdd, y2 = sd * sd * sd;
    return std::sqrt(std::max(0.0, bb * y0 * y0 + aa * y1 * y1 + cc * y2 * y2 + 2.0 * ab * y0 * y1 +
                                       2.0 * bc * y0 * y2 + 2.0 * ac * y1 * y2));
  }
};

/// Both channels at one path parameter.
using PathJet3 = std::array<ChannelJet3, 2>;

template <class V>
ChannelJet3 channelJet3(const V& b, const V& a, const V& c)
{
  ChannelJet3 j;
  j.bb = b.squaredNorm();
  j.ab = a.dot(b);
  j.aa = a.squaredNorm();
  j.bc = b.dot(c);
  j.ac = a.dot(c);
  j.cc = c.squaredNorm();
  return j;
}

/// Velocity, acceleration and jerk of a pose curve at one instant (spatial: ṗ, p̈, p⃛ and ω, ω̇, ω̈).
using Kinematics3 = MotionRates3;

/// The path jet of the rates (each part in one frame of its own: a rotation keeps the products).
inline PathJet3 pathJet3(const MotionRates3& r)
{
  return { channelJet3(r.velocity.linear, r.acceleration.linear, r.jerk.linear),
           channelJet3(r.velocity.angular, r.acceleration.angular, r.jerk.angular) };
}

/// From the third-order jet of a pose (coefficients c_k = q^(k)/k!): ω = 2 vec(q̇ q*),
/// ω̇ = 2 vec(q̈ q*), ω̈ = 2 vec(q⃛ q* + q̈ q̇*) (q̇ q̇* = |q̇|² is real).
inline Kinematics3 kinematics3FromJet(const Pose<Jet<3>>& x)
{
  Kinematics3 k;
  std::array<Quaternion<double>, 4> q;
  for (int c = 0; c < 4; ++c)
  {
    q[c] = Quaternion<double>(x.q.w().coefficient(c), x.q.x().coefficient(c), x.q.y().coefficient(c),
                              x.q.z().coefficient(c));
    if (c < 3)
      for (int i = 0; i < 3; ++i)
      {
        k.velocity.linear[i] = x.p[i].coefficient(1);
        k.acceleration.linear[i] = 2.0 * x.p[i].coefficient(2);
        k.jerk.linear[i] = 6.0 * x.p[i].coefficient(3);
      }
  }
  const Quaternion<double> q0c = q[0].conjugate();
  k.velocity.angular = 2.0 * (q[1] * q0c).vec();
  k.acceleration.angular = 4.0 * (q[2] * q0c).vec();
  k.jerk.angular = 12.0 * (q[3] * q0c).vec() + 4.0 * (q[2] * q[1].conjugate()).vec();
  return k;
}

/// The covariant velocity, acceleration and jerk of a sphere curve at one instant: of the jet
/// normalised onto the sphere y = x/|x| (exactly, in jet arithmetic), ẏ, P(ÿ) and
/// P(y⃛) + |ẏ|² ẏ (the covariant derivative of P(ÿ) = ÿ + |ẏ|² y; P the tangent projection).
inline std::array<Eigen::VectorXd, 3> sphereKinematics3FromJet(const VectorX<Jet<3>>& x)
{
  const Eigen::Index n = x.size();
  Jet<3> r2(0.0);
  for (Eigen::Index i = 0; i < n; ++i)
    r2 += x[i] * x[i];
  const Jet<3> r = sqrt(r2);
  Eigen::VectorXd y(n), y1(n), y2(n), y3(n);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Jet<3> yi = x[i] / r;
    y[i] = yi.value();
    y1[i] = yi.coefficient(1);
    y2[i] = 2.0 * yi.coefficient(2);
    y3[i] = 6.0 * yi.coefficient(3);
  }
  const Eigen::VectorXd acceleration = y2 - y.dot(y2) * y;
  const Eigen::VectorXd jerk = y3 - y.dot(y3) * y + y1.squaredNorm() * y1;
  return { y1, acceleration, jerk };
}

/// The third-order path derivatives from a curve's third-order jet in s: of a pose curve,
/// (p′, p″, p‴) and (ω_s, ω′_s, ω″_s).
template <class G>
struct PathJet3FromJet
{
  static PathJet3 of(const Pose<Jet<3>>& x) { return pathJet3(kinematics3FromJet(x)); }
};

/// On S^m only the angular channel moves.
template <>
struct PathJet3FromJet<Sphere>
{
  static PathJet3 of(const VectorX<Jet<3>>& x)
  {
    const auto k = sphereKinematics3FromJet(x);
    return { ChannelJet3(), channelJet3(k[0], k[1], k[2]) };
  }
};

/// The third-order path derivatives of a curve at s (PathJet3FromJet).
/// Throws InvalidInputError for a curve without third-order jets (jet3Of).
template <class G>
PathJet3 pathJet3At(const Curve<G>& curve, double s, Side side)
{
  return PathJet3FromJet<G>::of(jet3Of(curve, Jet<3>::variable(s), side));
}

inline PathJet3 pathJet3At(const Curve<Sphere>& curve, double s, Side side)
{
  return PathJet3FromJet<Sphere>::of(jet3Of(curve, Jet<3>::variable(s), side));
}

/// Relative jump of C″ across a breakpoint above which the motion must stop there (a jump of C″
/// at ṡ > 0 is a jump of the acceleration). Measured against |C″| on both sides plus |C′|/h (h the
/// shorter adjacent piece: the scale of C″ where the path hardly bends); far above the one-sided
/// jets' rounding and the interpolating solve's residual at the joints of C² curves (~1e-12).
constexpr double kAccelerationJumpTolerance = 1e-6;

/// Whether C″ jumps at the breakpoint s between pieces of which the shorter is h long.
template <class G>
bool accelerationJumps(const Curve<G>& curve, double s, double h)
{
  const Kinematics l = kinematicsAt(curve, s, Side::kLeft);
  const Kinematics r = kinematicsAt(curve, s, Side::kRight);
  auto jumps = [h](const Eigen::Vector3d& al, const Eigen::Vector3d& ar, const Eigen::Vector3d& v) {
    return (al - ar).norm() > kAccelerationJumpTolerance * (al.norm() + ar.norm() + v.norm() / h);
  };
  return jumps(l.acceleration.linear, r.acceleration.linear, l.velocity.linear) ||
         jumps(l.acceleration.angular, r.acceleration.angular, l.velocity.angular);
}

inline bool accelerationJumps(const Curve<Sphere>& curve, double s, double h)
{
  const SphereKinematics l = kinematicsAt(curve, s, Side::kLeft);
  const SphereKinematics r = kinematicsAt(curve, s, Side::kRight);
  return (l.acceleration - r.acceleration).norm() >
         kAccelerationJumpTolerance * (l.acceleration.norm() + r.acceleration.norm() + l.velocity.norm() / h);
}

}  // namespace timing
}  // namespace se3_interpolation
