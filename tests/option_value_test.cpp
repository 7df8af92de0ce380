// Values on the command line (app/number_list.h): the units of the scene
// files, bare numbers in the option's unit, and errors naming the option.
#include <gtest/gtest.h>

#include "layerlab/app/number_list.h"
#include "layerlab/framework/error.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::app {
namespace {

using testing::ErrorOf;

TEST(OptionValue, BareNumbersKeepTheOptionsUnit) {
  EXPECT_DOUBLE_EQ(ParseOptionValue("1.0", "--accommodation", kDiopters), 1.0);
  EXPECT_DOUBLE_EQ(ParseOptionValue("5", "--time-budget", kSeconds), 5.0);
  EXPECT_DOUBLE_EQ(ParseOptionValue(" 0.05 ", "--resolution", kDegrees), 0.05);
}

TEST(OptionValue, QuantitiesAreConvertedToTheOptionsUnit) {
  EXPECT_DOUBLE_EQ(ParseOptionValue("1.0 D", "--accommodation", kDiopters), 1.0);
  EXPECT_DOUBLE_EQ(ParseOptionValue("5 s", "--time-budget", kSeconds), 5.0);
  EXPECT_DOUBLE_EQ(ParseOptionValue("2 min", "--time-budget", kSeconds), 120.0);
  EXPECT_DOUBLE_EQ(ParseOptionValue("250 ms", "--time-budget", kSeconds), 0.25);
  EXPECT_NEAR(ParseOptionValue("3 arcmin", "--resolution", kDegrees), 0.05, 1e-12);  // 3/60 deg
  EXPECT_DOUBLE_EQ(ParseOptionValue("2 cpd", "--frequencies", kCyclesPerDegree), 2.0);
  // A depth given as a distance: 0.5 m in front of the eye is 2 D.
  EXPECT_DOUBLE_EQ(ParseOptionValue("0.5 m", "--depths", kDiopters, true), 2.0);
}

TEST(OptionValue, ListsMixBareNumbersAndQuantities) {
  EXPECT_EQ(ParseNumberList("0.7 D,1.3 D", "--depths", kDiopters, true), (std::vector<double>{0.7, 1.3}));
  EXPECT_EQ(ParseNumberList("0.7, 1.3 D,2 m", "--depths", kDiopters, true), (std::vector<double>{0.7, 1.3, 0.5}));
  const std::vector<double> stack = ParseRange("0 D:2.6 D:1.3 D", "--focal-stack", kDiopters);
  ASSERT_EQ(stack.size(), 3u);
  EXPECT_DOUBLE_EQ(stack[2], 2.6);
  EXPECT_EQ(ParseRange("0:1:0.5", "--focal-stack", kDiopters), (std::vector<double>{0, 0.5, 1}));
  // 27 states: the ends included within rounding (0.1 is not exact in binary).
  EXPECT_EQ(ParseRange("0:2.6:0.1", "--focal-stack", kDiopters).size(), 27u);
}

// A list whose items may be ranges, in order (retina --accommodation).
TEST(OptionValue, StatesMixValuesAndRanges) {
  EXPECT_EQ(ParseStates("0.4,1:2:0.5", "--accommodation", kDiopters), (std::vector<double>{0.4, 1, 1.5, 2}));
  // A single state may be a distance (0.5 m is 2 D); a range's ends and step are optical powers.
  EXPECT_EQ(ParseStates("1 D,0.5 m", "--accommodation", kDiopters, true), (std::vector<double>{1, 2}));
  EXPECT_NE(ErrorOf([] {
              ParseStates("0.5 m:1 m:0.5", "--accommodation", kDiopters, true);
            }).find("--accommodation: \"0.5 m\" is not a number or an optical power"),
            std::string::npos);
}

TEST(OptionValue, ErrorsNameTheOptionAndTheValue) {
  EXPECT_EQ(ErrorOf([] {
              ParseNumberList("1.3,near", "--accommodation", kDiopters);
            }).rfind("--accommodation: \"near\" is not a number or an optical power", 0),
            0u);
  const std::string wrong_unit = ErrorOf([] { ParseOptionValue("5 mm", "--time-budget", kSeconds); });
  EXPECT_NE(wrong_unit.find("--time-budget: \"5 mm\""), std::string::npos) << wrong_unit;
  EXPECT_NE(wrong_unit.find("a duration"), std::string::npos) << wrong_unit;
  EXPECT_NE(ErrorOf([] { ParseOptionValue("-1 s", "--time-budget", kSeconds); }).find("--time-budget: \"-1 s\""),
            std::string::npos);
  // The comma form of a range (before FROM:TO:STEP) is refused with the advice, never read as a list.
  const std::string comma = ErrorOf([] { ParseRange("0,2.6,0.1", "--focal-stack", kDiopters); });
  EXPECT_NE(comma.find("--focal-stack: \"0,2.6,0.1\": give a range FROM:TO:STEP"), std::string::npos) << comma;
  EXPECT_NE(ErrorOf([] { ParseRange("2:1:0.5", "--focal-stack", kDiopters); }).find("TO must exceed FROM"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseNumberList("", "--depths", kDiopters); }).find("--depths: give at least one value"),
            std::string::npos);
}

}  // namespace
}  // namespace layerlab::app
