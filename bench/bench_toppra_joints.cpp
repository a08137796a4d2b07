// Google Benchmark of the joint-limited time-optimal timing (docs/joint_space.md) against the
// Cartesian-only one and against TOPP-RA's C++ library (H. Pham, Q.-C. Pham, "A New Approach to
// Time-Optimal Path Parameterization based on Reachability Analysis", IEEE T-RO 34(3), 2018;
// github.com/hungpham2511/toppra, its `cpp/` library with the built-in Seidel LP solver) with joint
// velocity and acceleration boxes on the same joint path. TOPP-RA is an optional peer built only
// from a local copy given by path (SE3_BENCH_TOPPRA_DIR, scripts/run_benchmarks.sh), as for
// bench_toppra; nothing of it is part of the project.
//
// The problem: the UR5e walk of bench_joint_space (ur5e_walk.h), N = 100 and 1000 waypoints, an
// interpolating spline timed time-optimally from rest to rest under the request's Cartesian bounds
// (0.5 m/s, 1 rad/s, 2 m/s², 4 rad/s²) and the limits file's joint limits (π rad/s, 5 rad/s² each).
//
// The joint path TOPP-RA is given: the planner's untimed curve (validateRequest, waypointTimes and
// makeCurve, as the planner and the Python module build it), followed by the arm on the curve's own
// time axis s (arm::jointPathOf, as the planner's joint boxes are), sampled by JointPath::at on a
// grid of 16 uniform intervals per piece between the curve's breakpoints, at least 512 in all (the
// project's grid rule before its halvings, time_optimal.h), and joined by the quintic Hermite
// through q, dq/ds and d²q/ds² at every grid point. Quintic, not cubic: TOPP-RA imposes its
// constraints at its grid points with its path's q′ and q″ there, and the quintic's are exactly the
// joint path's (JointPath::at: Newton to 1e-12, then J⁻¹), so its constraints at its grid points are
// the joint limits on the arm's own path; a cubic Hermite's q″ there would be off by O(h²) and jump
// across every grid point. The grid points are the polynomial's breakpoints and TOPP-RA's grid; the
// quintic is checked against JointPath::at at every interval's middle (`path_dq`, the largest |Δq|
// in rad; the row is skipped above kSamePathTolerance).
//
// Per row (N), CPU time by the thread's clock, in ms per solve:
//  - the timed loop is `ours_ms`: generate() with the arm, all of it: validation, the curve, the
//    arm's tracking of the untimed curve (inverse kinematics), the time-optimal passes with the joint
//    boxes (each joint jet an inverse kinematics solve from the tracked neighbours), the tracking and
//    dense check of the timed motion, and its 100 samples with their joint states;
//  - inside it, with the loop's clock paused: `cart_ms`, generate() without the arm (the
//    Cartesian-only time-optimal timing, with its validation, curve and samples); `tracking_ms`,
//    arm::jointPathOf on the untimed curve alone (the first tracking inside ours); `solver_ms`, the
//    project's time-optimal timing (timeOptimalProfile) under the Cartesian bounds and the joint
//    limits with the joint jets from the quintic: the part of ours without inverse kinematics, on
//    TOPP-RA's input; `boxes_ms`, the same under the joint limits alone: TOPP-RA's problem on
//    TOPP-RA's grid (the halvings of the grid are made for bounded Cartesian channels: none here);
//    `toppra_ms`, TOPP-RA's solve on the quintic with LinearJointVelocity and
//    LinearJointAcceleration: the algorithm, its passes and its ConstAccel parametrization, as
//    bench_toppra times it. TOPP-RA gets the joint path for free: building it (tracking,
//    JointPath::at at every grid point, the quintic) is `toppra_input_ms`, measured once;
//    the ratios `ours/cart`, `ours/toppra`, `solver/toppra`, `boxes/toppra` are of the same run;
//  - durations (s): `ours_s`, `cart_s`, `solver_s`, `boxes_s`, `toppra_s` (boxes and TOPP-RA solve
//    the same problem on the same grid). TOPP-RA has no Cartesian bounds, so its duration is shorter
//    where they bind: its motion's peak Cartesian rates as ratios to the request's bounds are
//    `toppra_cart_v` (the larger of |v|/0.5, |ω|/1) and `toppra_cart_a` (of |a|/2, |α|/4);
//  - TOPP-RA's motion evaluated densely (kDenseSamples per grid interval, as bench_toppra): its peak
//    |q̇_k|/V_k and |q̈_k|/A_k over the joints (`toppra_qd`, `toppra_qdd`; it imposes them at its grid
//    points only); ours as its result reports them (`ours_qd`, `ours_qdd`, from the planner's dense
//    check of the timed motion; `ours_cart_v`, `ours_cart_a` from its figures).
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <stdexcept>
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

#include "se3_interpolation/arm/joint_path.h"
#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "ur5e_walk.h"

namespace
{
using namespace se3_interpolation;
using Geometry = DoubleGeodesicSe3;

/// The project's grid rule (time_optimal.h, TimeOptimalOptions) before its halvings.
constexpr std::size_t kIntervalsPerPiece = 16;
constexpr std::size_t kMinIntervals = 512;
/// Samples per grid interval, ends included, for the peak rates between grid points.
constexpr int kDenseSamples = 9;
/// The quintic against the joint path at the intervals' middles (rad): its interpolation error is
/// O(h⁶), far below this; a larger difference is a wrong path.
constexpr double kSamePathTolerance = 1e-6;
/// The request's Cartesian bounds (ur5e_walk.h).
constexpr double kMaxLinearVelocity = 0.5, kMaxAngularVelocity = 1.0;
constexpr double kMaxLinearAcceleration = 2.0, kMaxAngularAcceleration = 4.0;

double threadCpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// The grid of the file comment on the joint path's pieces [b_k, b_k+1].
std::vector<double> gridOf(const std::vector<double>& breakpoints)
{
  const double span = breakpoints.back() - breakpoints.front();
  std::vector<double> grid{ breakpoints.front() };
  for (std::size_t k = 0; k + 1 < breakpoints.size(); ++k)
  {
    const double a = breakpoints[k], b = breakpoints[k + 1];
    const std::size_t n =
        std::max(kIntervalsPerPiece,
                 static_cast<std::size_t>(std::ceil(static_cast<double>(kMinIntervals) * (b - a) / span)));
    for (std::size_t i = 1; i < n; ++i)
      grid.push_back(a + (b - a) * static_cast<double>(i) / static_cast<double>(n));
    grid.push_back(b);
  }
  return grid;
}

/// The quintic Hermite through (q, q′, q″) at every grid point: per interval the power coefficients
/// c_0 … c_5 (of τ = s − s_i) per joint, and its evaluation for both benchmarked solvers.
class QuinticJointPath
{
public:
  QuinticJointPath(const arm::JointPath& path, std::vector<double> grid) : grid_(std::move(grid)), dof_(0)
  {
    std::vector<arm::JointState> at;
    for (std::size_t i = 0; i < grid_.size(); ++i)
      at.push_back(path.at(grid_[i], i + 1 == grid_.size() ? Side::kLeft : Side::kRight));
    dof_ = static_cast<std::size_t>(at.front().position.size());
    coefficients_.resize((grid_.size() - 1) * 6 * dof_);
    for (std::size_t i = 0; i + 1 < grid_.size(); ++i)
    {
      const double h = grid_[i + 1] - grid_[i];
      const arm::JointState &a = at[i], &b = at[i + 1];
      for (std::size_t k = 0; k < dof_; ++k)
      {
        const Eigen::Index j = static_cast<Eigen::Index>(k);
        const double q0 = a.position[j], v0 = a.velocity[j], a0 = a.acceleration[j];
        // The end conditions left after c_0 = q0, c_1 = v0, c_2 = a0/2.
        const double d = b.position[j] - q0 - v0 * h - 0.5 * a0 * h * h;
        const double e = (b.velocity[j] - v0 - a0 * h) * h;
        const double f = (b.acceleration[j] - a0) * h * h;
        const double c[6] = { q0,
                              v0,
                              0.5 * a0,
                              (10.0 * d - 4.0 * e + 0.5 * f) / (h * h * h),
                              (-15.0 * d + 7.0 * e - f) / (h * h * h * h),
                              (6.0 * d - 3.0 * e + 0.5 * f) / (h * h * h * h * h) };
        for (std::size_t p = 0; p < 6; ++p)
          coefficients_[(i * 6 + p) * dof_ + k] = c[p];
      }
    }
  }

  std::size_t dof() const { return dof_; }
  const std::vector<double>& grid() const { return grid_; }

  /// q, q′, q″ of every joint at s (one-sided at a grid point) into q[0, dof), w[0, dof), a[0, dof).
  void eval(double s, Side side, double* q, double* w, double* a) const
  {
    const std::size_t i = locate(s, side);
    const double t = s - grid_[i];
    for (std::size_t k = 0; k < dof_; ++k)
    {
      const double* c = &coefficients_[i * 6 * dof_ + k];
      const auto C = [&](std::size_t p) { return c[p * dof_]; };
      q[k] = C(0) + t * (C(1) + t * (C(2) + t * (C(3) + t * (C(4) + t * C(5)))));
      w[k] = C(1) + t * (2.0 * C(2) + t * (3.0 * C(3) + t * (4.0 * C(4) + t * 5.0 * C(5))));
      a[k] = 2.0 * C(2) + t * (6.0 * C(3) + t * (12.0 * C(4) + t * 20.0 * C(5)));
    }
  }

  /// TOPP-RA's piecewise polynomial of the same coefficients (its highest power first).
  std::shared_ptr<toppra::PiecewisePolyPath> toppraPath() const
  {
    toppra::Matrices coefficients;
    for (std::size_t i = 0; i + 1 < grid_.size(); ++i)
    {
      toppra::Matrix m(6, static_cast<Eigen::Index>(dof_));
      for (std::size_t p = 0; p < 6; ++p)
        for (std::size_t k = 0; k < dof_; ++k)
          m(static_cast<Eigen::Index>(5 - p), static_cast<Eigen::Index>(k)) = coefficients_[(i * 6 + p) * dof_ + k];
      coefficients.push_back(m);
    }
    return std::make_shared<toppra::PiecewisePolyPath>(coefficients, grid_);
  }

private:
  std::size_t locate(double s, Side side) const
  {
    const std::size_t last = grid_.size() - 2;
    std::size_t i = static_cast<std::size_t>(std::upper_bound(grid_.begin(), grid_.end(), s) - grid_.begin());
    i = i == 0 ? 0 : i - 1;
    if (side == Side::kLeft && i > 0 && s == grid_[i])
      --i;
    return std::min(i, last);
  }

  std::vector<double> grid_;
  std::size_t dof_;
  std::vector<double> coefficients_;
};

/// The joint limits as the project's box constraint (time_optimal.h (4), (5)), its jets from the
/// quintic instead of the arm's inverse kinematics.
class QuinticJointBoxes final : public timing::BoxConstraint
{
public:
  QuinticJointBoxes(std::shared_ptr<const QuinticJointPath> path, std::vector<double> v, std::vector<double> a)
    : path_(std::move(path)), v_(std::move(v)), a_(std::move(a))
  {
  }
  std::size_t size() const override { return path_->dof(); }
  double velocityLimit(std::size_t k) const override { return v_[k]; }
  double accelerationLimit(std::size_t k) const override { return a_[k]; }
  void jet(double s, Side side, double* w, double* a) const override
  {
    std::array<double, timing::kMaxBoxComponents> q;
    path_->eval(s, side, q.data(), w, a);
  }

private:
  std::shared_ptr<const QuinticJointPath> path_;
  std::vector<double> v_, a_;
};

/// The largest |Δq| (rad) between the quintic and the joint path at every interval's middle.
double pathDifference(const QuinticJointPath& quintic, const arm::JointPath& path)
{
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < quintic.grid().size(); ++i)
  {
    const double s = 0.5 * (quintic.grid()[i] + quintic.grid()[i + 1]);
    const arm::JointState exact = path.at(s);
    std::array<double, timing::kMaxBoxComponents> q, w, a;
    quintic.eval(s, Side::kRight, q.data(), w.data(), a.data());
    for (std::size_t k = 0; k < quintic.dof(); ++k)
      worst = std::max(worst, std::abs(q[k] - exact.position[static_cast<Eigen::Index>(k)]));
  }
  return worst;
}

/// TOPP-RA's solution: its motion (constant s̈ per interval) and ṡ² at its grid points.
struct ToppraMotion
{
  std::shared_ptr<toppra::parametrizer::ConstAccel> motion;
  toppra::Vector x;
};

/// TOPP-RA from rest to rest on `grid` with the Seidel solver, or a null motion with its error
/// message in `error` (as bench_toppra).
ToppraMotion solveToppra(const toppra::LinearConstraintPtrs& constraints,
                         const std::shared_ptr<toppra::PiecewisePolyPath>& path, const toppra::Vector& grid,
                         std::string* error)
{
  toppra::algorithm::TOPPRA algorithm(constraints, path);
  algorithm.setGridpoints(grid);
  algorithm.solver(std::make_shared<toppra::solver::Seidel>());
  if (algorithm.computePathParametrization(0.0, 0.0) != toppra::ReturnCode::OK)
  {
    *error = algorithm.getErrorMessage();
    std::replace(error->begin(), error->end(), '\n', ' ');
    return {};
  }
  const toppra::ParametrizationData& data = algorithm.getParameterizationData();
  return { std::make_shared<toppra::parametrizer::ConstAccel>(path, data.gridpoints, data.parametrization),
           data.parametrization };
}

/// Peak rates as ratios to their bounds (the largest over the joints, resp. over the linear and
/// angular channels).
struct Peaks
{
  double joint_velocity = 0.0, joint_acceleration = 0.0;
  double cartesian_velocity = 0.0, cartesian_acceleration = 0.0;
};

/// TOPP-RA's motion at kDenseSamples per grid interval: the joints by its own evaluation (its path,
/// the quintic), the tool by the curve at the same path parameters: on interval i, with
/// ṡ_i = √x_i and s̈ = (x_i+1 − x_i) / (2 Δs), s = s_i + ṡ_i τ + s̈ τ²/2 (as ConstAccel evaluates).
Peaks toppraPeaks(const ToppraMotion& solved, const toppra::Vector& grid, const Curve<Geometry>& curve,
                  const std::vector<double>& v_max, const std::vector<double>& a_max)
{
  const toppra::Vector& t = solved.motion->getTimes();
  const Eigen::Index intervals = t.size() - 1;
  toppra::Vector samples(intervals * kDenseSamples);
  Peaks peaks;
  for (Eigen::Index i = 0; i < intervals; ++i)
  {
    const double dt = t[i + 1] - t[i];
    const double rate = std::sqrt(solved.x[i]);
    const double path_acceleration = (solved.x[i + 1] - solved.x[i]) / (2.0 * (grid[i + 1] - grid[i]));
    for (int j = 0; j < kDenseSamples; ++j)
    {
      const double tau = dt * j / (kDenseSamples - 1);
      samples[i * kDenseSamples + j] = t[i] + tau;
      const double s = std::clamp(grid[i] + rate * tau + 0.5 * path_acceleration * tau * tau, grid[i], grid[i + 1]);
      const double sd = rate + path_acceleration * tau;
      const Kinematics k = kinematicsAt(curve, s, j + 1 == kDenseSamples ? Side::kLeft : Side::kRight);
      const auto rateOf = [&](const Eigen::Vector3d& w, const Eigen::Vector3d& a) {
        return a * sd * sd + w * path_acceleration;
      };
      peaks.cartesian_velocity =
          std::max({ peaks.cartesian_velocity, k.velocity.linear.norm() * sd / kMaxLinearVelocity,
                     k.velocity.angular.norm() * sd / kMaxAngularVelocity });
      peaks.cartesian_acceleration =
          std::max({ peaks.cartesian_acceleration,
                     rateOf(k.velocity.linear, k.acceleration.linear).norm() / kMaxLinearAcceleration,
                     rateOf(k.velocity.angular, k.acceleration.angular).norm() / kMaxAngularAcceleration });
    }
  }
  const toppra::Vectors qd = solved.motion->eval(samples, 1), qdd = solved.motion->eval(samples, 2);
  for (std::size_t n = 0; n < qd.size(); ++n)
    for (std::size_t k = 0; k < v_max.size(); ++k)
    {
      const Eigen::Index j = static_cast<Eigen::Index>(k);
      peaks.joint_velocity = std::max(peaks.joint_velocity, std::abs(qd[n][j]) / v_max[k]);
      peaks.joint_acceleration = std::max(peaks.joint_acceleration, std::abs(qdd[n][j]) / a_max[k]);
    }
  return peaks;
}

/// Ours as its result reports them: the joints from the planner's dense check, the tool from its
/// figures.
Peaks ourPeaks(const TrajectoryResult& result, const std::vector<double>& v_max, const std::vector<double>& a_max)
{
  Peaks peaks;
  for (std::size_t k = 0; k < result.joint_figures.peaks.size(); ++k)
  {
    peaks.joint_velocity = std::max(peaks.joint_velocity, result.joint_figures.peaks[k].velocity / v_max[k]);
    peaks.joint_acceleration =
        std::max(peaks.joint_acceleration, result.joint_figures.peaks[k].acceleration / a_max[k]);
  }
  const CurveFigures& f = result.figures;
  peaks.cartesian_velocity =
      std::max(f.max_linear_speed / kMaxLinearVelocity, f.max_angular_speed / kMaxAngularVelocity);
  peaks.cartesian_acceleration = std::max(f.max_linear_acceleration / kMaxLinearAcceleration,
                                          f.max_angular_acceleration / kMaxAngularAcceleration);
  return peaks;
}

timing::RateBounds cartesianBounds()
{
  timing::RateBounds b;
  b.velocity = { kMaxLinearVelocity, kMaxAngularVelocity };
  b.acceleration = { kMaxLinearAcceleration, kMaxAngularAcceleration };
  return b;
}

/// Everything a row needs besides the timed solves, built once.
struct Setup
{
  std::shared_ptr<const arm::ArmModel> model = se3_bench::ur5e();
  TrajectoryRequest with_arm, without_arm;
  PlannerLimits limits;
  std::shared_ptr<const Curve<Geometry>> curve;
  Eigen::VectorXd seed;
  std::vector<double> v_max, a_max;
  std::shared_ptr<const QuinticJointPath> quintic;
  double input_cpu = 0.0;  ///< s: the tracking, JointPath::at at every grid point and the quintic
  double path_dq = 0.0;
  /// TOPP-RA's input: the quintic as its path, its grid, its joint boxes.
  std::shared_ptr<toppra::PiecewisePolyPath> toppra_path;
  toppra::Vector grid;
  toppra::LinearConstraintPtrs toppra_boxes;
  /// The project's timing options with the joint limits on the quintic.
  timing::TimeOptimalOptions joint_options;

  explicit Setup(std::size_t n)
  {
    with_arm = se3_bench::ur5eWalk(*model, n);
    without_arm = with_arm;
    without_arm.joint_seed.clear();
    // The work estimate does not count the arm yet (bench_joint_space): a limit that lets it finish.
    limits.max_work_seconds = 100.0;
    const ValidatedRequest r = validateRequest(with_arm, limits);
    if (r.geometry != GeometryType::kDoubleGeodesic)
      throw std::runtime_error("bench_toppra_joints: the walk's geometry is not the double-geodesic one");
    curve = makeCurve<Geometry>(r, waypointTimes(r));
    seed = Eigen::Map<const Eigen::VectorXd>(with_arm.joint_seed.data(),
                                             static_cast<Eigen::Index>(with_arm.joint_seed.size()));
    for (const arm::ArmJoint& joint : model->joints())
    {
      if (!joint.limits.hasVelocityLimit() || !joint.limits.hasAccelerationLimit())
        throw std::runtime_error("bench_toppra_joints: joint " + joint.name +
                                 " lacks a velocity or acceleration limit");
      v_max.push_back(joint.limits.max_velocity);
      a_max.push_back(joint.limits.max_acceleration);
    }
    const double start = threadCpuSeconds();
    const arm::JointPath path = arm::jointPathOf<Geometry>(*model, curve, seed);
    quintic = std::make_shared<QuinticJointPath>(path, gridOf(path.breakpoints()));
    input_cpu = threadCpuSeconds() - start;
    path_dq = pathDifference(*quintic, path);
    if (!(path_dq <= kSamePathTolerance))
      throw std::runtime_error("bench_toppra_joints: the quintic differs from the joint path by " +
                               std::to_string(path_dq) + " rad");
    toppra_path = quintic->toppraPath();
    grid = Eigen::Map<const toppra::Vector>(quintic->grid().data(), static_cast<Eigen::Index>(quintic->grid().size()));
    const toppra::Vector v = Eigen::Map<const toppra::Vector>(v_max.data(), static_cast<Eigen::Index>(v_max.size()));
    const toppra::Vector a = Eigen::Map<const toppra::Vector>(a_max.data(), static_cast<Eigen::Index>(a_max.size()));
    toppra_boxes = { std::make_shared<toppra::constraint::LinearJointVelocity>(-v, v),
                     std::make_shared<toppra::constraint::LinearJointAcceleration>(-a, a) };
    joint_options.boxes = std::make_shared<QuinticJointBoxes>(quintic, v_max, a_max);
  }
};

/// One row's solves: CPU seconds summed over the iterations, and the last iteration's results.
struct Row
{
  double ours_cpu = 0.0, cart_cpu = 0.0, tracking_cpu = 0.0, solver_cpu = 0.0, boxes_cpu = 0.0, toppra_cpu = 0.0;
  TrajectoryResult ours, cart;
  timing::TimingProfile solver, boxes;
  ToppraMotion toppra;
};

/// The counters of the file comment.
void report(benchmark::State& state, const Setup& x, const Row& row)
{
  const double ms = 1e3 / static_cast<double>(state.iterations());
  const Peaks peer = toppraPeaks(row.toppra, x.grid, *x.curve, x.v_max, x.a_max);
  const Peaks ours = ourPeaks(row.ours, x.v_max, x.a_max);
  auto& c = state.counters;
  c["toppra_grid"] = static_cast<double>(x.grid.size() - 1);
  c["solver_grid"] = static_cast<double>(row.solver.s.size() - 1);
  c["boxes_grid"] = static_cast<double>(row.boxes.s.size() - 1);
  c["path_dq"] = x.path_dq;
  c["ours_ms"] = row.ours_cpu * ms;
  c["cart_ms"] = row.cart_cpu * ms;
  c["tracking_ms"] = row.tracking_cpu * ms;
  c["solver_ms"] = row.solver_cpu * ms;
  c["boxes_ms"] = row.boxes_cpu * ms;
  c["toppra_ms"] = row.toppra_cpu * ms;
  c["toppra_input_ms"] = 1e3 * x.input_cpu;
  c["ours/cart"] = row.ours_cpu / row.cart_cpu;
  c["ours/toppra"] = row.ours_cpu / row.toppra_cpu;
  c["solver/toppra"] = row.solver_cpu / row.toppra_cpu;
  c["boxes/toppra"] = row.boxes_cpu / row.toppra_cpu;
  c["ours_s"] = row.ours.duration;
  c["cart_s"] = row.cart.duration;
  c["solver_s"] = row.solver.duration();
  c["boxes_s"] = row.boxes.duration();
  c["toppra_s"] = row.toppra.motion->pathInterval()[1] - row.toppra.motion->pathInterval()[0];
  c["ours_qd"] = ours.joint_velocity;
  c["ours_qdd"] = ours.joint_acceleration;
  c["ours_cart_v"] = ours.cartesian_velocity;
  c["ours_cart_a"] = ours.cartesian_acceleration;
  c["toppra_qd"] = peer.joint_velocity;
  c["toppra_qdd"] = peer.joint_acceleration;
  c["toppra_cart_v"] = peer.cartesian_velocity;
  c["toppra_cart_a"] = peer.cartesian_acceleration;
}

void toppraJoints(benchmark::State& state)
{
  std::unique_ptr<Setup> setup;
  try
  {
    setup = std::make_unique<Setup>(static_cast<std::size_t>(state.range(0)));
  }
  catch (const std::exception& e)
  {
    state.SkipWithError(e.what());
    return;
  }
  const Setup& x = *setup;
  Row row;
  std::string error;
  for (auto _ : state)
  {
    double start = threadCpuSeconds();
    row.ours = generate(x.with_arm, x.limits, x.model);
    row.ours_cpu += threadCpuSeconds() - start;
    state.PauseTiming();
    start = threadCpuSeconds();
    row.cart = generate(x.without_arm, x.limits);
    row.cart_cpu += threadCpuSeconds() - start;
    start = threadCpuSeconds();
    benchmark::DoNotOptimize(arm::jointPathOf<Geometry>(*x.model, x.curve, x.seed).end());
    row.tracking_cpu += threadCpuSeconds() - start;
    start = threadCpuSeconds();
    row.solver = timing::timeOptimalProfile(timing::CurvePath<Geometry>(x.curve), cartesianBounds(), x.joint_options);
    row.solver_cpu += threadCpuSeconds() - start;
    start = threadCpuSeconds();
    row.boxes = timing::timeOptimalProfile(timing::CurvePath<Geometry>(x.curve), timing::RateBounds(), x.joint_options);
    row.boxes_cpu += threadCpuSeconds() - start;
    start = threadCpuSeconds();
    row.toppra = solveToppra(x.toppra_boxes, x.toppra_path, x.grid, &error);
    row.toppra_cpu += threadCpuSeconds() - start;
    state.ResumeTiming();
    if (!row.toppra.motion)
    {
      state.SkipWithError(("TOPP-RA failed: " + error).c_str());
      return;
    }
  }
  report(state, x, row);
}
}  // namespace

// 1000 waypoints: one iteration (ours, cart, tracking, solver, boxes, TOPP-RA) takes about a second.
BENCHMARK(toppraJoints)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
