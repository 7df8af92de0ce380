#include "layerlab/framework/params.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

std::string IntegerError(const nlohmann::json& value) {
  try {
    Params p(nlohmann::json{{"rows", value}}, {"s.json", "/views"});
    p.integer("rows", 1, 256);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Params, IntegersAreNeverTruncatedOrWrapped) {
  EXPECT_EQ(IntegerError(13), "");
  EXPECT_EQ(IntegerError(13.0), "");
  EXPECT_EQ(IntegerError(13.7), "s.json: /views/rows: expected an integer in [1, 256], got 13.7");
  EXPECT_EQ(IntegerError(-1), "s.json: /views/rows: expected an integer in [1, 256], got -1");
  EXPECT_EQ(IntegerError(1e12), "s.json: /views/rows: expected an integer in [1, 256], got 1000000000000.0");
  EXPECT_EQ(IntegerError(18446744073709551615ull),
            "s.json: /views/rows: expected an integer in [1, 256], got 18446744073709551615");
  EXPECT_EQ(IntegerError("13"), "s.json: /views/rows: expected an integer in [1, 256], got a string \"13\"");
}

TEST(Params, UnreadKeysAreErrorsWithASuggestion) {
  Params p(nlohmann::json{{"focal_lenght", "75 mm"}}, {"s.json", "/elements/1"});
  EXPECT_FALSE(p.optional_quantity("focal_length", Dimension::kLength));
  try {
    p.check_all_read();
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "s.json: /elements/1/focal_lenght: unknown key \"focal_lenght\"; did you mean \"focal_length\"?");
  }
}

TEST(Params, ChoicesSuggestTheClosest) {
  Params p(nlohmann::json{{"pupil_shape", "sqare"}}, {"s.json", "/elements/0"});
  try {
    p.choice("pupil_shape", {"square", "round"}, "square");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "s.json: /elements/0/pupil_shape: \"sqare\" is not one of square or round; did you mean \"square\"?");
  }
}

TEST(Params, FractionsAcceptRgbAndPercent) {
  Params p(nlohmann::json{{"a", {0.1, "20 %", 0.3}}, {"b", "50 %"}, {"c", 1.5}}, {"s.json", ""});
  EXPECT_DOUBLE_EQ(p.fraction_rgb("a")[1], 0.2);
  EXPECT_DOUBLE_EQ(p.fraction_rgb("b")[2], 0.5);
  EXPECT_THROW(p.fraction_rgb("c"), Error);
}

TEST(Params, EditDistance) {
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(EditDistance("", "abc"), 3u);
  EXPECT_EQ(ClosestWord("thin_lense", {"eye", "thin_lens", "lc_panel"}), "thin_lens");
  EXPECT_FALSE(ClosestWord("zzzzzz", {"eye", "thin_lens"}));
}

}  // namespace
}  // namespace layerlab
