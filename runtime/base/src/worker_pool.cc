// The runtime's worker threads (see relight/base/worker_pool.h).
#include "relight/base/worker_pool.h"

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
  {
    std::lock_guard<std::mutex> lock(mu_);
    task_ = task;
    context_ = context;
    running_ = threads_ - 1;
    ++generation_;
  }
  start_cv_.notify_all();
  task(context, 0);
  std::unique_lock<std::mutex> lock(mu_);
  done_cv_.wait(lock, [this] { return running_ == 0; });
}

void WorkerPool::WorkerMain(int index) {
  uint64_t seen = 0;
  for (;;) {
    Task task;
    void* context;
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      task = task_;
      context = context_;
    }
    task(context, index);
    bool last;
    {
      std::lock_guard<std::mutex> lock(mu_);
      last = --running_ == 0;
    }
    if (last) done_cv_.notify_one();
  }
}

}  // namespace relight
