#include "request_fields.h"

#include <array>
#include <string>
#include <type_traits>

#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"
#include "values.h"

namespace se3_interpolation
{
namespace python
{
namespace
{
/// Reads one field's value into the request (the value is neither absent nor None).
using Reader = void (*)(py::handle value, const std::string& field, TrajectoryRequest* r);

struct Field
{
  const char* name;
  Reader read;
  bool shapes_curve;  ///< taken by the curve builders (FieldSet::kCurve)
};

template <auto M>
void number(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  r->*M = toDouble(value, field);
}

template <auto M>
void numbers(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  r->*M = toDoubles(value, field);
}

template <auto M>
void text(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  r->*M = toString(value, field);
}

template <auto M>
void twist(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  r->*M = toTwist(value, field);
}

/// An unsigned integer field of the service (uint8, uint32): 0 … kMax, as the CLI reads it.
template <auto M, long long kMax>
void integer(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  using T = std::remove_reference_t<decltype(r->*M)>;
  r->*M = static_cast<T>(toInteger(value, field, 0, kMax));
}

void waypoints(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  r->waypoints = toPoses(value, field);
}

void velocities(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  r->velocities = toTwists(value, field);
}

void startState(py::handle value, const std::string& field, TrajectoryRequest* r)
{
  if (!isMapping(value))
    throw py::type_error(field + ": expected {pose: .., velocity: .., acceleration: ..}, got " +
                         std::string(Py_TYPE(value.ptr())->tp_name));
  requireKeys(value, field, { "pose", "velocity", "acceleration" });
  const py::object pose = value.attr("get")("pose");
  if (pose.is_none())
    throw InvalidInputError(field + ".pose: missing ({position: [x, y, z], orientation: [x, y, z, w]})");
  StartState state;
  state.pose = toPose(pose, field + ".pose");
  const py::object velocity = value.attr("get")("velocity");
  if (!velocity.is_none())
    state.velocity = toTwist(velocity, field + ".velocity");
  const py::object acceleration = value.attr("get")("acceleration");
  if (!acceleration.is_none())
    state.acceleration = toTwist(acceleration, field + ".acceleration");
  r->start_state = state;
}

/// The service's publish: checked, not used (the module publishes nothing).
void publish(py::handle value, const std::string& field, TrajectoryRequest* /*r*/)
{
  toBool(value, field);
}

/// The service's choice of response arrays: checked as the service checks it; the module returns
/// every array whatever it names.
void outputs(py::handle value, const std::string& field, TrajectoryRequest* /*r*/)
{
  parseResponseOutputs(toStrings(value, field));
}

void childFrameId(py::handle value, const std::string& field, TrajectoryRequest* /*r*/)
{
  validateFrameId(toString(value, field), field);
}

void fromCurrent(py::handle value, const std::string& field, TrajectoryRequest* /*r*/)
{
  if (toBool(value, field))
    throw InvalidInputError(field +
                            ": the Python module plays no trajectory, so there is no current motion to start "
                            "from; give the state explicitly as start_state={'pose': {'position': [x, y, z], "
                            "'orientation': [x, y, z, w]}, 'velocity': {'linear': [..], 'angular': [..]}, "
                            "'acceleration': {'linear': [..], 'angular': [..]}}");
}

void waypointFrames(py::handle /*value*/, const std::string& field, TrajectoryRequest* /*r*/)
{
  throw InvalidInputError(field +
                          ": the Python module has no TF to look frames up in; give their poses in waypoints "
                          "(the node's ~generate service takes waypoint_frames)");
}

using R = TrajectoryRequest;

/// Every field, in the order of srv/GenerateTrajectory.srv (then the CLI's start_state): the
/// order in which they are read, so that a request with several bad fields names the same one
/// whatever the order of its keys.
const std::array<Field, 39> kFields = { {
    { "waypoints", &waypoints, true },
    { "waypoint_frames", &waypointFrames, false },
    { "times", &numbers<&R::times>, true },
    { "curve", &text<&R::curve>, true },
    { "geometry", &text<&R::geometry>, true },
    { "degree", &integer<&R::degree, 255>, true },
    { "knots", &numbers<&R::knots>, true },
    { "continuity", &integer<&R::continuity, 255>, true },
    { "blend_radius", &number<&R::blend_radius>, true },
    { "end_condition", &text<&R::end_condition>, true },
    { "start_velocity", &twist<&R::start_velocity>, true },
    { "end_velocity", &twist<&R::end_velocity>, true },
    { "start_acceleration", &twist<&R::start_acceleration>, true },
    { "velocities", &velocities, true },
    { "parameterization", &text<&R::parameterization>, true },
    { "rotation_scale", &number<&R::rotation_scale>, true },
    { "duration", &number<&R::duration>, true },
    { "max_linear_velocity", &number<&R::max_linear_velocity>, false },
    { "max_angular_velocity", &number<&R::max_angular_velocity>, false },
    { "max_linear_acceleration", &number<&R::max_linear_acceleration>, false },
    { "max_angular_acceleration", &number<&R::max_angular_acceleration>, false },
    { "max_linear_jerk", &number<&R::max_linear_jerk>, false },
    { "max_angular_jerk", &number<&R::max_angular_jerk>, false },
    { "timing", &text<&R::timing>, false },
    { "speed", &number<&R::speed>, false },
    { "control_period", &number<&R::control_period>, true },
    { "smoothing", &number<&R::smoothing>, true },
    { "loss", &text<&R::loss>, true },
    { "loss_scale", &number<&R::loss_scale>, true },
    { "sample_times", &numbers<&R::sample_times>, false },
    { "sample_period", &number<&R::sample_period>, false },
    { "sample_count", &integer<&R::sample_count, 4294967295LL>, false },
    { "sample_tolerance", &number<&R::sample_tolerance>, false },
    { "joint_seed", &numbers<&R::joint_seed>, false },
    { "child_frame_id", &childFrameId, false },
    { "publish", &publish, false },
    { "from_current", &fromCurrent, false },
    { "outputs", &outputs, false },
    { "start_state", &startState, false },
} };

const Field* findField(const std::string& name)
{
  for (const Field& f : kFields)
    if (name == f.name)
      return &f;
  return nullptr;
}
}  // namespace

TrajectoryRequest requestFromMapping(py::handle fields, FieldSet set)
{
  if (!isMapping(fields))
    throw py::type_error("request: expected a dict of the service's fields, got " +
                         std::string(Py_TYPE(fields.ptr())->tp_name));
  // Unknown keys first (they are usually typos), as the CLI refuses them before reading any field.
  for (py::handle key : fields)
  {
    const std::string name = toString(key, "request key");
    const Field* f = findField(name);
    if (f == nullptr)
      throw InvalidInputError(name + ": unknown field");
    if (set == FieldSet::kCurve && !f->shapes_curve)
      throw InvalidInputError(name +
                              ": not a field of a curve (it shapes the timing or the samples; give it to "
                              "generate())");
  }
  TrajectoryRequest r;
  for (const Field& f : kFields)
  {
    const py::object value = fields.attr("get")(f.name);
    if (!value.is_none())
      f.read(value, f.name, &r);
  }
  return r;
}

py::list fieldNames(FieldSet set)
{
  py::list names;
  for (const Field& f : kFields)
    if (set == FieldSet::kRequest || f.shapes_curve)
      names.append(f.name);
  return names;
}

}  // namespace python
}  // namespace se3_interpolation
