// Inputs and peer implementations shared by bench_core (Google Benchmark) and count_ops
// (instruction counts under callgrind).
//
// Every input comes from a fixed-seed generator, so all runs (and both callgrind runs of
// count_ops) see the same data; the operations cycle through tables of kTableSize entries,
// so the compiler cannot fold them and the branch predictor sees varied angles.
// The peers are what a user of plain Eigen would write for the same double-geodesic
// interpolation: Quaternion::slerp for the rotation and a lerp for the translation, in the
// same de Casteljau / de Boor recursions as the library's curves.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bezier.h"

namespace se3_bench
{
using Pose3 = se3_interpolation::Pose<double>;
using Twist6 = Eigen::Matrix<double, 6, 1>;

/// Size of every input table (a power of two: indices wrap with a mask).
constexpr std::size_t kTableSize = 1024;
inline std::size_t wrap(std::size_t i)
{
  return i & (kTableSize - 1);
}

/// SplitMix64: a small deterministic generator, identical on every platform.
class Rng
{
public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}

  double uniform(double lo, double hi)
  {
    state_ += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return lo + (hi - lo) * static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
  }

  Eigen::Vector3d unitVector()
  {
    Eigen::Vector3d v;
    do
      v = Eigen::Vector3d(uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0));
    while (v.squaredNorm() > 1.0 || v.squaredNorm() < 1e-4);
    return v.normalized();
  }

private:
  std::uint64_t state_;
};

/// A pose with rotation angle uniform in [min_angle, max_angle] and translation in [−scale, scale]³.
inline Pose3 randomPose(Rng& rng, double min_angle, double max_angle, double scale = 1.0)
{
  const Eigen::Vector3d omega = rng.uniform(min_angle, max_angle) * rng.unitVector();
  return Pose3(se3_interpolation::so3Exp<double>(omega),
               Eigen::Vector3d(rng.uniform(-scale, scale), rng.uniform(-scale, scale), rng.uniform(-scale, scale)));
}

/// Pairs (a_i, b_i) with relative rotations of 0.3–2.5 rad (the closed forms, not the
/// small-angle series), parameters λ_i ∈ [0, 1] and twists with |ω| ∈ [0.3, 2.5].
struct StepInputs
{
  std::vector<Pose3> a;
  std::vector<Pose3> b;
  std::vector<double> lambda;
  std::vector<Twist6> twist;
};

inline StepInputs makeStepInputs()
{
  Rng rng(1);
  StepInputs in;
  for (std::size_t i = 0; i < kTableSize; ++i)
  {
    in.a.push_back(randomPose(rng, 0.0, 3.0));
    in.b.push_back(in.a.back() * randomPose(rng, 0.3, 2.5));
    in.lambda.push_back(rng.uniform(0.0, 1.0));
    Twist6 xi;
    xi << rng.uniform(0.3, 2.5) * rng.unitVector(), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0);
    in.twist.push_back(xi);
  }
  return in;
}

/// `count` control polygons of `points` poses, consecutive relative rotations 0.2–1.2 rad.
inline std::vector<std::vector<Pose3>> makePolygons(std::size_t count, std::size_t points, std::uint64_t seed)
{
  Rng rng(seed);
  std::vector<std::vector<Pose3>> polygons(count);
  for (auto& p : polygons)
  {
    p.push_back(randomPose(rng, 0.0, 3.0));
    for (std::size_t i = 1; i < points; ++i)
      p.push_back(p.back() * randomPose(rng, 0.2, 1.2, 0.5));
  }
  return polygons;
}

/// Curve parameters in [0, 1].
inline std::vector<double> makeParameters(std::uint64_t seed)
{
  Rng rng(seed);
  std::vector<double> t(kTableSize);
  for (double& x : t)
    x = rng.uniform(0.0, 1.0);
  return t;
}

/// Number of distinct curves the point benchmarks cycle through.
constexpr std::size_t kCurveCount = 16;
/// Control points of the B-splines of the point benchmarks (cubic, clamped uniform knots).
constexpr std::size_t kBsplinePoints = 8;

template <class G>
std::vector<std::shared_ptr<const se3_interpolation::Curve<G>>> makeBezierCurves()
{
  std::vector<std::shared_ptr<const se3_interpolation::Curve<G>>> curves;
  for (const auto& p : makePolygons(kCurveCount, 4, 2))
    curves.push_back(std::make_shared<se3_interpolation::BezierCurve<G>>(p, 0.0, 1.0));
  return curves;
}

template <class G>
std::vector<std::shared_ptr<const se3_interpolation::Curve<G>>> makeBsplineCurves()
{
  std::vector<std::shared_ptr<const se3_interpolation::Curve<G>>> curves;
  for (const auto& p : makePolygons(kCurveCount, kBsplinePoints, 3))
    curves.push_back(std::make_shared<se3_interpolation::BSplineCurve<G>>(
        p, 3, se3_interpolation::clampedUniformKnots(kBsplinePoints, 3, 0.0, 1.0)));
  return curves;
}

/// Waypoints for the sampling benchmarks: consecutive relative rotations 0.2–0.8 rad.
inline std::vector<Pose3> makeWaypoints(std::size_t n)
{
  Rng rng(4);
  std::vector<Pose3> w{ randomPose(rng, 0.0, 3.0) };
  for (std::size_t i = 1; i < n; ++i)
    w.push_back(w.back() * randomPose(rng, 0.2, 0.8, 0.5));
  return w;
}

/// The natural C² interpolating spline through `n` waypoints at times 0, 1, …, n − 1.
template <class G>
std::shared_ptr<const se3_interpolation::Curve<G>> makeInterpolatingCurve(std::size_t n)
{
  std::vector<double> times(n);
  for (std::size_t i = 0; i < n; ++i)
    times[i] = static_cast<double>(i);
  const Twist6 zero = Twist6::Zero();
  return se3_interpolation::makeInterpolatingSpline<G>(makeWaypoints(n), times,
                                                       se3_interpolation::EndCondition::kNatural, zero, zero, zero);
}

// --- The Eigen peer: slerp + lerp ------------------------------------------------------------

struct EigenPose
{
  Eigen::Quaterniond q;
  Eigen::Vector3d p;
};

inline EigenPose toEigen(const Pose3& x)
{
  return EigenPose{ Eigen::Quaterniond(x.q.w(), x.q.x(), x.q.y(), x.q.z()), x.p };
}

inline std::vector<EigenPose> toEigen(const std::vector<Pose3>& x)
{
  std::vector<EigenPose> out;
  for (const auto& p : x)
    out.push_back(toEigen(p));
  return out;
}

/// The double-geodesic step of plain Eigen: Quaternion::slerp and a linear interpolation.
inline EigenPose slerpLerp(const EigenPose& a, const EigenPose& b, double lambda)
{
  return EigenPose{ a.q.slerp(lambda, b.q), a.p + lambda * (b.p - a.p) };
}

/// Cubic de Casteljau (six interpolations) with any two-point interpolation.
template <class P, class Interp>
P cubicDeCasteljau(const P* c, double lambda, const Interp& interp)
{
  std::array<P, 3> b{ interp(c[0], c[1], lambda), interp(c[1], c[2], lambda), interp(c[2], c[3], lambda) };
  b[0] = interp(b[0], b[1], lambda);
  b[1] = interp(b[1], b[2], lambda);
  return interp(b[0], b[1], lambda);
}

/// Cubic de Boor (six interpolations) on knots u (as bspline.h) with any two-point interpolation.
template <class P, class Interp>
P cubicDeBoor(const std::vector<P>& d, const std::vector<double>& u, double t, const Interp& interp)
{
  const std::ptrdiff_t last = static_cast<std::ptrdiff_t>(d.size()) - 1;
  const std::ptrdiff_t k =
      std::min(std::max<std::ptrdiff_t>((std::upper_bound(u.begin(), u.end(), t) - u.begin()) - 1, 3), last);
  std::array<P, 4> p{ d[static_cast<std::size_t>(k - 3)], d[static_cast<std::size_t>(k - 2)],
                      d[static_cast<std::size_t>(k - 1)], d[static_cast<std::size_t>(k)] };
  for (std::ptrdiff_t r = 1; r <= 3; ++r)
    for (std::ptrdiff_t j = 3; j >= r; --j)
    {
      const std::size_t i = static_cast<std::size_t>(k - 3 + j);
      const double alpha = (t - u[i]) / (u[i + 4 - static_cast<std::size_t>(r)] - u[i]);
      p[static_cast<std::size_t>(j)] = interp(p[static_cast<std::size_t>(j - 1)], p[static_cast<std::size_t>(j)], alpha);
    }
  return p[3];
}

}  // namespace se3_bench
