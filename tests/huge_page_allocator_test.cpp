#include "layerlab/framework/huge_page_allocator.h"

#include <gtest/gtest.h>

#include <cstdint>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#include <vector>

namespace layerlab {
namespace {

TEST(HugePageAllocator, LargeBlocksAreAlignedToHugePagesAndSmallOnesWork) {
  for (size_t floats : {size_t(1), size_t(1000), size_t(3) << 19, (size_t(162) << 20) / 4}) {
    std::vector<float, HugePageAllocator<float>> v(floats, 1.5f);
    if (floats * sizeof(float) >= (size_t(2) << 20)) {
      EXPECT_EQ(reinterpret_cast<uintptr_t>(v.data()) % (uintptr_t(2) << 20), 0u) << floats;
    }
    v.back() = 2.5f;
    if (floats > 1) {
      EXPECT_EQ(v.front(), 1.5f);
    }
    EXPECT_EQ(v.back(), 2.5f);
    std::vector<float, HugePageAllocator<float>> copy = v;  // copies and frees through the same allocator
    EXPECT_EQ(copy, v);
  }
}

// What the memory estimates count: small blocks as they are, large ones in whole 2 MB pages.
TEST(HugePageAllocator, LargeBlocksTakeWholeHugePages) {
  const size_t page = size_t(2) << 20;
  EXPECT_EQ(LargeAllocationBytes(1), 1u);
  EXPECT_EQ(LargeAllocationBytes(page - 1), page - 1);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  EXPECT_EQ(LargeAllocationBytes(page), page);
  EXPECT_EQ(LargeAllocationBytes(page + 1), 2 * page);
  EXPECT_EQ(LargeAllocationBytes(7680000), 4 * page);  // one of quasi-newton's vectors at paper scale
#endif
}

TEST(HugePageAllocator, AnImpossibleSizeIsRefused) {
  HugePageAllocator<float> a;
  EXPECT_THROW(a.allocate(static_cast<size_t>(-1) / 2), std::bad_array_new_length);
  EXPECT_THROW(a.allocate(static_cast<size_t>(-1) / 4), std::bad_alloc);  // fits, but not once rounded to 2 MB
}

// A block freed while a LargeBlockReuse lives goes to the next allocation of its size, up to the bytes it may
// keep; a block of another size, or beyond them, is new; and outside one nothing is kept.
TEST(HugePageAllocator, FreedBlocksAreReusedWhileAReuseLives) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const size_t page = size_t(2) << 20;
  {
    const LargeBlockReuse reuse(5 * page);
    void* a = AllocateLarge(2 * page);
    FreeLarge(a, 2 * page);
    void* b = AllocateLarge(2 * page - 4096);  // the same whole pages
    EXPECT_EQ(b, a);
    EXPECT_EQ(LargeBlockReuse::Reused(), 1u);
    void* c = AllocateLarge(3 * page);
    FreeLarge(b, 2 * page);
    FreeLarge(c, 3 * page);  // 5 pages kept in all: still within the limit
    void* d = AllocateLarge(6 * page);
    FreeLarge(d, 6 * page);  // beyond the limit: freed, not kept
    void* again = AllocateLarge(6 * page);
    EXPECT_EQ(LargeBlockReuse::Reused(), 1u) << "a block beyond the limit was kept";
    FreeLarge(again, 6 * page);
    void* e = AllocateLarge(3 * page);
    EXPECT_EQ(e, c);
    EXPECT_EQ(LargeBlockReuse::Reused(), 2u);
    FreeLarge(e, 3 * page);
  }
  void* f = AllocateLarge(2 * page);
  FreeLarge(f, 2 * page);
  void* g = AllocateLarge(2 * page);
  FreeLarge(g, 2 * page);
  EXPECT_EQ(LargeBlockReuse::Reused(), 2u) << "a block was reused after the reuse ended";
#endif
}

}  // namespace
}  // namespace layerlab
