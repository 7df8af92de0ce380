// Work whose partial sums are cut into a fixed number of parts, whatever the
// number of threads that computes them: each part sums its items in order
// into buffers of its own, and the parts are merged in part order, so the
// result has the same bits on any team of at most `parts` threads. A solve
// fixes the parts at its thread count on an idle machine (ScopedParts) and
// may then run each iteration on fewer threads (framework/thread_budget.h)
// without changing a bit. With as many threads as parts, part p is thread p's
// share of a static schedule: what the kernels summed before parts existed.
#pragma once

#include <omp.h>

#include <cstddef>

namespace layerlab {

// The part count of the calling thread's solve (ScopedParts), or, outside
// one, omp_get_max_threads(). Read it before a parallel region: it is the
// starting thread's.
int FixedParts();

// Sets FixedParts() of this thread for its lifetime (and restores the one before).
class ScopedParts {
 public:
  explicit ScopedParts(int parts);
  ~ScopedParts();
  ScopedParts(const ScopedParts&) = delete;
  ScopedParts& operator=(const ScopedParts&) = delete;

 private:
  int saved_;
};

// Items [begin, end) of part `part` of `parts`, as OpenMP's static schedule
// (no chunk size) hands n items to a team of `parts` threads: the first
// n % parts parts one item more.
struct ItemRange {
  size_t begin = 0, end = 0;
};
inline ItemRange StaticShare(size_t n, int part, int parts) {
  const size_t q = n / parts, r = n % parts, p = static_cast<size_t>(part);
  const size_t begin = p * q + (p < r ? p : r);
  return {begin, begin + q + (p < r ? 1 : 0)};
}

// Inside a parallel region: body(p) for each part this thread owns (p = me,
// me + T, ... for a team of T threads), so that each part's buffers are
// used by one thread. Parts of a team larger than `parts` are left to the
// first `parts` threads.
template <class Body>
void ForEachPartOfThread(int parts, Body body) {
  const int me = omp_get_thread_num(), threads = omp_get_num_threads();
  for (int p = me; p < parts; p += threads) body(p);
}

}  // namespace layerlab
