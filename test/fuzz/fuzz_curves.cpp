// libFuzzer target, each curve family's construction and evaluation: bytes -> request ->
// validateRequest -> waypointTimes -> makeCurve in the request's SE(3) geometry -> value and
// second-order jet at decoded times in the curve's span, without the figures or sampling. The
// family is the request's `curve` (decode()'s name byte selects it). The C^2 solve of
// `interpolating` with end_condition natural or clamped, a path-following Newton iteration
// about ten times slower per input than the other families, is fuzz_c2's: here those requests
// stop after validation (end_condition start, the forward construction, is built here).
// Expected: an InterpolationError, or finite unit poses and finite derivatives. Input format:
// fuzz_common.h (corpus shared with fuzz_generate).
#include "fuzz_common.h"
#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/analysis/kinematics.h"

using namespace se3_interpolation;
using namespace se3_interpolation::fuzz;

namespace
{
template <class G>
void evaluate(const ValidatedRequest& v, const std::vector<double>& times, ByteReader& in)
{
  const std::shared_ptr<const Curve<G>> curve = makeCurve<G>(v, times);
  const double t0 = curve->startTime();
  const double t1 = curve->endTime();
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    fail("a curve with the span [" + list(std::vector<double>{ t0, t1 }) + "]");
  const int evaluations = 1 + in.byte() % 8;
  for (int k = 0; k < evaluations; ++k)
  {
    const double u = static_cast<double>(in.byte()) / 255.0;
    const double t = t0 + (t1 - t0) * u;
    const Pose<double> x = curve->value(t);
    checkPose(x, "value(t)");
    const Kinematics kin = kinematicsAt(*curve, t, in.byte() % 2 == 0 ? Side::kLeft : Side::kRight);
    checkPose(kin.pose, "kinematics(t).pose");
    checkFinite(kin.velocity.linear, "kinematics(t).velocity.linear");
    checkFinite(kin.velocity.angular, "kinematics(t).velocity.angular");
    checkFinite(kin.acceleration.linear, "kinematics(t).acceleration.linear");
    checkFinite(kin.acceleration.angular, "kinematics(t).acceleration.angular");
  }
}

void construct(const TrajectoryRequest& request, const PlannerLimits& limits, ByteReader& in)
{
  const ValidatedRequest v = validateRequest(request, limits);
  if (v.curve == CurveType::kInterpolating && v.end_condition != EndCondition::kStart)
    return;
  const std::vector<double> times = waypointTimes(v);
  if (v.geometry == GeometryType::kScrew)
    evaluate<ScrewSe3>(v, times, in);
  else
    evaluate<DoubleGeodesicSe3>(v, times, in);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  return runRequestTarget("fuzz_curves", data, size, construct);
}
