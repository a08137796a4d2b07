// se3_interpolation._core: the Python binding of the core library (Eigen only, no ROS), imported
// by the package se3_interpolation (src/se3_interpolation/__init__.py) beside the generated
// messages. The core's errors become Python exceptions of the same names, all ValueErrors: a bad
// request raises InvalidInputError with the message the service and the CLI give.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "se3_interpolation/exceptions.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m)
{
  namespace se3 = se3_interpolation;
  m.doc() = "The se3_interpolation core: generate(), curves, SO(3)/SE(3) exp and log, geodesic steps.";
  // Registered base first: pybind11 tries the translators last-registered first, so each error
  // becomes its own class.
  const auto& base = py::register_exception<se3::InterpolationError>(m, "InterpolationError", PyExc_ValueError);
  py::register_exception<se3::InvalidInputError>(m, "InvalidInputError", base.ptr());
  py::register_exception<se3::NonUniqueGeodesicError>(m, "NonUniqueGeodesicError", base.ptr());
  py::register_exception<se3::ConvergenceError>(m, "ConvergenceError", base.ptr());
  py::register_exception<se3::LimitExceededError>(m, "LimitExceededError", base.ptr());
  se3::python::bindTrajectory(m);
  se3::python::bindCurves(m);
  se3::python::bindGroups(m);
}
