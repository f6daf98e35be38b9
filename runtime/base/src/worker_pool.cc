// The runtime's worker threads (see relight/base/worker_pool.h).
#include "relight/base/worker_pool.h"

#include <chrono>
#include <cstdlib>

namespace relight {

int DefaultEngineThreads() {
  if (const char* v = std::getenv("RELIGHT_THREADS"); v != nullptr && *v != '\0') {
    char* end = nullptr;
    const long n = std::strtol(v, &end, 10);
    if (*end == '\0' && n >= 1) return n > kMaxEngineThreads ? kMaxEngineThreads : static_cast<int>(n);
  }
  const unsigned hw = std::thread::hardware_concurrency();
  return hw >= 2 ? 2 : 1;
}

namespace {

// Spins until done() or kWorkerSpinMicros pass; true when done() came.
// The clock is read every 64 pauses, so the spin costs next to nothing.
template <typename Done>
bool SpinUntil(Done done) {
  const auto limit = std::chrono::steady_clock::now() + std::chrono::microseconds(kWorkerSpinMicros);
  for (;;) {
    for (int i = 0; i < 64; ++i) {
      if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#elif defined(__aarch64__)
      asm volatile("yield");
#endif
    }
    if (std::chrono::steady_clock::now() >= limit) return done();
  }
}

}  // namespace

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::Start(int threads) {
  threads_ = threads < 1 ? 1 : (threads > kMaxEngineThreads ? kMaxEngineThreads : threads);
  workers_.reserve(static_cast<size_t>(threads_ - 1));
  for (int t = 1; t < threads_; ++t) workers_.emplace_back([this, t] { WorkerMain(t); });
}

void WorkerPool::Run(Task task, void* context) {
  if (threads_ == 1) {
    task(context, 0);
    return;
  }
  bool wake;
  {
    std::lock_guard<std::mutex> lock(mu_);
    task_ = task;
    context_ = context;
    running_.store(threads_ - 1);
    generation_.fetch_add(1);
    wake = sleepers_ > 0;  // the others are spinning and will see it
  }
  if (wake) start_cv_.notify_all();
  task(context, 0);
  if (SpinUntil([this] { return running_.load(std::memory_order_acquire) == 0; })) return;
  std::unique_lock<std::mutex> lock(mu_);
  caller_asleep_ = true;
  done_cv_.wait(lock, [this] { return running_.load() == 0; });
  caller_asleep_ = false;
}

void WorkerPool::WorkerMain(int index) {
  uint64_t seen = 0;
  for (;;) {
    const auto ready = [&] { return stop_.load(std::memory_order_acquire) || generation_.load() != seen; };
    if (!SpinUntil(ready)) {
      std::unique_lock<std::mutex> lock(mu_);
      ++sleepers_;
      start_cv_.wait(lock, ready);
      --sleepers_;
    }
    Task task;
    void* context;
    {
      // task_ and context_ were written under mu_ before the generation.
      std::lock_guard<std::mutex> lock(mu_);
      if (stop_) return;
      seen = generation_.load();
      task = task_;
      context = context_;
    }
    task(context, index);
    if (running_.fetch_sub(1) == 1) {  // the last: wake Run if it sleeps
      std::lock_guard<std::mutex> lock(mu_);
      if (caller_asleep_) done_cv_.notify_one();
    }
  }
}

}  // namespace relight
