// The 256-bit weight loads, the RGB interleave and the multiplier pairs shared by the AVX2 and AVX-VNNI bodies of the
// compressed recombination (compressed_recombine_avx2.cc,
// compressed_recombine_vnni.cc). x86-64 SIMD files only: include it inside
// their architecture guard.
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "compressed_recombine.h"

namespace relight {
namespace cpca_simd {

// R, G, B of receivers 0..7 (one vector each) -> 24 interleaved int32:
// each is turned so its lanes land where the output wants them, then blended.
__attribute__((target("avx2"), always_inline)) inline void StoreInterleaved(__m256i r, __m256i g,
                                                                           __m256i b, int32_t* out) {
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

// 8 receivers' int16 pairs of one component pair (16 weights), from int16
// or from int8 weights (sign-extended: the same int16 values).
__attribute__((target("avx2"), always_inline)) inline __m256i LoadPairs256(const int16_t* p) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}
__attribute__((target("avx2"), always_inline)) inline __m256i LoadPairs256(const int8_t* p) {
  return _mm256_cvtepi8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}
// 8 receivers' last weight of an odd r, one a 32-bit lane, low half the
// weight. int16: zero-extended (w, 0); int8: sign-extended, so the high
// half may be -1, which the pair's multiplier (K, 0) ignores.
__attribute__((target("avx2"), always_inline)) inline __m256i LoadLast256(const int16_t* p) {
  return _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}
__attribute__((target("avx2"), always_inline)) inline __m256i LoadLast256(const int8_t* p) {
  return _mm256_cvtepi8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
}

// Two multipliers per int32 lane: K_j in the low 16 bits, K_{j+1} in the
// high, the order unpack*_epi16(w_j, w_{j+1}) puts the weights in.
inline int32_t PackPair(int16_t a, int16_t b) {
  return static_cast<int32_t>((static_cast<uint32_t>(static_cast<uint16_t>(b)) << 16) |
                              static_cast<uint16_t>(a));
}

// The multipliers of every pair, and of an odd count's last component
// paired with 0 (its weights are zero-extended), as the int32 lanes madd /
// vpdpwssd take: packed[ch][p] (compressed_tiles.h's pair order).
inline void PairMultipliers(const ClusterMultipliers& m, uint32_t components,
                            int32_t (*packed)[kMaxCompressedComponents / 2 + 1]) {
  const uint32_t pairs = components / 2;
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t p = 0; p < pairs; ++p) {
      packed[ch][p] = PackPair(m.k[ch * components + 2 * p], m.k[ch * components + 2 * p + 1]);
    }
    if (components % 2 != 0) packed[ch][pairs] = PackPair(m.k[ch * components + components - 1], 0);
  }
}

}  // namespace cpca_simd
}  // namespace relight
