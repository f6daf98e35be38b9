// A minimal parallel loop over [0, count) for the baker's float64 stages:
// std::thread workers pull items from an atomic counter, so uneven items
// (long and short form-factor rows) balance themselves. Exceptions thrown by
// `body` are re-thrown on the calling thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace relight::baker {

// threads <= 0 means every core.
inline int ResolveThreads(int threads) {
  if (threads > 0) return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// body(item, worker) with worker in [0, workers).
template <typename Body>
void ParallelFor(size_t count, int threads, Body body) {
  const int workers = static_cast<int>(
      std::min<size_t>(static_cast<size_t>(ResolveThreads(threads)), std::max<size_t>(count, 1)));
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto run = [&](int worker) {
    try {
      for (size_t item = next++; item < count; item = next++) body(item, worker);
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = count;
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) pool.emplace_back(run, w);
  run(0);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace relight::baker
