// The registry of curve families: CurveFamilies lists every family's descriptor
// (planner/curve_family.h, one file each in planner/families/) in the order of CurveType.
// Validation, the work estimate, the planner's factory and the name table of CurveType read the
// families through it (visitFamily and the functions below), so a family is described in its
// own file and registered by one line here (docs/api.md, "Adding a curve family").
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "se3_interpolation/name_table.h"
#include "se3_interpolation/planner/families/bezier.h"
#include "se3_interpolation/planner/families/blended.h"
#include "se3_interpolation/planner/families/bspline.h"
#include "se3_interpolation/planner/families/fit.h"
#include "se3_interpolation/planner/families/hermite.h"
#include "se3_interpolation/planner/families/interpolating.h"
#include "se3_interpolation/planner/families/piecewise_geodesic.h"

namespace se3_interpolation
{
/// Every curve family, in the order of CurveType (one line per family).
using CurveFamilies = std::tuple<PiecewiseGeodesicFamily, BezierFamily, BsplineFamily, InterpolatingFamily,
                                 HermiteFamily, BlendedFamily, FitFamily>;

/// The number of registered families.
constexpr std::size_t kCurveFamilyCount = std::tuple_size_v<CurveFamilies>;

namespace detail
{
template <std::size_t... I>
constexpr bool familiesInTypeOrder(std::index_sequence<I...>)
{
  return ((static_cast<std::size_t>(std::tuple_element_t<I, CurveFamilies>::kType) == I) && ...);
}
}  // namespace detail

static_assert(detail::familiesInTypeOrder(std::make_index_sequence<kCurveFamilyCount>{}),
              "CurveFamilies must list the families in the order of CurveType");

/// Calls `visit` with a value of the descriptor type of `type`'s family.
/// @param type a registered family
/// @param visit a callable taking any descriptor and returning the same type for all
/// @return what `visit` returns
template <std::size_t I = 0, class Visit>
decltype(auto) visitFamily(CurveType type, Visit&& visit)
{
  if constexpr (I + 1 < kCurveFamilyCount)
    if (static_cast<std::size_t>(type) != I)
      return visitFamily<I + 1>(type, std::forward<Visit>(visit));
  return visit(std::tuple_element_t<I, CurveFamilies>{});
}

/// @param type a family
/// @return the request fields only some families take that `type` takes (FamilyField bits)
inline unsigned familyFields(CurveType type)
{
  return visitFamily(type, [](auto family) { return decltype(family)::kFields; });
}

/// @param type a family
/// @return whether it needs the request's `times` (CurveFamilyDefaults::kRequiresTimes)
inline bool familyRequiresTimes(CurveType type)
{
  return visitFamily(type, [](auto family) { return decltype(family)::kRequiresTimes; });
}

/// @param field one FamilyField
/// @return the families that take `field`, quoted and joined by " or " (e.g. "'bspline'")
inline std::string familiesTaking(FamilyField field)
{
  std::string names;
  std::apply(
      [&names, field](auto... family) {
        auto add = [&names, field](auto f) {
          if ((decltype(f)::kFields & field) != 0u)
            names += (names.empty() ? "'" : " or '") + std::string(decltype(f)::kName) + "'";
        };
        (add(family), ...);
      },
      CurveFamilies{});
  return names;
}

/// The names of the families in the order of CurveType: what the node's dynamic_reconfigure
/// description of `curve` (cfg/InterpolationNode.cfg) must list.
inline std::vector<std::string> curveFamilyNames()
{
  return std::apply([](auto... family) { return std::vector<std::string>{ decltype(family)::kName... }; },
                    CurveFamilies{});
}

/// @param request a validated request
/// @return whether its family's curve starts in request.start_state itself (CurveFamilyDefaults)
template <class Request>
bool continuesStartState(const Request& request)
{
  return visitFamily(request.curve, [&request](auto family) { return decltype(family)::continuesStartState(request); });
}

/// The curve a validated request asks for, in geometry G, with its blend radii.
/// @param request the validated request
/// @param times the waypoints' times (s)
/// @return the family's curve (CurveFamilyDefaults, make)
/// @throws InterpolationError subclasses where the family's construction refuses the data
template <class G, class Space>
FamilyCurve<G> makeFamilyCurve(const BasicValidatedRequest<Space>& request, const std::vector<double>& times)
{
  return visitFamily(request.curve, [&](auto family) { return decltype(family)::template make<G>(request, times); });
}

namespace detail
{
template <std::size_t... I>
constexpr std::array<std::pair<const char*, CurveType>, sizeof...(I)> curveNames(std::index_sequence<I...>)
{
  return { { { std::tuple_element_t<I, CurveFamilies>::kName, std::tuple_element_t<I, CurveFamilies>::kType }... } };
}
}  // namespace detail

/// The names of CurveType: the registered families' (request field `curve`).
template <>
struct NameTable<CurveType>
{
  static constexpr std::array<std::pair<const char*, CurveType>, kCurveFamilyCount> kNames =
      detail::curveNames(std::make_index_sequence<kCurveFamilyCount>{});
};

}  // namespace se3_interpolation
