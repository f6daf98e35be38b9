// Recombination speed against the memory-bandwidth ceiling (issue 4 a, c).
//
//   BM_StreamRead      a plain read of the same basis bytes (the baseline:
//                      what memory bandwidth allows)
//   BM_Recombine       RecombineQ12 over those bytes (terms x receivers x RGB)
//   BM_EngineMove      Engine::Update() after a pan/tilt change (one luminaire
//                      recombined: its SH terms and its direct term)
//   BM_EngineDimmer    Engine::Update() after a dimmer change (no SH term touched)
//
// Report ratios within one run: Recombine / StreamRead at the same size, and
// EngineDimmer / EngineMove. docs/performance.md has the figures and command.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "recombine.h"
#include "relight/bake.h"
#include "relight/engine.h"
#include "relight/sh_index.h"

namespace {

// Smooth-ish random int16 data: what the bake's quantised bases look like to
// the memory system (values do not change the kernel's speed).
std::vector<int16_t> MakeBasis(uint32_t terms, uint32_t receivers) {
  std::vector<int16_t> basis(static_cast<size_t>(terms) * receivers * 3);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> step(-64, 64);
  int v = 0;
  for (int16_t& q : basis) {
    v = std::max(-32767, std::min(32767, v + step(rng)));
    q = static_cast<int16_t>(v);
  }
  return basis;
}

// The baseline: sum every 64-bit word of the buffer (the compiler vectorises
// this freely; it is bound by memory bandwidth, like the kernel should be).
void BM_StreamRead(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const std::vector<int16_t> basis = MakeBasis(terms, receivers);
  const size_t words = basis.size() * sizeof(int16_t) / sizeof(uint64_t);
  for (auto _ : state) {
    const uint64_t* p = reinterpret_cast<const uint64_t*>(basis.data());
    uint64_t sum = 0;
    for (size_t i = 0; i < words; ++i) sum += p[i];
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(basis.size() * 2));
}

void BM_Recombine(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const std::vector<int16_t> basis = MakeBasis(terms, receivers);
  std::vector<int32_t> k(static_cast<size_t>(terms) * 3);
  for (size_t i = 0; i < k.size(); ++i) k[i] = static_cast<int32_t>(1000003 * (i + 1) % 2000000) - 1000000;
  std::vector<int64_t> scratch(static_cast<size_t>(state.range(2)));
  std::vector<int32_t> out(static_cast<size_t>(receivers) * 3);
  for (auto _ : state) {
    relight::RecombineQ12(basis.data(), terms, receivers, k.data(), 20, scratch.data(),
                          static_cast<uint32_t>(scratch.size()), out.data());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(basis.size() * 2));
}

// 36 + 81 terms: one luminaire of degree 5 and one of degree 8 (Dobashi 5),
// recombined back to back over the same receivers.
void SizeArgs(benchmark::internal::Benchmark* b) {
  for (int64_t receivers : {16384, 100000}) {
    b->Args({receivers, 36});
    b->Args({receivers, 81});
    b->Args({receivers, 117});
  }
  b->Unit(benchmark::kMicrosecond);
}
BENCHMARK(BM_StreamRead)->Apply(SizeArgs);
// Third argument: the scratch length the engine gives the kernel (3 int64 per receiver of a block).
void ScratchArgs(benchmark::internal::Benchmark* b) {
  for (int64_t receivers : {16384, 100000}) {
    for (int64_t terms : {36, 81, 117}) {
      for (int64_t scratch : {3 * 512, 3 * 2048}) b->Args({receivers, terms, scratch});
    }
  }
  b->Unit(benchmark::kMicrosecond);
}
BENCHMARK(BM_Recombine)->Apply(ScratchArgs);

// A synthetic bake: V vertices on a floor, one exact-direct luminaire of degree 8.
relight::Bake MakeBake(uint32_t vertices, int degree) {
  relight::Bake bake;
  bake.scene_name = "bench";
  for (uint32_t v = 0; v < vertices; ++v) {
    const int32_t x = static_cast<int32_t>(v % 1024) * 1000, y = static_cast<int32_t>(v / 1024) * 1000;
    bake.mesh.positions.insert(bake.mesh.positions.end(), {x, y, 0});
    bake.mesh.normals.insert(bake.mesh.normals.end(), {0, 0, 16384});
    bake.mesh.albedo.insert(bake.mesh.albedo.end(), {32768, 32768, 32768});
  }
  for (uint32_t t = 0; t + 2 < vertices; t += 3) bake.mesh.triangles.insert(bake.mesh.triangles.end(), {t, t + 1, t + 2});
  bake.mesh.triangle_surface.assign(bake.mesh.triangle_count(), 0);
  bake.mesh.surface_names = {"floor"};
  relight::BakeLuminaire lum;
  lum.name = "spot";
  lum.position[2] = 3 << 16;
  lum.sh_degree = static_cast<uint8_t>(degree);
  lum.use_sigma = 0;
  for (int i = 0; i <= 180; ++i) lum.lid.candela.push_back(static_cast<int64_t>(1000 - 5 * i) << 16);
  relight::BakeLightReceivers rx;
  const uint32_t terms = relight::ShTermCount(degree);
  for (uint32_t v = 0; v < vertices; ++v) rx.direction.insert(rx.direction.end(), {0, 0, -16384});
  rx.geometry.assign(vertices, 1u << 30);
  rx.geometry_scale = {1 << 29, -30};
  rx.basis = MakeBasis(terms, vertices);
  rx.basis_scale.assign(static_cast<size_t>(terms) * 3, relight::QuantScale{1 << 29, -20});
  lum.receivers.push_back(std::move(rx));
  bake.luminaires.push_back(std::move(lum));
  return bake;
}

void BM_EngineMove(benchmark::State& state) {
  relight::Engine engine;
  if (!engine.Open(MakeBake(static_cast<uint32_t>(state.range(0)), 8)).ok()) {
    state.SkipWithError("Open failed");
    return;
  }
  int32_t pan = 0;
  for (auto _ : state) {
    pan += 1 << 16;  // one degree per iteration
    (void)engine.SetPanTilt(0, relight::Q16_16::FromRaw(pan), relight::Q16_16::FromInt(30));
    engine.Update();
    benchmark::DoNotOptimize(engine.vertex_luminance());
  }
}

void BM_EngineDimmer(benchmark::State& state) {
  relight::Engine engine;
  if (!engine.Open(MakeBake(static_cast<uint32_t>(state.range(0)), 8)).ok()) {
    state.SkipWithError("Open failed");
    return;
  }
  (void)engine.SetPanTilt(0, relight::Q16_16::FromInt(10), relight::Q16_16::FromInt(30));
  engine.Update();
  int16_t level = 0;
  for (auto _ : state) {
    level = static_cast<int16_t>((level + 97) & 0x7fff);
    (void)engine.SetDimmer(0, relight::Q1_15::FromRaw(level));
    engine.Update();
    benchmark::DoNotOptimize(engine.vertex_luminance());
  }
}
BENCHMARK(BM_EngineMove)->Arg(16384)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EngineDimmer)->Arg(16384)->Arg(100000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
