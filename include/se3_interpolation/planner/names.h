// The names of the request's string fields (curve, geometry, parameterization, timing): one
// table per enum (name_table.h), read by the planner, the node's parameters and the CLI, so that
// a name is spelled in one place. end_condition's table lives with its enum in
// curves/interpolating_solver.h (curves/ must not include planner/).
#pragma once

#include <array>
#include <string>
#include <utility>

#include "se3_interpolation/name_table.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
template <>
struct NameTable<CurveType>
{
  static constexpr std::array<std::pair<const char*, CurveType>, 6> kNames = { {
      { "piecewise_geodesic", CurveType::kPiecewiseGeodesic },
      { "bezier", CurveType::kBezier },
      { "bspline", CurveType::kBspline },
      { "interpolating", CurveType::kInterpolating },
      { "hermite", CurveType::kHermite },
      { "blended", CurveType::kBlended },
  } };
};

template <>
struct NameTable<GeometryType>
{
  static constexpr std::array<std::pair<const char*, GeometryType>, 2> kNames = { {
      { "double_geodesic", GeometryType::kDoubleGeodesic },
      { "screw", GeometryType::kScrew },
  } };
};

template <>
struct NameTable<Parameterization>
{
  static constexpr std::array<std::pair<const char*, Parameterization>, 3> kNames = { {
      { "chord", Parameterization::kChord },
      { "uniform", Parameterization::kUniform },
      { "centripetal", Parameterization::kCentripetal },
  } };
};

template <>
struct NameTable<Timing>
{
  static constexpr std::array<std::pair<const char*, Timing>, 2> kNames = { {
      { "stretch", Timing::kStretch },
      { "time_optimal", Timing::kTimeOptimal },
  } };
};

}  // namespace se3_interpolation
