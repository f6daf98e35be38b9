// Recombination of a compressed basis: see compressed_recombine.h for the
// steps and the scaling and overflow.
#include "compressed_recombine.h"

#include <cstddef>

#include "compressed_recombine_avx2.h"
#include "recombine.h"
#include "recombine_avx2.h"
#include "relight/base/status.h"
#include "weights.h"

namespace relight {
namespace {

constexpr int32_t kMeanLimit = (int32_t{1} << 30) - 1;
constexpr int kMaxClusterShift = 31;

// round(a 2^s / kCompressedWeightOne) for a >= 0, halves up; a < 2^31, s <= 31: < 2^62.
int64_t ScaledMagnitude(int64_t a, int s) {
  const int64_t num = a << s;
  return (num + kCompressedWeightOne / 2) / kCompressedWeightOne;
}

}  // namespace

int32_t CompressedMultiplierLimit(uint32_t components) {
  if (components == 0) return kCompressedWeightOne;
  const int64_t limit = ((int64_t{1} << 30) - 1) / (int64_t{components} * kCompressedWeightOne);
  return limit < kCompressedWeightOne ? static_cast<int32_t>(limit) : kCompressedWeightOne;
}

void ClusterMultipliersQ12(const int32_t* projection, uint32_t components, ClusterMultipliers* m) {
  const int64_t limit = CompressedMultiplierLimit(components);
  for (int ch = 0; ch < 3; ++ch) {
    const int32_t mean = projection[ch];
    m->mean[ch] = mean > kMeanLimit ? kMeanLimit : (mean < -kMeanLimit ? -kMeanLimit : mean);
    int64_t largest = 0;
    for (uint32_t j = 0; j < components; ++j) {
      const int64_t p = projection[(1 + j) * 3 + ch];
      const int64_t a = p < 0 ? -p : p;
      if (a > largest) largest = a;
    }
    int s = kMaxClusterShift;
    while (s > 0 && ScaledMagnitude(largest, s) > limit) --s;
    m->shift[ch] = s;
    for (uint32_t j = 0; j < components; ++j) {
      const int64_t p = projection[(1 + j) * 3 + ch];
      int64_t k = ScaledMagnitude(p < 0 ? -p : p, s);
      if (k > limit) k = limit;  // only at s = 0: saturated (see the header)
      m->k[ch * components + j] = static_cast<int16_t>(p < 0 ? -k : k);
    }
  }
}

void CompressedClusterScalarQ12(const int16_t* w, uint32_t n, uint32_t components,
                                const ClusterMultipliers& m, int32_t* out) {
  for (int ch = 0; ch < 3; ++ch) {
    const int16_t* k = m.k + ch * components;
    const int s = m.shift[ch];
    const int32_t half = s > 0 ? int32_t{1} << (s - 1) : 0;
    for (uint32_t i = 0; i < n; ++i) {
      int32_t acc = 0;  // exact: |acc| < 2^30 (see the header)
      for (uint32_t j = 0; j < components; ++j) acc += int32_t{w[size_t{j} * n + i]} * k[j];
      out[size_t{i} * 3 + ch] = m.mean[ch] + ((acc + half) >> s);
    }
  }
}

void CompressedClusterQ12(const int16_t* w, uint32_t n, uint32_t components,
                          const ClusterMultipliers& m, int32_t* out) {
  uint32_t done = 0;
  if (CpuHasAvx2() && n >= 16) {
    done = n - n % 16;
    CompressedClusterAvx2Q12(w, n, components, m, out);
  }
  if (done == n) return;
  // The tail: same integers on the scalar path, weights still at stride n.
  for (int ch = 0; ch < 3; ++ch) {
    const int16_t* k = m.k + ch * components;
    const int s = m.shift[ch];
    const int32_t half = s > 0 ? int32_t{1} << (s - 1) : 0;
    for (uint32_t i = done; i < n; ++i) {
      int32_t acc = 0;
      for (uint32_t j = 0; j < components; ++j) acc += int32_t{w[size_t{j} * n + i]} * k[j];
      out[size_t{i} * 3 + ch] = m.mean[ch] + ((acc + half) >> s);
    }
  }
}

uint64_t CompressedProjectionValues(const BakeCompressedBasis& cpca) {
  return 3 * uint64_t{cpca.cluster_count()} * (cpca.components + 1);
}

uint32_t RecombineCompressedQ12(const BakeCompressedBasis& cpca, int terms, const int64_t* coef_q16,
                                int32_t* k_terms, int64_t* scratch, uint32_t scratch_len,
                                int32_t* projection, int32_t* out) {
  const uint32_t r = cpca.components;
  RELIGHT_CHECK(r <= kMaxCompressedComponents);
  const uint32_t vectors = cpca.cluster_count() * (r + 1);
  const int shift = ChannelMultipliersQ12(coef_q16, terms, cpca.vector_scale.data(), k_terms);
  const uint32_t used = RecombineQ12(cpca.vectors.data(), static_cast<uint32_t>(terms), vectors,
                                     k_terms, shift, scratch, scratch_len, projection);
  ClusterMultipliers m;
  for (uint32_t c = 0; c < cpca.cluster_count(); ++c) {
    const uint32_t start = cpca.cluster_start[c], n = cpca.cluster_start[c + 1] - start;
    ClusterMultipliersQ12(projection + size_t{c} * (r + 1) * 3, r, &m);
    CompressedClusterQ12(cpca.weights.data() + size_t{start} * r, n, r, m, out + size_t{start} * 3);
  }
  return used;
}

}  // namespace relight
