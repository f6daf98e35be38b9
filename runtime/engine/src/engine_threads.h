// Engine::Update on every core (issue 13 "both cores"): the luminaires that
// changed are rebuilt in parallel (each by one thread, with that thread's own
// scratch; a luminaire's cache depends on nothing another thread writes) and
// the remix is split into receiver slices (remix.h RemixSliceQ12). So the
// outputs are bit for bit those of one thread, whatever the thread count and
// whichever thread took which luminaire. Everything is sized at Open; Update
// allocates nothing.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "luminaire.h"
#include "mix.h"
#include "relight/bake/bake.h"
#include "remix.h"
#include "relight/base/worker_pool.h"

namespace relight {

struct EngineThreads {
  WorkerPool pool;
  // Thread t >= 1's scratch at [t - 1] (thread 0 uses the engine's own).
  std::vector<CacheWorkspace> work;
  std::vector<std::vector<MixSource>> mix;
  std::vector<uint32_t> rebuild;  // luminaire indices of this Update, capacity: all
  uint32_t rebuild_count = 0;
  std::atomic<uint32_t> next{0};
  int terms[kMaxEngineThreads] = {};
};

// Open time: `threads` (1 .. kMaxEngineThreads; 0 = DefaultEngineThreads()),
// copies of thread 0's workspace and mix array for the others, the workers.
void StartEngineThreads(int threads, const CacheWorkspace& work0, size_t luminaires,
                        EngineThreads* t);

// Rebuilds luminaires t->rebuild[0 .. t->rebuild_count) (a pending zoom
// first: zoom.h ApplyZoom, then luminaire_cache.h) on all threads; clears
// their dirty flags; returns the SH term passes made.
int RebuildLuminaires(Bake* bake, std::vector<LuminaireRuntime>* lums, CacheWorkspace* work0,
                      EngineThreads* t);

// RemixQ12 in one slice per thread.
void RemixOnThreads(const Bake& bake, const std::vector<LuminaireRuntime>& lums,
                    CacheWorkspace* work0, MixSource* mix0, EngineThreads* t, EngineOutputs* out);

}  // namespace relight
