// The end conditions of the C² spline `interpolating` (request field `end_condition`) and their
// names: what the request needs of the solve without the solve itself.
#pragma once

#include <array>
#include <utility>

#include "se3_interpolation/name_table.h"

namespace se3_interpolation
{
/// The end conditions of the C² spline (request field `end_condition`).
enum class EndCondition
{
  kNatural,  ///< "natural": zero acceleration at both ends
  kClamped,  ///< "clamped": the given start and end velocities
  kStart     ///< "start": the given start velocity and acceleration (Crouch Case 2)
};

/// The names of EndCondition (the request's `end_condition`).
template <>
struct NameTable<EndCondition>
{
  static constexpr std::array<std::pair<const char*, EndCondition>, 3> kNames = { {
      { "natural", EndCondition::kNatural },
      { "clamped", EndCondition::kClamped },
      { "start", EndCondition::kStart },
  } };
};

}  // namespace se3_interpolation
