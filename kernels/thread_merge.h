// Per-thread float sums merged into double in thread order, each thread of a
// team merging its own share of the values: the same bits for a given thread
// count (an OpenMP critical section or reduction merges in arrival order).
#pragma once

#include <cstddef>
#include <vector>

namespace layerlab {

// out[p * 3 + c] = the sum over `parts`, in their order, of part[p * lanes + c]
// (c < 3; lanes 3 for packed RGB, 4 for padded), for share `me` of `threads`
// of the `pixels`. Writes, so `out` need not be cleared first.
inline void MergeInThreadOrder(const std::vector<const float*>& parts, size_t pixels, int lanes, int me, int threads,
                               double* out) {
  const size_t begin = pixels * me / threads, end = pixels * (me + 1) / threads;
  for (size_t p = begin; p < end; ++p)
    for (int c = 0; c < 3; ++c) out[p * 3 + c] = 0.0;
  for (const float* part : parts)
    for (size_t p = begin; p < end; ++p)
      for (int c = 0; c < 3; ++c) out[p * 3 + c] += part[p * lanes + c];
}

}  // namespace layerlab
