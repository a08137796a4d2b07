// The names of the request's string fields (curve, geometry, end_condition, parameterization,
// timing, the entries of outputs): one table per enum, read by the planner, the node's parameters and the CLI, so that
// a name is spelled in one place. parseName gives the default for "" and refuses an unknown
// name with an InvalidInputError naming the field and listing the known names.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
/// The name table of enum E: NameTable<E>::kNames, an array of (name, value).
template <class E>
struct NameTable;

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
struct NameTable<EndCondition>
{
  static constexpr std::array<std::pair<const char*, EndCondition>, 3> kNames = { {
      { "natural", EndCondition::kNatural },
      { "clamped", EndCondition::kClamped },
      { "start", EndCondition::kStart },
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

template <>
struct NameTable<ResponseOutput>
{
  static constexpr std::array<std::pair<const char*, ResponseOutput>, 2> kNames = { {
      { "path", ResponseOutput::kPath },
      { "trajectory", ResponseOutput::kTrajectory },
  } };
};

/// The name of `value` in its table.
template <class E>
const char* toString(E value)
{
  for (const auto& n : NameTable<E>::kNames)
    if (n.second == value)
      return n.first;
  return "";
}

/// "a, b, c": the known names of E, for messages.
template <class E>
std::string knownNames()
{
  std::string known;
  for (const auto& n : NameTable<E>::kNames)
    known += (known.empty() ? "" : ", ") + std::string(n.first);
  return known;
}

/// The value named `name`; "" gives `default_value`. Unknown names throw InvalidInputError
/// naming `field`, quoting the name (at most a prefix) and listing the known ones.
template <class E>
E parseName(const std::string& name, const std::string& field, E default_value)
{
  if (name.empty())
    return default_value;
  for (const auto& n : NameTable<E>::kNames)
    if (name == n.first)
      return n.second;
  throw InvalidInputError(field + ": unknown value " + quotedText(name) + " (expected one of: " + knownNames<E>() + ")");
}

/// The arrays named in a request's `outputs` (empty: all of them, the behaviour before the field
/// existed). An empty, unknown or repeated name throws InvalidInputError naming outputs[i].
inline ResponseOutputs parseResponseOutputs(const std::vector<std::string>& outputs)
{
  if (outputs.empty())
    return ResponseOutputs();
  ResponseOutputs chosen;
  chosen.path = false;
  chosen.trajectory = false;
  for (std::size_t i = 0; i < outputs.size(); ++i)
  {
    const std::string field = indexedField("outputs", i);
    if (outputs[i].empty())
      throw InvalidInputError(field + ": empty name (expected one of: " + knownNames<ResponseOutput>() + ")");
    bool& slot = parseName(outputs[i], field, ResponseOutput::kPath) == ResponseOutput::kPath ? chosen.path
                                                                                             : chosen.trajectory;
    if (slot)
      throw InvalidInputError(field + ": " + quotedText(outputs[i]) + " is named twice");
    slot = true;
  }
  return chosen;
}

}  // namespace se3_interpolation
