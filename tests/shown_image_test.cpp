// framework/shown_image.h: a picture wider than its place on the page is
// reduced by a whole factor, each pixel the mean of its block, against block
// means computed here by hand.
#include <gtest/gtest.h>

#include "layerlab/framework/error.h"
#include "layerlab/framework/shown_image.h"

namespace layerlab {
namespace {

TEST(ShownImage, TheSmallestWholeFactorThatFits) {
  EXPECT_EQ(ShrinkFactor(400, 480), 1);
  EXPECT_EQ(ShrinkFactor(480, 480), 1);
  EXPECT_EQ(ShrinkFactor(481, 480), 2);
  EXPECT_EQ(ShrinkFactor(3550, 720), 5);
  EXPECT_EQ(ShrinkFactor(3601, 720), 6);
}

TEST(ShownImage, AnImageThatFitsIsKeptAsItIs) {
  const std::vector<float> rgb = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
  const ShownImage<float> shown = ShrinkToWidth(2, 1, 3, rgb, 2);
  EXPECT_EQ(shown.factor, 1);
  EXPECT_EQ(shown.width, 2);
  EXPECT_EQ(shown.height, 1);
  EXPECT_EQ(shown.pixels, rgb);
}

// A 5 x 3 gray image, value 10 * row + col, into width 2: factor 3, 2 x 1 pixels. The left block is
// rows 0-2, cols 0-2: mean 10 + 1 = 11; the right block is the partial one, cols 3-4: mean 10 + 3.5.
TEST(ShownImage, EachPixelIsTheMeanOfItsBlockAndTheEdgeBlockOfWhatItCovers) {
  std::vector<float> gray(15);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 5; ++c) gray[r * 5 + c] = static_cast<float>(10 * r + c);
  const ShownImage<float> shown = ShrinkToWidth(5, 3, 1, gray, 2);
  EXPECT_EQ(shown.factor, 3);
  ASSERT_EQ(shown.width, 2);
  ASSERT_EQ(shown.height, 1);
  EXPECT_FLOAT_EQ(shown.pixels[0], 11.0f);
  EXPECT_FLOAT_EQ(shown.pixels[1], 13.5f);
  // Two channels kept apart, and codes rounded to the nearest: (1 + 2) / 2 = 1.5 -> 2, (200 + 255) / 2 -> 228.
  const std::vector<uint8_t> codes = {1, 200, 2, 255};
  const ShownImage<uint8_t> coded = ShrinkToWidth(2, 1, 2, codes, 1);
  ASSERT_EQ(coded.pixels.size(), 2u);
  EXPECT_EQ(coded.pixels[0], 2);
  EXPECT_EQ(coded.pixels[1], 228);
}

TEST(ShownImage, AWrongPixelCountIsRefused) { EXPECT_THROW(ShrinkToWidth(4, 4, 3, std::vector<float>(47), 2), Error); }

}  // namespace
}  // namespace layerlab
