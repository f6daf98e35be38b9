// ClusterMultipliersQ12 in vectors: see compressed_multipliers_avx512.h.
//
// The division by the weight of 1: q = (x M) >> K, M = ceil(2^K / one), is
// floor(x / one) for x < 2^K / (one (M - 2^K / one)):
//   one = 127:   K = 38, M = 2164392969 (2^38 / 127 = 2164392968.063),
//                bound 2^38 / (127 x 0.937) = 4.3 x 2^29;
//   one = 16383: K = 45, M = 2147614729 (2^45 / 16383 = 2147614728.0005),
//                bound 2^45 / (16383 x 0.9995) = 4.0 x 2^29.
// x < 2^29 and M < 2^32, so x M < 2^61 (vpmuludq, 32 x 32 -> 64).
#include "compressed_multipliers_avx512.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include "compressed_recombine_interleave.h"  // x86-64 only (immintrin.h)
#define RELIGHT_HAVE_AVX512_PATH 1
// GCC 12's AVX-512 headers fill unused merge operands with
// _mm512_undefined_*(), which -Wmaybe-uninitialized and -Wuninitialized
// report once inlined (a header artefact: every lane is written).
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#define RELIGHT_TARGET_AVX512 __attribute__((target("avx2,avx512f,avx512bw,avx512vl")))
#endif

namespace relight {

#ifdef RELIGHT_HAVE_AVX512_PATH

namespace {

// The projection's values after the mean, component j's channel ch at
// 3 j + ch, sixteen a vector: vector c's lane l is channel (c + l) mod 3
// (16 = 1 mod 3). kChannelLanes[c mod 3][ch]: the lanes of channel ch.
struct ChannelLanes {
  uint16_t mask[3][3];
  constexpr ChannelLanes() : mask() {
    for (int phase = 0; phase < 3; ++phase)
      for (int l = 0; l < 16; ++l) mask[phase][(phase + l) % 3] = static_cast<uint16_t>(mask[phase][(phase + l) % 3] | (1u << l));
  }
};
constexpr ChannelLanes kChannelLanes;

template <uint64_t kM, int kK>
RELIGHT_TARGET_AVX512 inline __m512i Divide(__m512i x) {
  const __m512i m = _mm512_set1_epi64(static_cast<long long>(kM));
  const __m512i even = _mm512_srli_epi64(_mm512_mul_epu32(x, m), kK);
  const __m512i odd = _mm512_srli_epi64(_mm512_mul_epu32(_mm512_srli_epi64(x, 32), m), kK);
  return _mm512_or_si512(even, _mm512_slli_epi64(odd, 32));  // each quotient < 2^23
}

template <int32_t kOne, uint64_t kM, int kK>
RELIGHT_TARGET_AVX512 bool Multipliers(const int32_t* projection, uint32_t components, PackedClusterMultipliers* m) {
  const uint32_t values = 3 * components;
  const int32_t* p = projection + 3;
  const uint32_t vectors = (values + 15) / 16;
  __m512i largest[3] = {_mm512_setzero_si512(), _mm512_setzero_si512(), _mm512_setzero_si512()};
  for (uint32_t c = 0; c < vectors; ++c) {
    const uint32_t left = values - 16 * c;
    const __mmask16 lanes = left >= 16 ? __mmask16{0xFFFF} : static_cast<__mmask16>((1u << left) - 1);
    // |INT32_MIN| is 2^31 as an unsigned lane, as the scalar path's int64.
    const __m512i a = _mm512_abs_epi32(_mm512_maskz_loadu_epi32(lanes, p + 16 * c));
    for (int ch = 0; ch < 3; ++ch)
      largest[ch] = _mm512_mask_max_epu32(largest[ch], kChannelLanes.mask[c % 3][ch] & lanes, largest[ch], a);
  }
  int shift[3];
  for (int ch = 0; ch < 3; ++ch) {
    shift[ch] = ClusterShiftQ12(_mm512_reduce_max_epu32(largest[ch]), components, kOne);
    if (shift[ch] < 0) return false;
    m->mean[ch] = ClusterMeanQ12(projection[ch]);
    m->shift[ch] = shift[ch];
  }
  alignas(64) int32_t k[3 * kMaxCompressedComponents];
  const __m512i half = _mm512_set1_epi32(kOne / 2);
  const __m512i limit = _mm512_set1_epi32(CompressedMultiplierLimit(components, kOne));
  const __m512i s0 = _mm512_set1_epi32(shift[0]), s1 = _mm512_set1_epi32(shift[1]), s2 = _mm512_set1_epi32(shift[2]);
  for (uint32_t c = 0; c < vectors; ++c) {
    const uint32_t left = values - 16 * c;
    const __mmask16 lanes = left >= 16 ? __mmask16{0xFFFF} : static_cast<__mmask16>((1u << left) - 1);
    const __m512i v = _mm512_maskz_loadu_epi32(lanes, p + 16 * c);
    const uint16_t* mask = kChannelLanes.mask[c % 3];
    const __m512i s = _mm512_mask_blend_epi32(mask[2], _mm512_mask_blend_epi32(mask[1], s0, s1), s2);
    // |P| 2^s < 2^28 in every lane (see the header), so the 32-bit shift
    // cannot lose bits and the dividend is below 2^29.
    const __m512i x = _mm512_add_epi32(_mm512_sllv_epi32(_mm512_abs_epi32(v), s), half);
    const __m512i q = _mm512_min_epu32(Divide<kM, kK>(x), limit);
    const __mmask16 negative = _mm512_cmplt_epi32_mask(v, _mm512_setzero_si512());
    _mm512_store_si512(k + 16 * c, _mm512_mask_sub_epi32(q, negative, _mm512_setzero_si512(), q));
  }
  const uint32_t pairs = components / 2;
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t j = 0; j < pairs; ++j)
      m->packed[ch][j] = cpca_simd::PackPair(static_cast<int16_t>(k[6 * j + ch]), static_cast<int16_t>(k[6 * j + 3 + ch]));
    if (components % 2 != 0)
      m->packed[ch][pairs] = cpca_simd::PackPair(static_cast<int16_t>(k[3 * (components - 1) + ch]), 0);
  }
  return true;
}

}  // namespace

bool ClusterMultipliersAvx512(const int32_t* projection, uint32_t components, int32_t weight_one,
                              PackedClusterMultipliers* m) {
  if (components > kMaxCompressedComponents) return false;
  if (weight_one == kCompressedWeightOne8) return Multipliers<kCompressedWeightOne8, 2164392969u, 38>(projection, components, m);
  if (weight_one == kCompressedWeightOne) return Multipliers<kCompressedWeightOne, 2147614729u, 45>(projection, components, m);
  return false;
}

#else  // no AVX-512 path on this target

bool ClusterMultipliersAvx512(const int32_t*, uint32_t, int32_t, PackedClusterMultipliers*) { return false; }

#endif

}  // namespace relight
