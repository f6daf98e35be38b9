// WorkerPool (relight/base/worker_pool.h): every thread runs every task
// once, whether the workers are still spinning from the last task or have
// gone to sleep, and the pool stops cleanly from either state. Functional
// checks only; the cost of a Run is in docs/performance.md.
#include "relight/base/worker_pool.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

namespace relight {
namespace {

struct Tally {
  std::array<std::atomic<int>, kMaxEngineThreads> runs{};
  std::atomic<int> seen_before{0};  // tasks that found the previous Run unfinished
  int expected = 0;                 // runs per thread after the previous Run
  int threads = 1;
};

void Count(void* context, int thread) {
  Tally& t = *static_cast<Tally*>(context);
  // Run returns only after every thread finished, so each thread must find
  // every other at the count the previous Run left.
  for (int k = 0; k < t.threads; ++k) {
    const int r = t.runs[static_cast<size_t>(k)].load();
    if (r < t.expected) t.seen_before.fetch_add(1);
  }
  t.runs[static_cast<size_t>(thread)].fetch_add(1);
}

void RunAndCheck(WorkerPool& pool, Tally& tally, int runs, std::chrono::microseconds gap) {
  for (int i = 0; i < runs; ++i) {
    pool.Run(&Count, &tally);
    ++tally.expected;
    for (int k = 0; k < pool.threads(); ++k)
      ASSERT_EQ(tally.runs[static_cast<size_t>(k)].load(), tally.expected) << "thread " << k << ", run " << i;
    if (gap.count() > 0) std::this_thread::sleep_for(gap);
  }
}

TEST(WorkerPool, EveryThreadRunsEveryTaskBackToBack) {
  for (const int threads : {1, 2, 3}) {
    WorkerPool pool;
    pool.Start(threads);
    Tally tally;
    tally.threads = threads;
    // Back to back: the workers are still spinning when the next task comes.
    RunAndCheck(pool, tally, 20000, std::chrono::microseconds(0));
    // Threads that are not in the pool never ran.
    for (int k = threads; k < kMaxEngineThreads; ++k) EXPECT_EQ(tally.runs[static_cast<size_t>(k)].load(), 0);
    EXPECT_EQ(tally.seen_before.load(), 0);
  }
}

TEST(WorkerPool, WorkersThatWentToSleepWakeForTheNextTask) {
  WorkerPool pool;
  pool.Start(2);
  Tally tally;
  tally.threads = 2;
  // Gaps of 40 times the spin: every worker is asleep when the task comes.
  RunAndCheck(pool, tally, 50, std::chrono::microseconds(40 * kWorkerSpinMicros));
  // Gaps about the spin's length: some wake spinning, some asleep.
  RunAndCheck(pool, tally, 400, std::chrono::microseconds(kWorkerSpinMicros));
  EXPECT_EQ(tally.seen_before.load(), 0);
}

void SlowOnWorkers(void* context, int thread) {
  // The workers finish long after the caller, so Run goes to sleep waiting.
  if (thread != 0) std::this_thread::sleep_for(std::chrono::microseconds(20 * kWorkerSpinMicros));
  Count(context, thread);
}

TEST(WorkerPool, RunThatWentToSleepWakesWhenTheWorkersFinish) {
  WorkerPool pool;
  pool.Start(3);
  Tally tally;
  tally.threads = 3;
  for (int i = 0; i < 30; ++i) {
    pool.Run(&SlowOnWorkers, &tally);
    ++tally.expected;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(tally.runs[static_cast<size_t>(k)].load(), tally.expected);
  }
  EXPECT_EQ(tally.seen_before.load(), 0);
}

TEST(WorkerPool, StopsWhileSpinningAndWhileAsleep) {
  for (const int sleep_us : {0, 40 * kWorkerSpinMicros}) {
    Tally tally;
    {
      WorkerPool pool;
      pool.Start(2);
      pool.Run(&Count, &tally);
      std::this_thread::sleep_for(std::chrono::microseconds(sleep_us));
    }  // joins here; a lost stop would hang the test (ctest's timeout)
    EXPECT_EQ(tally.runs[0].load(), 1);
    EXPECT_EQ(tally.runs[1].load(), 1);
  }
}

}  // namespace
}  // namespace relight
