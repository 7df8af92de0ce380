#include "layerlab/framework/checked_count.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace layerlab {
namespace {

TEST(CheckedCount, ProductsThatFitAreExact) {
  EXPECT_EQ(CheckedProduct({13, 13, 400, 200}, "rays"), size_t{13} * 13 * 400 * 200);
  EXPECT_EQ(CheckedProduct({}, "empty"), 1u);
  EXPECT_EQ(CheckedProduct({size_t{1} << 32, (size_t{1} << 32) - 1}, "x"), (size_t{1} << 32) * ((size_t{1} << 32) - 1));
  EXPECT_EQ(CheckedProduct({0, SIZE_MAX}, "zero"), 0u);
}

TEST(CheckedCount, SixtyFourFactorsOfTwoAreRefusedNotWrappedToZero) {
  size_t p = 1;
  EXPECT_FALSE(MultiplyFits(size_t{1} << 63, 2, &p));
  try {
    CheckedProduct({size_t{1} << 32, size_t{1} << 32}, "the sweep's grid");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "the sweep's grid: 4294967296 x 4294967296 does not fit in 64 bits");
  }
  EXPECT_THROW(CheckedProduct({SIZE_MAX, 2}, Location{"s.json", "/parameters"}, "grid"), Error);
}

TEST(CheckedCount, SumsThatOverflowAreRefused) {
  EXPECT_EQ(CheckedSum(SIZE_MAX - 1, 1, "bytes"), SIZE_MAX);
  EXPECT_THROW(CheckedSum(SIZE_MAX, 1, "bytes"), Error);
}

}  // namespace
}  // namespace layerlab
