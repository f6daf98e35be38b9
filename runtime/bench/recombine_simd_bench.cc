// The recombination kernels' vector paths side by side (issue 13, VNNI):
// every path this CPU has (recombine_dispatch.h: AVX2, AVX-VNNI, AVX-512
// VNNI) timed alternately in the same iterations, each against a vectorised
// read of the bytes it reads (SumWordsSimd), so that "before" (AVX2) and
// "after" (VNNI) come from one run under the same load.
//
//   BM_CompressedRecombinePathsOverStream/receivers/terms/r/cluster
//       RecombineCompressedQ12 per path; counters ratio_simd_<path> (its time
//       / the read of its weights and cluster vectors), <path>_us, and the
//       uncompressed RecombineQ12 over the same terms and receivers per path
//       (unc_ratio_simd_<path>, unc_<path>_us).
//   BM_RecombinePathsOverStream/receivers/terms
//       RecombineQ12 per path against the read of its basis, as
//       BM_RecombineOverStream (recombine_bench.cc) has it for the active path.
//   BM_MixPaths/receivers/luminaires
//       MixLuminairesQ12 (every luminaire's cache, a alone) per path
//       (scalar, AVX2, AVX-512) against a read of the caches.
//
// Built into recombine_bench: --benchmark_filter=Paths selects these.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "compressed_recombine.h"
#include "mix.h"
#include "recombine.h"
#include "recombine_bench_data.h"
#include "recombine_dispatch.h"
#include "relight/bake/bake.h"

namespace {

using Clock = std::chrono::steady_clock;
using relight::SimdLevel;

double Seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// The vector levels this CPU has, lowest first.
std::vector<SimdLevel> VectorLevels(bool compressed) {
  std::vector<SimdLevel> levels;
  for (SimdLevel l : {SimdLevel::kAvx2, SimdLevel::kAvxVnni, SimdLevel::kAvx512Vnni}) {
    // RecombineQ12 has no AVX-VNNI body of its own (that level runs its AVX2 body).
    if (!compressed && l == SimdLevel::kAvxVnni) continue;
    if (relight::CpuSupportsSimdLevel(l)) levels.push_back(l);
  }
  return levels;
}

// Runs fn once per level with the cap set, timing each; restores the cap.
template <typename Fn>
void TimeLevels(const std::vector<SimdLevel>& levels, std::vector<std::vector<double>>* seconds, Fn fn) {
  const SimdLevel before = relight::ActiveSimdLevel();
  for (size_t i = 0; i < levels.size(); ++i) {
    relight::SetSimdLevelCap(levels[i]);
    const auto t0 = Clock::now();
    fn();
    (*seconds)[i].push_back(Seconds(t0, Clock::now()));
  }
  relight::SetSimdLevelCap(before);
}

void BM_CompressedRecombinePathsOverStream(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const relight::BakeCompressedBasis cpca = relight_bench::MakeCompressed(
      terms, receivers, static_cast<uint32_t>(state.range(2)), static_cast<uint32_t>(state.range(3)));
  const std::vector<int16_t> basis = relight_bench::MakeBasis(terms, receivers);
  std::vector<int64_t> coef(terms);
  for (uint32_t t = 0; t < terms; ++t) coef[t] = (int64_t{1000} + 37 * t) << 16;
  std::vector<int32_t> k_terms(size_t{terms} * 3), projection(relight::CompressedProjectionValues(cpca));
  const std::vector<int32_t> k = relight_bench::MakeMultipliers(terms);
  std::vector<int64_t> scratch(3 * 2048);  // what the engine passes
  std::vector<int32_t> out(static_cast<size_t>(receivers) * 3);
  const std::vector<SimdLevel> levels = VectorLevels(true), unc_levels = VectorLevels(false);
  if (levels.empty()) {
    state.SkipWithError("no vector path on this CPU");
    return;
  }
  std::vector<std::vector<double>> cpca_s(levels.size()), base_s(unc_levels.size());
  std::vector<double> cpca_read_s, base_read_s;
  for (auto _ : state) {
    auto t0 = Clock::now();
    benchmark::DoNotOptimize(relight_bench::SumWordsSimd(cpca.weights) + relight_bench::SumWordsSimd(cpca.vectors));
    cpca_read_s.push_back(Seconds(t0, Clock::now()));
    TimeLevels(levels, &cpca_s, [&] {
      relight::RecombineCompressedQ12(cpca, static_cast<int>(terms), coef.data(), k_terms.data(), scratch.data(),
                                      static_cast<uint32_t>(scratch.size()), projection.data(), out.data());
      benchmark::DoNotOptimize(out.data());
    });
    t0 = Clock::now();
    benchmark::DoNotOptimize(relight_bench::SumWordsSimd(basis));
    base_read_s.push_back(Seconds(t0, Clock::now()));
    TimeLevels(unc_levels, &base_s, [&] {
      relight::RecombineQ12(basis.data(), terms, receivers, k.data(), 20, scratch.data(),
                            static_cast<uint32_t>(scratch.size()), out.data());
      benchmark::DoNotOptimize(out.data());
    });
    state.SetIterationTime(cpca_s.back().back());  // the highest level's
  }
  const double read = relight_bench::Median(cpca_read_s), base_read = relight_bench::Median(base_read_s);
  for (size_t i = 0; i < levels.size(); ++i) {
    const std::string name = relight::SimdLevelName(levels[i]);
    state.counters[name + "_us"] = relight_bench::Median(cpca_s[i]) * 1e6;
    state.counters["ratio_simd_" + name] = relight_bench::Median(cpca_s[i]) / read;
  }
  for (size_t i = 0; i < unc_levels.size(); ++i) {
    const std::string name = relight::SimdLevelName(unc_levels[i]);
    state.counters["unc_" + name + "_us"] = relight_bench::Median(base_s[i]) * 1e6;
    state.counters["unc_ratio_simd_" + name] = relight_bench::Median(base_s[i]) / base_read;
  }
  state.counters["ratio_simd"] = relight_bench::Median(cpca_s.back()) / read;
  state.counters["read_us"] = read * 1e6;
}
BENCHMARK(BM_CompressedRecombinePathsOverStream)
    ->Apply(relight_bench::CompressedShapes)
    ->Unit(benchmark::kMicrosecond)
    ->UseManualTime();

void BM_RecombinePathsOverStream(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t terms = static_cast<uint32_t>(state.range(1));
  const std::vector<int16_t> basis = relight_bench::MakeBasis(terms, receivers);
  const std::vector<int32_t> k = relight_bench::MakeMultipliers(terms);
  std::vector<int64_t> scratch(3 * 2048);
  std::vector<int32_t> out(static_cast<size_t>(receivers) * 3);
  const std::vector<SimdLevel> levels = VectorLevels(false);
  if (levels.empty()) {
    state.SkipWithError("no vector path on this CPU");
    return;
  }
  std::vector<std::vector<double>> recombine_s(levels.size());
  std::vector<double> read_s;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(relight_bench::SumWordsSimd(basis));
    read_s.push_back(Seconds(t0, Clock::now()));
    TimeLevels(levels, &recombine_s, [&] {
      relight::RecombineQ12(basis.data(), terms, receivers, k.data(), 20, scratch.data(),
                            static_cast<uint32_t>(scratch.size()), out.data());
      benchmark::DoNotOptimize(out.data());
    });
    state.SetIterationTime(recombine_s.back().back());
  }
  const double read = relight_bench::Median(read_s);
  for (size_t i = 0; i < levels.size(); ++i) {
    const std::string name = relight::SimdLevelName(levels[i]);
    state.counters[name + "_us"] = relight_bench::Median(recombine_s[i]) * 1e6;
    state.counters["ratio_simd_" + name] = relight_bench::Median(recombine_s[i]) / read;
  }
  state.counters["read_us"] = read * 1e6;
}
BENCHMARK(BM_RecombinePathsOverStream)
    ->Args({16384, 36})
    ->Args({16384, 81})
    ->Args({100000, 36})
    ->Args({100000, 81})
    ->Unit(benchmark::kMicrosecond)
    ->UseManualTime();

void BM_MixPaths(benchmark::State& state) {
  const uint32_t receivers = static_cast<uint32_t>(state.range(0));
  const uint32_t luminaires = static_cast<uint32_t>(state.range(1));
  std::vector<std::vector<int16_t>> caches;  // int32 light, held as int16 pairs for SumWordsSimd
  std::vector<relight::MixSource> sources(luminaires);
  for (uint32_t l = 0; l < luminaires; ++l) {
    caches.push_back(relight_bench::MakeBasis(2, receivers * 3 / 2 + 1));
    sources[l].a = reinterpret_cast<const int32_t*>(caches.back().data());
    for (int c = 0; c < 3; ++c) sources[l].gain[c] = relight::Q1_30::FromRaw((1 << 29) + 1000 * static_cast<int32_t>(l + c));
  }
  std::vector<int64_t> scratch(3 * 2048);
  std::vector<int32_t> out(static_cast<size_t>(receivers) * 3);
  std::vector<SimdLevel> levels = {SimdLevel::kScalar};
  for (SimdLevel l : {SimdLevel::kAvx2, SimdLevel::kAvx512Vnni}) {
    if (relight::CpuSupportsSimdLevel(l)) levels.push_back(l);
  }
  std::vector<std::vector<double>> mix_s(levels.size());
  std::vector<double> read_s;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    uint64_t sum = 0;
    for (const auto& c : caches) sum += relight_bench::SumWordsSimd(c);
    benchmark::DoNotOptimize(sum);
    read_s.push_back(Seconds(t0, Clock::now()));
    TimeLevels(levels, &mix_s, [&] {
      relight::MixLuminairesQ12(sources.data(), luminaires, receivers, scratch.data(),
                                static_cast<uint32_t>(scratch.size()), out.data());
      benchmark::DoNotOptimize(out.data());
    });
    state.SetIterationTime(mix_s.back().back());
  }
  const double read = relight_bench::Median(read_s);
  for (size_t i = 0; i < levels.size(); ++i) {
    const std::string name = relight::SimdLevelName(levels[i]);
    state.counters[name + "_us"] = relight_bench::Median(mix_s[i]) * 1e6;
    state.counters["ratio_simd_" + name] = relight_bench::Median(mix_s[i]) / read;
  }
  state.counters["read_us"] = read * 1e6;
}
BENCHMARK(BM_MixPaths)->Args({17533, 52})->Unit(benchmark::kMicrosecond)->UseManualTime();

}  // namespace
