// Optional peers of the benchmarks, compiled in only when a local copy is given by path
// (scripts/run_benchmarks.sh and scripts/instruction_counts.sh: SE3_BENCH_SOPHUS_DIR,
// SE3_BENCH_MANIF_DIR, SE3_BENCH_BASALT_DIR, which define SE3_BENCH_SOPHUS / _MANIF / _BASALT and
// add the include paths; basalt-headers needs Sophus as well). Nothing of the peers is part of
// the project: they are read from the given directories at build time only.
//
// Operations (the same inputs as the project's rows, bench_fixtures.h):
//  - Sophus / manif SE(3) exp and log, and the screw step a Exp(λ Log(a⁻¹ b)) written with
//    their groups: the same mathematics as se3Exp / se3Log / geodesic<ScrewSe3>; checked equal
//    to 1e-9 (their tangent is (v, ω), ours (ω, v)).
//  - basalt's cumulative uniform cubic B-spline (So3Spline<4> and RdSpline<3, 4>, the SO(3) × R³
//    spline of Se3Spline) point, and point + velocity + acceleration. Not the same curve as the
//    project's de Boor geodesic recursion in SO(3) (the cumulative form composes Exp of weighted
//    relative logs); what is the same and checked to 1e-9: the translation (both the Euclidean
//    cubic B-spline of the control points on uniform knots) with its velocity and acceleration,
//    and the whole pose, angular velocity and acceleration when every control rotation turns
//    about one fixed axis (the abelian case, where both reduce to the scalar B-spline of the angle).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_fixtures.h"

#ifdef SE3_BENCH_SOPHUS
#include <sophus/se3.hpp>
#endif
#ifdef SE3_BENCH_MANIF
#include <manif/SE3.h>
#endif
#ifdef SE3_BENCH_BASALT
#include <basalt/spline/rd_spline.h>
#include <basalt/spline/so3_spline.h>
#endif

namespace se3_bench
{
/// (ω, v) → (v, ω): our twist order to Sophus' and manif's.
inline Twist6 swapTwist(const Twist6& xi)
{
  Twist6 out;
  out << xi.tail<3>(), xi.head<3>();
  return out;
}

inline bool near(double a, double b, double tol = 1e-9)
{
  return std::abs(a - b) <= tol * std::max(1.0, std::abs(b));
}

/// |x − y| ≤ tol for poses (quaternions up to sign).
inline bool samePose(const Pose3& x, const Eigen::Quaterniond& q, const Eigen::Vector3d& p, double tol = 1e-9)
{
  const Eigen::Quaterniond xq(x.q.w(), x.q.x(), x.q.y(), x.q.z());
  return std::min((xq.coeffs() - q.coeffs()).norm(), (xq.coeffs() + q.coeffs()).norm()) <= tol && (x.p - p).norm() <= tol;
}

#ifdef SE3_BENCH_SOPHUS
inline Sophus::SE3d toSophus(const Pose3& x)
{
  return Sophus::SE3d(Eigen::Quaterniond(x.q.w(), x.q.x(), x.q.y(), x.q.z()), x.p);
}
inline std::vector<Sophus::SE3d> toSophus(const std::vector<Pose3>& x)
{
  std::vector<Sophus::SE3d> out;
  for (const auto& p : x)
    out.push_back(toSophus(p));
  return out;
}
/// The screw step with Sophus' group: a Exp(λ Log(a⁻¹ b)).
inline Sophus::SE3d sophusScrewStep(const Sophus::SE3d& a, const Sophus::SE3d& b, double lambda)
{
  return a * Sophus::SE3d::exp(lambda * (a.inverse() * b).log());
}
#endif

#ifdef SE3_BENCH_MANIF
inline manif::SE3d toManif(const Pose3& x)
{
  return manif::SE3d(x.p, Eigen::Quaterniond(x.q.w(), x.q.x(), x.q.y(), x.q.z()));
}
inline std::vector<manif::SE3d> toManif(const std::vector<Pose3>& x)
{
  std::vector<manif::SE3d> out;
  for (const auto& p : x)
    out.push_back(toManif(p));
  return out;
}
/// The screw step with manif's group: a ⊕ λ (b ⊖ a), right plus and minus.
inline manif::SE3d manifScrewStep(const manif::SE3d& a, const manif::SE3d& b, double lambda)
{
  return a.rplus(b.rminus(a) * lambda);
}
#endif

#ifdef SE3_BENCH_BASALT
/// One second between knots, in basalt's integer nanoseconds.
constexpr std::int64_t kBasaltDtNs = 1000000000;

/// basalt's cumulative cubic B-spline over the control poses (rotation and translation apart).
struct BasaltSpline
{
  basalt::So3Spline<4> so3{ kBasaltDtNs };
  basalt::RdSpline<3, 4> pos{ kBasaltDtNs };
  explicit BasaltSpline(const std::vector<Pose3>& control)
  {
    for (const auto& c : control)
    {
      so3.knotsPushBack(Sophus::SO3d(Eigen::Quaterniond(c.q.w(), c.q.x(), c.q.y(), c.q.z())));
      pos.knotsPushBack(c.p);
    }
  }
  /// Parameter s ∈ [0, 1] of the valid span [0, (n − 3) dt], in whole nanoseconds.
  std::int64_t timeNs(double s) const
  {
    return static_cast<std::int64_t>(std::floor(s * static_cast<double>(pos.maxTimeNs() - 1)));
  }
};

/// Pose, body angular velocity and acceleration, world linear velocity and acceleration.
struct BasaltKinematics
{
  Sophus::SO3d rotation;
  Eigen::Vector3d position, angular_velocity, angular_acceleration, linear_velocity, linear_acceleration;
};

inline BasaltKinematics basaltKinematics(const BasaltSpline& s, std::int64_t t_ns)
{
  BasaltKinematics k;
  k.rotation = s.so3.evaluate(t_ns);
  k.angular_acceleration = s.so3.accelerationBody(t_ns, &k.angular_velocity);
  k.position = s.pos.evaluate(t_ns);
  k.linear_velocity = s.pos.velocity(t_ns);
  k.linear_acceleration = s.pos.acceleration(t_ns);
  return k;
}

/// The project's double-geodesic cubic B-spline on basalt's knots: uniform, unclamped,
/// u_j = (j − 3) dt, so that its span [u_3, u_n] is basalt's [0, (n − 3) dt].
inline se3_interpolation::BSplineCurve<se3_interpolation::DoubleGeodesicSe3> uniformBspline(
    const std::vector<Pose3>& control)
{
  std::vector<double> knots;
  for (std::size_t j = 0; j < control.size() + 4; ++j)
    knots.push_back(static_cast<double>(j) - 3.0);
  return se3_interpolation::BSplineCurve<se3_interpolation::DoubleGeodesicSe3>(control, 3, knots);
}
#endif

/// Checks the peers that are compiled in against the project (see the file comment); prints
/// each disagreement and returns false if there is one.
inline bool checkPeersAgree()
{
  namespace si = se3_interpolation;
  bool ok = true;
  [[maybe_unused]] auto fail = [&ok](const char* what, std::size_t i) {
    std::fprintf(stderr, "peer check failed: %s differs from the project's at input %zu\n", what, i);
    ok = false;
  };
#if defined(SE3_BENCH_SOPHUS) || defined(SE3_BENCH_MANIF)
  const StepInputs in = makeStepInputs();
  for (std::size_t i = 0; i < kTableSize; i += 7)
  {
    const Pose3 rel = in.a[i].inverse() * in.b[i];
    const Pose3 ours_exp = si::se3Exp<double>(in.twist[i]);
    const Twist6 ours_log = si::se3Log<double>(rel);
    const Pose3 ours_step = si::geodesic<si::ScrewSe3>(in.a[i], in.b[i], in.lambda[i]);
#ifdef SE3_BENCH_SOPHUS
    {
      const Sophus::SE3d e = Sophus::SE3d::exp(swapTwist(in.twist[i]));
      if (!samePose(ours_exp, e.unit_quaternion(), e.translation()))
        fail("Sophus SE3::exp", i);
      if ((swapTwist(toSophus(rel).log()) - ours_log).norm() > 1e-9)
        fail("Sophus SE3::log", i);
      const Sophus::SE3d s = sophusScrewStep(toSophus(in.a[i]), toSophus(in.b[i]), in.lambda[i]);
      if (!samePose(ours_step, s.unit_quaternion(), s.translation()))
        fail("Sophus screw step", i);
    }
#endif
#ifdef SE3_BENCH_MANIF
    {
      const manif::SE3d e = manif::SE3Tangentd(swapTwist(in.twist[i])).exp();
      if (!samePose(ours_exp, e.quat(), e.translation()))
        fail("manif SE3Tangent::exp", i);
      if ((swapTwist(toManif(rel).log().coeffs()) - ours_log).norm() > 1e-9)
        fail("manif SE3::log", i);
      const manif::SE3d s = manifScrewStep(toManif(in.a[i]), toManif(in.b[i]), in.lambda[i]);
      if (!samePose(ours_step, s.quat(), s.translation()))
        fail("manif screw step", i);
    }
#endif
  }
#endif
#ifdef SE3_BENCH_BASALT
  {
    // General control polygons: the translation and its derivatives; single-axis rotations
    // (about z, angles of the polygon's own): everything.
    std::vector<std::vector<Pose3>> polygons = makePolygons(kCurveCount, kBsplinePoints, 3);
    const std::size_t general = polygons.size();
    Rng rng(6);
    for (std::size_t c = 0; c < general; ++c)
    {
      std::vector<Pose3> axis = polygons[c];
      double angle = rng.uniform(-3.0, 3.0);
      for (auto& x : axis)
      {
        x.q = si::so3Exp<double>(Eigen::Vector3d(0.0, 0.0, angle));
        angle += rng.uniform(-1.2, 1.2);
      }
      polygons.push_back(axis);
    }
    const std::vector<double> s = makeParameters(7);
    for (std::size_t c = 0; c < polygons.size(); ++c)
    {
      const BasaltSpline b(polygons[c]);
      const auto ours = uniformBspline(polygons[c]);
      for (std::size_t j = 0; j < 64; ++j)
      {
        const std::int64_t t_ns = b.timeNs(s[j]);
        const BasaltKinematics k = basaltKinematics(b, t_ns);
        const si::Kinematics o = si::kinematicsAt(ours, static_cast<double>(t_ns) * 1e-9);
        const bool translation = (o.pose.p - k.position).norm() <= 1e-9 &&
                                 (o.velocity.linear - k.linear_velocity).norm() <= 1e-9 &&
                                 (o.acceleration.linear - k.linear_acceleration).norm() <= 1e-9;
        if (!translation)
          fail("basalt RdSpline position / velocity / acceleration", c * 64 + j);
        if (c >= general)
        {
          // basalt's rates are in the body frame; about a fixed axis body = spatial.
          if (!samePose(o.pose, k.rotation.unit_quaternion(), k.position) ||
              (o.velocity.angular - k.angular_velocity).norm() > 1e-9 ||
              (o.acceleration.angular - k.angular_acceleration).norm() > 1e-9)
            fail("basalt So3Spline (rotations about one axis)", c * 64 + j);
        }
      }
    }
  }
#endif
  return ok;
}

}  // namespace se3_bench
