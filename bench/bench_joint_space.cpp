// Google Benchmark of joint space (docs/joint_space.md) on the UR5e of config/robots/:
//  - inverse kinematics along a motion, per sample: arm::JointPath's at() (each sample from the
//    tracked neighbours, Newton to 1e-12) against KDL's ChainIkSolverPos_LMA seeded by the previous
//    sample's solution (its default accuracy 1e-5), on the same 1000 poses of an interpolating
//    spline; and the tracking that JointPath's construction does once per motion, per sample;
//  - the time-optimal timing with the joint limits against the Cartesian bounds alone, through
//    generate() (interpolating spline, 100 samples), N = 100 and 1000 waypoints.
// Waypoints and bounds: the UR5e's random walk in joint space of ur5e_walk.h (shared with
// bench_toppra_joints); the limits file's joint limits.
#include <benchmark/benchmark.h>

#include <kdl/chain.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include <memory>
#include <vector>

#include "../test/unit/arm/arm_test_utils.h"
#include "se3_interpolation/arm/joint_path.h"
#include "se3_interpolation/planner/planner.h"
#include "ur5e_walk.h"

namespace
{
using namespace se3_interpolation;

using se3_bench::ur5e;

const std::vector<double>& kHome = se3_bench::ur5eHome();

/// The motion of a 50-waypoint walk sampled 1000 times, as poses and as the samples' times.
struct Samples
{
  std::shared_ptr<const arm::ArmModel> model = ur5e();
  TrajectoryResult motion;
  Samples()
  {
    TrajectoryRequest r = se3_bench::ur5eWalk(*model, 50);
    r.sample_count = 1000;
    motion = generate(r, PlannerLimits(), model);
  }
};

const Samples& samples()
{
  static const Samples s;
  return s;
}

void jointPathPerSample(benchmark::State& state)
{
  const Samples& s = samples();
  const std::function<Kinematics(double, Side)> motion = [&s](double t, Side) {
    const TrajectorySample q = s.motion.state_at(t);
    return Kinematics{ q.pose, q.velocity, q.acceleration };
  };
  const arm::JointPath path(*s.model, motion, { s.motion.start_time, s.motion.start_time + s.motion.duration },
                            Eigen::Map<const Eigen::VectorXd>(kHome.data(), 6));
  for (auto _ : state)
    for (const TrajectorySample& sample : s.motion.samples)
      benchmark::DoNotOptimize(path.at(sample.time).position);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.motion.samples.size()));
}

void jointPathTrackingPerSample(benchmark::State& state)
{
  const Samples& s = samples();
  const std::function<Kinematics(double, Side)> motion = [&s](double t, Side) {
    const TrajectorySample q = s.motion.state_at(t);
    return Kinematics{ q.pose, q.velocity, q.acceleration };
  };
  for (auto _ : state)
  {
    const arm::JointPath path(*s.model, motion, { s.motion.start_time, s.motion.start_time + s.motion.duration },
                              Eigen::Map<const Eigen::VectorXd>(kHome.data(), 6));
    benchmark::DoNotOptimize(path.end());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.motion.samples.size()));
}

void kdlLmaPerSample(benchmark::State& state)
{
  const Samples& s = samples();
  const KDL::Chain chain = test::kdlChain(test::readText(test::robotFile("ur5e.urdf")), "base_link", "tool0");
  KDL::ChainIkSolverPos_LMA solver(chain);
  KDL::JntArray seed(6), out(6);
  for (auto _ : state)
  {
    for (unsigned k = 0; k < 6; ++k)
      seed(k) = kHome[k];
    for (const TrajectorySample& sample : s.motion.samples)
    {
      const Eigen::Quaterniond& q = sample.pose.q;
      const KDL::Frame target(KDL::Rotation::Quaternion(q.x(), q.y(), q.z(), q.w()),
                              KDL::Vector(sample.pose.p.x(), sample.pose.p.y(), sample.pose.p.z()));
      solver.CartToJnt(seed, target, out);
      seed = out;
    }
    benchmark::DoNotOptimize(out.data);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.motion.samples.size()));
}

void timeOptimal(benchmark::State& state, bool with_arm)
{
  const auto model = ur5e();
  const TrajectoryRequest with = se3_bench::ur5eWalk(*model, static_cast<std::size_t>(state.range(0)));
  TrajectoryRequest without = with;
  without.joint_seed.clear();
  // (The work estimate does not count the arm yet: a limit that lets the largest request finish.)
  const PlannerLimits limits = test::armLimits();
  double duration = 0.0;
  for (auto _ : state)
    duration = (with_arm ? generate(with, limits, model) : generate(without, limits)).duration;
  state.counters["duration_s"] = duration;
}

void jointLimitedTimeOptimal(benchmark::State& state)
{
  timeOptimal(state, true);
}

void cartesianTimeOptimal(benchmark::State& state)
{
  timeOptimal(state, false);
}
}  // namespace

BENCHMARK(jointPathPerSample)->Unit(benchmark::kMicrosecond);
BENCHMARK(jointPathTrackingPerSample)->Unit(benchmark::kMicrosecond);
BENCHMARK(kdlLmaPerSample)->Unit(benchmark::kMicrosecond);
BENCHMARK(cartesianTimeOptimal)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(jointLimitedTimeOptimal)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
