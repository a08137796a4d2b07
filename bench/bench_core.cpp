// Timing benchmarks of the core against KDL and plain Eigen (Google Benchmark).
//
// For each SE(3) geometry (screw, double_geodesic): the exp and log maps, one geodesic step,
// one point of a cubic Bézier curve and of a cubic B-spline (value, and value + velocity +
// acceleration through Jet<2>), and sampling an interpolating spline through 100 waypoints
// (kinematicsAt: pose, velocity, acceleration) at 10³ … 10⁵ times, directly and through the
// planner. The peers do the same double-geodesic work: KDL's Path_Line with
// RotationalInterpolation_SingleAxis and its diff/addDelta frame interpolation, and Eigen's
// Quaternion::slerp with a lerp of the translation, in the same de Casteljau / de Boor
// recursions (bench_fixtures.h). Before timing, the peers' results are checked against ours.
// After the usual output, a table of ratios (ours / peer, median CPU time per operation over
// the repetitions) and a sampling table are printed.
//
// The interpolating solve itself (N = 10 … 10⁴ waypoints) is measured by bench_interpolating.
//
// Usage: bench_core [Google Benchmark flags], e.g. --benchmark_repetitions=5
//        --benchmark_min_time=0.2 --benchmark_filter=double_geodesic
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <kdl/frames.hpp>
#include <kdl/path_line.hpp>
#include <kdl/rotational_interpolation_sa.hpp>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <unistd.h>
#include <vector>

#include "bench_fixtures.h"
#include "bench_peers.h"
#include "se3_interpolation/planner/planner.h"

namespace
{
namespace si = se3_interpolation;
using se3_bench::EigenPose;
using se3_bench::Pose3;
using se3_bench::wrap;

const se3_bench::StepInputs& stepInputs()
{
  static const se3_bench::StepInputs in = se3_bench::makeStepInputs();
  return in;
}

/// Relative poses a⁻¹b (rotation angles 0.3–2.5 rad): inputs of the log maps.
const std::vector<Pose3>& relativePoses()
{
  static const std::vector<Pose3> rel = [] {
    std::vector<Pose3> r;
    for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
      r.push_back(stepInputs().a[i].inverse() * stepInputs().b[i]);
    return r;
  }();
  return rel;
}

const std::vector<double>& parameters()
{
  static const std::vector<double> t = se3_bench::makeParameters(5);
  return t;
}

/// Runs op(i) once per iteration with i cycling through the input tables.
template <class Op>
void registerOp(const std::string& name, Op op)
{
  benchmark::RegisterBenchmark(name.c_str(), [op](benchmark::State& state) {
    std::size_t i = 0;
    for (auto _ : state)
    {
      auto r = op(wrap(i++));
      benchmark::DoNotOptimize(r);
    }
  })->Unit(benchmark::kNanosecond);
}

// --- KDL ------------------------------------------------------------------------------------

KDL::Frame toKdl(const Pose3& x)
{
  return KDL::Frame(KDL::Rotation::Quaternion(x.q.x(), x.q.y(), x.q.z(), x.q.w()),
                    KDL::Vector(x.p.x(), x.p.y(), x.p.z()));
}

std::vector<KDL::Frame> toKdl(const std::vector<Pose3>& x)
{
  std::vector<KDL::Frame> out;
  for (const auto& p : x)
    out.push_back(toKdl(p));
  return out;
}

/// KDL's frame interpolation: addDelta(a, diff(a, b), λ) (rotation about the fixed axis of a⁻¹b).
KDL::Frame kdlInterp(const KDL::Frame& a, const KDL::Frame& b, double lambda)
{
  return KDL::addDelta(a, KDL::diff(a, b), lambda);
}

/// A line from a to b with the single-axis rotational interpolation, owning it.
std::unique_ptr<KDL::Path_Line> kdlLine(const KDL::Frame& a, const KDL::Frame& b)
{
  return std::make_unique<KDL::Path_Line>(a, b, new KDL::RotationalInterpolation_SingleAxis(), 1.0, true);
}

/// Velocity and acceleration of plain Eigen poses at t − h, t, t + h by central differences
/// (rotation: spatial rotation vectors relative to the middle pose).
si::Kinematics finiteDifferences(const EigenPose& m, const EigenPose& x, const EigenPose& p, double h)
{
  const Eigen::AngleAxisd back(m.q * x.q.conjugate());
  const Eigen::AngleAxisd ahead(p.q * x.q.conjugate());
  const Eigen::Vector3d phi_m = back.angle() * back.axis();
  const Eigen::Vector3d phi_p = ahead.angle() * ahead.axis();
  si::Kinematics k;
  k.pose.q = x.q;
  k.pose.p = x.p;
  k.velocity.linear = (p.p - m.p) / (2.0 * h);
  k.acceleration.linear = (p.p - 2.0 * x.p + m.p) / (h * h);
  k.velocity.angular = (phi_p - phi_m) / (2.0 * h);
  k.acceleration.angular = (phi_p + phi_m) / (h * h);
  return k;
}

// --- Checks that the peers compute what we compute --------------------------------------------

bool samePose(const Pose3& x, const KDL::Frame& f)
{
  return KDL::Equal(toKdl(x), f, 1e-9);
}

bool samePose(const Pose3& x, const EigenPose& e)
{
  return Eigen::Quaterniond(x.q.w(), x.q.x(), x.q.y(), x.q.z()).angularDistance(e.q) < 1e-9 &&
         (x.p - e.p).norm() < 1e-9;
}

bool checkPeers()
{
  using DG = si::DoubleGeodesicSe3;
  const auto& in = stepInputs();
  const auto& t = parameters();
  const auto bezier = se3_bench::makeBezierCurves<DG>();
  const auto bspline = se3_bench::makeBsplineCurves<DG>();
  const auto polygons = se3_bench::makePolygons(se3_bench::kCurveCount, 4, 2);
  const auto control = se3_bench::makePolygons(se3_bench::kCurveCount, se3_bench::kBsplinePoints, 3);
  const std::vector<double> knots = si::clampedUniformKnots(se3_bench::kBsplinePoints, 3, 0.0, 1.0);
  for (std::size_t i = 0; i < 64; ++i)
  {
    const Pose3 ours = si::geodesic<DG>(in.a[i], in.b[i], in.lambda[i]);
    const auto line = kdlLine(toKdl(in.a[i]), toKdl(in.b[i]));
    const double length = line->PathLength();
    if (!samePose(ours, se3_bench::slerpLerp(se3_bench::toEigen(in.a[i]), se3_bench::toEigen(in.b[i]), in.lambda[i])) ||
        !samePose(ours, line->Pos(in.lambda[i] * length)) ||
        !samePose(ours, kdlInterp(toKdl(in.a[i]), toKdl(in.b[i]), in.lambda[i])))
    {
      std::cerr << "peer check failed: double-geodesic step " << i << "\n";
      return false;
    }
    const si::Kinematics k = si::kinematicsFromJet(si::geodesicFromLog<DG>(
        in.a[i], DG::log(in.a[i], in.b[i]), si::Jet<2>::variable(in.lambda[i])));
    const KDL::Twist v = line->Vel(in.lambda[i] * length, length);
    if ((k.velocity.linear - Eigen::Vector3d(v.vel.x(), v.vel.y(), v.vel.z())).norm() > 1e-9 ||
        (k.velocity.angular - Eigen::Vector3d(v.rot.x(), v.rot.y(), v.rot.z())).norm() > 1e-9 ||
        k.acceleration.linear.norm() + k.acceleration.angular.norm() > 1e-9)
    {
      std::cerr << "peer check failed: double-geodesic step velocity " << i << "\n";
      return false;
    }
    const std::size_t c = i % se3_bench::kCurveCount;
    const std::vector<EigenPose> pe = se3_bench::toEigen(polygons[c]);
    const std::vector<KDL::Frame> pk = toKdl(polygons[c]);
    const Pose3 b = bezier[c]->value(t[i]);
    if (!samePose(b, se3_bench::cubicDeCasteljau(pe.data(), t[i], se3_bench::slerpLerp)) ||
        !samePose(b, se3_bench::cubicDeCasteljau(pk.data(), t[i], kdlInterp)))
    {
      std::cerr << "peer check failed: double-geodesic Bézier point " << i << "\n";
      return false;
    }
    const Pose3 s = bspline[c]->value(t[i]);
    if (!samePose(s, se3_bench::cubicDeBoor(se3_bench::toEigen(control[c]), knots, t[i], se3_bench::slerpLerp)) ||
        !samePose(s, se3_bench::cubicDeBoor(toKdl(control[c]), knots, t[i], kdlInterp)))
    {
      std::cerr << "peer check failed: double-geodesic B-spline point " << i << "\n";
      return false;
    }
  }
  return true;
}

// --- Registration ------------------------------------------------------------------------------

void registerLieGroups()
{
  const auto& in = stepInputs();
  const auto& rel = relativePoses();
  registerOp("so3/exp", [&in](std::size_t i) { return si::so3Exp<double>(in.twist[i].head<3>()); });
  registerOp("so3/log", [&rel](std::size_t i) { return si::so3Log<double>(rel[i].q); });
  registerOp("se3/exp", [&in](std::size_t i) { return si::se3Exp<double>(in.twist[i]); });
  registerOp("se3/log", [&rel](std::size_t i) { return si::se3Log<double>(rel[i]); });

  registerOp("eigen/so3_exp", [&in](std::size_t i) {
    const Eigen::Vector3d w = in.twist[i].head<3>();
    const double angle = w.norm();
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
  });
  registerOp("eigen/so3_log", [&rel](std::size_t i) {
    const Eigen::AngleAxisd aa(Eigen::Quaterniond(rel[i].q.w(), rel[i].q.x(), rel[i].q.y(), rel[i].q.z()));
    return Eigen::Vector3d(aa.angle() * aa.axis());
  });
  const auto kdl_rel = std::make_shared<std::vector<KDL::Frame>>(toKdl(rel));
  registerOp("kdl/so3_exp", [&in](std::size_t i) {
    return KDL::Rot(KDL::Vector(in.twist[i][0], in.twist[i][1], in.twist[i][2]));
  });
  registerOp("kdl/so3_log", [kdl_rel](std::size_t i) { return (*kdl_rel)[i].M.GetRot(); });
}

template <class G>
void registerGeometry(const std::string& g)
{
  const auto& in = stepInputs();
  const auto& t = parameters();
  registerOp(g + "/exp", [&in](std::size_t i) { return G::exp(in.a[i], in.twist[i]); });
  registerOp(g + "/log", [&in](std::size_t i) { return G::log(in.a[i], in.b[i]); });
  registerOp(g + "/step", [&in](std::size_t i) { return si::geodesic<G>(in.a[i], in.b[i], in.lambda[i]); });

  auto logs = std::make_shared<std::vector<se3_bench::Twist6>>();
  for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
    logs->push_back(G::log(in.a[i], in.b[i]));
  registerOp(g + "/step_from_log",
             [&in, logs](std::size_t i) { return si::geodesicFromLog<G>(in.a[i], (*logs)[i], in.lambda[i]); });
  registerOp(g + "/step_jet", [&in, logs](std::size_t i) {
    return si::geodesicKinematicsFromLog<G>(in.a[i], (*logs)[i], si::Jet<2>::variable(in.lambda[i]));
  });

  const auto bezier = se3_bench::makeBezierCurves<G>();
  const auto bspline = se3_bench::makeBsplineCurves<G>();
  registerOp(g + "/bezier_point", [bezier, &t](std::size_t i) { return bezier[i & 15]->value(t[i]); });
  registerOp(g + "/bezier_point_jet", [bezier, &t](std::size_t i) { return si::kinematicsAt(*bezier[i & 15], t[i]); });
  registerOp(g + "/bspline_point", [bspline, &t](std::size_t i) { return bspline[i & 15]->value(t[i]); });
  registerOp(g + "/bspline_point_jet",
             [bspline, &t](std::size_t i) { return si::kinematicsAt(*bspline[i & 15], t[i]); });

  // Sampling: N evenly spaced kinematicsAt of the natural interpolating spline through 100 waypoints.
  const std::shared_ptr<const si::Curve<G>> spline = se3_bench::makeInterpolatingCurve<G>(100);
  benchmark::RegisterBenchmark((g + "/sample_interpolating").c_str(),
                               [spline](benchmark::State& state) {
                                 const std::size_t n = static_cast<std::size_t>(state.range(0));
                                 const double t0 = spline->startTime();
                                 const double dt = (spline->endTime() - t0) / static_cast<double>(n - 1);
                                 for (auto _ : state)
                                   for (std::size_t j = 0; j < n; ++j)
                                   {
                                     si::Kinematics k = si::kinematicsAt(*spline, t0 + dt * static_cast<double>(j));
                                     benchmark::DoNotOptimize(k);
                                   }
                                 state.SetItemsProcessed(state.iterations() * state.range(0));
                                 state.SetComplexityN(state.range(0));
                               })
      ->RangeMultiplier(10)
      ->Range(1000, 100000)
      ->Complexity(benchmark::oN)
      ->Unit(benchmark::kMillisecond);

  // The planner end to end (validation, solve, figures, sampling) with sample_count N.
  si::TrajectoryRequest request;
  request.waypoints = se3_bench::makeWaypoints(100);
  for (std::size_t i = 0; i < 100; ++i)
    request.times.push_back(static_cast<double>(i));
  request.curve = "interpolating";
  request.geometry = g == "screw" ? "screw" : "double_geodesic";
  benchmark::RegisterBenchmark((g + "/planner_interpolating").c_str(),
                               [request](benchmark::State& state) {
                                 si::TrajectoryRequest r = request;
                                 r.sample_count = static_cast<std::uint32_t>(state.range(0));
                                 for (auto _ : state)
                                 {
                                   si::TrajectoryResult result = si::generate(r, si::PlannerLimits());
                                   benchmark::DoNotOptimize(result.samples.data());
                                 }
                                 state.SetItemsProcessed(state.iterations() * state.range(0));
                               })
      ->RangeMultiplier(10)
      ->Range(1000, 100000)
      ->Unit(benchmark::kMillisecond);
}

void registerPeers()
{
  const auto& in = stepInputs();
  const auto& t = parameters();

  // Eigen: slerp + lerp.
  auto ea = std::make_shared<std::vector<EigenPose>>(se3_bench::toEigen(in.a));
  auto eb = std::make_shared<std::vector<EigenPose>>(se3_bench::toEigen(in.b));
  registerOp("eigen/step",
             [ea, eb, &in](std::size_t i) { return se3_bench::slerpLerp((*ea)[i], (*eb)[i], in.lambda[i]); });
  auto epoly = std::make_shared<std::vector<std::vector<EigenPose>>>();
  for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, 4, 2))
    epoly->push_back(se3_bench::toEigen(p));
  auto econtrol = std::make_shared<std::vector<std::vector<EigenPose>>>();
  for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, se3_bench::kBsplinePoints, 3))
    econtrol->push_back(se3_bench::toEigen(p));
  const std::vector<double> knots = si::clampedUniformKnots(se3_bench::kBsplinePoints, 3, 0.0, 1.0);
  registerOp("eigen/bezier_point", [epoly, &t](std::size_t i) {
    return se3_bench::cubicDeCasteljau((*epoly)[i & 15].data(), t[i], se3_bench::slerpLerp);
  });
  registerOp("eigen/bspline_point", [econtrol, knots, &t](std::size_t i) {
    return se3_bench::cubicDeBoor((*econtrol)[i & 15], knots, t[i], se3_bench::slerpLerp);
  });
  // Velocity and acceleration by central differences: three evaluations per point.
  constexpr double kH = 1e-4;
  registerOp("eigen/bezier_point_fd", [epoly, &t](std::size_t i) {
    const EigenPose* c = (*epoly)[i & 15].data();
    return finiteDifferences(se3_bench::cubicDeCasteljau(c, t[i] - kH, se3_bench::slerpLerp),
                             se3_bench::cubicDeCasteljau(c, t[i], se3_bench::slerpLerp),
                             se3_bench::cubicDeCasteljau(c, t[i] + kH, se3_bench::slerpLerp), kH);
  });
  registerOp("eigen/bspline_point_fd", [econtrol, knots, &t](std::size_t i) {
    const std::vector<EigenPose>& c = (*econtrol)[i & 15];
    return finiteDifferences(se3_bench::cubicDeBoor(c, knots, t[i] - kH, se3_bench::slerpLerp),
                             se3_bench::cubicDeBoor(c, knots, t[i], se3_bench::slerpLerp),
                             se3_bench::cubicDeBoor(c, knots, t[i] + kH, se3_bench::slerpLerp), kH);
  });

  // KDL: Path_Line + RotationalInterpolation_SingleAxis, and diff/addDelta.
  auto ka = std::make_shared<std::vector<KDL::Frame>>(toKdl(in.a));
  auto kb = std::make_shared<std::vector<KDL::Frame>>(toKdl(in.b));
  registerOp("kdl/step", [ka, kb, &in](std::size_t i) {
    KDL::RotationalInterpolation_SingleAxis rotation;
    KDL::Path_Line line((*ka)[i], (*kb)[i], &rotation, 1.0, false);
    return line.Pos(in.lambda[i] * line.PathLength());
  });
  registerOp("kdl/step_delta", [ka, kb, &in](std::size_t i) { return kdlInterp((*ka)[i], (*kb)[i], in.lambda[i]); });
  auto lines = std::make_shared<std::vector<std::unique_ptr<KDL::Path_Line>>>();
  auto lengths = std::make_shared<std::vector<double>>();
  for (std::size_t i = 0; i < se3_bench::kTableSize; ++i)
  {
    lines->push_back(kdlLine((*ka)[i], (*kb)[i]));
    lengths->push_back(lines->back()->PathLength());
  }
  registerOp("kdl/path_pos",
             [lines, lengths, &in](std::size_t i) { return (*lines)[i]->Pos(in.lambda[i] * (*lengths)[i]); });
  registerOp("kdl/path_pos_vel_acc", [lines, lengths, &in](std::size_t i) {
    const double s = in.lambda[i] * (*lengths)[i];
    const double sd = (*lengths)[i];
    const KDL::Path_Line& line = *(*lines)[i];
    return std::make_tuple(line.Pos(s), line.Vel(s, sd), line.Acc(s, sd, 0.0));
  });
  auto kpoly = std::make_shared<std::vector<std::vector<KDL::Frame>>>();
  for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, 4, 2))
    kpoly->push_back(toKdl(p));
  auto kcontrol = std::make_shared<std::vector<std::vector<KDL::Frame>>>();
  for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, se3_bench::kBsplinePoints, 3))
    kcontrol->push_back(toKdl(p));
  registerOp("kdl/bezier_point",
             [kpoly, &t](std::size_t i) { return se3_bench::cubicDeCasteljau((*kpoly)[i & 15].data(), t[i], kdlInterp); });
  registerOp("kdl/bspline_point", [kcontrol, knots, &t](std::size_t i) {
    return se3_bench::cubicDeBoor((*kcontrol)[i & 15], knots, t[i], kdlInterp);
  });
}

/// The optional peers of bench_peers.h (Sophus, manif, basalt) that are compiled in.
void registerOptionalPeers()
{
#if defined(SE3_BENCH_SOPHUS) || defined(SE3_BENCH_MANIF)
  const auto& in = stepInputs();
  const auto& rel = relativePoses();
  auto twist = std::make_shared<std::vector<se3_bench::Twist6>>();
  for (const auto& xi : in.twist)
    twist->push_back(se3_bench::swapTwist(xi));
#endif
#ifdef SE3_BENCH_SOPHUS
  auto sa = std::make_shared<std::vector<Sophus::SE3d>>(se3_bench::toSophus(in.a));
  auto sb = std::make_shared<std::vector<Sophus::SE3d>>(se3_bench::toSophus(in.b));
  auto srel = std::make_shared<std::vector<Sophus::SE3d>>(se3_bench::toSophus(rel));
  registerOp("sophus/se3_exp", [twist](std::size_t i) { return Sophus::SE3d::exp((*twist)[i]); });
  registerOp("sophus/se3_log", [srel](std::size_t i) { return (*srel)[i].log(); });
  registerOp("sophus/screw_step",
             [sa, sb, &in](std::size_t i) { return se3_bench::sophusScrewStep((*sa)[i], (*sb)[i], in.lambda[i]); });
#endif
#ifdef SE3_BENCH_MANIF
  auto ma = std::make_shared<std::vector<manif::SE3d>>(se3_bench::toManif(in.a));
  auto mb = std::make_shared<std::vector<manif::SE3d>>(se3_bench::toManif(in.b));
  auto mrel = std::make_shared<std::vector<manif::SE3d>>(se3_bench::toManif(rel));
  registerOp("manif/se3_exp", [twist](std::size_t i) { return manif::SE3Tangentd((*twist)[i]).exp(); });
  registerOp("manif/se3_log", [mrel](std::size_t i) { return (*mrel)[i].log(); });
  registerOp("manif/screw_step",
             [ma, mb, &in](std::size_t i) { return se3_bench::manifScrewStep((*ma)[i], (*mb)[i], in.lambda[i]); });
#endif
#ifdef SE3_BENCH_BASALT
  auto splines = std::make_shared<std::vector<se3_bench::BasaltSpline>>();
  for (const auto& p : se3_bench::makePolygons(se3_bench::kCurveCount, se3_bench::kBsplinePoints, 3))
    splines->emplace_back(p);
  const auto& t = parameters();
  registerOp("basalt/bspline_point", [splines, &t](std::size_t i) {
    const auto& b = (*splines)[i & 15];
    const std::int64_t t_ns = b.timeNs(t[i]);
    return std::make_pair(b.so3.evaluate(t_ns), b.pos.evaluate(t_ns));
  });
  registerOp("basalt/bspline_point_jet", [splines, &t](std::size_t i) {
    const auto& b = (*splines)[i & 15];
    return se3_bench::basaltKinematics(b, b.timeNs(t[i]));
  });
#endif
}

// --- Reporting ---------------------------------------------------------------------------------

/// The console output, plus the CPU time per iteration (ns) of every repetition kept by name
/// (or, with --benchmark_display_aggregates_only, the median aggregate).
class CollectingReporter : public benchmark::ConsoleReporter
{
public:
  explicit CollectingReporter(OutputOptions options) : ConsoleReporter(options) {}

  void ReportRuns(const std::vector<Run>& runs) override
  {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs)
    {
      if (r.error_occurred)
        continue;
      std::string name = r.run_name.function_name;
      if (!r.run_name.args.empty())
        name += "/" + r.run_name.args;
      const double ns = r.GetAdjustedCPUTime() * 1e9 / benchmark::GetTimeUnitMultiplier(r.time_unit);
      if (r.run_type == Run::RT_Iteration)
        times_[name].push_back(ns);
      else if (r.aggregate_name == "median")
        medians_[name] = { ns, static_cast<std::size_t>(r.repetitions) };
    }
  }

  /// Median CPU time per iteration in ns, or NaN when the benchmark did not run.
  double median(const std::string& name) const
  {
    const auto it = times_.find(name);
    if (it == times_.end() || it->second.empty())
    {
      const auto m = medians_.find(name);
      return m == medians_.end() ? std::nan("") : m->second.first;
    }
    std::vector<double> v = it->second;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }

  std::size_t repetitions() const
  {
    std::size_t r = 0;
    for (const auto& kv : times_)
      r = std::max(r, kv.second.size());
    for (const auto& kv : medians_)
      r = std::max(r, kv.second.second);
    return r;
  }

private:
  std::map<std::string, std::vector<double>> times_;
  std::map<std::string, std::pair<double, std::size_t>> medians_;
};

struct Comparison
{
  std::string label;
  std::string ours;
  std::string peer;
  std::string peer_label;
  double target;  ///< the largest acceptable ratio, or 0 when there is no target
};

void printRatios(const CollectingReporter& rep)
{
  std::vector<Comparison> rows = {
    { "so3 exp", "so3/exp", "eigen/so3_exp", "Eigen AngleAxis->Quaternion", 0.0 },
    { "so3 exp", "so3/exp", "kdl/so3_exp", "KDL Rot(vector)", 0.0 },
    { "so3 log", "so3/log", "eigen/so3_log", "Eigen Quaternion->AngleAxis", 0.0 },
    { "so3 log", "so3/log", "kdl/so3_log", "KDL Rotation::GetRot", 0.0 },
  };
  for (const std::string g : { "double_geodesic", "screw" })
  {
    const double target = g == "double_geodesic" ? 1.0 : 0.0;
    rows.push_back({ g + " step (two poses)", g + "/step", "eigen/step", "Eigen slerp+lerp", target });
    rows.push_back({ g + " step (two poses)", g + "/step", "kdl/step", "KDL Path_Line built + Pos", 0.0 });
    rows.push_back({ g + " step (two poses)", g + "/step", "kdl/step_delta", "KDL addDelta(diff)", 0.0 });
    rows.push_back({ g + " step (precomputed log)", g + "/step_from_log", "eigen/step", "Eigen slerp+lerp", target });
    rows.push_back({ g + " step (precomputed log)", g + "/step_from_log", "kdl/path_pos", "KDL Path_Line::Pos", 0.0 });
    rows.push_back({ g + " step + vel + acc", g + "/step_jet", "kdl/path_pos_vel_acc", "KDL Pos+Vel+Acc", 0.0 });
    rows.push_back({ g + " cubic Bezier point", g + "/bezier_point", "eigen/bezier_point", "Eigen slerp+lerp", target });
    rows.push_back({ g + " cubic Bezier point", g + "/bezier_point", "kdl/bezier_point", "KDL addDelta(diff)", 0.0 });
    rows.push_back({ g + " cubic Bezier point + vel + acc", g + "/bezier_point_jet", "eigen/bezier_point_fd",
                     "Eigen 3 evaluations (FD)", 0.0 });
    rows.push_back({ g + " cubic B-spline point", g + "/bspline_point", "eigen/bspline_point", "Eigen slerp+lerp", target });
    rows.push_back({ g + " cubic B-spline point", g + "/bspline_point", "kdl/bspline_point", "KDL addDelta(diff)", 0.0 });
    rows.push_back({ g + " cubic B-spline point + vel + acc", g + "/bspline_point_jet", "eigen/bspline_point_fd",
                     "Eigen 3 evaluations (FD)", 0.0 });
  }

  // The optional peers (rows without a measured peer are left out below).
  rows.push_back({ "se3 exp", "se3/exp", "sophus/se3_exp", "Sophus SE3::exp", 0.0 });
  rows.push_back({ "se3 exp", "se3/exp", "manif/se3_exp", "manif SE3Tangent::exp", 0.0 });
  rows.push_back({ "se3 log", "se3/log", "sophus/se3_log", "Sophus SE3::log", 0.0 });
  rows.push_back({ "se3 log", "se3/log", "manif/se3_log", "manif SE3::log", 0.0 });
  rows.push_back({ "screw step (two poses)", "screw/step", "sophus/screw_step", "Sophus a*exp(l*log)", 0.0 });
  rows.push_back({ "screw step (two poses)", "screw/step", "manif/screw_step", "manif a.rplus(l*rminus)", 0.0 });
  for (const std::string g : { "double_geodesic", "screw" })
  {
    rows.push_back({ g + " cubic B-spline point", g + "/bspline_point", "basalt/bspline_point",
                     "basalt cumulative SO3xR3", 0.0 });
    rows.push_back({ g + " cubic B-spline point + vel + acc", g + "/bspline_point_jet", "basalt/bspline_point_jet",
                     "basalt cumulative SO3xR3", 1.0 });
  }

  std::printf("\nRatios ours / peer (median CPU time per operation over %zu repetition(s); < 1: ours faster)\n",
              rep.repetitions());
  std::printf("%-50s %9s  %-28s %9s %7s  %s\n", "operation", "ours ns", "peer", "peer ns", "ratio", "target");
  for (const Comparison& c : rows)
  {
    const double a = rep.median(c.ours);
    const double b = rep.median(c.peer);
    if (std::isnan(a) || std::isnan(b))
      continue;
    const double ratio = a / b;
    std::string verdict;
    if (c.target > 0.0)
      verdict = (ratio <= c.target ? "<= " : "MISS <= ") + std::to_string(c.target).substr(0, 4);
    std::printf("%-50s %9.1f  %-28s %9.1f %7.2f  %s\n", c.label.c_str(), a, c.peer_label.c_str(), b, ratio,
                verdict.c_str());
  }

  std::printf("\nSampling with velocity and acceleration (kinematicsAt; target >= 1e6 samples/s, linear in N)\n");
  std::printf("%-38s %8s %10s %11s %14s\n", "benchmark", "N", "ms/batch", "ns/sample", "samples/s");
  for (const std::string g : { "double_geodesic", "screw" })
    for (const std::string what : { "sample_interpolating", "planner_interpolating" })
    {
      double previous_ns = std::nan("");
      double previous_n = 0.0;
      for (const int n : { 1000, 10000, 100000 })
      {
        const double ns = rep.median(g + "/" + what + "/" + std::to_string(n));
        if (std::isnan(ns))
          continue;
        std::printf("%-38s %8d %10.3f %11.1f %14.3g", (g + "/" + what).c_str(), n, ns * 1e-6, ns / n, n / (ns * 1e-9));
        if (!std::isnan(previous_ns))
          std::printf("   marginal %.1f ns/sample", (ns - previous_ns) / (n - previous_n));
        std::printf("\n");
        previous_ns = ns;
        previous_n = n;
      }
    }
}

}  // namespace

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  if (!checkPeers() || !se3_bench::checkPeersAgree())
    return 1;
  registerLieGroups();
  registerGeometry<si::DoubleGeodesicSe3>("double_geodesic");
  registerGeometry<si::ScrewSe3>("screw");
  registerPeers();
  registerOptionalPeers();
  // Colour only on a terminal (--benchmark_color is honoured by the default reporter only).
  CollectingReporter reporter(isatty(fileno(stdout)) ? benchmark::ConsoleReporter::OO_ColorTabular
                                                     : benchmark::ConsoleReporter::OO_Tabular);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  std::fflush(stdout);
  std::cout.flush();
  printRatios(reporter);
  return 0;
}
