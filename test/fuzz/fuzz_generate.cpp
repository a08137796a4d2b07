// libFuzzer target: bytes -> TrajectoryRequest -> generate (validation, timing,
// curve, stretch, sampling): the whole request. The per-layer targets (fuzz_lie, fuzz_validate,
// fuzz_curves, fuzz_sphere, fuzz_yaml) run the layers alone, much faster.
//
// The expected outcomes are a result or an InterpolationError. Anything else aborts so that
// the fuzzer reports it: another exception, a sanitizer report, or a result with a
// non-finite number or a non-unit quaternion (the error contract: no NaN in outputs). Input format:
// fuzz_common.h.
#include "fuzz_common.h"

using namespace se3_interpolation;
using namespace se3_interpolation::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  return runRequestTarget("fuzz_generate", data, size,
                          [](const TrajectoryRequest& request, const PlannerLimits& limits, ByteReader&) {
                            checkResult(generate(request, limits), limits);
                          });
}
