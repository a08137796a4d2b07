// Python values → the core's values, for the module's request fields and arguments: numbers,
// strings, number lists, poses, twists and arrays of them, each named by the field it fills.
//
// A Python value of the wrong type (a string for a number, a float for an integer) raises
// TypeError; a value of the right type that the request cannot take (a wrong length or shape, an
// integer out of range, an unknown key of a mapping) raises the core's InvalidInputError, whose
// Python class subclasses ValueError. Messages start with the field and index as the service's
// and the CLI's do ("waypoints[2].orientation: expected 4 numbers [x, y, z, w], got 3").
//
// The accepted spellings: a vector [x, y, z] or {x: .., y: .., z: ..} (a missing component is 0,
// as rosservice fills a message); a pose [x, y, z, qx, qy, qz, qw], a pair (position, quaternion)
// or {position: [..], orientation: [..]} (no orientation: the identity); a twist
// [vx, vy, vz, wx, wy, wz], a pair (linear, angular) or {linear: [..], angular: [..]}; lists of
// poses or twists also as (N, 7) and (N, 6) arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
namespace python
{
namespace py = pybind11;

/// A float64 array of `value` (a copy only when it is not one already), C-contiguous.
/// @throws TypeError naming `field` when `value` is not numeric
py::array_t<double, py::array::c_style | py::array::forcecast> numericArray(py::handle value, const std::string& field);

/// "(2, 3)": an array's shape, for messages.
std::string shapeText(const py::array& a);

double toDouble(py::handle value, const std::string& field);
/// An integer in [lo, hi]; the CLI's message when outside.
long long toInteger(py::handle value, const std::string& field, long long lo, long long hi);
std::string toString(py::handle value, const std::string& field);
bool toBool(py::handle value, const std::string& field);
/// A 1-D sequence or array of numbers.
std::vector<double> toDoubles(py::handle value, const std::string& field);
/// A sequence of strings.
std::vector<std::string> toStrings(py::handle value, const std::string& field);

Pose<double> toPose(py::handle value, const std::string& field);
Twist toTwist(py::handle value, const std::string& field);
/// Poses: an (N, 7) array, or a sequence of poses in any spelling, or a geometry_msgs/PoseArray
/// mapping {header: {..}, poses: [..]}.
std::vector<Pose<double>> toPoses(py::handle value, const std::string& field);
/// Twists: an (N, 6) array or a sequence of twists in any spelling.
std::vector<Twist> toTwists(py::handle value, const std::string& field);

/// A new dict with the items of `mapping` (py::dict(x) of a dict would be x itself, and the
/// module never changes what it was given).
py::dict copyMapping(py::handle mapping);

/// Whether `value` is a mapping (dict or any collections.abc.Mapping).
bool isMapping(py::handle value);

/// Refuses a key of `mapping` not in `allowed` (InvalidInputError "field.key: unknown field").
void requireKeys(py::handle mapping, const std::string& field, const std::vector<std::string>& allowed);

}  // namespace python
}  // namespace se3_interpolation
