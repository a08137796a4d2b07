// Name tables: one table per enum, so that each name is spelled in one place, and the functions
// that read them. A table is a specialisation NameTable<E> with kNames, an array of (name, value),
// written next to the enum (planner/names.h for the request's enums, planner/curve_families.h for
// CurveType, made from the registered families, curves/end_condition.h for EndCondition).
// parseName gives the default for "" and refuses an unknown name with an InvalidInputError naming
// the field and listing the known names.
#pragma once

#include <string>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
/// The name table of enum E: NameTable<E>::kNames, an array of (name, value).
template <class E>
struct NameTable;

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
  throw InvalidInputError(field + ": unknown value " + quotedText(name) + " (expected one of: " + knownNames<E>() +
                          ")");
}

}  // namespace se3_interpolation
