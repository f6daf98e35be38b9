// AVX2 body of CompressedClusterQ12: see compressed_recombine_avx2.h.
// Integer instructions only (madd of int16 pairs, int32 adds and shifts,
// permutes and blends).
#include "compressed_recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include "compressed_recombine_interleave.h"

namespace relight {
using cpca_simd::PackPair;
using cpca_simd::StoreInterleaved;

__attribute__((target("avx2"))) void CompressedClusterAvx2Q12(const int16_t* w, uint32_t n,
                                                              uint32_t components,
                                                              const ClusterMultipliers& m,
                                                              int32_t* out) {
  const uint32_t pairs = (components + 1) / 2;
  __m256i k[3][kMaxCompressedComponents / 2];
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t p = 0; p < pairs; ++p) {
      const uint32_t j = 2 * p;
      // An odd count pairs the last component with a zero multiplier.
      const int16_t kb = j + 1 < components ? m.k[ch * components + j + 1] : int16_t{0};
      k[ch][p] = _mm256_set1_epi32(PackPair(m.k[ch * components + j], kb));
    }
  }
  __m256i half[3], mean[3];
  __m128i shift[3];
  for (int ch = 0; ch < 3; ++ch) {
    const int s = m.shift[ch];
    half[ch] = _mm256_set1_epi32(s > 0 ? int32_t{1} << (s - 1) : 0);
    mean[ch] = _mm256_set1_epi32(m.mean[ch]);
    shift[ch] = _mm_cvtsi32_si128(s);
  }
  const uint32_t blocks = n / 16;
  for (uint32_t blk = 0; blk < blocks; ++blk) {
    const uint32_t i0 = 16 * blk;
    __m256i lo[3], hi[3];  // receivers i0 + {0..3 | 8..11}, i0 + {4..7 | 12..15}
    for (int ch = 0; ch < 3; ++ch) lo[ch] = hi[ch] = _mm256_setzero_si256();
    for (uint32_t p = 0; p < pairs; ++p) {
      const uint32_t j = 2 * p;
      const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w + size_t{j} * n + i0));
      const __m256i b = j + 1 < components
                            ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w + size_t{j + 1} * n + i0))
                            : _mm256_setzero_si256();
      const __m256i ul = _mm256_unpacklo_epi16(a, b), uh = _mm256_unpackhi_epi16(a, b);
      for (int ch = 0; ch < 3; ++ch) {
        lo[ch] = _mm256_add_epi32(lo[ch], _mm256_madd_epi16(ul, k[ch][p]));
        hi[ch] = _mm256_add_epi32(hi[ch], _mm256_madd_epi16(uh, k[ch][p]));
      }
    }
    __m256i first[3], second[3];  // receivers i0 + 0..7, i0 + 8..15
    for (int ch = 0; ch < 3; ++ch) {
      const __m256i l = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(_mm256_add_epi32(lo[ch], half[ch]), shift[ch]));
      const __m256i h = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(_mm256_add_epi32(hi[ch], half[ch]), shift[ch]));
      first[ch] = _mm256_permute2x128_si256(l, h, 0x20);
      second[ch] = _mm256_permute2x128_si256(l, h, 0x31);
    }
    StoreInterleaved(first[0], first[1], first[2], out + size_t{i0} * 3);
    StoreInterleaved(second[0], second[1], second[2], out + size_t{i0} * 3 + 24);
  }
}

}  // namespace relight

#else  // no AVX2 path on this target: CompressedClusterQ12 stays scalar

namespace relight {
void CompressedClusterAvx2Q12(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
}  // namespace relight

#endif
