// Node parameter validation (ros/node_parameters.h), without a roscore: the pure checks that
// start-up and dynamic_reconfigure share, each against the message and range written here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "se3_interpolation/ros/node_parameters.h"

using namespace se3_interpolation;

TEST(NodeParameters, DefaultsAreTheCoreRequestDefaults)
{
  const NodeParameters p;
  EXPECT_EQ(p.curve, "interpolating");
  EXPECT_EQ(p.geometry, "double_geodesic");
  EXPECT_EQ(p.parameterization, "chord");
  EXPECT_EQ(p.timing, "stretch");
  EXPECT_EQ(p.sample_count, 100);
  EXPECT_FALSE(p.loop);
  EXPECT_TRUE(p.replan_from_current);
  EXPECT_EQ(p.replan_lead, 0.1);
}

TEST(NodeParameters, StringParametersUseTheRequestNameTables)
{
  for (const char* curve : { "piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended" })
    EXPECT_EQ(stringParameterError("curve", curve), "") << curve;
  EXPECT_EQ(stringParameterError("timing", "time_optimal"), "");
  EXPECT_EQ(stringParameterError("curve", "bspine"),
            "~curve: unknown value 'bspine' (expected one of: piecewise_geodesic, bezier, bspline, interpolating, "
            "hermite, blended)");
  EXPECT_EQ(stringParameterError("timing", "fast").rfind("~timing: unknown value 'fast'", 0), 0u);
  EXPECT_EQ(stringParameterError("geometry", "").rfind("~geometry: refused (empty", 0), 0u);
  // Frame ids: tf2's rules, a bounded quote.
  EXPECT_EQ(stringParameterError("child_frame_id", "tool0"), "");
  EXPECT_EQ(stringParameterError("frame_id", "/map").rfind("~frame_id: '/map' starts with '/'", 0), 0u);
  const std::string long_id = stringParameterError("frame_id", std::string(1000, 'a'));
  EXPECT_LT(long_id.size(), 200u) << long_id;
}

TEST(NodeParameters, NumericRangesAreInclusiveWhereDocumented)
{
  EXPECT_EQ(numberParameterError("replan_lead", 0.0), "");
  EXPECT_EQ(numberParameterError("replan_lead", 10.0), "");
  EXPECT_EQ(numberParameterError("replan_lead", 10.5), "~replan_lead: refused 10.5 (must be in [0, 10] s)");
  EXPECT_EQ(numberParameterError("tf_rate", 1000.0), "");
  EXPECT_NE(numberParameterError("tf_rate", 0.0), "");  // (0, 1000]: 0 excluded
  EXPECT_NE(numberParameterError("tf_rate", NAN), "");
  EXPECT_NE(numberParameterError("service_threads", 0.0), "");
  EXPECT_EQ(numberParameterError("service_threads", 64.0), "");
  // A name without a range has nothing to refuse.
  EXPECT_EQ(numberParameterError("no_such_parameter", -1.0), "");
}
