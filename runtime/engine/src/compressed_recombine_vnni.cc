// VNNI bodies of CompressedClusterQ12: see compressed_recombine_vnni.h.
// Integer instructions only (vpdpwssd, int32 adds and shifts, permutes,
// masked loads and stores).
#include "compressed_recombine_vnni.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

// GCC 12's AVX-512 headers fill unused merge operands with
// _mm512_undefined_*(), a self-initialised variable that -Wmaybe-uninitialized
// reports once inlined here (a header artefact: every lane is written).
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "compressed_recombine_interleave.h"

#define RELIGHT_TARGET_AVX512_VNNI __attribute__((target("avx2,avx512f,avx512bw,avx512vl,avx512vnni")))
#define RELIGHT_TARGET_AVX_VNNI __attribute__((target("avx2,avxvnni")))

namespace relight {
namespace {

using cpca_simd::PackPair;

// Permute indices (vpermt2d: 0..15 the first source, 16..31 the second).
struct Indices {
  // R, G, B of 16 receivers in order -> output vector v (elements 16v ..
  // 16v + 15 of the 48, element g = receiver g / 3, channel g % 3): first
  // R and G (rg[v]), then B into that (b[v]).
  int32_t rg[3][16];
  int32_t b[3][16];
  // vpermt2w: weights of components j (0..31) and j + 1 (32..63) paired per
  // receiver, in receiver order: pairs[h] for receivers 16h .. 16h + 15.
  int16_t pairs[2][32];
  constexpr Indices() : rg(), b(), pairs() {
    for (int h = 0; h < 2; ++h) {
      for (int q = 0; q < 16; ++q) {
        pairs[h][2 * q] = static_cast<int16_t>(16 * h + q);
        pairs[h][2 * q + 1] = static_cast<int16_t>(32 + 16 * h + q);
      }
    }
    for (int v = 0; v < 3; ++v) {
      for (int e = 0; e < 16; ++e) {
        const int g = 16 * v + e, i = g / 3, c = g % 3;
        rg[v][e] = c == 0 ? i : (c == 1 ? 16 + i : 0);
        b[v][e] = c == 2 ? 16 + i : e;
      }
    }
  }
};
alignas(64) constexpr Indices kIndices;

RELIGHT_TARGET_AVX512_VNNI inline __m512i Load(const int32_t* p) { return _mm512_loadu_si512(p); }

// R, G, B of `count` receivers (1 .. 16, in order) -> 3 count interleaved int32.
RELIGHT_TARGET_AVX512_VNNI inline void StoreRgb(const __m512i* rgb, uint32_t count, int32_t* out) {
  const int elements = 3 * static_cast<int>(count);
  for (int v = 0; v < 3; ++v) {
    const __m512i t = _mm512_permutex2var_epi32(rgb[0], Load(kIndices.rg[v]), rgb[1]);
    const __m512i o = _mm512_permutex2var_epi32(t, Load(kIndices.b[v]), rgb[2]);
    const int left = elements - 16 * v;
    if (left >= 16) {
      _mm512_storeu_si512(out + 16 * v, o);
    } else if (left > 0) {
      _mm512_mask_storeu_epi32(out + 16 * v, static_cast<__mmask16>((1u << left) - 1), o);
    }
  }
}

}  // namespace

RELIGHT_TARGET_AVX512_VNNI void CompressedClusterAvx512VnniQ12(const int16_t* w, uint32_t n,
                                                              uint32_t components,
                                                              const ClusterMultipliers& m,
                                                              int32_t* out) {
  const uint32_t pairs = (components + 1) / 2;
  __m512i k[3][kMaxCompressedComponents / 2];
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t p = 0; p < pairs; ++p) {
      const uint32_t j = 2 * p;
      // An odd count pairs the last component with a zero multiplier.
      const int16_t kb = j + 1 < components ? m.k[ch * components + j + 1] : int16_t{0};
      k[ch][p] = _mm512_set1_epi32(PackPair(m.k[ch * components + j], kb));
    }
  }
  __m512i half[3], mean[3];
  __m128i shift[3];
  for (int ch = 0; ch < 3; ++ch) {
    const int s = m.shift[ch];
    half[ch] = _mm512_set1_epi32(s > 0 ? int32_t{1} << (s - 1) : 0);
    mean[ch] = _mm512_set1_epi32(m.mean[ch]);
    shift[ch] = _mm_cvtsi32_si128(s);
  }
  const __m512i pair_first = _mm512_loadu_si512(kIndices.pairs[0]), pair_second = _mm512_loadu_si512(kIndices.pairs[1]);
  for (uint32_t i0 = 0; i0 < n; i0 += 32) {
    const uint32_t left = n - i0;
    // The last step reads only its receivers (masked lanes do not fault).
    const __mmask32 lanes = left >= 32 ? ~__mmask32{0} : static_cast<__mmask32>((1u << left) - 1);
    __m512i lo[3], hi[3];  // receivers i0 + 0..15, i0 + 16..31; from the rounding half (header)
    for (int ch = 0; ch < 3; ++ch) lo[ch] = hi[ch] = half[ch];
    for (uint32_t p = 0; p < pairs; ++p) {
      const uint32_t j = 2 * p;
      // Plain loads but on the last step: AMD's prefetchers follow masked
      // loads less well (recombine_vnni.cc).
      const int16_t* wa = w + size_t{j} * n + i0;
      const __m512i a = left >= 32 ? _mm512_loadu_si512(wa) : _mm512_maskz_loadu_epi16(lanes, wa);
      const __m512i b = j + 1 >= components ? _mm512_setzero_si512()
                        : left >= 32        ? _mm512_loadu_si512(wa + n)
                                            : _mm512_maskz_loadu_epi16(lanes, wa + n);
      const __m512i ul = _mm512_permutex2var_epi16(a, pair_first, b);
      const __m512i uh = _mm512_permutex2var_epi16(a, pair_second, b);
      for (int ch = 0; ch < 3; ++ch) {
        lo[ch] = _mm512_dpwssd_epi32(lo[ch], ul, k[ch][p]);
        hi[ch] = _mm512_dpwssd_epi32(hi[ch], uh, k[ch][p]);
      }
    }
    __m512i first[3], second[3];  // receivers i0 + 0..15, i0 + 16..31
    for (int ch = 0; ch < 3; ++ch) {
      first[ch] = _mm512_add_epi32(mean[ch], _mm512_sra_epi32(lo[ch], shift[ch]));
      second[ch] = _mm512_add_epi32(mean[ch], _mm512_sra_epi32(hi[ch], shift[ch]));
    }
    StoreRgb(first, left < 16 ? left : 16, out + size_t{i0} * 3);
    if (left > 16) StoreRgb(second, left - 16 < 16 ? left - 16 : 16, out + size_t{i0} * 3 + 48);
  }
}

RELIGHT_TARGET_AVX_VNNI void CompressedClusterAvxVnniQ12(const int16_t* w, uint32_t n, uint32_t components,
                                                         const ClusterMultipliers& m, int32_t* out) {
  const uint32_t pairs = (components + 1) / 2;
  __m256i k[3][kMaxCompressedComponents / 2];
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t p = 0; p < pairs; ++p) {
      const uint32_t j = 2 * p;
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
    for (int ch = 0; ch < 3; ++ch) lo[ch] = hi[ch] = half[ch];
    for (uint32_t p = 0; p < pairs; ++p) {
      const uint32_t j = 2 * p;
      const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w + size_t{j} * n + i0));
      const __m256i b = j + 1 < components
                            ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w + size_t{j + 1} * n + i0))
                            : _mm256_setzero_si256();
      const __m256i ul = _mm256_unpacklo_epi16(a, b), uh = _mm256_unpackhi_epi16(a, b);
      for (int ch = 0; ch < 3; ++ch) {
        lo[ch] = _mm256_dpwssd_avx_epi32(lo[ch], ul, k[ch][p]);
        hi[ch] = _mm256_dpwssd_avx_epi32(hi[ch], uh, k[ch][p]);
      }
    }
    __m256i first[3], second[3];  // receivers i0 + 0..7, i0 + 8..15
    for (int ch = 0; ch < 3; ++ch) {
      const __m256i l = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(lo[ch], shift[ch]));
      const __m256i h = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(hi[ch], shift[ch]));
      first[ch] = _mm256_permute2x128_si256(l, h, 0x20);
      second[ch] = _mm256_permute2x128_si256(l, h, 0x31);
    }
    cpca_simd::StoreInterleaved(first[0], first[1], first[2], out + size_t{i0} * 3);
    cpca_simd::StoreInterleaved(second[0], second[1], second[2], out + size_t{i0} * 3 + 24);
  }
}

}  // namespace relight

#else  // no x86-64 vector path on this target: CompressedClusterQ12 stays scalar

namespace relight {
void CompressedClusterAvx512VnniQ12(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
void CompressedClusterAvxVnniQ12(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
}  // namespace relight

#endif
