// The request deadline (deadline.h): the long loops of the core stop with a LimitExceededError
// naming their phase once the current thread's deadline has passed, and nothing is checked
// without one. Each case runs a computation that takes seconds without a deadline under one of
// 50 ms, and asserts that it ends within 10 times that (a functional deadline with margin, not a
// performance figure). The time measured is the thread's CPU time, not the wall time: the core
// computes on the calling thread, and on a loaded machine the wall time of the work before the
// first check grows with the load while its CPU time does not (the deadline itself is wall time,
// so the CPU time at which it passes is at most the wall time).
#include <gtest/gtest.h>

#include <chrono>
#include <ctime>
#include <random>
#include <string>
#include <thread>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/planner/planner.h"
#include "test_utils.h"

using namespace se3_interpolation;

namespace
{
constexpr double kDeadline = 0.05;
// The work before the first check (validating 3·10⁵ waypoints) runs several times slower under
// the sanitizers.
#if defined(__SANITIZE_ADDRESS__)
constexpr double kMargin = 100.0;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr double kMargin = 100.0;
#else
constexpr double kMargin = 10.0;
#endif
#else
constexpr double kMargin = 10.0;
#endif

TrajectoryRequest bigRequest(const char* curve, std::size_t n)
{
  std::mt19937 rng(26);
  TrajectoryRequest r;
  r.waypoints = test::randomPolygon(rng, n, 0.5);
  r.curve = curve;
  r.geometry = "screw";
  return r;
}

/// The calling thread's CPU time (s).
double threadSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Runs `f` under a deadline of kDeadline; returns the LimitExceededError's message ("" when
/// none was thrown) and the thread's CPU time it took.
template <class F>
std::pair<std::string, double> underDeadline(F f)
{
  const double start = threadSeconds();
  std::string message;
  {
    Deadline deadline(kDeadline, kDeadline);
    const ScopedDeadline scope(deadline);
    try
    {
      f();
    }
    catch (const LimitExceededError& e)
    {
      message = e.what();
    }
  }
  return { message, threadSeconds() - start };
}
}  // namespace

TEST(Deadline, NothingIsCheckedWithoutOne)
{
  EXPECT_NO_THROW(checkDeadline("phase"));
  Deadline past(-1.0, 1.0);
  {
    const ScopedDeadline scope(past);
    EXPECT_THROW(checkDeadline("phase"), LimitExceededError);
    {
      // A later deadline inside an earlier one keeps the earlier (a request inside a caller's).
      Deadline future(100.0, 100.0);
      const ScopedDeadline inner(future);
      EXPECT_THROW(checkDeadline("phase"), LimitExceededError);
    }
    EXPECT_THROW(checkDeadline("phase"), LimitExceededError);
  }
  EXPECT_NO_THROW(checkDeadline("phase"));
  Deadline later(100.0, 100.0);
  const ScopedDeadline outer(later);
  EXPECT_NO_THROW(checkDeadline("phase"));
  {
    const ScopedDeadline inner(past);
    EXPECT_THROW(checkDeadline("phase"), LimitExceededError);
  }
  EXPECT_NO_THROW(checkDeadline("phase"));
}

TEST(Deadline, APauseSuspendsItAndPostponesItByItsLength)
{
  // 0.2 s of limit; 0.3 s spent in the caller's work between two checks.
  const auto caller = [] { std::this_thread::sleep_for(std::chrono::milliseconds(300)); };
  {
    Deadline deadline(0.2, 0.2);
    const ScopedDeadline scope(deadline);
    caller();
    EXPECT_THROW(checkDeadline("phase"), LimitExceededError);
  }
  Deadline deadline(0.2, 0.2);
  const ScopedDeadline scope(deadline);
  {
    const ScopedDeadlinePause pause;
    caller();
    // Nothing is checked inside the pause: the caller's work is not the request's.
    EXPECT_NO_THROW(checkDeadline("phase"));
  }
  EXPECT_NO_THROW(checkDeadline("phase"));
}

TEST(Deadline, MessageNamesThePhaseAndTheLimit)
{
  Deadline past(-1.0, 0.25);
  const ScopedDeadline scope(past);
  try
  {
    checkDeadline("timing: 'time_optimal'");
    FAIL();
  }
  catch (const LimitExceededError& e)
  {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("timing: 'time_optimal': the request ran past its work limit of 0.25 s", 0), 0u) << m;
    EXPECT_NE(m.find("max_work_seconds"), std::string::npos) << m;
  }
}

// Each long phase stops: the C² solve, the time-optimal passes, the figures, the sampling and a
// Bezier's de Casteljau recursion (planner's limits raised so that the estimate lets them in).
TEST(Deadline, EveryLongPhaseStops)
{
  PlannerLimits unlimited;
  unlimited.max_work_seconds = 1e6;
  unlimited.max_waypoints = 1000000;
  unlimited.max_samples = 100000000;
  struct Case
  {
    const char* name;
    TrajectoryRequest request;
  };
  std::vector<Case> cases;
  cases.push_back({ "interpolating", bigRequest("interpolating", 100000) });
  TrajectoryRequest optimal = bigRequest("hermite", 50000);
  optimal.timing = "time_optimal";
  optimal.max_linear_velocity = optimal.max_angular_velocity = 1.0;
  optimal.max_linear_acceleration = optimal.max_angular_acceleration = 2.0;
  cases.push_back({ "time_optimal", optimal });
  TrajectoryRequest sampling = bigRequest("hermite", 3);
  sampling.sample_count = 2000000;
  cases.push_back({ "sampling", sampling });
  cases.push_back({ "bezier", bigRequest("bezier", 3000) });
  TrajectoryRequest blends = bigRequest("piecewise_geodesic", 300000);
  blends.blend_radius = 0.1;
  cases.push_back({ "figures", blends });
  for (const Case& c : cases)
  {
    const auto [message, seconds] = underDeadline([&] { generate(c.request, unlimited); });
    EXPECT_NE(message.find("ran past its work limit of 0.05 s"), std::string::npos) << c.name << ": " << message;
    EXPECT_LT(seconds, kMargin * kDeadline) << c.name;
  }
}

// The planner sets its own deadline from PlannerLimits::max_work_seconds (at least
// kMinDeadlineSeconds): a request refused by the estimate, or stopped by the deadline, ends fast.
TEST(Deadline, GenerateStopsAtItsOwnDeadline)
{
  TrajectoryRequest r = bigRequest("interpolating", 20000);
  PlannerLimits limits;
  limits.max_work_seconds = 1e-4;
  limits.max_waypoints = 1000000;
  const double start = threadSeconds();
  EXPECT_THROW(generate(r, limits), LimitExceededError);
  EXPECT_LT(threadSeconds() - start, kMargin * kDeadline);
}
