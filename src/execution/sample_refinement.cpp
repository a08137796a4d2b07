#include "se3_interpolation/execution/sample_refinement.h"

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
namespace
{
/// (D) tests the interval at its eighths (sample_refinement.h).
constexpr double kDeviationPoints = 8.0;
/// Interval tests between two checks of the request's deadline (deadline.h): ~30 µs each.
constexpr std::uint64_t kTestsPerDeadlineCheck = 64;

/// A sample as a goal's point, its time counted from `origin` (the goal's polynomial depends only
/// on the interval's length; counting from the interval's start keeps time_from_start ≥ 0).
GoalPoint pointOf(const TrajectorySample& s, double origin)
{
  GoalPoint p;
  p.time_from_start = s.time - origin;
  p.pose = s.pose;
  p.velocity = s.velocity;
  p.acceleration = s.acceleration;
  return p;
}

bool anyBound(const MotionLimits& l)
{
  return l.max_linear_velocity > 0.0 || l.max_angular_velocity > 0.0 || l.max_linear_acceleration > 0.0 ||
         l.max_angular_acceleration > 0.0 || l.max_linear_jerk > 0.0 || l.max_angular_jerk > 0.0;
}
}  // namespace

SampleRefiner::SampleRefiner(SampleRefinement settings, std::function<TrajectorySample(double)> sample_at,
                             std::size_t budget)
  : settings_(std::move(settings))
  , sample_at_(std::move(sample_at))
  , budget_(budget)
  , bounded_(anyBound(settings_.limits))
{
}

SampleRefiner::Verdict SampleRefiner::test(const TrajectorySample& a, const TrajectorySample& b,
                                           const TrajectorySample& middle) const
{
  Verdict v;
  std::optional<GoalTrajectory> goal;
  try
  {
    goal.emplace(std::vector<GoalPoint>{ pointOf(a, a.time), pointOf(b, a.time) }, settings_.geometry);
  }
  catch (const InvalidGoalError&)
  {
    // Half a turn apart, or too short for its data: the points in between are what the goal needs.
    v.deviates = true;
    return v;
  }
  // (D) at the middle first, then the other eighths: the motion's own sample against the goal's pose.
  const double h = b.time - a.time;
  for (int k : { 4, 2, 6, 1, 3, 5, 7 })
  {
    if (v.deviates)
      break;
    const TrajectorySample m = k == 4 ? middle : sample_at_(a.time + h * k / kDeviationPoints);
    const TrajectorySample g = goal->stateAt(m.time - a.time);
    v.deviates = !(chordDistance(m.pose, g.pose, settings_.rotation_scale) <= settings_.tolerance);
  }
  if (!bounded_)
    return v;
  v.excess = goal->boundExcess(settings_.limits, kRefinementLimitTolerance);
  return v;
}

void SampleRefiner::between(const TrajectorySample& a, const TrajectorySample& b,
                            const std::function<void(const TrajectorySample&)>& emit)
{
  // Depth first, so that the samples come out in time order; the depth is at most
  // log2((b − a) / kMinSampleSpacing), a few tens.
  const std::function<void(const TrajectorySample&, const TrajectorySample&, double, int)> refine =
      [&](const TrajectorySample& lo, const TrajectorySample& hi, double smallest_excess, int stalled) {
        if (!(hi.time - lo.time >= 2.0 * kMinSampleSpacing))
          return;
        checkDeadlineEvery(tests_++, kTestsPerDeadlineCheck, "sample_tolerance");
        const TrajectorySample middle = sample_at_(0.5 * (lo.time + hi.time));
        const Verdict v = test(lo, hi, middle);
        bool halve = v.deviates;
        if (v.excess > kRefinementLimitTolerance)
        {
          if (v.excess < kExcessConvergence * smallest_excess)
          {
            smallest_excess = v.excess;
            stalled = 0;
          }
          else
            ++stalled;
          halve = halve || stalled < kExcessPatience;
        }
        if (!halve)
          return;
        if (inserted_ == budget_)
          throw LimitExceededError("sample_tolerance: " + formatNumber(settings_.tolerance) +
                                   " m needs more samples than the ~max_samples limit allows (" +
                                   formatNumber(static_cast<double>(inserted_)) + " inserted so far, before t = " +
                                   formatNumber(middle.time) + " s); give a larger tolerance or fewer samples");
        ++inserted_;
        refine(lo, middle, smallest_excess, stalled);
        emit(middle);
        refine(middle, hi, smallest_excess, stalled);
      };
  refine(a, b, std::numeric_limits<double>::infinity(), 0);
}

}  // namespace se3_interpolation
