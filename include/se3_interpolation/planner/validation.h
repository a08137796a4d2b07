// Validation of a request, written once over the space (poses, spheres): one function per
// rule, each naming the field and index, and the sample times themselves.
// Every check throws an InterpolationError subclass whose message starts with the field and
// index, e.g. "times[2]: 1 is not after times[1] = 1 (...)".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "se3_interpolation/geometry/value_checks.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
/// A sphere tangent may have a normal component up to 1 % of its length (rounded input); more
/// means the vector belongs to another point.
constexpr double kMaxNormalFraction = 0.01;

/// Checks every field of a request in space Space (PoseSpace or SphereSpace). Nothing is computed
/// for a rejected request.
/// @param request the raw request
/// @param limits the resource bounds the request must keep
/// @return the request with its names parsed, defaults resolved and points normalised
/// @throws InvalidInputError, NonUniqueGeodesicError or LimitExceededError naming the field and
///         index
template <class Space>
BasicValidatedRequest<Space> validateRequest(const BasicRequest<Space>& request, const PlannerLimits& limits);

/// The limits of PlannerLimits as an error message names them ("the limit (max_samples)"), with
/// `prefix` in front: a caller whose limits are its own parameters names those (the node: "~").
/// @param message an error message of the core
/// @param prefix what to put before each limit's name
/// @return the message with "(max_samples)", "(max_waypoints)" and "(max_work_seconds)" prefixed
std::string withLimitPrefix(const std::string& message, const std::string& prefix);

void requireFiniteNonNegative(double x, const std::string& field);

// --- Time as ROS carries it -------------------------------------------------------------
// Every time of a trajectory reaches ROS: sample times as time_from_start (ros::Duration),
// the stamp plus a sample time as a ros::Time, the moving frame's clock. ros::Time holds
// unsigned 32-bit seconds and ros::Duration signed 32-bit seconds (roscpp's TimeBase and
// DurationBase, nanoseconds in a second 32-bit field); out of range, roscpp throws
// std::runtime_error. The core checks the values against these ranges so no ROS code throws.

/// Largest ros::Time in whole seconds: 2^32 - 1 (unsigned 32-bit seconds).
constexpr double kRosTimeMaxSeconds = 4294967295.0;
/// Largest |ros::Duration| in whole seconds: 2^31 - 1 (signed 32-bit seconds).
constexpr double kRosDurationMaxSeconds = 2147483647.0;
/// Resolution of ros::Duration (and so of time_from_start): 1 ns.
constexpr double kRosDurationResolution = 1e-9;

/// |t| <= kRosDurationMaxSeconds, else InvalidInputError naming `field`.
void requireRosDuration(double t, const std::string& field);

/// The trajectory's span [start_time, end_time] (s after the stamp) fits ros::Duration;
/// `cause` names the field responsible if it does not (e.g. the max_* bound that stretched it).
void validateTimeSpan(double start_time, double end_time, const std::string& cause);

/// stamp + start_time >= 0 and stamp + end_time <= kRosTimeMaxSeconds (stamp in s since the
/// epoch): every sample's stamp is a valid ros::Time. Errors name `stamp_field`.
void validateStampedSpan(double stamp, double start_time, double end_time, const std::string& stamp_field);

// --- Frame ids ----------------------------------------------------------------------------
/// tf2 frame ids are short names; longer ids are refused so that no message, log line or TF
/// frame carries an unbounded string.
constexpr std::size_t kMaxFrameIdLength = 256;

/// A tf2 frame id: non-empty, at most kMaxFrameIdLength characters, no leading '/', no white
/// space or control characters. Throws InvalidInputError naming `field` (quoting a prefix).
void validateFrameId(const std::string& id, const std::string& field);

/// `times` empty, or one finite, strictly increasing time per waypoint, each within ROS's
/// duration range and at least kRosDurationResolution after the previous one.
void validateTimes(const std::vector<double>& times, std::size_t num_waypoints);

/// Checks sample_times (finite, non-decreasing), sample_period (finite, ≥ 0), sample_count
/// (not 1) and the ~max_samples limit where it can be known before timing.
Sampling validateSampling(const std::vector<double>& sample_times, double sample_period, std::uint32_t sample_count,
                          const PlannerLimits& limits);

/// The sample times on [t0, t1]: the explicit ones (each within the trajectory), else every
/// sample_period from t0 with t1 included, else sample_count evenly spaced; both ends are
/// always included. Distinct sample times closer than kRosDurationResolution (which
/// time_from_start cannot tell apart) are refused, naming the sampling field.
std::vector<double> sampleTimes(const Sampling& sampling, double t0, double t1, const PlannerLimits& limits);

}  // namespace se3_interpolation
