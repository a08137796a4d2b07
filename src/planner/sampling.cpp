// The sampling fields' rules and the sample times (validation.h): sample_times, sample_period and
// sample_count checked against each other and ~max_samples before the timing, then the times on the
// timed motion's [t0, t1], each at least 1 ns after the previous one (time_from_start's resolution).
#include <algorithm>
#include <cmath>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
/// A step of at least 1 ns keeps rounded nanoseconds distinct; the margin absorbs the
/// rounding of t0 + (t1 - t0) i / (n - 1) near 1 ns spacing.
constexpr double kResolvableStep = kRosDurationResolution * (1.0 - 1e-6);

/// Generated sample times: each after the previous by at least 1 ns.
void requireResolvable(const std::vector<double>& ts, const std::string& field)
{
  for (std::size_t i = 1; i < ts.size(); ++i)
    if (!(ts[i] - ts[i - 1] >= kResolvableStep))
      throw InvalidInputError(field + ": samples " + std::to_string(i - 1) + " and " + std::to_string(i) + " are " +
                              formatNumber(ts[i] - ts[i - 1]) +
                              " s apart, below the 1 ns resolution of time_from_start" +
                              " (fewer samples or a longer duration)");
}
}  // namespace

Sampling validateSampling(const std::vector<double>& sample_times, double sample_period, std::uint32_t sample_count,
                          const PlannerLimits& limits)
{
  if (sample_times.size() > limits.max_samples)
    throw LimitExceededError("sample_times: " + std::to_string(sample_times.size()) +
                             " samples requested; the limit (max_samples) is " + std::to_string(limits.max_samples));
  for (std::size_t i = 0; i < sample_times.size(); ++i)
  {
    requireFinite(sample_times[i], indexedField("sample_times", i));
    requireRosDuration(sample_times[i], indexedField("sample_times", i));
    if (i > 0 && sample_times[i] < sample_times[i - 1])
      throw InvalidInputError(indexedField("sample_times", i) + ": " + formatNumber(sample_times[i]) +
                              " is before the previous sample time (sample_times must be non-decreasing)");
  }
  requireFiniteNonNegative(sample_period, "sample_period");
  if (sample_period > 0.0 && sample_period < kRosDurationResolution)
    throw InvalidInputError("sample_period: " + formatNumber(sample_period) +
                            " s is below the 1 ns resolution of time_from_start");
  if (sample_count == 1)
    throw InvalidInputError("sample_count: 1 is too few (at least 2: both ends)");
  Sampling s;
  s.sample_times = sample_times;
  s.sample_period = sample_period;
  s.sample_count = sample_count == 0 ? RequestDefaults::kSampleCount : sample_count;
  if (sample_times.empty() && sample_period == 0.0 && s.sample_count > limits.max_samples)
    throw LimitExceededError("sample_count: " + std::to_string(s.sample_count) +
                             " samples requested; the limit (max_samples) is " + std::to_string(limits.max_samples));
  return s;
}

std::vector<double> sampleTimes(const Sampling& r, double t0, double t1, const PlannerLimits& limits)
{
  std::vector<double> ts;
  if (!r.sample_times.empty())
  {
    const double tol = 1e-9 * std::max(1.0, std::abs(t1));
    for (std::size_t i = 0; i < r.sample_times.size(); ++i)
    {
      const double t = r.sample_times[i];
      if (t < t0 - tol || t > t1 + tol)
        throw InvalidInputError(indexedField("sample_times", i) + ": " + formatNumber(t) +
                                " s is outside the trajectory [" + formatNumber(t0) + ", " + formatNumber(t1) + "] s");
      ts.push_back(std::min(std::max(t, t0), t1));
      const double step = i > 0 ? ts[i] - ts[i - 1] : 0.0;
      if (step > 0.0 && step < kResolvableStep)
        throw InvalidInputError(indexedField("sample_times", i) + ": " + formatNumber(t) + " s is only " +
                                formatNumber(step) + " s after the previous sample (time_from_start resolves 1 ns)");
    }
    return ts;
  }
  if (r.sample_period > 0.0)
  {
    if (r.sample_period < kRosDurationResolution)
      throw InvalidInputError("sample_period: " + formatNumber(r.sample_period) +
                              " s is below the 1 ns resolution of time_from_start");
    const double count = std::floor((t1 - t0) / r.sample_period) + 2.0;
    if (!(count <= static_cast<double>(limits.max_samples)))
      throw LimitExceededError("sample_period: " + formatNumber(r.sample_period) + " s gives " + formatNumber(count) +
                               " samples; the limit (max_samples) is " + std::to_string(limits.max_samples));
    // Both ends always; a regular sample closer to t1 than the tolerance merges into t1.
    const double tol = std::max(1e-9 * r.sample_period, kRosDurationResolution);
    ts.push_back(t0);
    for (std::size_t i = 1;; ++i)
    {
      const double t = t0 + static_cast<double>(i) * r.sample_period;
      if (!(t < t1 - tol))
        break;
      ts.push_back(t);
    }
    ts.push_back(t1);
    requireResolvable(ts, "sample_period");
    return ts;
  }
  ts.resize(r.sample_count);
  for (std::size_t i = 0; i < ts.size(); ++i)
    ts[i] = t0 + (t1 - t0) * static_cast<double>(i) / static_cast<double>(ts.size() - 1);
  ts.back() = t1;
  requireResolvable(ts, "sample_count");
  return ts;
}

}  // namespace se3_interpolation
