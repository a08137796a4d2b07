// Google Benchmark of the time-optimal timing (timing/time_optimal.h) against TOPP-RA's C++ API
// (H. Pham, Q.-C. Pham, IEEE T-RO 34(3), 2018; github.com/hungpham2511/toppra, its `cpp/`
// library with the built-in Seidel LP solver), an optional peer built only when a local copy is
// given by path (SE3_BENCH_TOPPRA_DIR: CMakeLists.txt, scripts/run_benchmarks.sh). Nothing of
// TOPP-RA is part of the project: the peer is read from the given directory at build time only.
//
// The problem: the natural interpolating double-geodesic spline through
// N = 10 … 10⁴ waypoints at chord-spaced times (1 m of chord per second), identity orientations,
// timed from rest to rest under |v| ≤ 1 m/s and |a| ≤ 2 m/s² only. With the rotation constant
// the translation of that spline is exactly the classical cubic spline through the positions, so
// TOPP-RA is given it as a cubic piecewise polynomial whose coefficients are the project's own
// exact derivatives at each segment start (p, p′, p″, and p‴ constant on the segment), and the
// project's own grid (its profile's path parameters: 16 intervals per segment, at least 512, and
// its halvings). Paths: a line along x (waypoint spacing 0.2 … 1 m), a 270° arc of radius 0.4 m
// in the xy-plane (|a| = v²/r: acceleration-limited on the arc, at 0.89 m/s) and the 3-D random
// walk of bench_time_optimal (random_walk.h).
//
// Per row (path × N):
//  - the timed loop is the project's timing; inside it, with the loop's clock paused, TOPP-RA
//    solves the same path with per-coordinate box constraints (|v_k| ≤ 1, |a_k| ≤ 2: its
//    LinearJointVelocity and LinearJointAcceleration, its joint limits). Both are
//    also timed by the thread's CPU clock: `cpu_ratio` = TOPP-RA's / the project's CPU per solve;
//  - once, the same constraint sets: the velocity norm exactly (an x bound ṡ² ≤ v²/|p′|², which
//    is the norm bound itself) and the acceleration norm ball by its circumscribed polytope
//    (line: ±x, exact on a path along x; arc: a 16-sided polygon in the plane of the path; walk:
//    kWalkDirections directions on a Fibonacci sphere). `duration_ratio` = TOPP-RA's duration /
//    the project's; the run stops when they differ by more than kDurationTolerance;
//  - both motions are then evaluated densely (kDenseSamples per grid interval): their true peak
//    |v| and |a| (`*_v`, `*_a`; TOPP-RA imposes its constraints at the grid points only, the
//    project checks between them too, time_optimal.h), and TOPP-RA's peak of its own polytope's
//    measure max_k n_k · a (`toppra_a_polytope`: its overshoot between grid points alone, without
//    the polytope's corners).
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <toppra/algorithm/toppra.hpp>
#include <toppra/constraint.hpp>
#include <toppra/constraint/linear_joint_acceleration.hpp>
#include <toppra/constraint/linear_joint_velocity.hpp>
#include <toppra/geometric_path.hpp>
#include <toppra/geometric_path/piecewise_poly_path.hpp>
#include <toppra/parametrizer/const_accel.hpp>
#include <toppra/solver/seidel.hpp>

#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "random_walk.h"

namespace
{
using namespace se3_interpolation;
using Geometry = DoubleGeodesicSe3;

/// The bounds compared: |v| ≤ 1 m/s, |a| ≤ 2 m/s² (linear only; the rotation does not move).
constexpr double kMaxLinearVelocity = 1.0;
constexpr double kMaxLinearAcceleration = 2.0;
/// The acceptance: both durations within 1 % (the project is within ~0.3 % of the
/// optimum on its grid, time_optimal.h; the polytopes' corners shorten TOPP-RA's, by at most
/// 1 − √cos(gap / 2), and far less where the acceleration does not point into one).
constexpr double kDurationTolerance = 0.01;
/// The polygon of the planar path (16 sides: the norm ball within 2 %).
constexpr int kPolygonSides = 16;
/// Directions of the walk's polytope: their largest angular gap (0.24 rad, sampled) lets the
/// polytope reach 1/cos(0.24) = 1.029 times the bound (the 16-gon: 1/cos(π/16) = 1.020).
constexpr int kWalkDirections = 128;
/// Samples per grid interval, ends included, for the peak rates between grid points.
constexpr int kDenseSamples = 9;
/// The arc: 270° of radius 0.4 m (v²/r at 1 m/s is 2.5 m/s², above the bound).
constexpr double kArcRadius = 0.4;
constexpr double kArcAngle = 1.5 * M_PI;
/// TOPP-RA's cubic pieces against the project's spline (rounding of the power basis: ~1e-15 relative).
constexpr double kSamePathTolerance = 1e-9;
/// ṡ² where |p′| = 0 (no velocity limit): TOPP-RA's own LinearJointVelocity default (ṡ ≤ 1e8).
constexpr double kUnboundedPathSpeedSquared = 1e16;

enum class PathKind
{
  kLine,
  kArc,
  kWalk
};

/// The waypoint positions of `kind` (identity orientations).
std::vector<Pose<double>> waypoints(PathKind kind, std::size_t n)
{
  std::vector<Pose<double>> out;
  if (kind == PathKind::kWalk)
  {
    for (const Pose<double>& p : se3_bench::randomWalk(n))
      out.emplace_back(Quaternion<double>::Identity(), p.p);
    return out;
  }
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> spacing(0.2, 1.0);
  double x = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double phi = kArcAngle * static_cast<double>(i) / static_cast<double>(n - 1);
    const Eigen::Vector3d p = kind == PathKind::kLine ?
                                  Eigen::Vector3d(x, 0.0, 0.0) :
                                  Eigen::Vector3d(kArcRadius * std::cos(phi), kArcRadius * std::sin(phi), 0.0);
    out.emplace_back(Quaternion<double>::Identity(), p);
    x += spacing(rng);
  }
  return out;
}

/// The natural interpolating spline through `points` at chord-spaced times (1 m per second).
std::shared_ptr<const Curve<Geometry>> spline(const std::vector<Pose<double>>& points)
{
  std::vector<double> times{ 0.0 };
  for (std::size_t i = 1; i < points.size(); ++i)
    times.push_back(times.back() + (points[i].p - points[i - 1].p).norm());
  const Geometry::Tangent<double> zero = Geometry::Tangent<double>::Zero();
  return makeInterpolatingSpline<Geometry>(points, times, EndCondition::kNatural, zero, zero, zero);
}

/// The spline's translation as TOPP-RA's cubic piecewise polynomial: per segment the rows
/// p‴/6, p″/2, p′, p (its highest power first) from the project's jets at the segment start.
std::shared_ptr<toppra::PiecewisePolyPath> toppraPath(const Curve<Geometry>& curve)
{
  const std::vector<double> breaks = curve.breakpoints();
  toppra::Matrices coefficients;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
  {
    const Kinematics start = kinematicsAt(curve, breaks[i], Side::kRight);
    const Kinematics end = kinematicsAt(curve, breaks[i + 1], Side::kLeft);
    const Eigen::Vector3d jerk = (end.acceleration.linear - start.acceleration.linear) / (breaks[i + 1] - breaks[i]);
    toppra::Matrix c(4, 3);
    c.row(0) = jerk / 6.0;
    c.row(1) = start.acceleration.linear / 2.0;
    c.row(2) = start.velocity.linear;
    c.row(3) = start.pose.p;
    coefficients.push_back(c);
  }
  auto path = std::make_shared<toppra::PiecewisePolyPath>(coefficients, breaks);
  // The same curve: position and velocity at every segment's middle, to kSamePathTolerance.
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
  {
    const double s = 0.5 * (breaks[i] + breaks[i + 1]);
    const Kinematics k = kinematicsAt(curve, s);
    if ((path->eval_single(s, 0) - k.pose.p).norm() > kSamePathTolerance * std::max(1.0, k.pose.p.norm()) ||
        (path->eval_single(s, 1) - k.velocity.linear).norm() > kSamePathTolerance)
    {
      std::fprintf(stderr, "bench_toppra: TOPP-RA's polynomial differs from the spline in segment %zu\n", i);
      std::exit(EXIT_FAILURE);
    }
  }
  return path;
}

/// |p′ ṡ| ≤ v_max exactly, as TOPP-RA's x bound ṡ² ≤ v_max² / |p′|² at each grid point.
class NormVelocityConstraint : public toppra::LinearConstraint
{
public:
  explicit NormVelocityConstraint(double max_velocity)
    : toppra::LinearConstraint(0, 0, true, false, true), max_velocity_(max_velocity)
  {
  }

private:
  void computeParams_impl(const toppra::GeometricPath& path, const toppra::Vector& gridpoints, toppra::Vectors&,
                          toppra::Vectors&, toppra::Vectors&, toppra::Matrices&, toppra::Vectors&, toppra::Bounds&,
                          toppra::Bounds& xbound) override
  {
    for (Eigen::Index i = 0; i < gridpoints.size(); ++i)
    {
      const double speed_squared = path.eval_single(gridpoints[i], 1).squaredNorm();
      xbound[i] << 0.0,
          speed_squared > 0.0 ? max_velocity_ * max_velocity_ / speed_squared : kUnboundedPathSpeedSquared;
    }
  }
  double max_velocity_;
};

/// n_k · (p″ ṡ² + p′ s̈) ≤ a_max for the unit rows n_k of `normals`: the polytope circumscribing
/// the ball |a| ≤ a_max (it contains the ball; its corners reach a_max / cos(largest gap / 2)).
class PolytopeAccelerationConstraint : public toppra::LinearConstraint
{
public:
  PolytopeAccelerationConstraint(toppra::Matrix normals, double max_acceleration)
    : toppra::LinearConstraint(normals.rows(), 3, true, false, false)
    , normals_(std::move(normals))
    , max_acceleration_(max_acceleration)
  {
  }

private:
  void computeParams_impl(const toppra::GeometricPath& path, const toppra::Vector& gridpoints, toppra::Vectors& a,
                          toppra::Vectors& b, toppra::Vectors& c, toppra::Matrices& F, toppra::Vectors& g,
                          toppra::Bounds&, toppra::Bounds&) override
  {
    F[0] = normals_;
    g[0].setConstant(max_acceleration_);
    for (Eigen::Index i = 0; i < gridpoints.size(); ++i)
    {
      a[i] = path.eval_single(gridpoints[i], 1);
      b[i] = path.eval_single(gridpoints[i], 2);
      c[i].setZero();
    }
  }
  toppra::Matrix normals_;
  double max_acceleration_;
};

/// The outward normals of the acceleration polytope for `kind` (see the file comment).
toppra::Matrix polytopeNormals(PathKind kind)
{
  if (kind == PathKind::kLine)
  {
    toppra::Matrix n(2, 3);
    n << 1.0, 0.0, 0.0, -1.0, 0.0, 0.0;
    return n;
  }
  if (kind == PathKind::kArc)
  {
    toppra::Matrix n(kPolygonSides, 3);
    for (int k = 0; k < kPolygonSides; ++k)
      n.row(k) << std::cos(2.0 * M_PI * k / kPolygonSides), std::sin(2.0 * M_PI * k / kPolygonSides), 0.0;
    return n;
  }
  // Fibonacci sphere: heights uniform in (−1, 1), azimuths by the golden angle.
  toppra::Matrix n(kWalkDirections, 3);
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < kWalkDirections; ++k)
  {
    const double z = 1.0 - (2.0 * k + 1.0) / kWalkDirections;
    const double r = std::sqrt(1.0 - z * z);
    n.row(k) << r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z;
  }
  return n;
}

/// TOPP-RA's per-coordinate boxes |v_k| ≤ v_max, |a_k| ≤ a_max.
toppra::LinearConstraintPtrs boxConstraints()
{
  const toppra::Vector v = toppra::Vector::Constant(3, kMaxLinearVelocity);
  const toppra::Vector a = toppra::Vector::Constant(3, kMaxLinearAcceleration);
  return { std::make_shared<toppra::constraint::LinearJointVelocity>(-v, v),
           std::make_shared<toppra::constraint::LinearJointAcceleration>(-a, a) };
}

toppra::LinearConstraintPtrs normConstraints(PathKind kind)
{
  return { std::make_shared<NormVelocityConstraint>(kMaxLinearVelocity),
           std::make_shared<PolytopeAccelerationConstraint>(polytopeNormals(kind), kMaxLinearAcceleration) };
}

/// TOPP-RA from rest to rest on `grid` with the Seidel solver; its motion (constant s̈ per
/// interval), or null with its error message in `error` when it fails (a row is then skipped
/// with that message: TOPP-RA's passes can fail on rounding, see docs/performance.md).
std::shared_ptr<toppra::parametrizer::ConstAccel> solveToppra(const toppra::LinearConstraintPtrs& constraints,
                                                              const std::shared_ptr<toppra::PiecewisePolyPath>& path,
                                                              const toppra::Vector& grid, std::string* error)
{
  toppra::algorithm::TOPPRA algorithm(constraints, path);
  algorithm.setGridpoints(grid);
  algorithm.solver(std::make_shared<toppra::solver::Seidel>());
  if (algorithm.computePathParametrization(0.0, 0.0) != toppra::ReturnCode::OK)
  {
    *error = algorithm.getErrorMessage();
    std::replace(error->begin(), error->end(), '\n', ' ');
    return nullptr;
  }
  const toppra::ParametrizationData& data = algorithm.getParameterizationData();
  return std::make_shared<toppra::parametrizer::ConstAccel>(path, data.gridpoints, data.parametrization);
}

timing::RateBounds linearBounds()
{
  timing::RateBounds b;
  b.velocity = { kMaxLinearVelocity, 0.0 };
  b.acceleration = { kMaxLinearAcceleration, 0.0 };
  return b;
}

double threadCpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Times from t_i to t_{i+1} of every interval of `grid_times`, kDenseSamples each.
toppra::Vector denseTimes(const std::vector<double>& grid_times)
{
  toppra::Vector out((grid_times.size() - 1) * kDenseSamples);
  for (std::size_t i = 0; i + 1 < grid_times.size(); ++i)
    for (int j = 0; j < kDenseSamples; ++j)
      out[static_cast<Eigen::Index>(i * kDenseSamples + j)] =
          grid_times[i] + (grid_times[i + 1] - grid_times[i]) * j / (kDenseSamples - 1);
  return out;
}

struct Peaks
{
  double velocity = 0.0;
  double acceleration = 0.0;
  /// TOPP-RA's: max_k n_k · a over its polytope's normals (its own constraint's measure of |a|:
  /// above the bound only between grid points, unlike |a|, which also reaches into the corners).
  double polytope_acceleration = 0.0;
};

Peaks toppraPeaks(const toppra::parametrizer::ConstAccel& motion, const toppra::Matrix& normals)
{
  const toppra::Vector& t = motion.getTimes();
  const toppra::Vector samples = denseTimes(std::vector<double>(t.data(), t.data() + t.size()));
  Peaks peaks;
  for (const toppra::Vector& v : motion.eval(samples, 1))
    peaks.velocity = std::max(peaks.velocity, v.norm());
  for (const toppra::Vector& a : motion.eval(samples, 2))
  {
    peaks.acceleration = std::max(peaks.acceleration, a.norm());
    peaks.polytope_acceleration = std::max(peaks.polytope_acceleration, (normals * a).maxCoeff());
  }
  return peaks;
}

/// The project's motion at the same density, each interval from its own side at its ends.
Peaks projectPeaks(const std::shared_ptr<const Curve<Geometry>>& path, const timing::TimingProfile& profile)
{
  const timing::TimeOptimalCurve<Geometry> motion(path, profile);
  Peaks peaks;
  for (std::size_t i = 0; i + 1 < profile.t.size(); ++i)
    for (int j = 0; j < kDenseSamples; ++j)
    {
      const double t = profile.t[i] + (profile.t[i + 1] - profile.t[i]) * j / (kDenseSamples - 1);
      const Kinematics k = kinematicsAt(motion, t, j + 1 == kDenseSamples ? Side::kLeft : Side::kRight);
      peaks.velocity = std::max(peaks.velocity, k.velocity.linear.norm());
      peaks.acceleration = std::max(peaks.acceleration, k.acceleration.linear.norm());
    }
  return peaks;
}

void toppraPeer(benchmark::State& state, PathKind kind, const char* name)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const auto curve = spline(waypoints(kind, n));
  const timing::CurvePath<Geometry> project_path(curve);
  const auto peer_path = toppraPath(*curve);
  const timing::TimingProfile reference = timing::timeOptimalProfile(project_path, linearBounds());
  const toppra::Vector grid = Eigen::Map<const toppra::Vector>(reference.s.data(),
                                                               static_cast<Eigen::Index>(reference.s.size()));

  // The same constraint sets: durations and peaks.
  const double norm_start = threadCpuSeconds();
  std::string error;
  const auto same = solveToppra(normConstraints(kind), peer_path, grid, &error);
  const double norm_cpu = threadCpuSeconds() - norm_start;
  if (!same)
  {
    state.SkipWithError(("TOPP-RA failed under the norm constraints: " + error).c_str());
    return;
  }
  const double peer_duration = same->pathInterval()[1] - same->pathInterval()[0];
  const double duration_ratio = peer_duration / reference.duration();
  if (std::abs(duration_ratio - 1.0) > kDurationTolerance)
  {
    std::fprintf(stderr,
                 "bench_toppra: %s, N = %zu: TOPP-RA's duration %.6f s and the project's %.6f s differ by "
                 "%.2f %% (> %.0f %%)\n",
                 name, n, peer_duration, reference.duration(), 100.0 * (duration_ratio - 1.0),
                 100.0 * kDurationTolerance);
    std::exit(EXIT_FAILURE);
  }
  const Peaks peer_peaks = toppraPeaks(*same, polytopeNormals(kind));
  const Peaks project_peaks = projectPeaks(curve, reference);

  // CPU: the project against TOPP-RA's boxes.
  const toppra::LinearConstraintPtrs boxes = boxConstraints();
  double project_cpu = 0.0, peer_cpu = 0.0, box_duration = 0.0;
  for (auto _ : state)
  {
    const double start = threadCpuSeconds();
    benchmark::DoNotOptimize(timing::timeOptimalProfile(project_path, linearBounds()));
    project_cpu += threadCpuSeconds() - start;
    state.PauseTiming();
    const double peer_start = threadCpuSeconds();
    const auto boxed = solveToppra(boxes, peer_path, grid, &error);
    peer_cpu += threadCpuSeconds() - peer_start;
    if (!boxed)
    {
      state.ResumeTiming();
      state.SkipWithError(("TOPP-RA failed under the box constraints: " + error).c_str());
      return;
    }
    box_duration = boxed->pathInterval()[1] - boxed->pathInterval()[0];
    state.ResumeTiming();
  }
  const double iterations = static_cast<double>(state.iterations());
  const double per_1000 = 1000.0 / static_cast<double>(n);
  state.counters["grid"] = static_cast<double>(grid.size() - 1);
  state.counters["duration"] = reference.duration();
  state.counters["duration_ratio"] = duration_ratio;
  state.counters["box_duration_ratio"] = box_duration / reference.duration();
  state.counters["project_v"] = project_peaks.velocity;
  state.counters["project_a"] = project_peaks.acceleration;
  state.counters["toppra_v"] = peer_peaks.velocity;
  state.counters["toppra_a"] = peer_peaks.acceleration;
  state.counters["toppra_a_polytope"] = peer_peaks.polytope_acceleration;
  state.counters["project_ms_per_1000"] = 1e3 * project_cpu / iterations * per_1000;
  state.counters["toppra_box_ms_per_1000"] = 1e3 * peer_cpu / iterations * per_1000;
  state.counters["toppra_norm_ms_per_1000"] = 1e3 * norm_cpu * per_1000;
  state.counters["cpu_ratio"] = peer_cpu / project_cpu;
}

// 10⁴ waypoints: one solve of each takes about a second.
BENCHMARK_CAPTURE(toppraPeer, line, PathKind::kLine, "line")
    ->Arg(10)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(toppraPeer, arc, PathKind::kArc, "arc")
    ->Arg(10)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(toppraPeer, walk, PathKind::kWalk, "walk")
    ->Arg(10)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
