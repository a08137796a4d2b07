// Curves as objects: a family's curve built from the request's curve fields (request_fields.h,
// FieldSet::kCurve) exactly as the planner builds it before timing (planner/curve_families.h,
// makeFamilyCurve), in either SE(3) geometry, and evaluated at arrays of times.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "arrays.h"
#include "bindings.h"
#include "request_fields.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/deadline.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "values.h"

namespace se3_interpolation
{
namespace python
{
namespace
{
/// The CLI's limit on waypoints, as generate() keeps it (trajectory.cpp).
constexpr std::size_t kMaxWaypoints = 1000000;

using AnyCurve = std::variant<std::shared_ptr<const Curve<DoubleGeodesicSe3>>, std::shared_ptr<const Curve<ScrewSe3>>>;

/// A family's untimed curve with what built it.
struct PyCurve
{
  AnyCurve curve;
  py::dict fields;  ///< the curve fields it was built from (Curve.fields; the Python timed() reads them)
  std::vector<double> waypoint_times;
  std::vector<Pose<double>> waypoints;  ///< validated (normalised)
  std::optional<FitSummary> fit;

  double startTime() const
  {
    return std::visit([](const auto& c) { return c->startTime(); }, curve);
  }
  double endTime() const
  {
    return std::visit([](const auto& c) { return c->endTime(); }, curve);
  }
};

template <class G>
void keep(FamilyCurve<G>&& built, PyCurve* out)
{
  out->curve = std::move(built.curve);
  out->fit = std::move(built.fit);
}

/// The curve of family `curve` through `waypoints` with the other curve fields: validated as the
/// planner validates a request, spaced in time by its waypointTimes and built by the family's
/// factory, without the GIL and within max_work_seconds (the planner's deadline rule).
PyCurve makeCurve(const std::string& curve, const py::object& waypoints, double max_work_seconds,
                  const py::kwargs& fields)
{
  if (!(max_work_seconds > 0.0) || !std::isfinite(max_work_seconds))
    throw py::value_error("max_work_seconds: " + formatNumber(max_work_seconds) + " is not a positive number");
  PyCurve out;
  out.fields = copyMapping(fields);
  out.fields["curve"] = curve;
  out.fields["waypoints"] = waypoints;
  const TrajectoryRequest request = requestFromMapping(out.fields, FieldSet::kCurve);
  PlannerLimits limits;
  limits.max_waypoints = kMaxWaypoints;
  limits.max_work_seconds = max_work_seconds;
  {
    py::gil_scoped_release release;
    Deadline deadline(std::max(kDeadlineFactor * max_work_seconds, kMinDeadlineSeconds), max_work_seconds);
    const ScopedDeadline scope(deadline);
    const ValidatedRequest r = validateRequest(request, limits);
    out.waypoint_times = waypointTimes(r);
    out.waypoints = r.waypoints;
    if (r.geometry == GeometryType::kScrew)
      keep(makeFamilyCurve<ScrewSe3>(r, out.waypoint_times), &out);
    else
      keep(makeFamilyCurve<DoubleGeodesicSe3>(r, out.waypoint_times), &out);
  }
  return out;
}

/// The curve's pose, velocity and acceleration at `times` (each within its span), quaternions
/// sign-continuous from the first (w ≥ 0), as the planner samples a curve.
SampleArrays evaluate(const PyCurve& self, const py::handle& times)
{
  const std::vector<double> at = toDoubles(times, "t");
  const double t0 = self.startTime();
  const double t1 = self.endTime();
  for (std::size_t i = 0; i < at.size(); ++i)
    if (!(at[i] >= t0 && at[i] <= t1))
      throw InvalidInputError(indexedField("t", i) + ": " + formatNumber(at[i]) + " is outside the curve [" +
                              formatNumber(t0) + ", " + formatNumber(t1) + "]");
  SampleColumns columns;
  {
    py::gil_scoped_release release;
    columns.reserve(at.size());
    std::visit(
        [&](const auto& curve) {
          Quaternion<double> previous = Quaternion<double>::Identity();
          for (double t : at)
          {
            Kinematics k = kinematicsAt(*curve, t);
            if (k.pose.q.coeffs().dot(previous.coeffs()) < 0.0)
              k.pose.q.coeffs() = -k.pose.q.coeffs();
            previous = k.pose.q;
            columns.add(t, k.pose, k.velocity, k.acceleration);
          }
        },
        self.curve);
  }
  return SampleArrays(std::move(columns));
}

py::array_t<double> controlPoses(const PyCurve& self)
{
  return posesArray(std::visit([](const auto& c) { return c->controlPoints(); }, self.curve));
}

py::array_t<double> breakpoints(const PyCurve& self)
{
  return vectorArray(std::visit([](const auto& c) { return c->breakpoints(); }, self.curve));
}
}  // namespace

void bindCurves(py::module_& m)
{
  py::class_<PyCurve>(m, "Curve", "An untimed curve of a family (make_curve, or the family's function).")
      .def_property_readonly("start_time", &PyCurve::startTime)
      .def_property_readonly("end_time", &PyCurve::endTime)
      .def_property_readonly(
          "fields", [](const PyCurve& c) { return copyMapping(c.fields); },
          "the curve fields it was built from (a copy)")
      .def_property_readonly("family", [](const PyCurve& c) { return c.fields["curve"]; })
      .def_property_readonly("waypoint_times", [](const PyCurve& c) { return vectorArray(c.waypoint_times); })
      .def_property_readonly("waypoints", [](const PyCurve& c) { return posesArray(c.waypoints); })
      .def_property_readonly("control_poses", &controlPoses, "(K, 7) the control polygon, or the waypoints")
      .def_property_readonly("breakpoints", &breakpoints, "times between which the curve is analytic")
      .def_property_readonly("residual_linear", [](const PyCurve& c) { return c.fit ? c.fit->residual_linear : 0.0; })
      .def_property_readonly("residual_angular", [](const PyCurve& c) { return c.fit ? c.fit->residual_angular : 0.0; })
      .def_property_readonly("knots",
                             [](const PyCurve& c) { return vectorArray(c.fit ? c.fit->knots : std::vector<double>()); })
      .def("evaluate", &evaluate, py::arg("t"),
           "Pose (M, 7), velocity (M, 6) and acceleration (M, 6) at the times t (M,): Samples, which\n"
           "unpacks as pose, velocity, acceleration.")
      .def("__repr__", [](const PyCurve& c) {
        return "<se3_interpolation.Curve " + c.fields["curve"].cast<std::string>() + " on [" +
               formatNumber(c.startTime()) + ", " + formatNumber(c.endTime()) + "] s>";
      });

  m.def("make_curve", &makeCurve, py::arg("curve"), py::arg("waypoints"), py::kw_only(),
        py::arg("max_work_seconds") = PlannerLimits().max_work_seconds,
        "make_curve(curve, waypoints, *, max_work_seconds=1.0, **fields)\n\n"
        "The untimed curve of family `curve` through `waypoints`, with the request's curve fields\n"
        "(times, geometry, degree, knots, end_condition, ...), as the planner builds it: a Curve.");
  m.attr("CURVE_FAMILIES") = curveFamilyNames();
  m.attr("CURVE_FIELDS") = fieldNames(FieldSet::kCurve);
}

}  // namespace python
}  // namespace se3_interpolation
