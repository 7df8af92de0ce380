// The bytes the C++ heap takes for a block: what memory estimates count for
// buffers too small for HugePageAllocator (framework/huge_page_allocator.h).
#pragma once

#include <cstddef>

namespace layerlab {

// glibc's malloc on 64-bit Linux: an 8-byte header, 16-byte granules, 32
// bytes at least; blocks from its mmap threshold (128 KiB) on are mapped
// whole pages with a 16-byte header. An empty vector holds no block: 0.
inline size_t HeapBlockBytes(size_t bytes) {
  if (bytes == 0) return 0;
  constexpr size_t kMmapThreshold = size_t(128) << 10, kPage = 4096;
  if (bytes >= kMmapThreshold) return (bytes + 16 + kPage - 1) / kPage * kPage;
  const size_t chunk = (bytes + 8 + 15) / 16 * 16;
  return chunk < 32 ? 32 : chunk;
}

}  // namespace layerlab
