// Data and baselines shared by the recombination benchmarks
// (recombine_bench.cc, recombine_simd_bench.cc): synthetic int16 bases,
// multipliers, compressed bases, and the reads the kernels are held against.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "relight/bake/bake.h"

namespace relight_bench {

// The compressed shapes every compressed benchmark runs (receivers, terms,
// components, cluster size), so the paths and the baseline compare alike.
// Args {receivers, 81 terms, r, 512}, then `bits` (if not 0) as a fifth.
inline void CompressedShapeArgs(benchmark::internal::Benchmark* b, int64_t bits) {
  for (int64_t receivers : {16384, 100000}) {
    for (int64_t r : {8, 16}) {
      if (bits == 0) {
        b->Args({receivers, 81, r, 512});
      } else {
        b->Args({receivers, 81, r, 512, bits});
      }
    }
  }
}
inline void CompressedShapes(benchmark::internal::Benchmark* b) { CompressedShapeArgs(b, 0); }
// The same shapes with a fifth argument, the weights' bits (16, 8).
inline void CompressedShapesWithBits(benchmark::internal::Benchmark* b) {
  CompressedShapeArgs(b, 16);
  CompressedShapeArgs(b, 8);
}

// Smooth-ish random int16 data: what the bake's quantised bases look like to
// the memory system (values do not change the kernel's speed).
inline std::vector<int16_t> MakeBasis(uint32_t terms, uint32_t receivers) {
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

inline uint64_t SumWords(const std::vector<int16_t>& basis) {
  const size_t words = basis.size() * sizeof(int16_t) / sizeof(uint64_t);
  const uint64_t* p = reinterpret_cast<const uint64_t*>(basis.data());
  uint64_t sum = 0;
  for (size_t i = 0; i < words; ++i) sum += p[i];
  return sum;
}

// Per-term, per-channel multipliers spread over +-10^6 (|k| < 2^24: the vector path).
inline std::vector<int32_t> MakeMultipliers(uint32_t terms) {
  std::vector<int32_t> k(static_cast<size_t>(terms) * 3);
  for (size_t i = 0; i < k.size(); ++i) k[i] = static_cast<int32_t>(1000003 * (i + 1) % 2000000) - 1000000;
  return k;
}

// A harder baseline: the same bytes read with 256-bit loads into four
// independent accumulators (what the load ports allow, not just what a plain
// loop gets). Reported beside the plain one, as "ratio_simd".
template <typename T>
__attribute__((target("avx2"))) inline uint64_t SumWordsSimd(const std::vector<T>& basis) {
  const size_t vectors = basis.size() * sizeof(T) / sizeof(__m256i);
  const __m256i* p = reinterpret_cast<const __m256i*>(basis.data());
  __m256i s0 = _mm256_setzero_si256(), s1 = s0, s2 = s0, s3 = s0;
  size_t i = 0;
  for (; i + 4 <= vectors; i += 4) {
    s0 = _mm256_add_epi64(s0, _mm256_loadu_si256(p + i));
    s1 = _mm256_add_epi64(s1, _mm256_loadu_si256(p + i + 1));
    s2 = _mm256_add_epi64(s2, _mm256_loadu_si256(p + i + 2));
    s3 = _mm256_add_epi64(s3, _mm256_loadu_si256(p + i + 3));
  }
  for (; i < vectors; ++i) s0 = _mm256_add_epi64(s0, _mm256_loadu_si256(p + i));
  const __m256i s = _mm256_add_epi64(_mm256_add_epi64(s0, s1), _mm256_add_epi64(s2, s3));
  alignas(32) uint64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), s);
  return lanes[0] + lanes[1] + lanes[2] + lanes[3];
}

inline double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// A compressed basis (bake.h BakeCompressedBasis) of `terms` terms over
// `receivers` in clusters of `cluster` receivers with r components, random
// values in range (values do not change the kernel's speed); weight_bits 8
// gives the engine's byte tiles (weights8) as a CPC8 basis has them.
inline relight::BakeCompressedBasis MakeCompressed(uint32_t terms, uint32_t receivers, uint32_t r,
                                            uint32_t cluster, uint8_t weight_bits = 16) {
  relight::BakeCompressedBasis c;
  c.components = r;
  for (uint32_t s = 0; s < receivers; s += cluster) c.cluster_start.push_back(s);
  c.cluster_start.push_back(receivers);
  const size_t vectors = size_t{c.cluster_count()} * (r + 1);
  c.vectors = MakeBasis(terms, static_cast<uint32_t>(vectors));
  c.vector_scale.assign(size_t{terms} * 3, relight::QuantScale{1 << 29, -20});
  std::mt19937 rng(11);
  const int one = relight::CompressedWeightOne(weight_bits);
  std::uniform_int_distribution<int> w(-one, one);
  c.weight_bits = weight_bits;
  if (weight_bits == 8) {
    c.weights8.resize(size_t{receivers} * r);
    for (int8_t& q : c.weights8) q = static_cast<int8_t>(w(rng));
  } else {
    c.weights.resize(size_t{receivers} * r);
    for (int16_t& q : c.weights) q = static_cast<int16_t>(w(rng));
  }
  c.weight_order = relight::CompressedWeightOrder::kTiles16;  // random values: read as the engine's order
  return c;
}

}  // namespace relight_bench
