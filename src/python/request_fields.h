// The request of generate() and of the curve builders from a Python mapping whose keys are the
// service's field names (srv/GenerateTrajectory.srv) and the CLI's start_state, read through one
// table: each field's name, its reader (values.h) and whether a curve builder takes it. Absent
// keys and None keep the request's defaults (empty strings and zeros, resolved by the core's
// validation as for the service and the CLI); unknown keys are refused, as the CLI refuses them.
// The fields the service reads but the module has no use for are checked as the CLI checks them
// (publish, outputs, child_frame_id) or refused with its message (from_current: there is no
// motion playing; waypoint_frames: there is no TF).
#pragma once

#include <pybind11/pybind11.h>

#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace python
{
namespace py = pybind11;

/// Which of the table's fields a reader takes.
enum class FieldSet
{
  kRequest,  ///< generate(): every field
  kCurve     ///< the curve builders: the fields that shape the curve and its waypoints' times
};

/// The request of `fields` (keys: field names).
/// @throws InvalidInputError naming the field for an unknown key, a field the set does not take, a
///         wrong length or an integer out of range; TypeError naming it for a value of the wrong type
TrajectoryRequest requestFromMapping(py::handle fields, FieldSet set);

/// The names of the fields of `set`, in the table's order (the module's documentation lists them).
py::list fieldNames(FieldSet set);

}  // namespace python
}  // namespace se3_interpolation
