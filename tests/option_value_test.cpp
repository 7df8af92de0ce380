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
  const std::vector<double> stack = ParseRange("0 D,2.6 D,1.3 D", "--focal-stack", kDiopters);
  ASSERT_EQ(stack.size(), 3u);
  EXPECT_DOUBLE_EQ(stack[2], 2.6);
  EXPECT_EQ(ParseRange("0,1,0.5", "--focal-stack", kDiopters), (std::vector<double>{0, 0.5, 1}));
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
  EXPECT_NE(
      ErrorOf([] { ParseRange("0 D,2.6 D", "--focal-stack", kDiopters); }).find("--focal-stack: give first,last,step"),
      std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseNumberList("", "--depths", kDiopters); }).find("--depths: give at least one value"),
            std::string::npos);
}

}  // namespace
}  // namespace layerlab::app
