// Builds the curve a validated request asks for, in geometry G (docs/curves.md), through the
// factory of its family's descriptor (planner/curve_families.h).
#pragma once

#include <memory>
#include <vector>

#include "se3_interpolation/planner/curve_families.h"

namespace se3_interpolation
{
/// The curve of a validated request in geometry G (its blend radii: makeFamilyCurve).
/// @param r the validated request
/// @param times the waypoints' times (s)
/// @return the curve of r.curve's family
/// @throws InterpolationError subclasses where the family's construction refuses the data
template <class G, class Space>
std::shared_ptr<const Curve<G>> makeCurve(const BasicValidatedRequest<Space>& r, const std::vector<double>& times)
{
  return makeFamilyCurve<G>(r, times).curve;
}

}  // namespace se3_interpolation
