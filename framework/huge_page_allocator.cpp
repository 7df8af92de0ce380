#include "layerlab/framework/huge_page_allocator.h"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace layerlab {
namespace {
constexpr size_t kHugePage = size_t(2) << 20;
}

size_t LargeAllocationBytes(size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (bytes >= kHugePage && bytes <= static_cast<size_t>(-1) - (kHugePage - 1))
    return (bytes + kHugePage - 1) / kHugePage * kHugePage;
#endif
  return bytes;
}

void* AllocateLarge(size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (bytes >= kHugePage) {
    if (bytes > static_cast<size_t>(-1) - (kHugePage - 1)) throw std::bad_alloc();
    const size_t rounded = LargeAllocationBytes(bytes);
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (p == nullptr) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: refused, the pages are just small
    return p;
  }
#endif
  return ::operator new(bytes);
}

void FreeLarge(void* p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (bytes >= kHugePage) {
    std::free(p);
    return;
  }
#endif
  ::operator delete(p);
}

}  // namespace layerlab
