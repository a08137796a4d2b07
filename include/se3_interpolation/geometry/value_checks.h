// geometry/value_checks.h: the checks of the numbers a pose or motion is given by, shared by the
// planner's validation of requests and the execution's of goals: finite, of bounded magnitude,
// unit quaternions (normalised). Each throws InvalidInputError naming the field (and component).
#pragma once

#include <string>

#include <Eigen/Core>

#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
/// A unit quaternion or sphere point is accepted with a norm in [0.99, 1.01] (the README's
/// conventions: room for values printed with few digits) and normalised.
constexpr double kMinUnitNorm = 0.99;
constexpr double kMaxUnitNorm = 1.01;
/// Positions (m) and the components of every velocity and acceleration of a request (twists:
/// m/s, rad/s, m/s^2, rad/s^2; sphere tangents: rad/s, rad/s^2) are accepted up to this
/// magnitude. A curve's acceleration is made of terms up to 6 |dp|/h^2 (interpolating,
/// chart_cubic.h (C2)) and 6 |v|/h (hermite), with h >= 1 ns (validateTimes), so a magnitude M
/// gives terms up to about 1.2e19 M; the energy integrates their square over at most
/// 2 kRosDurationMaxSeconds. With M = 1e100 that is 1.2e119, squared times 4.3e9 s about
/// 6e247: below the largest double (1.8e308) with a factor 1e30 to spare for the families' own
/// factors (degrees, knot ratios). Beyond it a finite request could evaluate to an infinite
/// acceleration (the fuzz_curves finding: a hermite velocity of 1.8e308 m/s).
constexpr double kMaxMagnitude = 1e100;

/// A validated, normalised pose; throws InvalidInputError naming `field` (e.g. "waypoints[2]").
Pose<double> validatePose(const Pose<double>& raw, const std::string& field);

/// A finite quaternion with norm in [kMinUnitNorm, kMaxUnitNorm], normalised; throws
/// InvalidInputError naming `field` (a component as `field`.x … .w).
Quaternion<double> validateQuaternion(const Quaternion<double>& raw, const std::string& field);

/// A position or twist part with finite components of magnitude at most kMaxMagnitude; throws
/// InvalidInputError naming the component (`field`.x, .y, .z).
void requireBounded(const Eigen::Vector3d& v, const std::string& field);

/// A finite number; throws InvalidInputError naming `field`.
void requireFinite(double x, const std::string& field);

/// A finite number of magnitude at most kMaxMagnitude; throws InvalidInputError naming `field`.
void requireBounded(double x, const std::string& field);

/// A norm within [kMinUnitNorm, kMaxUnitNorm], else InvalidInputError naming `field`; `prefix`
/// goes before "norm" in the message and `what` says what the unit object is ("quaternion x, y,
/// z, w" or "vector").
void requireUnitNorm(double norm, const std::string& field, const std::string& prefix, const char* what);
}  // namespace se3_interpolation
