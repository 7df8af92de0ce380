#include <numbers>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;

std::string UnitError(const std::string& text, Dimension d) {
  try {
    ParseQuantity(text, d);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Units, ConvertsToSi) {
  EXPECT_TRUE(Close(ParseQuantity("75 mm", Dimension::kLength), 0.075, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("117 um", Dimension::kLength), 117e-6, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("117 \xC2\xB5m", Dimension::kLength), 117e-6, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("1 cm", Dimension::kLength), 0.01, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("550nm", Dimension::kLength), 550e-9, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("0.4 D", Dimension::kOpticalPower), 0.4, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("36 deg", Dimension::kAngle), 36 * std::numbers::pi / 180, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("60 arcmin", Dimension::kAngle), std::numbers::pi / 180, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("250 cd/m2", Dimension::kLuminance), 250, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("30 %", Dimension::kFraction), 0.3, 1e-15));
  EXPECT_TRUE(Close(ParseQuantity("0.3", Dimension::kFraction), 0.3, 1e-15));
}

TEST(Units, DepthsAreDiopters) {
  EXPECT_DOUBLE_EQ(ParseDepth("0.4 D").diopters, 0.4);
  EXPECT_DOUBLE_EQ(ParseDepth("2.5 m").diopters, 0.4);
  EXPECT_DOUBLE_EQ(ParseDepth("250 cm").diopters, 0.4);
  EXPECT_DOUBLE_EQ(ParseDepth("0 D").diopters, 0.0);  // infinity, finite in diopters
}

TEST(Units, RefusesBadUnitsWithTheAcceptedOnes) {
  EXPECT_EQ(UnitError("75 mg", Dimension::kLength),
            "unknown unit 'mg' in \"75 mg\"; expected a length in m, cm, mm, um, nm");
  EXPECT_EQ(UnitError("75 deg", Dimension::kLength), "'deg' is an angle unit; expected a length in m, cm, mm, um, nm");
  EXPECT_EQ(UnitError("75", Dimension::kLength), "\"75\" has no unit; expected a length in m, cm, mm, um, nm");
  EXPECT_EQ(UnitError("mm", Dimension::kLength), "\"mm\" does not start with a number");
  EXPECT_EQ(UnitError("1e400 mm", Dimension::kLength), "the number in \"1e400 mm\" is out of range");
  EXPECT_EQ(UnitError("nan mm", Dimension::kLength), "\"nan mm\" is not a finite number");
  EXPECT_EQ(UnitError("inf D", Dimension::kOpticalPower), "\"inf D\" is not a finite number");
}

TEST(Units, RefusesImpossibleDepths) {
  EXPECT_THROW(ParseDepth("-1 D"), Error);
  EXPECT_THROW(ParseDepth("0 m"), Error);
  EXPECT_THROW(ParseDepth("3 deg"), Error);
}

// Found by fuzz/units_fuzz (corpus: fuzz/corpus/units/depth_subnormal_meters): a
// subnormal distance has an infinite power and used to come back as inf diopters.
TEST(Units, RefusesDepthsWithoutAFinitePower) {
  try {
    ParseDepth("1e-320 m");
    ADD_FAILURE() << "1e-320 m was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "a depth of 1e-320 m is too close to the eye (its optical power is not finite)");
  }
  EXPECT_THROW(ParseDepth("1e-300 nm"), Error);
  EXPECT_DOUBLE_EQ(ParseDepth("1e-300 m").diopters, 1e300);
}

}  // namespace
}  // namespace layerlab
