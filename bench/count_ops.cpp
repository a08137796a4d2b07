// Runs one named core operation N times, for instruction counts under callgrind
// (scripts/instruction_counts.sh runs it with N = 0 and N = 2000 and divides the difference).
//
// Usage: count_ops OPERATION N     (prints a checksum so that nothing is optimised away)
//        count_ops --list          (the operation names, one a line)
//
// The inputs are the deterministic tables of bench_fixtures.h, cycled with the loop index;
// everything an operation needs is built before the loop, identically for every N. The optional
// peers of bench_peers.h (Sophus, manif, basalt) are listed when compiled in.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <kdl/frames.hpp>
#include <kdl/path_line.hpp>
#include <kdl/rotational_interpolation_sa.hpp>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "bench_fixtures.h"
#include "bench_peers.h"

namespace
{
namespace si = se3_interpolation;
using se3_bench::Pose3;
using se3_bench::wrap;

double checksum(const Pose3& x)
{
  return x.q.w() + x.q.x() + x.p.x() + x.p.z();
}
double checksum(const se3_bench::EigenPose& x)
{
  return x.q.w() + x.q.x() + x.p.x() + x.p.z();
}
double checksum(const si::Quaternion<double>& q)
{
  return q.w() + q.z();
}
template <int R>
double checksum(const Eigen::Matrix<double, R, 1>& v)
{
  return v.sum();
}
double checksum(const KDL::Frame& f)
{
  return f.p.x() + f.p.z() + f.M(0, 0) + f.M(1, 2);
}
double checksum(const KDL::Twist& t)
{
  return t.vel.x() + t.rot.y();
}
double checksum(const std::tuple<KDL::Frame, KDL::Twist, KDL::Twist>& r)
{
  return checksum(std::get<0>(r)) + checksum(std::get<1>(r)) + checksum(std::get<2>(r));
}
double checksum(const si::Kinematics& k)
{
  return checksum(k.pose) + k.velocity.angular.x() + k.velocity.linear.y() + k.acceleration.angular.z() +
         k.acceleration.linear.x();
}

#ifdef SE3_BENCH_SOPHUS
double checksum(const Sophus::SE3d& x)
{
  return x.unit_quaternion().w() + x.unit_quaternion().x() + x.translation().x() + x.translation().z();
}
#endif
#ifdef SE3_BENCH_MANIF
double checksum(const manif::SE3d& x)
{
  return x.quat().w() + x.quat().x() + x.translation().x() + x.translation().z();
}
double checksum(const manif::SE3Tangentd& v)
{
  return v.coeffs().sum();
}
#endif
#ifdef SE3_BENCH_BASALT
double checksum(const std::pair<Sophus::SO3d, Eigen::Vector3d>& x)
{
  return x.first.unit_quaternion().w() + x.first.unit_quaternion().z() + x.second.x();
}
double checksum(const se3_bench::BasaltKinematics& k)
{
  return k.rotation.unit_quaternion().w() + k.position.y() + k.angular_velocity.x() + k.angular_acceleration.z() +
         k.linear_velocity.y() + k.linear_acceleration.x();
}
#endif

KDL::Frame toKdl(const Pose3& x)
{
  return KDL::Frame(KDL::Rotation::Quaternion(x.q.x(), x.q.y(), x.q.z(), x.q.w()),
                    KDL::Vector(x.p.x(), x.p.y(), x.p.z()));
}

/// The loop: op(i) for i = 0 … n − 1, inputs cycled through the tables.
template <class Op>
double repeat(std::size_t n, const Op& op)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    sum += checksum(op(wrap(i)));
  return sum;
}

using Runner = std::function<double(std::size_t)>;

/// Lie group maps and two-point steps over the shared step inputs.
std::vector<std::pair<std::string, Runner>> stepOperations()
{
  static const se3_bench::StepInputs in = se3_bench::makeStepInputs();
  static const std::vector<Pose3> rel = [] {
    std::vector<Pose3> r;
    for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
      r.push_back(in.a[i].inverse() * in.b[i]);
    return r;
  }();
  static const std::vector<se3_bench::EigenPose> ea = se3_bench::toEigen(in.a);
  static const std::vector<se3_bench::EigenPose> eb = se3_bench::toEigen(in.b);
  static const std::vector<se3_bench::Twist6> screw_logs = [] {
    std::vector<se3_bench::Twist6> l;
    for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
      l.push_back(si::ScrewSe3::log(in.a[i], in.b[i]));
    return l;
  }();
  static const std::vector<se3_bench::Twist6> dg_logs = [] {
    std::vector<se3_bench::Twist6> l;
    for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
      l.push_back(si::DoubleGeodesicSe3::log(in.a[i], in.b[i]));
    return l;
  }();
  return {
    { "so3_exp",
      [](std::size_t n) { return repeat(n, [](std::size_t i) { return si::so3Exp<double>(in.twist[i].head<3>()); }); } },
    { "so3_log", [](std::size_t n) { return repeat(n, [](std::size_t i) { return si::so3Log<double>(rel[i].q); }); } },
    { "se3_exp", [](std::size_t n) { return repeat(n, [](std::size_t i) { return si::se3Exp<double>(in.twist[i]); }); } },
    { "se3_log", [](std::size_t n) { return repeat(n, [](std::size_t i) { return si::se3Log<double>(rel[i]); }); } },
    { "screw_step",
      [](std::size_t n) {
        return repeat(n, [](std::size_t i) { return si::geodesic<si::ScrewSe3>(in.a[i], in.b[i], in.lambda[i]); });
      } },
    { "double_geodesic_step",
      [](std::size_t n) {
        return repeat(n,
                      [](std::size_t i) { return si::geodesic<si::DoubleGeodesicSe3>(in.a[i], in.b[i], in.lambda[i]); });
      } },
    { "eigen_slerp_lerp_step",
      [](std::size_t n) {
        return repeat(n, [](std::size_t i) { return se3_bench::slerpLerp(ea[i], eb[i], in.lambda[i]); });
      } },
    { "screw_step_jet",
      [](std::size_t n) {
        return repeat(n, [](std::size_t i) {
          return si::geodesicKinematicsFromLog<si::ScrewSe3>(in.a[i], screw_logs[i], si::Jet<2>::variable(in.lambda[i]));
        });
      } },
    { "double_geodesic_step_jet",
      [](std::size_t n) {
        return repeat(n, [](std::size_t i) {
          return si::geodesicKinematicsFromLog<si::DoubleGeodesicSe3>(in.a[i], dg_logs[i], si::Jet<2>::variable(in.lambda[i]));
        });
      } },
    // KDL's peer of the step with velocity and acceleration: Path_Line (single-axis rotation)
    // built once per pair, Pos + Vel + Acc at path parameter λ·length, unit path speed.
    { "kdl_path_pos_vel_acc",
      [](std::size_t n) {
        std::vector<std::unique_ptr<KDL::Path_Line>> lines;
        for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
          lines.push_back(std::make_unique<KDL::Path_Line>(toKdl(in.a[i]), toKdl(in.b[i]),
                                                           new KDL::RotationalInterpolation_SingleAxis(), 1.0, true));
        return repeat(n, [&lines](std::size_t i) {
          const double length = lines[i]->PathLength();
          const double s = in.lambda[i] * length;
          return std::make_tuple(lines[i]->Pos(s), lines[i]->Vel(s, length), lines[i]->Acc(s, length, 0.0));
        });
      } },
  };
}

/// Points of cubic curves (value, or value + velocity + acceleration) in geometry G.
template <class G>
std::vector<std::pair<std::string, Runner>> curveOperations(const std::string& g)
{
  static const std::vector<double> t = se3_bench::makeParameters(5);
  auto bezier = [](std::size_t n) {
    const auto curves = se3_bench::makeBezierCurves<G>();
    return repeat(n, [&curves](std::size_t i) { return curves[i & 15]->value(t[i]); });
  };
  auto bezier_jet = [](std::size_t n) {
    const auto curves = se3_bench::makeBezierCurves<G>();
    return repeat(n, [&curves](std::size_t i) { return si::kinematicsAt(*curves[i & 15], t[i]); });
  };
  auto bspline = [](std::size_t n) {
    const auto curves = se3_bench::makeBsplineCurves<G>();
    return repeat(n, [&curves](std::size_t i) { return curves[i & 15]->value(t[i]); });
  };
  auto bspline_jet = [](std::size_t n) {
    const auto curves = se3_bench::makeBsplineCurves<G>();
    return repeat(n, [&curves](std::size_t i) { return si::kinematicsAt(*curves[i & 15], t[i]); });
  };
  auto sample = [](std::size_t n) {
    const auto curve = se3_bench::makeInterpolatingCurve<G>(100);
    const double t0 = curve->startTime();
    const double span = curve->endTime() - t0;
    return repeat(n, [&curve, t0, span](std::size_t i) { return si::kinematicsAt(*curve, t0 + span * t[i]); });
  };
  // The natural interpolating solve through N + 2 waypoints (of the same 2002 or more, built for
  // every N): its difference over N is the cost per waypoint (the solve is linear in N).
  auto solve = [](std::size_t n) {
    const std::vector<Pose3> all = se3_bench::makeWaypoints(std::max<std::size_t>(n, 2000) + 2);
    const std::vector<Pose3> waypoints(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(n + 2));
    std::vector<double> times(n + 2);
    for (std::size_t i = 0; i < times.size(); ++i)
      times[i] = static_cast<double>(i);
    const se3_bench::Twist6 zero = se3_bench::Twist6::Zero();
    const auto curve =
        si::solveC2Spline<G>(waypoints, times, si::EndCondition::kNatural, zero, zero);
    return curve->startRates()[n / 2].sum();
  };
  return { { g + "_bezier_point", bezier },
           { g + "_bezier_point_jet", bezier_jet },
           { g + "_bspline_point", bspline },
           { g + "_bspline_point_jet", bspline_jet },
           { g + "_sample_interpolating", sample },
           { g + "_solve_per_waypoint", solve } };
}

/// The same cubic curves with Eigen slerp + lerp (the peer of the double-geodesic points).
std::vector<std::pair<std::string, Runner>> eigenCurveOperations()
{
  static const std::vector<double> t = se3_bench::makeParameters(5);
  auto bezier = [](std::size_t n) {
    std::vector<std::vector<se3_bench::EigenPose>> polygons;
    for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, 4, 2))
      polygons.push_back(se3_bench::toEigen(p));
    return repeat(n, [&polygons](std::size_t i) {
      return se3_bench::cubicDeCasteljau(polygons[i & 15].data(), t[i], se3_bench::slerpLerp);
    });
  };
  auto bspline = [](std::size_t n) {
    std::vector<std::vector<se3_bench::EigenPose>> control;
    for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, se3_bench::kBsplinePoints, 3))
      control.push_back(se3_bench::toEigen(p));
    const std::vector<double> knots = si::clampedUniformKnots(se3_bench::kBsplinePoints, 3, 0.0, 1.0);
    return repeat(n, [&control, &knots](std::size_t i) {
      return se3_bench::cubicDeBoor(control[i & 15], knots, t[i], se3_bench::slerpLerp);
    });
  };
  return { { "eigen_bezier_point", bezier }, { "eigen_bspline_point", bspline } };
}

/// The optional peers (bench_peers.h), each checked against the project before its loop (the
/// check is the same for N = 0 and N = 2000, so it cancels from the count).
std::vector<std::pair<std::string, Runner>> peerOperations()
{
  std::vector<std::pair<std::string, Runner>> ops;
  [[maybe_unused]] auto checked = [] {
    static const bool agree = se3_bench::checkPeersAgree();
    if (!agree)
      std::exit(1);
  };
#if defined(SE3_BENCH_SOPHUS) || defined(SE3_BENCH_MANIF)
  static const se3_bench::StepInputs in = se3_bench::makeStepInputs();
  static const std::vector<Pose3> rel = [] {
    std::vector<Pose3> r;
    for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
      r.push_back(in.a[i].inverse() * in.b[i]);
    return r;
  }();
  static const std::vector<se3_bench::Twist6> twist = [] {
    std::vector<se3_bench::Twist6> t;
    for (const auto& xi : in.twist)
      t.push_back(se3_bench::swapTwist(xi));
    return t;
  }();
#endif
#ifdef SE3_BENCH_SOPHUS
  static const std::vector<Sophus::SE3d> sa = se3_bench::toSophus(in.a), sb = se3_bench::toSophus(in.b),
                                         srel = se3_bench::toSophus(rel);
  ops.push_back({ "sophus_se3_exp", [checked](std::size_t n) {
                   checked();
                   return repeat(n, [](std::size_t i) { return Sophus::SE3d::exp(twist[i]); });
                 } });
  ops.push_back({ "sophus_se3_log", [checked](std::size_t n) {
                   checked();
                   return repeat(n, [](std::size_t i) { return srel[i].log(); });
                 } });
  ops.push_back({ "sophus_screw_step", [checked](std::size_t n) {
                   checked();
                   return repeat(n, [](std::size_t i) { return se3_bench::sophusScrewStep(sa[i], sb[i], in.lambda[i]); });
                 } });
#endif
#ifdef SE3_BENCH_MANIF
  static const std::vector<manif::SE3d> ma = se3_bench::toManif(in.a), mb = se3_bench::toManif(in.b),
                                        mrel = se3_bench::toManif(rel);
  ops.push_back({ "manif_se3_exp", [checked](std::size_t n) {
                   checked();
                   return repeat(n, [](std::size_t i) { return manif::SE3Tangentd(twist[i]).exp(); });
                 } });
  ops.push_back({ "manif_se3_log", [checked](std::size_t n) {
                   checked();
                   return repeat(n, [](std::size_t i) { return mrel[i].log(); });
                 } });
  ops.push_back({ "manif_screw_step", [checked](std::size_t n) {
                   checked();
                   return repeat(n, [](std::size_t i) { return se3_bench::manifScrewStep(ma[i], mb[i], in.lambda[i]); });
                 } });
#endif
#ifdef SE3_BENCH_BASALT
  // The control polygons and parameters of the project's B-spline rows.
  auto splines = [] {
    std::vector<se3_bench::BasaltSpline> s;
    for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, se3_bench::kBsplinePoints, 3))
      s.emplace_back(p);
    return s;
  };
  static const std::vector<double> t = se3_bench::makeParameters(5);
  ops.push_back({ "basalt_bspline_point", [checked, splines](std::size_t n) {
                   checked();
                   const auto s = splines();
                   return repeat(n, [&s](std::size_t i) {
                     const auto& b = s[i & 15];
                     const std::int64_t t_ns = b.timeNs(t[i]);
                     return std::make_pair(b.so3.evaluate(t_ns), b.pos.evaluate(t_ns));
                   });
                 } });
  ops.push_back({ "basalt_bspline_point_jet", [checked, splines](std::size_t n) {
                   checked();
                   const auto s = splines();
                   return repeat(n, [&s](std::size_t i) {
                     const auto& b = s[i & 15];
                     return se3_bench::basaltKinematics(b, b.timeNs(t[i]));
                   });
                 } });
#endif
  return ops;
}

std::vector<std::pair<std::string, Runner>> operations()
{
  std::vector<std::pair<std::string, Runner>> ops = stepOperations();
  for (auto& op : curveOperations<si::ScrewSe3>("screw"))
    ops.push_back(std::move(op));
  for (auto& op : curveOperations<si::DoubleGeodesicSe3>("double_geodesic"))
    ops.push_back(std::move(op));
  for (auto& op : eigenCurveOperations())
    ops.push_back(std::move(op));
  for (auto& op : peerOperations())
    ops.push_back(std::move(op));
  return ops;
}

}  // namespace

int main(int argc, char** argv)
{
  const auto ops = operations();
  if (argc == 2 && std::string(argv[1]) == "--list")
  {
    for (const auto& op : ops)
      std::printf("%s\n", op.first.c_str());
    return 0;
  }
  char* end = nullptr;
  const unsigned long long n = argc == 3 ? std::strtoull(argv[2], &end, 10) : 0;
  if (argc != 3 || end == argv[2] || *end != '\0')
  {
    std::fprintf(stderr, "usage: %s OPERATION N | --list\n", argv[0]);
    return 2;
  }
  for (const auto& op : ops)
    if (op.first == argv[1])
    {
      std::printf("%s %llu checksum %.17g\n", argv[1], n, op.second(static_cast<std::size_t>(n)));
      return 0;
    }
  std::fprintf(stderr, "unknown operation '%s' (count_ops --list)\n", argv[1]);
  return 2;
}
