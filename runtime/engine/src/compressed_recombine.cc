// Recombination of a compressed basis: see compressed_recombine.h for the
// steps and the scaling and overflow.
#include "compressed_recombine.h"

#include <cstddef>
#include <cstdint>

#include "compressed_multipliers_avx512.h"
#include "compressed_recombine_avx2.h"
#include "compressed_recombine_vnni.h"
#include "compressed_tiles.h"
#include "recombine.h"
#include "recombine_dispatch.h"
#include "relight/base/status.h"
#include "weights.h"

namespace relight {
namespace {

constexpr int32_t kMeanLimit = (int32_t{1} << 30) - 1;
constexpr int kMaxClusterShift = 31;

constexpr int kMinClusterShift = -31;

// round(a 2^s / one) for 0 <= a <= 2^31 and `one` a weight of 1 (16383 or
// 127), halves up; for s >= 0 a 2^s <= 2^62, for s < 0 the divisor
// one 2^-s < 2^45: no overflow. `One` a template argument when it is one
// of the two weights of 1: the compiler then divides by a multiply and a
// shift (the same quotient), where a division by a variable costs tens of
// cycles and a cluster's multipliers take 3 (r + 1) of them.
template <int64_t kOne = 0>
int64_t ScaledMagnitude(int64_t a, int s, int64_t one) {
  if constexpr (kOne != 0) one = kOne;
  if (s >= 0) return ((a << s) + one / 2) / one;
  const int64_t d = one << -s;
  return (a + d / 2) / d;
}

// mean + the rounded shifted sum, as the header defines it for any shift.
inline int32_t Finish(int32_t mean, int32_t acc, int s) {
  if (s >= 0) {
    const int32_t half = s > 0 ? int32_t{1} << (s - 1) : 0;
    return mean + ((acc + half) >> s);
  }
  const int64_t v = int64_t{mean} + int64_t{acc} * (int64_t{1} << -s);  // |v| < 2^62
  return v > INT32_MAX ? INT32_MAX : (v < INT32_MIN ? INT32_MIN : static_cast<int32_t>(v));
}

int BitLength(uint64_t v) { return v == 0 ? 0 : 64 - __builtin_clzll(v); }

// The largest s in [-31, 31] with ScaledMagnitude(a, s, one) <= limit (-31
// if none), which is non-decreasing in s. Found from the bit lengths, then a
// step or two down, not by walking from 31 with a division a step: any s
// with a 2^s >= 2^bits(one) (limit + 1) gives more than the limit, and
// a >= 2^(bits(a) - 1), so the answer is at most
// bits(one) + bits(limit + 1) - bits(a).
template <int64_t kOne>
int LargestShift(int64_t a, int64_t limit, int64_t one) {
  if (a == 0) return kMaxClusterShift;
  int s = BitLength(static_cast<uint64_t>(one)) + BitLength(static_cast<uint64_t>(limit) + 1) -
          BitLength(static_cast<uint64_t>(a));
  s = s > kMaxClusterShift ? kMaxClusterShift : (s < kMinClusterShift ? kMinClusterShift : s);
  while (s > kMinClusterShift && ScaledMagnitude<kOne>(a, s, one) > limit) --s;
  return s;
}

template <typename W>
void ClusterTail(const W* w, uint32_t from, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                 int32_t* out) {
  const uint32_t pairs = components / 2;
  for (uint32_t i = from; i < n; ++i) {
    // Receiver i's tile (compressed_tiles.h): `width` receivers, i its q-th.
    const uint32_t first = i - i % kWeightTile, q = i % kWeightTile;
    const uint32_t width = n - first < kWeightTile ? n - first : kWeightTile;
    const W* tile = w + size_t{first} * components;
    for (int ch = 0; ch < 3; ++ch) {
      const int16_t* k = m.k + ch * components;
      int32_t acc = 0;  // exact: |acc| < 2^30 (see the header)
      for (uint32_t p = 0; p < pairs; ++p) {
        const W* pair = tile + size_t{p} * 2 * width + 2 * q;
        acc += int32_t{pair[0]} * k[2 * p] + int32_t{pair[1]} * k[2 * p + 1];
      }
      if (components % 2 != 0) acc += int32_t{tile[size_t{pairs} * 2 * width + q]} * k[components - 1];
      out[size_t{i} * 3 + ch] = Finish(m.mean[ch], acc, m.shift[ch]);
    }
  }
}

template <typename W>
void ClusterOnActivePath(const W* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                         int32_t* out) {
  uint32_t done = 0;
  const SimdLevel level = ActiveSimdLevel();
  if (level == SimdLevel::kAvx512Vnni) {
    CompressedClusterAvx512VnniQ12(w, n, components, m, out);  // every receiver and shift, tail masked
    return;
  }
  // Negative shifts (saturating left shifts: bright clusters, mostly with
  // 8-bit weights) take the AVX2 body, which has them; AVX-VNNI's does not.
  const bool left = m.shift[0] < 0 || m.shift[1] < 0 || m.shift[2] < 0;
  if (level >= SimdLevel::kAvx2 && n >= 16) {
    done = n - n % 16;
    if (level == SimdLevel::kAvxVnni && !left) {
      CompressedClusterAvxVnniQ12(w, n, components, m, out);
    } else {
      CompressedClusterAvx2Q12(w, n, components, m, out);
    }
  }
  // The tail (the cluster's last, short tile): same integers on the scalar path.
  if (done < n) ClusterTail(w, done, n, components, m, out);
}

}  // namespace

int32_t CompressedMultiplierLimit(uint32_t components, int32_t weight_one) {
  if (components == 0) return kCompressedWeightOne;
  const int64_t limit = ((int64_t{1} << 30) - 1) / (int64_t{components} * weight_one);
  return limit < kCompressedWeightOne ? static_cast<int32_t>(limit) : kCompressedWeightOne;
}

namespace {

template <int64_t kOne>
void MultipliersFor(const int32_t* projection, uint32_t components, int32_t weight_one, ClusterMultipliers* m) {
  const int64_t limit = CompressedMultiplierLimit(components, weight_one);
  for (int ch = 0; ch < 3; ++ch) {
    m->mean[ch] = ClusterMeanQ12(projection[ch]);
    int64_t largest = 0;
    for (uint32_t j = 0; j < components; ++j) {
      const int64_t p = projection[(1 + j) * 3 + ch];
      const int64_t a = p < 0 ? -p : p;
      if (a > largest) largest = a;
    }
    const int s = LargestShift<kOne>(largest, limit, weight_one);
    m->shift[ch] = s;
    for (uint32_t j = 0; j < components; ++j) {
      const int64_t p = projection[(1 + j) * 3 + ch];
      int64_t k = ScaledMagnitude<kOne>(p < 0 ? -p : p, s, weight_one);
      if (k > limit) k = limit;  // never for |P| < 2^31 at s = -31; kept as a guard
      m->k[ch * components + j] = static_cast<int16_t>(p < 0 ? -k : k);
    }
  }
}

}  // namespace

void ClusterMultipliersQ12(const int32_t* projection, uint32_t components, int32_t weight_one,
                           ClusterMultipliers* m) {
  if (weight_one == kCompressedWeightOne8) return MultipliersFor<kCompressedWeightOne8>(projection, components, weight_one, m);
  if (weight_one == kCompressedWeightOne) return MultipliersFor<kCompressedWeightOne>(projection, components, weight_one, m);
  MultipliersFor<0>(projection, components, weight_one, m);
}

int32_t ClusterMeanQ12(int32_t projected_mean) {
  return projected_mean > kMeanLimit ? kMeanLimit : (projected_mean < -kMeanLimit ? -kMeanLimit : projected_mean);
}

int ClusterShiftQ12(int64_t largest, uint32_t components, int32_t weight_one) {
  const int64_t limit = CompressedMultiplierLimit(components, weight_one);
  if (weight_one == kCompressedWeightOne8) return LargestShift<kCompressedWeightOne8>(largest, limit, weight_one);
  if (weight_one == kCompressedWeightOne) return LargestShift<kCompressedWeightOne>(largest, limit, weight_one);
  return LargestShift<0>(largest, limit, weight_one);
}

void CompressedClusterScalarQ12(const int16_t* w, uint32_t n, uint32_t components,
                                const ClusterMultipliers& m, int32_t* out) {
  ClusterTail(w, 0, n, components, m, out);
}
void CompressedClusterScalarQ12(const int8_t* w, uint32_t n, uint32_t components,
                                const ClusterMultipliers& m, int32_t* out) {
  ClusterTail(w, 0, n, components, m, out);
}

void CompressedClusterTailQ12(const int16_t* w, uint32_t from, uint32_t n, uint32_t components,
                              const ClusterMultipliers& m, int32_t* out) {
  ClusterTail(w, from, n, components, m, out);
}
void CompressedClusterTailQ12(const int8_t* w, uint32_t from, uint32_t n, uint32_t components,
                              const ClusterMultipliers& m, int32_t* out) {
  ClusterTail(w, from, n, components, m, out);
}

void CompressedClusterQ12(const int16_t* w, uint32_t n, uint32_t components,
                          const ClusterMultipliers& m, int32_t* out) {
  ClusterOnActivePath(w, n, components, m, out);
}
void CompressedClusterQ12(const int8_t* w, uint32_t n, uint32_t components,
                          const ClusterMultipliers& m, int32_t* out) {
  ClusterOnActivePath(w, n, components, m, out);
}

uint64_t CompressedProjectionValues(const BakeCompressedBasis& cpca) {
  return 3 * uint64_t{cpca.cluster_count()} * (cpca.components + 1);
}

namespace {

// Steps 2 and 3 for one cluster. On AVX-512 the multipliers come from
// vectors straight in the kernel's packed form; a cluster with a negative
// shift, or another level, takes the scalar multipliers.
template <typename W>
void ClusterFromProjection(const int32_t* projection, const W* w, uint32_t n, uint32_t r, int32_t one, bool avx512,
                           int32_t* out) {
  PackedClusterMultipliers packed;
  if (avx512 && ClusterMultipliersAvx512(projection, r, one, &packed))
    return CompressedClusterPackedAvx512VnniQ12(w, n, r, packed, out);
  ClusterMultipliers m;
  ClusterMultipliersQ12(projection, r, one, &m);
  ClusterOnActivePath(w, n, r, m, out);
}

}  // namespace

uint32_t RecombineCompressedQ12(const BakeCompressedBasis& cpca, int terms, const int64_t* coef_q16,
                                int32_t* k_terms, int64_t* scratch, uint32_t scratch_len,
                                int32_t* projection, int32_t* out) {
  const uint32_t r = cpca.components;
  RELIGHT_CHECK(r <= kMaxCompressedComponents && cpca.weight_order == CompressedWeightOrder::kTiles16);
  const uint32_t vectors = cpca.cluster_count() * (r + 1);
  const int shift = ChannelMultipliersQ12(coef_q16, terms, cpca.vector_scale.data(), k_terms);
  const uint32_t used = RecombineQ12(cpca.vectors.data(), static_cast<uint32_t>(terms), vectors,
                                     k_terms, shift, scratch, scratch_len, projection);
  const int32_t one = CompressedWeightOne(cpca.weight_bits);
  const bool avx512 = ActiveSimdLevel() == SimdLevel::kAvx512Vnni;
  for (uint32_t c = 0; c < cpca.cluster_count(); ++c) {
    const uint32_t start = cpca.cluster_start[c], n = cpca.cluster_start[c + 1] - start;
    const size_t first = size_t{start} * r;
    const int32_t* cluster_projection = projection + size_t{c} * (r + 1) * 3;
    int32_t* cluster_out = out + size_t{start} * 3;
    if (cpca.weight_bits == 8) {
      ClusterFromProjection(cluster_projection, cpca.weights8.data() + first, n, r, one, avx512, cluster_out);
    } else {
      ClusterFromProjection(cluster_projection, cpca.weights.data() + first, n, r, one, avx512, cluster_out);
    }
  }
  return used;
}

}  // namespace relight
