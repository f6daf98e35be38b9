// AVX2 body of CompressedClusterQ12: see compressed_recombine_avx2.h.
// Integer instructions only (madd of int16 pairs, int32 adds and shifts,
// permutes and blends).
#include "compressed_recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

namespace relight {
namespace {

// Two multipliers per int32 lane: K_j in the low 16 bits, K_{j+1} in the
// high, the order _mm256_unpack*_epi16(w_j, w_{j+1}) puts the weights in.
inline int32_t Pack(int16_t a, int16_t b) {
  return static_cast<int32_t>((static_cast<uint32_t>(static_cast<uint16_t>(b)) << 16) |
                              static_cast<uint16_t>(a));
}

// R, G, B of receivers 0..7 (one vector each) -> 24 interleaved int32:
// each is turned so its lanes land where the output wants them, then blended.
__attribute__((target("avx2"))) inline void StoreInterleaved(__m256i r, __m256i g, __m256i b,
                                                            int32_t* out) {
  const __m256i rp = _mm256_permutevar8x32_epi32(r, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
  const __m256i gp = _mm256_permutevar8x32_epi32(g, _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
  const __m256i bp = _mm256_permutevar8x32_epi32(b, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
  // Lane patterns: out0 = R G B R G B R G, out1 = B R G B R G B R, out2 = G B R G B R G B.
  const __m256i o0 = _mm256_blend_epi32(_mm256_blend_epi32(rp, gp, 0x92), bp, 0x24);
  const __m256i o1 = _mm256_blend_epi32(_mm256_blend_epi32(rp, gp, 0x24), bp, 0x49);
  const __m256i o2 = _mm256_blend_epi32(_mm256_blend_epi32(rp, gp, 0x49), bp, 0x92);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), o0);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 8), o1);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 16), o2);
}

}  // namespace

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
      k[ch][p] = _mm256_set1_epi32(Pack(m.k[ch * components + j], kb));
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
