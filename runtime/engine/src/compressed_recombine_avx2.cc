// AVX2 body of CompressedClusterQ12: see compressed_recombine_avx2.h.
// Integer instructions only (madd of int16 pairs, int32 adds and shifts,
// permutes and blends).
#include "compressed_recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include "compressed_recombine_interleave.h"

namespace relight {
using cpca_simd::LoadLast256;
using cpca_simd::LoadPairs256;
using cpca_simd::PairMultipliers;
using cpca_simd::StoreInterleaved;

namespace {

// Finish() for a negative shift, eight receivers: mean + acc 2^k saturated
// to int32, k = -shift in 1..31. |acc| < 2^30 (the header's bound), so
// acc 2^k < 2^61 and the sum fits int64 lanes; each lane is clamped to the
// int32 range, then the low halves are gathered in receiver order.
__attribute__((target("avx2"), always_inline)) inline __m256i Saturate32(__m256i x) {
  const __m256i top = _mm256_set1_epi64x(INT32_MAX), bottom = _mm256_set1_epi64x(INT32_MIN);
  x = _mm256_blendv_epi8(x, top, _mm256_cmpgt_epi64(x, top));
  return _mm256_blendv_epi8(x, bottom, _mm256_cmpgt_epi64(bottom, x));
}

__attribute__((target("avx2"), always_inline)) inline __m256i FinishLeft(__m256i acc, __m256i mean64, __m128i k) {
  const __m256i lo = _mm256_add_epi64(mean64, _mm256_sll_epi64(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(acc)), k));
  const __m256i hi =
      _mm256_add_epi64(mean64, _mm256_sll_epi64(_mm256_cvtepi32_epi64(_mm256_extracti128_si256(acc, 1)), k));
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  return _mm256_permute2x128_si256(_mm256_permutevar8x32_epi32(Saturate32(lo), low_halves),
                                   _mm256_permutevar8x32_epi32(Saturate32(hi), low_halves), 0x20);
}

// A tile's six sums, one per channel for receivers i0 + 0..7 (lo) and
// i0 + 8..15 (hi). Named members, not arrays indexed by channel: with
// lo[3] / hi[3] GCC kept the sums on the stack and ran the channels as a
// loop, so every add waited on a store-to-load round trip (perf on the
// stage show: the loop's adds and pointer bumps held most of the kernel's
// samples). Inlined, the members stay in registers.
struct TileSums {
  __m256i lo0, lo1, lo2, hi0, hi1, hi2;
};

// One pair of components: a (receivers 0..7) and c (8..15) times the
// pair's multiplier in each channel, added to the sums.
__attribute__((target("avx2"), always_inline)) inline void AddPair(__m256i a, __m256i c, __m256i k0, __m256i k1,
                                                                  __m256i k2, TileSums* s) {
  s->lo0 = _mm256_add_epi32(s->lo0, _mm256_madd_epi16(a, k0));
  s->hi0 = _mm256_add_epi32(s->hi0, _mm256_madd_epi16(c, k0));
  s->lo1 = _mm256_add_epi32(s->lo1, _mm256_madd_epi16(a, k1));
  s->hi1 = _mm256_add_epi32(s->hi1, _mm256_madd_epi16(c, k1));
  s->lo2 = _mm256_add_epi32(s->lo2, _mm256_madd_epi16(a, k2));
  s->hi2 = _mm256_add_epi32(s->hi2, _mm256_madd_epi16(c, k2));
}

template <typename W>
__attribute__((target("avx2"))) void ClusterAvx2(const W* w, uint32_t n, uint32_t components,
                                                 const ClusterMultipliers& m, int32_t* out) {
  const uint32_t pairs = components / 2;
  const bool odd = components % 2 != 0;
  int32_t packed[3][kMaxCompressedComponents / 2 + 1];
  PairMultipliers(m, components, packed);
  __m256i k[3][kMaxCompressedComponents / 2 + 1];
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t p = 0; p < (components + 1) / 2; ++p) k[ch][p] = _mm256_set1_epi32(packed[ch][p]);
  }
  __m256i half[3], mean[3], mean64[3];
  __m128i shift[3];
  bool left[3];  // a negative shift: the sum scaled up, saturated (bright clusters)
  for (int ch = 0; ch < 3; ++ch) {
    const int s = m.shift[ch];
    left[ch] = s < 0;
    half[ch] = _mm256_set1_epi32(s > 0 ? int32_t{1} << (s - 1) : 0);
    mean[ch] = _mm256_set1_epi32(m.mean[ch]);
    mean64[ch] = _mm256_set1_epi64x(m.mean[ch]);
    shift[ch] = _mm_cvtsi32_si128(left[ch] ? -s : s);
  }
  const uint32_t tiles = n / 16;  // full tiles (compressed_tiles.h): 16 receivers x r weights
  for (uint32_t b = 0; b < tiles; ++b) {
    const uint32_t i0 = 16 * b;
    const W* tile = w + size_t{i0} * components;
    const __m256i zero = _mm256_setzero_si256();
    TileSums s{zero, zero, zero, zero, zero, zero};
    for (uint32_t p = 0; p < pairs; ++p) {
      AddPair(LoadPairs256(tile + 32 * p), LoadPairs256(tile + 32 * p + 16), k[0][p], k[1][p], k[2][p], &s);
    }
    if (odd) {
      const W* last = tile + 32 * pairs;
      AddPair(LoadLast256(last), LoadLast256(last + 8), k[0][pairs], k[1][pairs], k[2][pairs], &s);
    }
    const __m256i lo[3] = {s.lo0, s.lo1, s.lo2}, hi[3] = {s.hi0, s.hi1, s.hi2};
    __m256i first[3], second[3];  // receivers i0 + 0..7, i0 + 8..15
    for (int ch = 0; ch < 3; ++ch) {
      if (left[ch]) {
        first[ch] = FinishLeft(lo[ch], mean64[ch], shift[ch]);
        second[ch] = FinishLeft(hi[ch], mean64[ch], shift[ch]);
        continue;
      }
      first[ch] = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(_mm256_add_epi32(lo[ch], half[ch]), shift[ch]));
      second[ch] = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(_mm256_add_epi32(hi[ch], half[ch]), shift[ch]));
    }
    StoreInterleaved(first[0], first[1], first[2], out + size_t{i0} * 3);
    StoreInterleaved(second[0], second[1], second[2], out + size_t{i0} * 3 + 24);
  }
}

}  // namespace

void CompressedClusterAvx2Q12(const int16_t* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                              int32_t* out) {
  ClusterAvx2(w, n, components, m, out);
}
void CompressedClusterAvx2Q12(const int8_t* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                              int32_t* out) {
  ClusterAvx2(w, n, components, m, out);
}

}  // namespace relight

#else  // no AVX2 path on this target: CompressedClusterQ12 stays scalar

namespace relight {
void CompressedClusterAvx2Q12(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
void CompressedClusterAvx2Q12(const int8_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
}  // namespace relight

#endif
