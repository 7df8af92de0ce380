#include "layerlab/framework/content_digest.h"

#include <gtest/gtest.h>

namespace layerlab {
namespace {

// The published FNV-1a 64-bit test vectors (Fowler, Noll, Vo: "FNV test suite").
TEST(ContentDigest, MatchesThePublishedFnv1aVectors) {
  EXPECT_EQ(ContentDigest().hex(), "cbf29ce484222325");
  EXPECT_EQ(ContentDigest().add("a").hex(), "af63dc4c8601ec8c");
  EXPECT_EQ(ContentDigest().add("foobar").hex(), "85944171f73967e8");
  EXPECT_EQ(ContentDigest().add("foo").add("bar").value(), ContentDigest().add("foobar").value());  // streamed
}

TEST(ContentDigest, OneChangedFloatChangesTheDigest) {
  std::vector<float> a(1000, 0.5f), b = a;
  b[617] = 0.50001f;
  EXPECT_NE(ContentDigest().add(a.data(), a.size() * 4).value(), ContentDigest().add(b.data(), b.size() * 4).value());
}

}  // namespace
}  // namespace layerlab
