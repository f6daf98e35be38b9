// AVX-512 mixing (see mix_avx512.h). The caller checks the level.
#include "mix_avx512.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

// GCC 12's AVX-512 headers fill unused merge operands with
// _mm512_undefined_*(), which -Wmaybe-uninitialized reports once inlined.
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#define RELIGHT_TARGET_AVX512 __attribute__((target("avx2,avx512f,avx512vl")))

namespace relight {
namespace {

// acc[0..8) += (a * g + 2^29) >> 30 on the lanes set in `lanes`.
RELIGHT_TARGET_AVX512 inline void AddEight(const int32_t* a, __m512i g, __mmask8 lanes, int64_t* acc) {
  const __m512i half = _mm512_set1_epi64(int64_t{1} << 29);
  const __m512i x = _mm512_cvtepi32_epi64(_mm256_maskz_loadu_epi32(lanes, a));
  const __m512i term = _mm512_srai_epi64(_mm512_add_epi64(_mm512_mul_epi32(x, g), half), 30);
  if (lanes == 0xFF) {
    _mm512_storeu_si512(acc, _mm512_add_epi64(_mm512_loadu_si512(acc), term));
  } else {
    _mm512_mask_storeu_epi64(acc, lanes, _mm512_add_epi64(_mm512_maskz_loadu_epi64(lanes, acc), term));
  }
}

RELIGHT_TARGET_AVX512 inline __mmask8 Lanes(uint32_t left) {
  return left >= 8 ? __mmask8{0xFF} : static_cast<__mmask8>((1u << left) - 1);
}

}  // namespace

RELIGHT_TARGET_AVX512 void MixAddAvx512(const int32_t* a, const int64_t gain[3], uint32_t elements,
                                        int64_t* acc) {
  // Element e of a step starts at a multiple of 24, so lane i of vector v has gain[(8v + i) % 3].
  const __m512i g0 = _mm512_setr_epi64(gain[0], gain[1], gain[2], gain[0], gain[1], gain[2], gain[0], gain[1]);
  const __m512i g1 = _mm512_setr_epi64(gain[2], gain[0], gain[1], gain[2], gain[0], gain[1], gain[2], gain[0]);
  const __m512i g2 = _mm512_setr_epi64(gain[1], gain[2], gain[0], gain[1], gain[2], gain[0], gain[1], gain[2]);
  uint32_t e = 0;
  for (; e + 24 <= elements; e += 24) {
    AddEight(a + e, g0, 0xFF, acc + e);
    AddEight(a + e + 8, g1, 0xFF, acc + e + 8);
    AddEight(a + e + 16, g2, 0xFF, acc + e + 16);
  }
  // The last step: fewer than 24 elements, masked (no read or write past them).
  const __m512i g[3] = {g0, g1, g2};
  for (int v = 0; v < 3 && e + 8 * v < elements; ++v) {
    AddEight(a + e + 8 * v, g[v], Lanes(elements - e - 8 * v), acc + e + 8 * v);
  }
}

RELIGHT_TARGET_AVX512 void SaturateAvx512(const int64_t* acc, uint32_t elements, int32_t* out) {
  uint32_t e = 0;
  for (; e + 8 <= elements; e += 8) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + e), _mm512_cvtsepi64_epi32(_mm512_loadu_si512(acc + e)));
  }
  if (e < elements) {
    const __mmask8 lanes = Lanes(elements - e);
    _mm512_mask_cvtsepi64_storeu_epi32(out + e, lanes, _mm512_maskz_loadu_epi64(lanes, acc + e));
  }
}

}  // namespace relight

#else  // no AVX-512 path on this target: MixLuminairesQ12 stays scalar

namespace relight {
void MixAddAvx512(const int32_t*, const int64_t*, uint32_t, int64_t*) {}
void SaturateAvx512(const int64_t*, uint32_t, int32_t*) {}
}  // namespace relight

#endif
