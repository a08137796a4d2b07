// name_table.h with the tables of planner/names.h and curves/end_condition.h: every name
// round-trips through parseName and toString, "" gives the default, and an unknown name is refused
// naming the field, quoting at most a prefix of it and listing the known names.
#include <gtest/gtest.h>

#include <string>

#include "se3_interpolation/name_table.h"
#include "se3_interpolation/planner/names.h"

using namespace se3_interpolation;

namespace
{
template <class E>
void expectRoundTrip(E default_value)
{
  for (const auto& n : NameTable<E>::kNames)
  {
    EXPECT_EQ(parseName(n.first, "field", default_value), n.second) << n.first;
    EXPECT_STREQ(toString(n.second), n.first);
  }
  EXPECT_EQ(parseName("", "field", default_value), default_value);
}

std::string errorOf(const std::string& name, const std::string& field)
{
  try
  {
    parseName(name, field, CurveType::kBezier);
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(NameTable, EveryTableRoundTrips)
{
  expectRoundTrip(CurveType::kBezier);
  expectRoundTrip(GeometryType::kScrew);
  expectRoundTrip(EndCondition::kClamped);
  expectRoundTrip(Parameterization::kUniform);
  expectRoundTrip(Timing::kTimeOptimal);
  EXPECT_STREQ(toString(CurveType::kPiecewiseGeodesic), "piecewise_geodesic");
  EXPECT_STREQ(toString(EndCondition::kStart), "start");
  EXPECT_EQ(knownNames<Timing>(), "stretch, time_optimal, constant_speed");
  EXPECT_EQ(knownNames<EndCondition>(), "natural, clamped, start");
}

TEST(NameTable, UnknownNamesAreRefusedByFieldWithTheKnownNames)
{
  EXPECT_EQ(errorOf("bspine", "~curve"), "~curve: unknown value 'bspine' (expected one of: piecewise_geodesic, bezier, "
                                         "bspline, interpolating, hermite, blended, fit)");
  // Names are case-sensitive and not trimmed.
  EXPECT_NE(errorOf("Bezier", "curve"), "");
  EXPECT_NE(errorOf(" bezier", "curve"), "");
  // A long name is quoted as a prefix only (kMaxQuotedLength characters), control bytes escaped.
  const std::string e = errorOf(std::string(10000, 'x') + "\x1b", "curve");
  EXPECT_LT(e.size(), 300u) << e;
  EXPECT_NE(e.find("'" + std::string(kMaxQuotedLength, 'x') + "'"), std::string::npos) << e;
  EXPECT_EQ(errorOf(std::string("be\x07zier"), "curve").find('\x07'), std::string::npos);
}
