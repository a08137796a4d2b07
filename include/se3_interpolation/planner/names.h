// The names of the request's string fields (curve, geometry, parameterization, timing, loss, the
// entries of outputs): one table per enum (name_table.h), read by the planner, the node's
// parameters and the CLI, so that a name is spelled in one place. curve's table is made from the
// registered families (planner/curve_families.h); end_condition's lives with its enum in
// curves/end_condition.h (curves/ must not include planner/).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/name_table.h"
#include "se3_interpolation/planner/curve_families.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
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
  static constexpr std::array<std::pair<const char*, Timing>, 3> kNames = { {
      { "stretch", Timing::kStretch },
      { "time_optimal", Timing::kTimeOptimal },
      { "constant_speed", Timing::kConstantSpeed },
  } };
};

template <>
struct NameTable<FitLoss>
{
  static constexpr std::array<std::pair<const char*, FitLoss>, 2> kNames = { {
      { "squared", FitLoss::kSquared },
      { "huber", FitLoss::kHuber },
  } };
};

template <>
struct NameTable<ResponseOutput>
{
  static constexpr std::array<std::pair<const char*, ResponseOutput>, 3> kNames = { {
      { "path", ResponseOutput::kPath },
      { "trajectory", ResponseOutput::kTrajectory },
      { "joint_trajectory", ResponseOutput::kJointTrajectory },
  } };
};

/// The arrays named in a request's `outputs` (empty: all of them, the behaviour before the field
/// existed). An empty, unknown or repeated name throws InvalidInputError naming outputs[i].
inline ResponseOutputs parseResponseOutputs(const std::vector<std::string>& outputs)
{
  if (outputs.empty())
    return ResponseOutputs();
  ResponseOutputs chosen;
  chosen.path = false;
  chosen.trajectory = false;
  chosen.joint_trajectory = false;
  for (std::size_t i = 0; i < outputs.size(); ++i)
  {
    const std::string field = indexedField("outputs", i);
    if (outputs[i].empty())
      throw InvalidInputError(field + ": empty name (expected one of: " + knownNames<ResponseOutput>() + ")");
    const ResponseOutput named = parseName(outputs[i], field, ResponseOutput::kPath);
    bool& slot = named == ResponseOutput::kPath       ? chosen.path :
                 named == ResponseOutput::kTrajectory ? chosen.trajectory :
                                                        chosen.joint_trajectory;
    if (slot)
      throw InvalidInputError(field + ": " + quotedText(outputs[i]) + " is named twice");
    slot = true;
  }
  return chosen;
}

}  // namespace se3_interpolation
