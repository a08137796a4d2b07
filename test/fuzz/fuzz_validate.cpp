// libFuzzer target, the validation layer alone: bytes -> TrajectoryRequest -> validateRequest
// and the work estimate. Expected: an InterpolationError, or a validated request whose
// waypoints are finite unit poses, whose times strictly increase within ROS's range, with a
// known degree, sample_count != 1 and a finite, positive work estimate. Input format:
// fuzz_common.h (the same as fuzz_generate, so the corpora are shared).
#include "fuzz_common.h"
#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"

using namespace se3_interpolation;
using namespace se3_interpolation::fuzz;

namespace
{
void validate(const TrajectoryRequest& request, const PlannerLimits& limits, ByteReader&)
{
  const ValidatedRequest v = validateRequest(request, limits);
  // A start state is put in front of the waypoints (unless waypoints[0] is the start pose).
  const std::size_t most = limits.max_waypoints + (request.start_state ? 1 : 0);
  if (v.waypoints.size() < 2 || v.waypoints.size() > most)
    fail("validated request with " + std::to_string(v.waypoints.size()) + " waypoints");
  for (const Pose<double>& x : v.waypoints)
    checkPose(x, "validated waypoints");
  for (std::size_t i = 0; i < v.times.size(); ++i)
  {
    checkFinite(v.times[i], "times");
    if (std::abs(v.times[i]) > kRosDurationMaxSeconds || (i > 0 && !(v.times[i] > v.times[i - 1])))
      fail("validated times out of range or not increasing");
  }
  if (v.degree < 1 || v.continuity < 1 || v.continuity > kMaxBlendingContinuity || v.sampling.sample_count == 1)
    fail("validated degree, continuity or sample_count out of range");
  if (!(std::abs(v.duration) <= kRosDurationMaxSeconds))
    fail("validated duration out of ROS's range");
  const WorkEstimate w = estimateWork(workShape(v), expectedSamples(workShape(v), 1.0));
  if (!std::isfinite(w.total) || !(w.total > 0.0))
    fail("work estimate not finite and positive");
  requireWorkWithin(w, workShape(v), limits);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  return runRequestTarget("fuzz_validate", data, size, validate);
}
