// The parts of the module se3_interpolation._core (module.cpp), each registered by one function:
// generate() and its Trajectory (trajectory.cpp), the curve objects (curves.cpp), the groups'
// exp, log and geodesic steps (groups.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace se3_interpolation
{
namespace python
{
namespace py = pybind11;

void bindTrajectory(py::module_& m);
void bindCurves(py::module_& m);
void bindGroups(py::module_& m);

}  // namespace python
}  // namespace se3_interpolation
