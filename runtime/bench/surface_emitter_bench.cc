// Run-time surface emitters (FE): time per change against a pan change, in
// one run (issue 15's bar: place, move by 10 cm, luminance, remove, each
// <= 5 ms median and <= 15 ms p99, as a ratio to a pan change):
//
//   BM_PanChange          Engine::Update() after a pan change: one luminaire's
//                         SH terms and direct term recombined (the baseline)
//   BM_EmitterPlace       a new light: SetSurfaceEmitter on a removed slot,
//                         where it overlaps nothing it was (cycling three
//                         spots) + Update(): clip, a solve from the
//                         emission alone, vertices, mix
//   BM_EmitterMove10cm    SetSurfaceEmitter 10 cm on (round a 10 cm square,
//                         never straight back) + Update(): clip, a solve
//                         starting from the previous one, vertices, mix
//   (adaptive refine's moves near where the emitter was last solved in full
//   are answered from their start without a sweep, EngineOptions::
//   emitter_quick_changes: quick_share counts them; mean_ms is the mean)
//   BM_EmitterDrag        AR round a 10 cm circle in 1.6 cm steps (a drag at
//                         frame rate), each SetSurfaceEmitter + Update() timed
//   BM_EmitterSettle      an idle Update() after a drag step answered quickly:
//                         the full solve from where it stands (untimed: the step)
//   BM_EmitterLuminance   SetSurfaceEmitterLuminance + Update(): a rescale
//   (Place and Move10cm run with fractional emissivity, ar:0, and adaptive
//   refine, ar:1: the refine's new link factors, surface_emitter_refine.h,
//   then a first-shot solve; the others use FE)
//   BM_EmitterRemove      RemoveSurfaceEmitter + Update(): the remix without it
//   BM_EmitterPlaceOnly   SetSurfaceEmitter alone: the clip
//
// Each iteration is timed on its own (wall clock, manual time); the counters
// give its median and 99th percentile (p50_ms, p99_ms), the median CPU time
// of the process (both engine threads, cpu_ms) and the median over the pan
// change's median of this run (x_pan). Sweeps: the last solve's count;
// sweeps_mean: the mean over the iterations.
//
//   surface_emitter_bench BAKE.rlb SURFACE x0,y0,z0 x1,y1,z1 x2,y2,z2 [--benchmark_...]
//
// RELIGHT_BENCH_BOUNCE_TABLE_MB=N in the environment sizes the engine's
// later-bounce table (EngineOptions::emitter_bounce_table_bytes; 0: none, as
// before it existed); it prints Open's time and the table's size.
//
// RELIGHT_BENCH_QUICK=0 solves every change at once (no quick answers:
// EngineOptions::emitter_quick_changes), the same binary's baseline.
//
// RELIGHT_BENCH_REFINE_BITS=N sets adaptive refine's threshold to 2^-N of
// the emitter's exitance (EngineOptions::emitter_refine_bits).
//
// On a loaded machine two threads' CPU time counts the pool's waiting:
// RELIGHT_THREADS=1 in the environment gives one thread's CPU per change.
//
// The emitter is the triangle given; the place spots are it and it moved by
// its first edge's length + 5 cm along that edge and across it, so the
// surface must have room for them. docs/hierarchy.md has the figures.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "relight/engine/engine.h"

namespace {

using Clock = std::chrono::steady_clock;

relight::Engine* g_engine = nullptr;
relight::SurfaceEmitterShape g_place[3];  // far apart
relight::SurfaceEmitterShape g_square[4];  // 10 cm apart
constexpr int kCircleSteps = 40;
relight::SurfaceEmitterShape g_circle[kCircleSteps];  // round a 10 cm radius, 1.6 cm a step
double g_pan_median_ms = 0;

// The shape with the method of the benchmark's argument: 0 FE, 1 AR.
relight::SurfaceEmitterShape With(const relight::SurfaceEmitterShape& shape, const benchmark::State& state) {
  relight::SurfaceEmitterShape s = shape;
  s.method = state.range(0) == 1 ? relight::SurfaceEmitterMethod::kAdaptiveRefine
                                 : relight::SurfaceEmitterMethod::kFractionalEmissivity;
  return s;
}

const relight::LightQ12 kWhite[3] = {relight::LightQ12::FromRaw(1000 << 12),
                                     relight::LightQ12::FromRaw(1000 << 12),
                                     relight::LightQ12::FromRaw(1000 << 12)};

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Times one change: `change` then Update(), wall and CPU.
class Samples {
 public:
  template <typename F>
  void Time(benchmark::State& state, F change) {
    const double cpu0 = CpuSeconds();
    const Clock::time_point t0 = Clock::now();
    change();
    g_engine->Update();
    benchmark::DoNotOptimize(g_engine->vertex_luminance());
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    state.SetIterationTime(wall);
    wall_ms_.push_back(1e3 * wall);
    cpu_ms_.push_back(1e3 * (CpuSeconds() - cpu0));
  }
  // Sets the counters; returns the wall median (ms).
  double Report(benchmark::State& state) {
    if (wall_ms_.empty()) return 0;
    const double median = Quantile(&wall_ms_, 0.5);
    state.counters["p50_ms"] = median;
    state.counters["p99_ms"] = Quantile(&wall_ms_, 0.99);
    state.counters["cpu_ms"] = Quantile(&cpu_ms_, 0.5);
    double sum = 0;
    for (const double ms : wall_ms_) sum += ms;
    state.counters["mean_ms"] = sum / static_cast<double>(wall_ms_.size());
    if (g_pan_median_ms > 0) state.counters["x_pan"] = median / g_pan_median_ms;
    return median;
  }

 private:
  static double Quantile(std::vector<double>* v, double q) {
    std::sort(v->begin(), v->end());
    const size_t i = static_cast<size_t>(std::ceil(q * static_cast<double>(v->size()))) - 1;
    return (*v)[std::min(i, v->size() - 1)];
  }
  std::vector<double> wall_ms_, cpu_ms_;
};

void BM_PanChange(benchmark::State& state) {
  Samples samples;
  int i = 0;
  for (auto _ : state) {
    samples.Time(state, [&] {
      (void)g_engine->SetPanTilt(0, relight::Q16_16::FromInt(10 + (i++ & 1) * 20), relight::Q16_16::FromInt(30));
    });
  }
  g_pan_median_ms = samples.Report(state);
}

void BM_EmitterPlace(benchmark::State& state) {
  Samples samples;
  int i = 0, sweeps = 0, total = 0, solves = 0, quick = 0;
  for (auto _ : state) {
    // A new light: removed first (untimed), so the solve starts from the emission.
    (void)g_engine->RemoveSurfaceEmitter(0);
    g_engine->Update();
    const relight::SurfaceEmitterShape shape = With(g_place[i++ % 3], state);
    samples.Time(state, [&] { (void)g_engine->SetSurfaceEmitter(0, shape, kWhite); });
    sweeps = g_engine->last_update_emitter_sweeps();
    total += sweeps;
    quick += g_engine->last_update_emitters_quick();
    ++solves;
  }
  samples.Report(state);
  state.counters["sweeps"] = sweeps;
  state.counters["sweeps_mean"] = solves > 0 ? static_cast<double>(total) / solves : 0;
  state.counters["quick_share"] = solves > 0 ? static_cast<double>(quick) / solves : 0;
}

void BM_EmitterMove10cm(benchmark::State& state) {
  Samples samples;
  int i = 0, sweeps = 0, total = 0, solves = 0, quick = 0;
  (void)g_engine->SetSurfaceEmitter(0, With(g_square[0], state), kWhite);
  g_engine->Update();
  for (auto _ : state) {
    const relight::SurfaceEmitterShape shape = With(g_square[++i % 4], state);
    samples.Time(state, [&] { (void)g_engine->SetSurfaceEmitter(0, shape, kWhite); });
    sweeps = g_engine->last_update_emitter_sweeps();
    total += sweeps;
    quick += g_engine->last_update_emitters_quick();
    ++solves;
  }
  samples.Report(state);
  state.counters["sweeps"] = sweeps;
  state.counters["sweeps_mean"] = solves > 0 ? static_cast<double>(total) / solves : 0;
  state.counters["quick_share"] = solves > 0 ? static_cast<double>(quick) / solves : 0;
}

// A drag at frame rate: adaptive refine round a circle of 10 cm radius in
// 1.6 cm steps, every step timed.
void BM_EmitterDrag(benchmark::State& state) {
  Samples samples;
  int i = 0, quick = 0, total = 0, moves = 0;
  (void)g_engine->SetSurfaceEmitter(0, g_circle[0], kWhite);
  g_engine->Update();
  g_engine->Update();
  for (auto _ : state) {
    const relight::SurfaceEmitterShape& shape = g_circle[++i % kCircleSteps];
    samples.Time(state, [&] { (void)g_engine->SetSurfaceEmitter(0, shape, kWhite); });
    quick += g_engine->last_update_emitters_quick();
    total += g_engine->last_update_emitter_sweeps();
    ++moves;
  }
  samples.Report(state);
  state.counters["quick_share"] = moves > 0 ? static_cast<double>(quick) / moves : 0;
  state.counters["sweeps_mean"] = moves > 0 ? static_cast<double>(total) / moves : 0;
}

// An idle Update() after a quick adaptive-refine move: the settle.
void BM_EmitterSettle(benchmark::State& state) {
  Samples samples;
  int i = 0, settles = 0;
  (void)g_engine->SetSurfaceEmitter(0, g_circle[0], kWhite);
  g_engine->Update();
  g_engine->Update();
  for (auto _ : state) {
    (void)g_engine->SetSurfaceEmitter(0, g_circle[++i % kCircleSteps], kWhite);  // one drag step, untimed
    g_engine->Update();
    const bool quick = !g_engine->emitters_settled();
    samples.Time(state, [] {});
    settles += quick && g_engine->last_update_emitters_solved() == 1 ? 1 : 0;
  }
  samples.Report(state);
  state.counters["settled_share"] = static_cast<double>(settles) / static_cast<double>(state.iterations());
}

void BM_EmitterLuminance(benchmark::State& state) {
  Samples samples;
  int i = 0;
  for (auto _ : state) {
    const int32_t l = (500 + (i++ & 1) * 300) << 12;
    const relight::LightQ12 rgb[3] = {relight::LightQ12::FromRaw(l), relight::LightQ12::FromRaw(l / 2),
                                      relight::LightQ12::FromRaw(l / 4)};
    samples.Time(state, [&] { (void)g_engine->SetSurfaceEmitterLuminance(0, rgb); });
  }
  samples.Report(state);
}

void BM_EmitterRemove(benchmark::State& state) {
  Samples samples;
  for (auto _ : state) {
    samples.Time(state, [&] { (void)g_engine->RemoveSurfaceEmitter(0); });
    // Back for the next one (the slot kept its solution: no solve), untimed.
    (void)g_engine->SetSurfaceEmitter(0, g_square[0], kWhite);
    g_engine->Update();
  }
  samples.Report(state);
}

void BM_EmitterPlaceOnly(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(g_engine->SetSurfaceEmitter(1, g_square[i++ & 1], kWhite));
  (void)g_engine->RemoveSurfaceEmitter(1);
}

BENCHMARK(BM_PanChange)->UseManualTime()->Iterations(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterPlace)->ArgName("ar")->Arg(0)->Arg(1)->UseManualTime()->Iterations(150)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterMove10cm)->ArgName("ar")->Arg(0)->Arg(1)->UseManualTime()->Iterations(200)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterDrag)->UseManualTime()->Iterations(200)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterSettle)->UseManualTime()->Iterations(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterLuminance)->UseManualTime()->Iterations(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterRemove)->UseManualTime()->Iterations(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterPlaceOnly)->Unit(benchmark::kMillisecond);

bool ParseCorner(const char* text, double out[3]) {
  return std::sscanf(text, "%lf,%lf,%lf", &out[0], &out[1], &out[2]) == 3;
}

relight::SurfaceEmitterShape Shape(const char* surface, const double c[3][3], const double offset_m[3]) {
  relight::SurfaceEmitterShape s;
  s.surface = surface;
  s.corner_count = 3;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) s.corners_q16[k][i] = static_cast<int32_t>(std::lround((c[k][i] + offset_m[i]) * 65536.0));
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  double c[3][3];
  if (argc != 6 || !ParseCorner(argv[3], c[0]) || !ParseCorner(argv[4], c[1]) || !ParseCorner(argv[5], c[2])) {
    std::fprintf(stderr, "usage: surface_emitter_bench BAKE.rlb SURFACE x,y,z x,y,z x,y,z [--benchmark_...]\n");
    return 2;
  }
  relight::EngineOptions options;
  if (const char* mb = std::getenv("RELIGHT_BENCH_BOUNCE_TABLE_MB"))  // 0: none (the build before the table)
    options.emitter_bounce_table_bytes = std::atoll(mb) << 20;
  if (const char* bits = std::getenv("RELIGHT_BENCH_REFINE_BITS")) options.emitter_refine_bits = std::atoi(bits);
  if (const char* quick = std::getenv("RELIGHT_BENCH_QUICK")) options.emitter_quick_changes = std::atoi(quick) != 0;
  relight::Engine engine;
  const Clock::time_point open_start = Clock::now();
  if (relight::Status st = engine.Open(argv[1], options); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.ToString().c_str());
    return 2;
  }
  std::printf("Open: %.2f s, later-bounce table: %d sources, %.1f MB; quick answers within %.3f m\n",
              std::chrono::duration<double>(Clock::now() - open_start).count(), engine.emitter_bounce_sources(),
              static_cast<double>(engine.emitter_bounce_table_size()) / (1 << 20), engine.emitter_quick_reach_q16() / 65536.0);
  // u along the first edge, w across it in the triangle's plane.
  double u[3], w[3], len = 0, dot = 0, wlen = 0;
  for (int i = 0; i < 3; ++i) len += (c[1][i] - c[0][i]) * (c[1][i] - c[0][i]);
  len = std::sqrt(len);
  for (int i = 0; i < 3; ++i) u[i] = (c[1][i] - c[0][i]) / len;
  for (int i = 0; i < 3; ++i) dot += (c[2][i] - c[0][i]) * u[i];
  for (int i = 0; i < 3; ++i) w[i] = c[2][i] - c[0][i] - dot * u[i];
  for (int i = 0; i < 3; ++i) wlen += w[i] * w[i];
  wlen = std::sqrt(wlen);
  for (int i = 0; i < 3; ++i) w[i] /= wlen;
  const double far = len + 0.05;
  for (int s = 0; s < 3; ++s) {
    double o[3];
    for (int i = 0; i < 3; ++i) o[i] = (s == 1 ? far * u[i] : 0) + (s == 2 ? far * w[i] : 0);
    g_place[s] = Shape(argv[2], c, o);
    g_place[s].method = relight::SurfaceEmitterMethod::kFractionalEmissivity;
  }
  const double square[4][2] = {{0, 0}, {0.1, 0}, {0.1, 0.1}, {0, 0.1}};
  for (int s = 0; s < 4; ++s) {
    double o[3];
    for (int i = 0; i < 3; ++i) o[i] = square[s][0] * u[i] + square[s][1] * w[i];
    g_square[s] = Shape(argv[2], c, o);
    g_square[s].method = relight::SurfaceEmitterMethod::kFractionalEmissivity;
  }
  for (int s = 0; s < kCircleSteps; ++s) {
    const double a = 2 * M_PI * s / kCircleSteps;
    double o[3];
    for (int i = 0; i < 3; ++i) o[i] = 0.1 * (std::cos(a) - 1) * u[i] + 0.1 * std::sin(a) * w[i];
    g_circle[s] = Shape(argv[2], c, o);  // AR, the shape's default
  }
  for (const relight::SurfaceEmitterShape* s : {&g_place[0], &g_place[1], &g_place[2], &g_square[2]}) {
    if (relight::Status st = engine.SetSurfaceEmitter(0, *s, kWhite); !st.ok()) {
      std::fprintf(stderr, "%s\n", st.ToString().c_str());
      return 2;
    }
  }
  engine.Update();
  g_engine = &engine;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
