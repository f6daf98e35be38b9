// BM_CompressedRecombineBakeOverStream: the Kernel bar of issue 13 on a real
// bake's compressed bases instead of synthetic ones -- every luminaire's
// surface basis recombined as a full update does (all heads moved), against
// a vectorised read of the bytes those recombinations read (weights and
// cluster vectors), timed alternately within each iteration like
// BM_CompressedRecombineOverStream. The bake comes from the environment:
//
//   RELIGHT_BENCH_BAKE=/path/stage.rlb recombine_bench --benchmark_filter=Bake
//
// (skipped with a message without it). Counters: ratio_simd (median kernel
// time over median read time), bytes (read per iteration), luminaires,
// eight_bit (how many bases have 8-bit weights), mean_r (components, mean
// over the bases weighted by receivers), cluster_receivers (receivers per
// cluster, mean), vector_share (of the bytes, the cluster vectors').
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "compressed_recombine.h"
#include "compressed_tiles.h"
#include "recombine_bench_data.h"
#include "relight/bake/bake.h"
#include "relight/base/sh_index.h"

namespace {

using relight_bench::Median;
using relight_bench::SumWordsSimd;

void BM_CompressedRecombineBakeOverStream(benchmark::State& state) {
  const char* path = std::getenv("RELIGHT_BENCH_BAKE");
  if (path == nullptr) {
    state.SkipWithError("set RELIGHT_BENCH_BAKE to a bake with compressed bases");
    return;
  }
  relight::Bake bake;
  relight::ReadBakeOptions read;
  read.hierarchy = false;
  read.grids = false;  // surfaces only, as relightd reads the stage
  const relight::Status st = relight::ReadBake(path, read, &bake);
  if (!st.ok()) {
    state.SkipWithError(st.ToString().c_str());
    return;
  }
  std::vector<relight::BakeCompressedBasis*> bases;
  std::vector<int> terms;
  double bytes = 0, r_weighted = 0, receivers = 0, clusters = 0, vector_bytes = 0;
  int eight_bit = 0;
  size_t most_terms = 0, most_projection = 0, most_receivers = 0;
  for (relight::BakeLuminaire& lum : bake.luminaires) {
    relight::BakeCompressedBasis& c = lum.receivers[0].compressed;
    if (!c.present()) continue;
    relight::TileCompressedWeights(&c);
    bases.push_back(&c);
    terms.push_back(relight::ShTermCount(lum.sh_degree));
    bytes += static_cast<double>(c.weights.size() * 2 + c.weights8.size() + c.vectors.size() * 2);
    const uint32_t n = c.cluster_start.back();
    r_weighted += static_cast<double>(c.components) * n;
    receivers += n;
    clusters += c.cluster_count();
    vector_bytes += static_cast<double>(c.vectors.size() * 2);
    eight_bit += c.weight_bits == 8 ? 1 : 0;
    most_terms = std::max(most_terms, static_cast<size_t>(terms.back()));
    most_projection = std::max(most_projection, static_cast<size_t>(relight::CompressedProjectionValues(c)));
    most_receivers = std::max(most_receivers, static_cast<size_t>(n));
  }
  if (bases.empty()) {
    state.SkipWithError("the bake has no compressed bases");
    return;
  }
  std::vector<int64_t> coef(most_terms);
  for (size_t t = 0; t < coef.size(); ++t) coef[t] = (int64_t{1000} + 37 * static_cast<int64_t>(t)) << 16;
  std::vector<int32_t> k_terms(most_terms * 3), projection(most_projection);
  std::vector<int64_t> scratch(3 * 2048);
  std::vector<int32_t> out(most_receivers * 3);
  using Clock = std::chrono::steady_clock;
  std::vector<double> kernel_s, read_s;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    uint64_t sum = 0;
    for (const relight::BakeCompressedBasis* c : bases)
      sum += SumWordsSimd(c->weights) + SumWordsSimd(c->weights8) + SumWordsSimd(c->vectors);
    benchmark::DoNotOptimize(sum);
    const auto t1 = Clock::now();
    for (size_t i = 0; i < bases.size(); ++i) {
      relight::RecombineCompressedQ12(*bases[i], terms[i], coef.data(), k_terms.data(), scratch.data(),
                                      static_cast<uint32_t>(scratch.size()), projection.data(), out.data());
      benchmark::DoNotOptimize(out.data());
    }
    const auto t2 = Clock::now();
    read_s.push_back(std::chrono::duration<double>(t1 - t0).count());
    kernel_s.push_back(std::chrono::duration<double>(t2 - t1).count());
    state.SetIterationTime(kernel_s.back());
  }
  state.counters["compressed_us"] = Median(kernel_s) * 1e6;
  state.counters["read_us"] = Median(read_s) * 1e6;
  state.counters["ratio_simd"] = Median(kernel_s) / Median(read_s);
  state.counters["bytes"] = bytes;
  state.counters["luminaires"] = static_cast<double>(bases.size());
  state.counters["eight_bit"] = eight_bit;
  state.counters["mean_r"] = r_weighted / receivers;
  // Receivers per cluster (each cluster pays its multipliers' set-up) and
  // the share of the bytes in the cluster vectors the projection reads.
  state.counters["cluster_receivers"] = receivers / clusters;
  state.counters["vector_share"] = vector_bytes / bytes;
}
BENCHMARK(BM_CompressedRecombineBakeOverStream)->Unit(benchmark::kMicrosecond)->UseManualTime();

}  // namespace
