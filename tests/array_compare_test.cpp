// The array comparisons of tests/support/array_compare.h pass what they
// should and fail, with the count and the first mismatch, what they should.
#include <limits>
#include <vector>

#include "layerlab/tests/support/array_compare.h"

namespace layerlab {
namespace {

using testing::ArraysNear;
using testing::ArraysNearUpToScale;
using testing::ArraysSameBits;

TEST(ArrayCompare, NearCountsAndShowsTheFirstMismatch) {
  const std::vector<double> e = {1, 2, 3, 4};
  EXPECT_TRUE(ArraysNear(std::vector<double>{1, 2.001, 3, 4}, e, 1e-3));
  const ::testing::AssertionResult r = ArraysNear(std::vector<double>{1, 2.1, 3, 4.5}, e, 1e-3, 1e-6);
  ASSERT_FALSE(r);
  EXPECT_STREQ(r.message(),
               "2 of 4 values differ by more than max(1e-06, 0.001 |expected|); the first at 1: 2.1 against 2");
  EXPECT_FALSE(ArraysNear(std::vector<double>{1, std::nan(""), 3, 4}, e, 1.0));
  EXPECT_STREQ(ArraysNear(std::vector<double>{1, 2}, e, 1.0).message(), "sizes differ: 2 against 4");
}

TEST(ArrayCompare, SameBitsTellsSignedZerosApart) {
  const std::vector<float> a = {0.0f, 1.5f}, b = {-0.0f, 1.5f};
  EXPECT_TRUE(ArraysSameBits(a, a));
  EXPECT_FALSE(ArraysSameBits(a, b));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(ArraysSameBits(std::vector<float>{nan}, std::vector<float>{nan}));
  EXPECT_STREQ(ArraysSameBits(a, std::vector<float>{0.0f, 1.25f}).message(),
               "1 of 2 values differ in their bits; the first at 1: 1.5 against 1.25");
}

TEST(ArrayCompare, UpToScaleFindsTheCommonFactor) {
  const std::vector<double> e = {1, -2, 4};
  EXPECT_TRUE(ArraysNearUpToScale(std::vector<double>{2.5, -5, 10}, e, 1e-12));
  EXPECT_TRUE(ArraysNearUpToScale(std::vector<double>{2.5, -5, 10.0001}, e, 1e-4));
  EXPECT_FALSE(ArraysNearUpToScale(std::vector<double>{2.5, -5, 11}, e, 1e-3));
  EXPECT_FALSE(ArraysNearUpToScale(std::vector<double>{-1, 2, -4}, e, 1e-3));  // a negative scale
  EXPECT_FALSE(ArraysNearUpToScale(std::vector<double>{0, 0, 0}, e, 1e-3));
  EXPECT_TRUE(ArraysNearUpToScale(std::vector<double>{0, 0}, std::vector<double>{0, 0}, 1e-3));
  EXPECT_FALSE(ArraysNearUpToScale(std::vector<double>{0, 1}, std::vector<double>{0, 0}, 1e-3));
}

}  // namespace
}  // namespace layerlab
