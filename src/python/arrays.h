// numpy arrays of the core's results, filled in C++ without a Python object per sample: rows of
// poses [x, y, z, qx, qy, qz, qw] (the CLI's column order) and twists [vx, vy, vz, wx, wy, wz]
// (linear first, as the CLI's velocity and acceleration columns), collected in std::vector and
// handed to numpy without a copy (the array owns the vector).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <vector>

#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
namespace python
{
namespace py = pybind11;

/// An array of `shape` that takes `data` over (moved; no copy). Needs the GIL.
py::array_t<double> ownedArray(std::vector<double>&& data, const std::vector<py::ssize_t>& shape);

/// An (N,) array of `values` (a copy).
py::array_t<double> vectorArray(const std::vector<double>& values);

/// An (N, 7) array of `poses`.
py::array_t<double> posesArray(const std::vector<Pose<double>>& poses);

/// Samples of a pose motion as columns: times, poses, velocities, accelerations. Filled without
/// the GIL; turned into arrays with it.
struct SampleColumns
{
  std::vector<double> t;
  std::vector<double> pose;          ///< 7 per sample
  std::vector<double> velocity;      ///< 6 per sample
  std::vector<double> acceleration;  ///< 6 per sample

  void reserve(std::size_t samples);
  void add(double time, const Pose<double>& x, const Twist& v, const Twist& a);
  std::size_t size() const { return t.size(); }
};

/// The arrays of `columns` (t (M,), pose (M, 7), velocity (M, 6), acceleration (M, 6)), taking
/// their memory over.
struct SampleArrays
{
  explicit SampleArrays(SampleColumns&& columns);

  py::array_t<double> t, pose, velocity, acceleration;
};

}  // namespace python
}  // namespace se3_interpolation
