// generate(): the whole planner from Python, as the service and the CLI run it (planner.h), with
// the samples collected into numpy arrays as the planner hands them on (SampleSink), without the
// GIL.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "arrays.h"
#include "bindings.h"
#include "request_fields.h"
#include "se3_interpolation/planner/planner.h"
#include "values.h"

namespace se3_interpolation
{
namespace python
{
namespace
{
/// The CLI's limit on waypoints (a recording of 10⁶ poses), so that the module refuses what the
/// CLI refuses; samples and work keep PlannerLimits' defaults, as the CLI does.
constexpr std::size_t kMaxWaypoints = 1000000;

/// A generated motion: the samples as arrays, the figures, the waypoints' times and the timed curve.
struct Trajectory
{
  py::array_t<double> t, pose, velocity, acceleration;
  py::array_t<double> waypoint_times, waypoints, control_poses, knots, blend_radii;
  TrajectoryResult result;  ///< without its samples (they are in the arrays)

  /// The figures the CLI prints, by its names and in its order (only those it prints for this
  /// motion: recovery_time, stop_time, the constant-speed window and the fit's residuals when set).
  py::dict figures() const
  {
    const CurveFigures& f = result.figures;
    py::dict d;
    d["duration"] = result.duration;
    d["length"] = f.length;
    d["rotation_length"] = f.rotation_length;
    d["max_linear_speed"] = f.max_linear_speed;
    d["max_angular_speed"] = f.max_angular_speed;
    d["peak_linear_acceleration"] = f.max_linear_acceleration;
    d["peak_angular_acceleration"] = f.max_angular_acceleration;
    d["peak_linear_jerk"] = f.max_linear_jerk;
    d["peak_angular_jerk"] = f.max_angular_jerk;
    d["energy"] = f.energy;
    if (result.recovery_time > 0.0)
      d["recovery_time"] = result.recovery_time;
    if (result.stop_time > 0.0)
      d["stop_time"] = result.stop_time;
    if (result.constant_speed_end > result.constant_speed_start)
    {
      d["constant_speed_start"] = result.constant_speed_start;
      d["constant_speed_end"] = result.constant_speed_end;
    }
    if (!result.knots.empty())
    {
      d["residual_linear"] = result.residual_linear;
      d["residual_angular"] = result.residual_angular;
    }
    return d;
  }
};

/// The request of generate()'s arguments: the mapping `request` and the keyword fields, a field
/// given in both being an error.
TrajectoryRequest mergedRequest(const py::object& request, const py::kwargs& fields)
{
  py::dict merged;
  if (!request.is_none())
  {
    if (!isMapping(request))
      throw py::type_error("request: expected a dict of the service's fields, got " +
                           std::string(Py_TYPE(request.ptr())->tp_name));
    merged = copyMapping(request);
  }
  for (const auto& kv : fields)
  {
    if (merged.contains(kv.first))
      throw py::type_error(py::str(kv.first).cast<std::string>() +
                           ": given both in the request and as a keyword argument");
    merged[kv.first] = kv.second;
  }
  return requestFromMapping(merged, FieldSet::kRequest);
}

/// The most samples reserved before the planner has validated the request (a larger answer grows
/// its vectors): a sample_count far beyond the limits must meet the planner's refusal, not an
/// allocation.
constexpr std::size_t kMaxReservedSamples = std::size_t(1) << 20;

/// The samples a request will have when it says (sample_times, sample_count), for reserving.
std::size_t expectedSamples(const TrajectoryRequest& r, const PlannerLimits& limits)
{
  std::size_t n = r.sample_period > 0.0 ? 0 : r.sample_times.size();
  if (n == 0 && r.sample_period <= 0.0)
    n = r.sample_count > 0 ? r.sample_count : RequestDefaults::kSampleCount;
  return std::min({ n, limits.max_samples, kMaxReservedSamples });
}

Trajectory generateTrajectory(const py::object& request, double max_work_seconds, std::size_t max_samples,
                              std::size_t max_waypoints, const py::kwargs& fields)
{
  const TrajectoryRequest r = mergedRequest(request, fields);
  PlannerLimits limits;
  limits.max_work_seconds = max_work_seconds;
  limits.max_samples = max_samples;
  limits.max_waypoints = max_waypoints;
  if (!(max_work_seconds > 0.0) || !std::isfinite(max_work_seconds))
    throw py::value_error("max_work_seconds: " + formatNumber(max_work_seconds) + " is not a positive number");
  SampleColumns columns;
  Trajectory out;
  {
    py::gil_scoped_release release;
    columns.reserve(expectedSamples(r, limits));
    out.result = generate(r, limits, SampleSink<PoseSpace>([&columns](const TrajectorySample* first, std::size_t n) {
                            for (const TrajectorySample* s = first; s != first + n; ++s)
                              columns.add(s->time, s->pose, s->velocity, s->acceleration);
                          }));
  }
  SampleArrays arrays(std::move(columns));
  out.t = arrays.t;
  out.pose = arrays.pose;
  out.velocity = arrays.velocity;
  out.acceleration = arrays.acceleration;
  out.waypoint_times = vectorArray(out.result.waypoint_times);
  out.waypoints = posesArray(out.result.waypoints);
  out.control_poses = posesArray(out.result.control_points);
  out.knots = vectorArray(out.result.knots);
  out.blend_radii = vectorArray(out.result.blend_radii);
  return out;
}

/// The timed motion's state at each of `times` (TrajectoryResult::state_at), quaternions
/// sign-continuous from the first.
SampleArrays stateAt(const Trajectory& self, const py::handle& times)
{
  const std::vector<double> at = toDoubles(times, "t");
  const double t0 = self.result.start_time;
  const double t1 = t0 + self.result.duration;
  for (std::size_t i = 0; i < at.size(); ++i)
    if (!(at[i] >= t0 && at[i] <= t1))
      throw InvalidInputError(indexedField("t", i) + ": " + formatNumber(at[i]) + " is outside the motion [" +
                              formatNumber(t0) + ", " + formatNumber(t1) + "]");
  SampleColumns columns;
  {
    py::gil_scoped_release release;
    columns.reserve(at.size());
    Quaternion<double> previous = Quaternion<double>::Identity();
    for (double t : at)
    {
      TrajectorySample s = self.result.state_at(t);
      if (s.pose.q.coeffs().dot(previous.coeffs()) < 0.0)
        s.pose.q.coeffs() = -s.pose.q.coeffs();
      previous = s.pose.q;
      columns.add(t, s.pose, s.velocity, s.acceleration);
    }
  }
  return SampleArrays(std::move(columns));
}
}  // namespace

void bindTrajectory(py::module_& m)
{
  py::class_<SampleArrays>(m, "Samples", "Poses, velocities and accelerations at times (numpy arrays).")
      .def_readonly("t", &SampleArrays::t, "times (M,), s")
      .def_readonly("pose", &SampleArrays::pose, "(M, 7): x, y, z, qx, qy, qz, qw")
      .def_readonly("velocity", &SampleArrays::velocity, "(M, 6): vx, vy, vz, wx, wy, wz (waypoints' frame)")
      .def_readonly("acceleration", &SampleArrays::acceleration, "(M, 6): ax, ay, az, alx, aly, alz")
      .def("__iter__",
           [](const SampleArrays& s) { return py::iter(py::make_tuple(s.pose, s.velocity, s.acceleration)); });

  auto figure = [](double TrajectoryResult::*member) {
    return [member](const Trajectory& self) { return self.result.*member; };
  };
  auto curveFigure = [](double CurveFigures::*member) {
    return [member](const Trajectory& self) { return self.result.figures.*member; };
  };
  py::class_<Trajectory>(m, "Trajectory", "A generated motion: generate()'s answer.")
      .def_readonly("t", &Trajectory::t, "sample times (M,), s")
      .def_readonly("pose", &Trajectory::pose, "(M, 7): x, y, z, qx, qy, qz, qw, quaternions sign-continuous")
      .def_readonly("velocity", &Trajectory::velocity, "(M, 6): vx, vy, vz, wx, wy, wz in the waypoints' frame")
      .def_readonly("acceleration", &Trajectory::acceleration, "(M, 6): ax, ay, az, alx, aly, alz")
      .def_readonly("waypoint_times", &Trajectory::waypoint_times, "(N,) the waypoints' final times, s")
      .def_readonly("waypoints", &Trajectory::waypoints, "(N, 7) the validated (normalised) waypoints")
      .def_readonly("control_poses", &Trajectory::control_poses, "(K, 7) the curve's control poses")
      .def_readonly("knots", &Trajectory::knots, "the fitted B-spline's knots (curve fit), else empty")
      .def_readonly("blend_radii", &Trajectory::blend_radii, "per waypoint, its corner blend's radius (m)")
      .def_property_readonly("start_time", figure(&TrajectoryResult::start_time))
      .def_property_readonly("duration", figure(&TrajectoryResult::duration))
      .def_property_readonly("time_scale", figure(&TrajectoryResult::time_scale))
      .def_property_readonly("recovery_time", figure(&TrajectoryResult::recovery_time))
      .def_property_readonly("stop_time", figure(&TrajectoryResult::stop_time))
      .def_property_readonly("constant_speed_start", figure(&TrajectoryResult::constant_speed_start))
      .def_property_readonly("constant_speed_end", figure(&TrajectoryResult::constant_speed_end))
      .def_property_readonly("residual_linear", figure(&TrajectoryResult::residual_linear))
      .def_property_readonly("residual_angular", figure(&TrajectoryResult::residual_angular))
      .def_property_readonly("length", curveFigure(&CurveFigures::length))
      .def_property_readonly("rotation_length", curveFigure(&CurveFigures::rotation_length))
      .def_property_readonly("energy", curveFigure(&CurveFigures::energy))
      .def_property_readonly("max_linear_speed", curveFigure(&CurveFigures::max_linear_speed))
      .def_property_readonly("max_angular_speed", curveFigure(&CurveFigures::max_angular_speed))
      .def_property_readonly("peak_linear_acceleration", curveFigure(&CurveFigures::max_linear_acceleration))
      .def_property_readonly("peak_angular_acceleration", curveFigure(&CurveFigures::max_angular_acceleration))
      .def_property_readonly("peak_linear_jerk", curveFigure(&CurveFigures::max_linear_jerk))
      .def_property_readonly("peak_angular_jerk", curveFigure(&CurveFigures::max_angular_jerk))
      .def_property_readonly("figures", &Trajectory::figures, "the figures the CLI prints, by its names")
      .def("evaluate", &stateAt, py::arg("t"),
           "The timed motion at the times t (within [start_time, start_time + duration]): Samples.")
      .def("__len__", [](const Trajectory& self) { return self.t.shape(0); })
      .def("__repr__", [](const Trajectory& self) {
        return "<se3_interpolation.Trajectory: " + std::to_string(self.t.shape(0)) + " samples over " +
               formatNumber(self.result.duration) + " s>";
      });

  m.def("generate", &generateTrajectory, py::arg("request") = py::none(), py::kw_only(),
        py::arg("max_work_seconds") = PlannerLimits().max_work_seconds,
        py::arg("max_samples") = PlannerLimits().max_samples, py::arg("max_waypoints") = kMaxWaypoints,
        "generate(request=None, *, max_work_seconds=1.0, max_samples=200000, max_waypoints=1000000, **fields)\n\n"
        "The trajectory of a request with the service's field names (a dict, keyword arguments or\n"
        "both), as the ~generate service and the se3_interpolate CLI compute it: a Trajectory.\n"
        "Raises InvalidInputError (a ValueError) naming the field and index for a bad request.");
  m.attr("REQUEST_FIELDS") = fieldNames(FieldSet::kRequest);
}

}  // namespace python
}  // namespace se3_interpolation
