// planner/curve_families.h: the registry of curve families is the one list that the name table,
// validation's field rules, the start-state handling and the blend radii agree with (the node's
// ~curve choices are read from it too: test_node_parameters); the core's limit messages name
// PlannerLimits' fields, which a caller prefixes (withLimitPrefix).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"

using namespace se3_interpolation;

namespace
{
/// The message of the InvalidInputError that validating `r` throws ("" if none).
std::string validationError(const TrajectoryRequest& r)
{
  try
  {
    validateRequest(r, PlannerLimits());
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}

ValidatedRequest validatedOf(const std::string& curve, const std::string& end_condition = "")
{
  TrajectoryRequest r;
  r.waypoints = { Pose<double>::Identity(), Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(1, 0, 0)),
                  Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(1, 1, 0)) };
  r.curve = curve;
  r.end_condition = end_condition;
  if (familyRequiresTimes(parseName(curve, "curve", RequestDefaults::kCurve)))
    r.times = { 0.0, 0.1, 0.2 };  // one knot interval of the default control period
  return validateRequest(r, PlannerLimits());
}
}  // namespace

TEST(CurveFamilies, NameTableIsTheRegistryInTheOrderOfCurveType)
{
  const std::vector<std::string> names = curveFamilyNames();
  ASSERT_EQ(names.size(), NameTable<CurveType>::kNames.size());
  for (std::size_t i = 0; i < names.size(); ++i)
  {
    EXPECT_EQ(names[i], NameTable<CurveType>::kNames[i].first);
    EXPECT_EQ(static_cast<std::size_t>(NameTable<CurveType>::kNames[i].second), i);
  }
  EXPECT_EQ(names.front(), "piecewise_geodesic");
  EXPECT_STREQ(toString(CurveType::kBlended), "blended");
}

TEST(CurveFamilies, ExclusiveFieldsNameTheFamiliesThatTakeThem)
{
  EXPECT_EQ(familiesTaking(kKnotsField), "'bspline'");
  EXPECT_EQ(familiesTaking(kBlendRadiusField), "'piecewise_geodesic'");
  EXPECT_EQ(familiesTaking(kVelocitiesField), "'hermite'");
  EXPECT_EQ(familiesTaking(kFitField), "'fit'");
  EXPECT_TRUE(familyRequiresTimes(CurveType::kFit));
  EXPECT_FALSE(familyRequiresTimes(CurveType::kBspline));
  EXPECT_NE(familyFields(CurveType::kBspline) & kDegreeField, 0u);
  EXPECT_EQ(familyFields(CurveType::kBezier), static_cast<unsigned>(kNoFields));

  TrajectoryRequest r;
  r.waypoints = { Pose<double>::Identity(), Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(1, 0, 0)) };
  r.curve = "hermite";
  r.knots = { 0, 0, 1, 1 };
  EXPECT_EQ(validationError(r), "knots: only used by curve 'bspline' (curve is 'hermite')");
  r.knots.clear();
  r.blend_radius = 0.1;
  EXPECT_EQ(validationError(r), "blend_radius: only used by curve 'piecewise_geodesic' (curve is 'hermite')");
}

// Only interpolating with end_condition start continues the start state on its own curve.
TEST(CurveFamilies, OnlyTheStartSplineContinuesTheStartState)
{
  for (const std::string& name : curveFamilyNames())
    EXPECT_FALSE(continuesStartState(validatedOf(name))) << name;
  EXPECT_TRUE(continuesStartState(validatedOf("interpolating", "start")));
  EXPECT_FALSE(continuesStartState(validatedOf("interpolating", "clamped")));
}

// The factory gives the blend radii of a corner-blended polyline, and none for other curves.
TEST(CurveFamilies, FactoryReportsBlendRadii)
{
  ValidatedRequest v = validatedOf("piecewise_geodesic");
  v.blend_radius = 0.2;
  const std::vector<double> times = waypointTimes(v);
  const FamilyCurve<DoubleGeodesicSe3> blended = makeFamilyCurve<DoubleGeodesicSe3>(v, times);
  ASSERT_EQ(blended.blend_radii.size(), 3u);
  EXPECT_EQ(blended.blend_radii[0], 0.0);
  EXPECT_NEAR(blended.blend_radii[1], 0.2, 1e-12);
  EXPECT_EQ(blended.blend_radii[2], 0.0);
  v.blend_radius = 0.0;
  EXPECT_TRUE(makeFamilyCurve<ScrewSe3>(v, times).blend_radii.empty());
  EXPECT_TRUE(makeFamilyCurve<ScrewSe3>(validatedOf("hermite"), times).blend_radii.empty());
}

// The core names the limits by PlannerLimits' fields; the node puts its parameters' "~" in front.
TEST(CurveFamilies, LimitMessagesNameTheLimitsField)
{
  TrajectoryRequest r;
  r.waypoints.resize(3);
  PlannerLimits limits;
  limits.max_waypoints = 2;
  std::string message;
  try
  {
    validateRequest(r, limits);
  }
  catch (const LimitExceededError& e)
  {
    message = e.what();
  }
  EXPECT_EQ(message, "waypoints: 3 given; the limit (max_waypoints) is 2");
  EXPECT_EQ(withLimitPrefix(message, "~"), "waypoints: 3 given; the limit (~max_waypoints) is 2");
  EXPECT_EQ(withLimitPrefix("(max_samples) and (max_samples), (max_work_seconds)", "~"),
            "(~max_samples) and (~max_samples), (~max_work_seconds)");
  EXPECT_EQ(withLimitPrefix("max_samples without parentheses", "~"), "max_samples without parentheses");
}
