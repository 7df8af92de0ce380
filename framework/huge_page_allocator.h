// An allocator for light-field-sized arrays: blocks of 2 MB and more are
// 2 MB-aligned and marked for transparent huge pages (madvise), so that the
// first touch of a 162 MB light field takes a hundred page faults instead of
// forty thousand (each costly on a virtual machine) and the streaming passes
// walk fewer TLB entries. Smaller blocks, and systems without madvise, get
// plain operator new.
#pragma once

#include <cstddef>
#include <new>

namespace layerlab {

void* AllocateLarge(size_t bytes);
// The bytes AllocateLarge takes for `bytes`: blocks of 2 MB and more are
// rounded up to whole 2 MB pages (what the memory estimates count).
size_t LargeAllocationBytes(size_t bytes);
void FreeLarge(void* p, size_t bytes);

// While one is alive, blocks of 2 MB and more that are freed are kept, up to `keep_bytes` in all, and handed
// to the next allocation of the same size: a loop that makes and frees the same buffers (a frame sequence's
// renders and solves) pays their page faults once. When it ends the kept blocks are freed. One nested in
// another changes nothing: the outermost sets the limit and frees the blocks.
class LargeBlockReuse {
 public:
  explicit LargeBlockReuse(size_t keep_bytes);
  ~LargeBlockReuse();
  LargeBlockReuse(const LargeBlockReuse&) = delete;
  LargeBlockReuse& operator=(const LargeBlockReuse&) = delete;
  // Allocations served from kept blocks so far (for tests and reports).
  static size_t Reused();
};

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(size_t n) {
    if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(AllocateLarge(n * sizeof(T)));
  }
  void deallocate(T* p, size_t n) { FreeLarge(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const {
    return false;
  }
};

}  // namespace layerlab
