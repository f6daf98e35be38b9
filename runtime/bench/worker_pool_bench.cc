// BM_WorkerPoolRun/W: one WorkerPool::Run of a task that keeps each of the
// two threads busy for W microseconds; the counter overhead_us is the wall
// time of a Run beyond W: what handing a step to both cores costs. The
// engine's update and the emitter solve call Run several times a frame.
#include <benchmark/benchmark.h>

#include <chrono>

#include "relight/base/worker_pool.h"

namespace {

using Clock = std::chrono::steady_clock;

void Busy(void* context, int) {
  const auto until = Clock::now() + std::chrono::microseconds(*static_cast<const int64_t*>(context));
  while (Clock::now() < until) {
  }
}

void BM_WorkerPoolRun(benchmark::State& state) {
  relight::WorkerPool pool;
  pool.Start(2);
  int64_t work_us = state.range(0);
  const auto start = Clock::now();
  for (auto _ : state) pool.Run(&Busy, &work_us);
  const double wall_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  state.counters["overhead_us"] =
      wall_us / static_cast<double>(state.iterations()) - static_cast<double>(work_us);
}
BENCHMARK(BM_WorkerPoolRun)->Arg(0)->Arg(20)->Arg(200)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
