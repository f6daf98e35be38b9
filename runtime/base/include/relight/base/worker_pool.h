// A fixed pool of worker threads for Engine::Update (issue 13 "both
// cores"): started once at Engine::Open, joined in ~Engine; the renderer's
// still-camera resolve has one of its own, started with the frame. Run() hands the
// same task to every thread (the caller is thread 0) and returns when all
// have finished it; the task splits its work by the thread index, so the
// result never depends on which thread ran what. Run allocates nothing (a
// mutex, two condition variables and atomic counters). Not reentrant: one
// thread (the engine's owner) calls Run.
//
// Waiting spins first, then sleeps: an update or a solve calls Run many
// times a few microseconds apart, and a sleeping thread takes 40-60 us to
// wake through the condition variable (measured on the 2-core box), about
// what a whole small step costs. So a worker watches for the next task for
// up to kWorkerSpinMicros before it sleeps, and Run watches for the workers'
// finish as long before it sleeps; a pool left idle sleeps as before.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace relight {

// Threads Engine uses when asked for 0: RELIGHT_THREADS if set (1 ..
// kMaxEngineThreads), else the hardware's, capped at 2 (the target box's
// cores; the renderer and the inputs need the rest of a bigger one).
inline constexpr int kMaxEngineThreads = 16;
// How long a waiting thread spins before it sleeps.
inline constexpr int kWorkerSpinMicros = 50;
int DefaultEngineThreads();

class WorkerPool {
 public:
  using Task = void (*)(void* context, int thread);

  WorkerPool() = default;
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // Starts threads - 1 workers (threads clamped to 1 .. kMaxEngineThreads).
  // Open time only: allocates the threads.
  void Start(int threads);
  int threads() const { return threads_; }

  // task(context, t) for every t in 0 .. threads() - 1, t = 0 on the caller.
  void Run(Task task, void* context);

 private:
  void WorkerMain(int index);

  // generation_ and stop_ change under mu_ (so a thread about to sleep on
  // start_cv_ cannot miss them) and are read without it while spinning.
  std::mutex mu_;
  std::condition_variable start_cv_, done_cv_;
  std::atomic<uint64_t> generation_{0};  // bumped by each Run
  std::atomic<int> running_{0};          // workers still on the current task
  std::atomic<bool> stop_{false};
  int sleepers_ = 0;                     // workers asleep on start_cv_ (under mu_)
  bool caller_asleep_ = false;           // Run asleep on done_cv_ (under mu_)
  Task task_ = nullptr;
  void* context_ = nullptr;
  int threads_ = 1;
  std::vector<std::thread> workers_;
};

}  // namespace relight
