// Work split over the machine's cores for coarse tasks (views, files) that
// may throw: the first exception stops the others and is rethrown.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace layerlab {

// Runs body(i) for i in [0, n) on up to `max_workers` threads (0: all cores).
template <class Body>
void ParallelFor(size_t n, Body body, unsigned max_workers = 0) {
  unsigned workers = std::max(1u, std::thread::hardware_concurrency());
  if (max_workers) workers = std::min(workers, max_workers);
  workers = static_cast<unsigned>(std::min<size_t>(workers, n));
  if (workers <= 1) {
    for (size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  std::vector<std::thread> threads;
  for (unsigned w = 0; w < workers; ++w)
    threads.emplace_back([&] {
      for (size_t i; !failed && (i = next++) < n;) {
        try {
          body(i);
        } catch (...) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (!error) error = std::current_exception();
          failed = true;
        }
      }
    });
  for (auto& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace layerlab
