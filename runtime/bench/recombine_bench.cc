// Recombination speed against the memory-bandwidth ceiling (issue 4 a, c).
//
//   BM_StreamRead      a plain read of the same basis bytes (the baseline:
//                      what memory bandwidth allows)
//   BM_Recombine       RecombineQ12 over those bytes (terms x receivers x RGB)
//   BM_EngineMove      Engine::Update() after a pan/tilt change (one luminaire
//                      recombined: its SH terms and its direct term)
//   BM_EngineDimmer    Engine::Update() after a dimmer change (no SH term touched)
//   BM_CompressedRecombineOverStream  a compressed basis recombined in compressed
//                      form against a vectorised read of its bytes, with the
//                      uncompressed path's ratio beside it (issue 13)
//   BM_DirectTerm      the aimed direct term of one head over V vertices
//                      (direct_aimed.h), counter per_vertex (seconds); BM_DirectTermFull
//                      the full path (direct.h: root and atan2 per vertex);
//                      BM_DirectTermBeam a spot's beam with a cut-off over
//                      receivers in mesh order (most of them skipped)
//
// Report ratios within one run: Recombine / StreamRead at the same size, and
// EngineDimmer / EngineMove. docs/performance.md has the figures and command.
#include <benchmark/benchmark.h>
#include <immintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "compressed_recombine.h"
#include "recombine_bench_data.h"
#include "direct.h"
#include "direct_aimed.h"
#include "recombine.h"
#include "recombine_dispatch.h"
#include "relight/bake/bake.h"
#include "relight/engine/engine.h"
#include "relight/base/sh_index.h"

namespace {

using relight_bench::MakeBasis;
using relight_bench::MakeCompressed;
using relight_bench::MakeMultipliers;
using relight_bench::Median;
using relight_bench::SumWords;
using relight_bench::SumWordsSimd;

// The baseline: sum every 64-bit word of the buffer (the compiler vectorises
// this freely; it is bound by memory bandwidth, like the kernel should be).
void BM_StreamRead(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const std::vector<int16_t> basis = MakeBasis(terms, receivers);
  for (auto _ : state) {
    benchmark::DoNotOptimize(SumWords(basis));
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(basis.size() * 2));
}

// The bar itself: StreamRead and Recombine timed alternately on the same
// bytes within each iteration, so a noisy neighbour slows both alike.
// Counter "ratio" = median recombination time / median streaming-read time.
void BM_RecombineOverStream(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const std::vector<int16_t> basis = MakeBasis(terms, receivers);
  const std::vector<int32_t> k = MakeMultipliers(terms);
  std::vector<int64_t> scratch(3 * 2048);  // what the engine passes
  std::vector<int32_t> out(static_cast<size_t>(receivers) * 3);
  std::vector<double> read_s, simd_s, recombine_s;
  for (auto _ : state) {
    const auto ts = Clock::now();
    benchmark::DoNotOptimize(SumWordsSimd(basis));
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(SumWords(basis));
    const auto t1 = Clock::now();
    relight::RecombineQ12(basis.data(), terms, receivers, k.data(), 20, scratch.data(),
                          static_cast<uint32_t>(scratch.size()), out.data());
    benchmark::DoNotOptimize(out.data());
    const auto t2 = Clock::now();
    simd_s.push_back(std::chrono::duration<double>(t0 - ts).count());
    read_s.push_back(std::chrono::duration<double>(t1 - t0).count());
    recombine_s.push_back(std::chrono::duration<double>(t2 - t1).count());
    state.SetIterationTime(recombine_s.back());
  }
  state.counters["read_us"] = Median(read_s) * 1e6;
  state.counters["recombine_us"] = Median(recombine_s) * 1e6;
  state.counters["ratio"] = Median(recombine_s) / Median(read_s);
  state.counters["ratio_simd"] = Median(recombine_s) / Median(simd_s);
}

void BM_Recombine(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const std::vector<int16_t> basis = MakeBasis(terms, receivers);
  const std::vector<int32_t> k = MakeMultipliers(terms);
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
BENCHMARK(BM_RecombineOverStream)->Apply(SizeArgs)->UseManualTime();
// The compressed kernel's bar (issue 13): RecombineCompressedQ12 (projection
// of the look onto the cluster vectors, then r-long dot products per
// receiver) against a vectorised read of the bytes it reads (its weights and
// cluster vectors), timed alternately like BM_RecombineOverStream; and, in
// the same iterations, the uncompressed path (RecombineQ12 over the int16
// basis of the same terms and receivers) against a vectorised read of its
// bytes. Counters: ratio_simd (compressed / its read), uncompressed_ratio_simd,
// speedup (uncompressed time / compressed time).
// Args: receivers, terms, r, cluster length, weight bits (16, or 8: the
// engine's byte tiles, half the weight bytes for the same arithmetic).
void BM_CompressedRecombineOverStream(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const relight::BakeCompressedBasis cpca =
      MakeCompressed(terms, receivers, static_cast<uint32_t>(state.range(2)),
                     static_cast<uint32_t>(state.range(3)), static_cast<uint8_t>(state.range(4)));
  const std::vector<int16_t> basis = MakeBasis(terms, receivers);
  std::vector<int64_t> coef(terms);
  for (uint32_t t = 0; t < terms; ++t) coef[t] = (int64_t{1000} + 37 * t) << 16;
  std::vector<int32_t> k_terms(size_t{terms} * 3), projection(relight::CompressedProjectionValues(cpca));
  const std::vector<int32_t> k = MakeMultipliers(terms);
  std::vector<int64_t> scratch(3 * 2048);
  std::vector<int32_t> out(static_cast<size_t>(receivers) * 3);
  std::vector<double> cpca_s, cpca_read_s, base_s, base_read_s;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  for (auto _ : state) {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(SumWordsSimd(cpca.weights) + SumWordsSimd(cpca.weights8) + SumWordsSimd(cpca.vectors));
    const auto t1 = Clock::now();
    relight::RecombineCompressedQ12(cpca, static_cast<int>(terms), coef.data(), k_terms.data(),
                                    scratch.data(), static_cast<uint32_t>(scratch.size()),
                                    projection.data(), out.data());
    benchmark::DoNotOptimize(out.data());
    const auto t2 = Clock::now();
    benchmark::DoNotOptimize(SumWordsSimd(basis));
    const auto t3 = Clock::now();
    relight::RecombineQ12(basis.data(), terms, receivers, k.data(), 20, scratch.data(),
                          static_cast<uint32_t>(scratch.size()), out.data());
    benchmark::DoNotOptimize(out.data());
    const auto t4 = Clock::now();
    cpca_read_s.push_back(seconds(t0, t1));
    cpca_s.push_back(seconds(t1, t2));
    base_read_s.push_back(seconds(t2, t3));
    base_s.push_back(seconds(t3, t4));
    state.SetIterationTime(cpca_s.back());
  }
  state.counters["compressed_us"] = Median(cpca_s) * 1e6;
  state.counters["uncompressed_us"] = Median(base_s) * 1e6;
  state.counters["ratio_simd"] = Median(cpca_s) / Median(cpca_read_s);
  state.counters["uncompressed_ratio_simd"] = Median(base_s) / Median(base_read_s);
  state.counters["speedup"] = Median(base_s) / Median(cpca_s);
  state.counters["bytes_ratio"] = static_cast<double>(basis.size() * 2) /
                                  static_cast<double>(cpca.memory_bytes());
}
BENCHMARK(BM_CompressedRecombineOverStream)
    ->Apply(relight_bench::CompressedShapesWithBits)
    ->Unit(benchmark::kMicrosecond)
    ->UseManualTime();

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
// V receivers on a 30 x 30 m floor under a head 6 m up, a wide beam aimed
// somewhere new each iteration (as a chase does), luminance with albedo.
struct DirectScene {
  std::vector<int16_t> direction;
  std::vector<uint32_t> geometry;
  std::vector<uint32_t> rho;
  std::vector<int64_t> lid;
  relight::DirectReceivers rx;
  relight::DirectPoints points;
  std::vector<int32_t> out;
  explicit DirectScene(uint32_t n) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> xy(-15.0, 15.0);
    for (uint32_t i = 0; i < n; ++i) {
      const double d[3] = {xy(rng), xy(rng), -6.0};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double c : d) direction.push_back(static_cast<int16_t>(std::lround(c / len * 16384)));
      geometry.push_back(static_cast<uint32_t>(6.0 / (len * len * len) * 4e9));
    }
    std::vector<uint16_t> albedo(static_cast<size_t>(n) * 3, 40000);
    rho.resize(albedo.size());
    relight::ReflectanceOverPiQ32(albedo.data(), static_cast<uint32_t>(albedo.size()), rho.data());
    for (int i = 0; i <= 180; ++i) lid.push_back(static_cast<int64_t>(20000.0 * std::pow(std::cos(std::min(i, 89) * M_PI / 180), 8) * 65536));
    rx = relight::DirectReceivers{direction.data(), geometry.data(), relight::QuantScale{1 << 29, -31}, n};
    relight::PrepareDirectPoints(rx, &points);
    out.assign(static_cast<size_t>(n) * 3, 0);
  }
};

void AxisOf(int iteration, int32_t axis[3]) {
  // A unit vector swept round the downward cone (Q1.30, from integers only).
  const double a = iteration * 0.37, t = 0.2 + 0.5 * ((iteration * 7) % 10) / 10.0;
  axis[0] = static_cast<int32_t>(std::lround(std::sin(t) * std::cos(a) * (1 << 30)));
  axis[1] = static_cast<int32_t>(std::lround(std::sin(t) * std::sin(a) * (1 << 30)));
  axis[2] = static_cast<int32_t>(std::lround(-std::cos(t) * (1 << 30)));
}

void SetPerVertex(benchmark::State& state, uint32_t n) {
  // Seconds of CPU per vertex: printed as e.g. 4.2n (ns).
  state.counters["per_vertex"] = benchmark::Counter(static_cast<double>(state.iterations()) * n,
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The direct benchmarks' second argument caps the vector level
// (recombine_dispatch.h SimdLevel): 0 the scalar path, 1 AVX2, 3 the CPU's
// best (AVX-512 where it has CD and DQ: direct_aimed_simd.h), so the set in
// one run gives each body's gain.
class DirectPathCap {
 public:
  explicit DirectPathCap(const benchmark::State& state) {
    relight::SetSimdLevelCap(static_cast<relight::SimdLevel>(state.range(1)));
  }
  ~DirectPathCap() { relight::SetSimdLevelCap(relight::SimdLevel::kAvx512Vnni); }
  DirectPathCap(const DirectPathCap&) = delete;
  DirectPathCap& operator=(const DirectPathCap&) = delete;
};

void BM_DirectTerm(benchmark::State& state) {
  const DirectPathCap path(state);
  const uint32_t n = static_cast<uint32_t>(state.range(0));
  DirectScene scene(n);
  const relight::GammaTable& table = relight::SharedGammaTable();
  int i = 0;
  double vector_share = 0;
  for (auto _ : state) {
    int32_t axis[3];
    AxisOf(i++, axis);
    vector_share = relight::DirectLightAimedQ12(scene.points, table, axis, scene.lid.data(), 180, scene.rho.data(),
                                                relight::DirectStore::kWrite, scene.out.data()) / double(n);
    benchmark::DoNotOptimize(scene.out.data());
  }
  SetPerVertex(state, n);
  state.counters["vector_share"] = vector_share;  // receivers the AVX2 body did, of all
}

void BM_DirectTermFull(benchmark::State& state) {
  const uint32_t n = static_cast<uint32_t>(state.range(0));
  DirectScene scene(n);
  int i = 0;
  for (auto _ : state) {
    int32_t axis[3];
    AxisOf(i++, axis);
    relight::DirectLightQ12(scene.rx, axis, scene.lid.data(), 180, scene.rho.data(),
                            relight::DirectStore::kWrite, scene.out.data());
    benchmark::DoNotOptimize(scene.out.data());
  }
  SetPerVertex(state, n);
}

// The stage's case: receivers in raster order on the floor (neighbours in
// the list are neighbours on the floor, as the mesher's are) under the
// profile spot's beam (fixtures/stage.toml: beam 24, field 34 degrees, cut
// to 0 at 1 % of the peak: docs/scene-format.md "beam"), so most receivers
// are past the cut-off and skipped (direct_cull.h). per_vertex counts every
// receiver, lit or not.
void BM_DirectTermBeam(benchmark::State& state) {
  const DirectPathCap path(state);
  const uint32_t n = static_cast<uint32_t>(state.range(0));
  const uint32_t side = static_cast<uint32_t>(std::lround(std::sqrt(static_cast<double>(n))));
  DirectScene scene(0);
  std::vector<int16_t> direction;
  std::vector<uint32_t> geometry;
  for (uint32_t y = 0; y < side; ++y) {
    for (uint32_t x = 0; x < side; ++x) {
      const double d[3] = {-15.0 + 30.0 * x / (side - 1), -15.0 + 30.0 * y / (side - 1), -6.0};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double c : d) direction.push_back(static_cast<int16_t>(std::lround(c / len * 16384)));
      geometry.push_back(static_cast<uint32_t>(6.0 / (len * len * len) * 4e9));
    }
  }
  const uint32_t count = side * side;
  std::vector<uint16_t> albedo(static_cast<size_t>(count) * 3, 40000);
  scene.rho.resize(albedo.size());
  relight::ReflectanceOverPiQ32(albedo.data(), static_cast<uint32_t>(albedo.size()), scene.rho.data());
  const double p = std::log(std::log2(10.0)) / std::log(34.0 / 24.0);
  const double x_end = std::pow(std::log2(100.0), 1.0 / p);
  scene.lid.clear();
  for (int i = 0; i <= 180; ++i) {
    const double x = i / 12.0;  // gamma / (beam / 2)
    scene.lid.push_back(x > x_end ? 0 : static_cast<int64_t>(20000.0 * std::exp(-std::log(2.0) * std::pow(x, p)) * 65536));
  }
  const relight::DirectReceivers rx{direction.data(), geometry.data(), relight::QuantScale{1 << 29, -31}, count};
  relight::PrepareDirectPoints(rx, &scene.points);
  scene.out.assign(static_cast<size_t>(count) * 3, 0);
  const relight::GammaTable& table = relight::SharedGammaTable();
  int i = 0;
  double vector_share = 0;
  for (auto _ : state) {
    int32_t axis[3];
    AxisOf(i++, axis);
    vector_share = relight::DirectLightAimedQ12(scene.points, table, axis, scene.lid.data(), 180, scene.rho.data(),
                                                relight::DirectStore::kAdd, scene.out.data()) / double(count);
    benchmark::DoNotOptimize(scene.out.data());
  }
  SetPerVertex(state, count);
  state.counters["vector_share"] = vector_share;  // of every receiver, lit or not (culled blocks: none)
}

BENCHMARK(BM_DirectTerm)->ArgsProduct({{16384, 100000}, {0, 1, 3}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DirectTermBeam)->ArgsProduct({{16384, 100000}, {0, 1, 3}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DirectTermFull)->Arg(16384)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EngineMove)->Arg(16384)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EngineDimmer)->Arg(16384)->Arg(100000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
