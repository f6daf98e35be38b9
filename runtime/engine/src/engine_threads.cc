// Update's parallel steps (see engine_threads.h).
#include "engine_threads.h"

#include "luminaire_cache.h"

namespace relight {
namespace {

CacheWorkspace* WorkOf(EngineThreads* t, CacheWorkspace* work0, int thread) {
  return thread == 0 ? work0 : &t->work[static_cast<size_t>(thread) - 1];
}

struct RebuildJob {
  Bake* bake;
  std::vector<LuminaireRuntime>* lums;
  CacheWorkspace* work0;
  EngineThreads* t;
};

void RebuildTask(void* context, int thread) {
  RebuildJob& job = *static_cast<RebuildJob*>(context);
  EngineThreads& t = *job.t;
  CacheWorkspace* work = WorkOf(&t, job.work0, thread);
  int terms = 0;
  // Luminaires taken in turn from a shared counter: the split varies from run
  // to run, the caches do not (each is one thread's work on its own data).
  for (uint32_t k; (k = t.next.fetch_add(1, std::memory_order_relaxed)) < t.rebuild_count;) {
    const uint32_t i = t.rebuild[k];
    LuminaireRuntime& lum = (*job.lums)[i];
    BakeLuminaire& b = job.bake->luminaires[i];
    if (lum.zoom_pending) ApplyZoom(&b, &lum, work->zoom_samples_q16.data());
    terms += RecomputeLuminaireCacheQ12(*job.bake, b, work, &lum);
    lum.dirty = false;
  }
  t.terms[thread] = terms;
}

struct RemixJob {
  const Bake* bake;
  const std::vector<LuminaireRuntime>* lums;
  CacheWorkspace* work0;
  MixSource* mix0;
  EngineThreads* t;
  EngineOutputs* out;
};

void RemixTask(void* context, int thread) {
  RemixJob& job = *static_cast<RemixJob*>(context);
  CacheWorkspace* work = WorkOf(job.t, job.work0, thread);
  MixSource* mix = thread == 0 ? job.mix0 : job.t->mix[static_cast<size_t>(thread) - 1].data();
  RemixSliceQ12(*job.bake, *job.lums, static_cast<uint32_t>(thread),
                static_cast<uint32_t>(job.t->pool.threads()), mix, work->scratch.data(),
                static_cast<uint32_t>(work->scratch.size()), job.out);
}

}  // namespace

void StartEngineThreads(int threads, const CacheWorkspace& work0, size_t luminaires,
                        EngineThreads* t) {
  if (threads <= 0) threads = DefaultEngineThreads();
  if (threads > kMaxEngineThreads) threads = kMaxEngineThreads;
  t->work.assign(static_cast<size_t>(threads) - 1, work0);  // read-only tables shared
  t->mix.assign(static_cast<size_t>(threads) - 1, std::vector<MixSource>(luminaires));
  t->rebuild.assign(luminaires, 0);
  t->pool.Start(threads);
}

int RebuildLuminaires(Bake* bake, std::vector<LuminaireRuntime>* lums, CacheWorkspace* work0,
                      EngineThreads* t) {
  if (t->rebuild_count == 0) return 0;
  RebuildJob job{bake, lums, work0, t};
  t->next.store(0, std::memory_order_relaxed);
  for (int& n : t->terms) n = 0;
  // One luminaire: no other thread to wake.
  if (t->rebuild_count == 1) {
    RebuildTask(&job, 0);
  } else {
    t->pool.Run(RebuildTask, &job);  // the pool's mutex orders next and the writes
  }
  int terms = 0;
  for (int n : t->terms) terms += n;
  return terms;
}

void RemixOnThreads(const Bake& bake, const std::vector<LuminaireRuntime>& lums,
                    CacheWorkspace* work0, MixSource* mix0, EngineThreads* t, EngineOutputs* out) {
  RemixJob job{&bake, &lums, work0, mix0, t, out};
  t->pool.Run(RemixTask, &job);
}

}  // namespace relight
