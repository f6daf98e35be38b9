// AVX2 mixing (see mix_avx2.h). The caller checks CpuHasAvx2().
#include "mix_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define RELIGHT_HAVE_AVX2_PATH 1
#endif

namespace relight {

#ifdef RELIGHT_HAVE_AVX2_PATH

namespace {

// (x * g + 2^29) >> 30 on four int64 lanes; x sign-extended int32, g >= 0 < 2^31.
__attribute__((target("avx2"), always_inline)) inline __m256i Term(__m256i x, __m256i g) {
  const __m256i half = _mm256_set1_epi64x(int64_t{1} << 29);
  const __m256i v = _mm256_add_epi64(_mm256_mul_epi32(x, g), half);
  const __m256i sign = _mm256_cmpgt_epi64(_mm256_setzero_si256(), v);  // -1 where negative
  return _mm256_or_si256(_mm256_srli_epi64(v, 30), _mm256_slli_epi64(sign, 34));
}

__attribute__((target("avx2"), always_inline)) inline void AddFour(const int32_t* a, __m256i g, int64_t* acc) {
  const __m256i x = _mm256_cvtepi32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a)));
  __m256i* p = reinterpret_cast<__m256i*>(acc);
  _mm256_storeu_si256(p, _mm256_add_epi64(_mm256_loadu_si256(p), Term(x, g)));
}

}  // namespace

__attribute__((target("avx2"))) void MixAddAvx2(const int32_t* a, const int64_t gain[3], uint32_t elements,
                                                int64_t* acc) {
  // Twelve elements (four receivers) a step: the gains' pattern repeats.
  const __m256i g0 = _mm256_setr_epi64x(gain[0], gain[1], gain[2], gain[0]);
  const __m256i g1 = _mm256_setr_epi64x(gain[1], gain[2], gain[0], gain[1]);
  const __m256i g2 = _mm256_setr_epi64x(gain[2], gain[0], gain[1], gain[2]);
  uint32_t e = 0;
  for (; e + 12 <= elements; e += 12) {
    AddFour(a + e, g0, acc + e);
    AddFour(a + e + 4, g1, acc + e + 4);
    AddFour(a + e + 8, g2, acc + e + 8);
  }
  for (; e < elements; ++e) {
    acc[e] += (static_cast<int64_t>(a[e]) * gain[e % 3] + (int64_t{1} << 29)) >> 30;
  }
}

__attribute__((target("avx2"))) void SaturateAvx2(const int64_t* acc, uint32_t elements, int32_t* out) {
  const __m256i hi = _mm256_set1_epi64x(0x7fffffff);
  const __m256i lo = _mm256_set1_epi64x(-0x7fffffffLL - 1);
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  uint32_t e = 0;
  for (; e + 4 <= elements; e += 4) {
    __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(acc + e));
    v = _mm256_blendv_epi8(v, hi, _mm256_cmpgt_epi64(v, hi));
    v = _mm256_blendv_epi8(v, lo, _mm256_cmpgt_epi64(lo, v));
    const __m256i packed = _mm256_permutevar8x32_epi32(v, low_halves);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + e), _mm256_castsi256_si128(packed));
  }
  for (; e < elements; ++e) {
    const int64_t v = acc[e];
    out[e] = v > 0x7fffffff ? 0x7fffffff : (v < -0x7fffffffLL - 1 ? static_cast<int32_t>(-0x7fffffffLL - 1)
                                                                    : static_cast<int32_t>(v));
  }
}

#else  // no AVX2 path on this target: MixLuminairesQ12 stays scalar

void MixAddAvx2(const int32_t*, const int64_t*, uint32_t, int64_t*) {}
void SaturateAvx2(const int64_t*, uint32_t, int32_t*) {}

#endif

}  // namespace relight
