// Error types of the core library (modelled on tf2's exception hierarchy).
//
// Every error the mathematics can raise derives from std::invalid_argument, so a
// caller that only wants "bad input, here is why" catches that; callers that need
// to react differently catch the specific type. Messages name the offending
// request field and index, e.g. "waypoints[3].orientation: ...".
#pragma once

#include <stdexcept>
#include <string>

namespace se3_interpolation
{
/// Base of every error thrown by the core: the input cannot produce a curve.
class InterpolationError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// A request field is malformed (non-finite, out of range, wrong length, unknown name).
class InvalidInputError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

/// Two points to be joined are exactly antipodal (rotation angle π, or x and −x on
/// S^m): the minimising geodesic between them is not unique.
class NonUniqueGeodesicError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

/// An iterative solve (interpolating spline) did not reach its tolerance.
class ConvergenceError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

/// A request would exceed a configured resource limit (samples, waypoints).
class LimitExceededError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

}  // namespace se3_interpolation
