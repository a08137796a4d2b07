// The validation building blocks shared by every planner (poses, spheres): field-naming
// checks of numbers, time vectors and the sampling fields, and the sample times themselves.
// Every check throws an InterpolationError subclass whose message starts with the field and
// index, e.g. "times[2]: 1 is not after times[1] = 1 (...)".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "se3_interpolation/planner.h"

namespace se3_interpolation
{
/// "field[i]".
std::string indexedField(const std::string& field, std::size_t i);
/// A number with 17 significant digits (round-trips).
std::string formatNumber(double x);

void requireFinite(double x, const std::string& field);
void requireFiniteNonNegative(double x, const std::string& field);

/// `times` empty, or one finite, strictly increasing time per waypoint.
void validateTimes(const std::vector<double>& times, std::size_t num_waypoints);

/// The sampling fields after validation (`sample_count` defaulted to 100).
struct Sampling
{
  std::vector<double> sample_times;
  double sample_period = 0.0;
  std::uint32_t sample_count = 100;
};

/// Checks sample_times (finite, non-decreasing), sample_period (finite, ≥ 0), sample_count
/// (not 1) and the ~max_samples limit where it can be known before timing.
Sampling validateSampling(const std::vector<double>& sample_times, double sample_period, std::uint32_t sample_count,
                          const PlannerLimits& limits);

/// The sample times on [t0, t1]: the explicit ones (each within the trajectory), else every
/// sample_period from t0 with t1 included, else sample_count evenly spaced including both ends.
std::vector<double> sampleTimes(const Sampling& sampling, double t0, double t1, const PlannerLimits& limits);

}  // namespace se3_interpolation
