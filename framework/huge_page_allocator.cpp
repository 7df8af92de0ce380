#include "layerlab/framework/huge_page_allocator.h"

#include <cstdlib>
#include <map>
#include <mutex>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace layerlab {
namespace {
constexpr size_t kHugePage = size_t(2) << 20;

// The blocks a LargeBlockReuse keeps, by size.
struct KeptBlocks {
  std::mutex mutex;
  int depth = 0;  // LargeBlockReuse scopes alive: a nested one changes nothing
  bool active = false;
  size_t limit = 0, bytes = 0, reused = 0;
  std::multimap<size_t, void*> blocks;
};
KeptBlocks& Kept() {
  static KeptBlocks kept;
  return kept;
}

void* TakeKept(size_t rounded) {
  KeptBlocks& k = Kept();
  std::lock_guard<std::mutex> lock(k.mutex);
  if (!k.active) return nullptr;
  auto it = k.blocks.find(rounded);
  if (it == k.blocks.end()) return nullptr;
  void* p = it->second;
  k.blocks.erase(it);
  k.bytes -= rounded;
  ++k.reused;
  return p;
}

bool Keep(void* p, size_t rounded) {
  KeptBlocks& k = Kept();
  std::lock_guard<std::mutex> lock(k.mutex);
  if (!k.active || k.bytes + rounded > k.limit) return false;
  try {
    k.blocks.emplace(rounded, p);
  } catch (const std::bad_alloc&) {
    return false;  // freed instead
  }
  k.bytes += rounded;
  return true;
}
}  // namespace

LargeBlockReuse::LargeBlockReuse(size_t keep_bytes) {
  KeptBlocks& k = Kept();
  std::lock_guard<std::mutex> lock(k.mutex);
  if (k.depth++ > 0) return;
  k.active = true;
  k.limit = keep_bytes;
  k.reused = 0;
}

LargeBlockReuse::~LargeBlockReuse() {
  KeptBlocks& k = Kept();
  std::lock_guard<std::mutex> lock(k.mutex);
  if (--k.depth > 0) return;
  for (auto& [size, p] : k.blocks) std::free(p);
  k.blocks.clear();
  k.bytes = 0;
  k.active = false;
}

size_t LargeBlockReuse::Reused() {
  KeptBlocks& k = Kept();
  std::lock_guard<std::mutex> lock(k.mutex);
  return k.reused;
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
    if (void* kept = TakeKept(rounded)) return kept;
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
    if (!Keep(p, LargeAllocationBytes(bytes))) std::free(p);
    return;
  }
#endif
  ::operator delete(p);
}

}  // namespace layerlab
