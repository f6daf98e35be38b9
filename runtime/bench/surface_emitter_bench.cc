// Run-time surface emitters (FE) against one full recombination, in one run:
//
//   BM_PanChange          Engine::Update() after a pan change: one luminaire's
//                         SH terms and direct term recombined (the baseline)
//   BM_EmitterMove        SetSurfaceEmitter to a new place + Update(): clip,
//                         fixed-point solve (3 channels unless they reflect
//                         alike), leaves to vertices, mix
//   BM_EmitterPlaceOnly   SetSurfaceEmitter alone: the clip
//   BM_EmitterLuminance   SetSurfaceEmitterLuminance + Update(): a rescale
//   BM_EmitterMoveAr, BM_EmitterPlaceOnlyAr   the same two with adaptive
//                         refine (the others use FE): clip, the refine's new
//                         link factors (surface_emitter_refine.h), first-shot solve
//
//   surface_emitter_bench BAKE.rlb SURFACE x0,y0,z0 x1,y1,z1 x2,y2,z2 [--benchmark_...]
//
// The emitter is the triangle given, alternating with itself moved by 0.25 of
// its first edge. docs/hierarchy.md has the figures and the command.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "relight/engine/engine.h"

namespace {

relight::Engine* g_engine = nullptr;
relight::SurfaceEmitterShape g_shape[2], g_shape_ar[2];

const relight::LightQ12 kWhite[3] = {relight::LightQ12::FromRaw(1000 << 12),
                                     relight::LightQ12::FromRaw(1000 << 12),
                                     relight::LightQ12::FromRaw(1000 << 12)};

void BM_PanChange(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) {
    (void)g_engine->SetPanTilt(0, relight::Q16_16::FromInt(10 + (i++ & 1) * 20), relight::Q16_16::FromInt(30));
    g_engine->Update();
    benchmark::DoNotOptimize(g_engine->vertex_luminance());
  }
}

void BM_EmitterMove(benchmark::State& state) {
  int i = 0, sweeps = 0;
  for (auto _ : state) {
    (void)g_engine->SetSurfaceEmitter(0, g_shape[i++ & 1], kWhite);
    g_engine->Update();
    sweeps = g_engine->last_update_emitter_sweeps();
    benchmark::DoNotOptimize(g_engine->vertex_luminance());
  }
  state.counters["sweeps"] = sweeps;
}

void BM_EmitterPlaceOnly(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(g_engine->SetSurfaceEmitter(1, g_shape[i++ & 1], kWhite));
  (void)g_engine->RemoveSurfaceEmitter(1);
}

void BM_EmitterLuminance(benchmark::State& state) {
  (void)g_engine->SetSurfaceEmitter(0, g_shape[0], kWhite);
  g_engine->Update();
  int i = 0;
  for (auto _ : state) {
    const int32_t l = (500 + (i++ & 1) * 300) << 12;
    const relight::LightQ12 rgb[3] = {relight::LightQ12::FromRaw(l), relight::LightQ12::FromRaw(l / 2),
                                      relight::LightQ12::FromRaw(l / 4)};
    (void)g_engine->SetSurfaceEmitterLuminance(0, rgb);
    g_engine->Update();
    benchmark::DoNotOptimize(g_engine->vertex_luminance());
  }
}

void BM_EmitterMoveAr(benchmark::State& state) {
  int i = 0, sweeps = 0;
  for (auto _ : state) {
    (void)g_engine->SetSurfaceEmitter(0, g_shape_ar[i++ & 1], kWhite);
    g_engine->Update();
    sweeps = g_engine->last_update_emitter_sweeps();
    benchmark::DoNotOptimize(g_engine->vertex_luminance());
  }
  state.counters["sweeps"] = sweeps;
}

void BM_EmitterPlaceOnlyAr(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(g_engine->SetSurfaceEmitter(1, g_shape_ar[i++ & 1], kWhite));
  (void)g_engine->RemoveSurfaceEmitter(1);
}

BENCHMARK(BM_PanChange)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterMove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterPlaceOnly)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterLuminance)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterMoveAr)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterPlaceOnlyAr)->Unit(benchmark::kMillisecond);

bool ParseCorner(const char* text, double out[3]) {
  return std::sscanf(text, "%lf,%lf,%lf", &out[0], &out[1], &out[2]) == 3;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  double c[3][3];
  if (argc != 6 || !ParseCorner(argv[3], c[0]) || !ParseCorner(argv[4], c[1]) || !ParseCorner(argv[5], c[2])) {
    std::fprintf(stderr, "usage: surface_emitter_bench BAKE.rlb SURFACE x,y,z x,y,z x,y,z [--benchmark_...]\n");
    return 2;
  }
  relight::Engine engine;
  if (relight::Status st = engine.Open(argv[1]); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.ToString().c_str());
    return 2;
  }
  for (int s = 0; s < 2; ++s) {
    g_shape[s].surface = argv[2];
    g_shape[s].corner_count = 3;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i)
        g_shape[s].corners_q16[k][i] =
            static_cast<int32_t>(std::lround((c[k][i] + 0.25 * s * (c[1][i] - c[0][i])) * 65536.0));
    g_shape_ar[s] = g_shape[s];
    g_shape[s].method = relight::SurfaceEmitterMethod::kFractionalEmissivity;
    g_shape_ar[s].method = relight::SurfaceEmitterMethod::kAdaptiveRefine;
  }
  if (relight::Status st = engine.SetSurfaceEmitter(0, g_shape[1], kWhite); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.ToString().c_str());
    return 2;
  }
  engine.Update();
  g_engine = &engine;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
