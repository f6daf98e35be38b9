// AVX-512 body of the aimed direct term: see direct_aimed_simd.h
// (DirectAimedRangeAvx512). Eight receivers a step, each lane the scalar
// PointLuxQ12 and AimedRange's RGB step (direct_aimed.cc), with what AVX2
// lacks: vplzcntq for the octave of u (CD), vpsraq and vpabsq, vpmullq for
// the 64-bit products (DQ), compare masks; table reads as plain loads, as
// in the AVX2 body. Integer instructions only.
#include "direct_aimed_simd.h"

#include <cstddef>

#include "recombine_dispatch.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define RELIGHT_HAVE_AVX512_PATH 1
// GCC 12's AVX-512 headers fill unused merge operands with
// _mm512_undefined_*(), which -Wmaybe-uninitialized reports once inlined.
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#endif

namespace relight {

bool DirectAimedHasAvx512() {
#ifdef RELIGHT_HAVE_AVX512_PATH
  // The avx512vnni level (F, BW, VL, VNNI, the OS saving ZMM; honours the
  // caps) plus CD and DQ, which that level does not check.
  static const bool cd_dq = __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq");
  return cd_dq && ActiveSimdLevel() >= SimdLevel::kAvx512Vnni;
#else
  return false;
#endif
}

#ifdef RELIGHT_HAVE_AVX512_PATH

namespace {

#define RELIGHT_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512cd,avx512dq"), always_inline)) inline

RELIGHT_AVX512 __m512i Set64(int64_t v) { return _mm512_set1_epi64(v); }

// Four 128-bit values as the lanes of a 512-bit one.
RELIGHT_AVX512 __m512i Join(__m128i v0, __m128i v1, __m128i v2, __m128i v3) {
  const __m256i low = _mm256_inserti128_si256(_mm256_castsi128_si256(v0), v1, 1);
  const __m256i high = _mm256_inserti128_si256(_mm256_castsi128_si256(v2), v3, 1);
  return _mm512_inserti64x4(_mm512_castsi256_si512(low), high, 1);
}

RELIGHT_AVX512 __m128i Load8(const void* p) { return _mm_loadl_epi64(static_cast<const __m128i*>(p)); }
RELIGHT_AVX512 __m128i Load16(const void* p) { return _mm_loadu_si128(static_cast<const __m128i*>(p)); }

// The 8 bytes at base + 4 at[i], lane i: eight plain loads, which Zen 4
// runs faster than vpgatherqq (perf of BM_DirectTerm: the gathers held
// a third of this body's samples).
RELIGHT_AVX512 __m512i Read8(const uint32_t* base, const int64_t at[8]) {
  return Join(_mm_unpacklo_epi64(Load8(base + at[0]), Load8(base + at[1])),
              _mm_unpacklo_epi64(Load8(base + at[2]), Load8(base + at[3])),
              _mm_unpacklo_epi64(Load8(base + at[4]), Load8(base + at[5])),
              _mm_unpacklo_epi64(Load8(base + at[6]), Load8(base + at[7])));
}

// GammaFromCosQ60 (gamma_table.h), eight lanes.
RELIGHT_AVX512 __m512i GammaFromCos(const GammaTable& gt, __m512i cos_q60) {
  const __mmask8 backward = _mm512_cmplt_epi64_mask(cos_q60, _mm512_setzero_si512());
  const __m512i u = _mm512_max_epi64(_mm512_sub_epi64(Set64(int64_t{1} << 60), _mm512_abs_epi64(cos_q60)),
                                     _mm512_setzero_si512());
  const __m512i table_start = Set64(int64_t{1} << kGammaMinOctave);
  const __mmask8 small = _mm512_cmplt_epu64_mask(u, table_start);
  // Below the table: bam[0] u >> 23 (u < 2^23); the table lanes' u >= 2^23.
  const __m512i g_small = _mm512_srli_epi64(_mm512_mul_epu32(Set64(gt.bam[0]), u), kGammaMinOctave);
  const __m512i ut = _mm512_max_epu64(u, table_start);
  const __m512i e = _mm512_sub_epi64(Set64(63), _mm512_lzcnt_epi64(ut));
  const __m512i m = _mm512_and_si512(_mm512_srlv_epi64(ut, _mm512_sub_epi64(e, Set64(kGammaSegmentBits))),
                                     Set64((1 << kGammaSegmentBits) - 1));
  const __m512i frac = _mm512_and_si512(
      _mm512_srlv_epi64(ut, _mm512_sub_epi64(e, Set64(kGammaSegmentBits + 16))), Set64(0xffff));
  const __m512i index = _mm512_add_epi64(
      _mm512_slli_epi64(_mm512_sub_epi64(e, Set64(kGammaMinOctave)), kGammaSegmentBits), m);
  // bam[i] and bam[i + 1] in one 8-byte element (i + 1 < kGammaEntries).
  alignas(64) int64_t at[8];
  _mm512_store_si512(at, index);
  const __m512i ab = Read8(gt.bam, at);
  const __m512i a = _mm512_and_si512(ab, Set64(0xffffffff));
  const __m512i b = _mm512_srli_epi64(ab, 32);
  // The table rises, so b - a < 2^31 (DirectAimedSimd.GammaTableRises).
  const __m512i g_table = _mm512_add_epi64(
      a, _mm512_srli_epi64(_mm512_add_epi64(_mm512_mul_epu32(_mm512_sub_epi64(b, a), frac), Set64(0x8000)), 16));
  const __m512i g = _mm512_mask_blend_epi64(small, g_table, g_small);
  return _mm512_mask_sub_epi64(g, backward, Set64(int64_t{1} << 31), g);
}

// LidIntensityFastQ16 (direct_aimed.h), eight lanes, gamma in [0, 2^31].
RELIGHT_AVX512 __m512i LidIntensity(const int64_t* lid_q16, int lid_m, __m512i gamma) {
  const __m512i pos = _mm512_srli_epi64(
      _mm512_add_epi64(_mm512_mul_epu32(gamma, Set64(lid_m)), Set64(int64_t{1} << 14)), 15);
  const __m512i index = _mm512_srli_epi64(pos, 16);
  const __mmask8 top = _mm512_cmpge_epu64_mask(index, Set64(lid_m));  // the last sample itself
  alignas(64) int64_t at[8];
  _mm512_store_si512(at, _mm512_min_epu64(index, Set64(lid_m - 1)));
  // Samples i and i + 1 of each lane in one 16-byte read; lanes 0, 2, 4, 6
  // and 1, 3, 5, 7 interleaved back into order.
  const __m512i even = Join(Load16(lid_q16 + at[0]), Load16(lid_q16 + at[2]), Load16(lid_q16 + at[4]),
                            Load16(lid_q16 + at[6]));
  const __m512i odd = Join(Load16(lid_q16 + at[1]), Load16(lid_q16 + at[3]), Load16(lid_q16 + at[5]),
                           Load16(lid_q16 + at[7]));
  const __m512i a = _mm512_unpacklo_epi64(even, odd);
  const __m512i b = _mm512_unpackhi_epi64(even, odd);
  const __m512i step = _mm512_mullo_epi64(_mm512_sub_epi64(b, a), _mm512_and_si512(pos, Set64(0xffff)));
  const __m512i value = _mm512_add_epi64(a, _mm512_srai_epi64(_mm512_add_epi64(step, Set64(int64_t{1} << 15)), 16));
  return _mm512_mask_blend_epi64(top, value, Set64(lid_q16[lid_m]));
}

}  // namespace

__attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512cd,avx512dq"))) uint32_t DirectAimedRangeAvx512(
    const DirectPoint* points, uint32_t count, const DirectAimedCall& k, const GammaTable& gt,
    const int64_t* lid_q16, int lid_m, const uint32_t* rho_q32, bool add, int32_t* out) {
  const uint32_t steps = count / 8;
  const __m512i a0 = Set64(k.a0), a1 = Set64(k.a1), a2 = Set64(k.a2);
  const __m512i zero_cos = Set64(k.zero_cos_q60);
  const __m128i intensity_shift = _mm_cvtsi32_si128(k.intensity_shift);
  const __m128i e_shift = _mm_cvtsi32_si128(k.e_shift);
  const __m512i max_lux = Set64((int64_t{1} << 33) - 1), max_value = Set64(0x7fffffff);
  // A point is two 64-bit elements (x, y) and (z, geometry).
  const __m512i even = _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14), odd = _mm512_setr_epi64(1, 3, 5, 7, 9, 11, 13, 15);
  // Value 8 v + L of the 24 (3 per receiver) is receiver (8 v + L) / 3's.
  const __m512i spread[3] = {_mm512_setr_epi64(0, 0, 0, 1, 1, 1, 2, 2), _mm512_setr_epi64(2, 3, 3, 3, 4, 4, 4, 5),
                             _mm512_setr_epi64(5, 5, 6, 6, 6, 7, 7, 7)};
  for (uint32_t s = 0; s < steps; ++s) {
    const DirectPoint* p = points + static_cast<size_t>(s) * 8;
    const __m512i p03 = _mm512_loadu_si512(p), p47 = _mm512_loadu_si512(p + 4);
    const __m512i xy = _mm512_permutex2var_epi64(p03, even, p47);
    const __m512i zg = _mm512_permutex2var_epi64(p03, odd, p47);
    const __m512i cos_q60 =
        _mm512_add_epi64(_mm512_add_epi64(_mm512_mul_epi32(xy, a0), _mm512_mul_epi32(_mm512_srli_epi64(xy, 32), a1)),
                         _mm512_mul_epi32(zg, a2));
    const __mmask8 lit = _mm512_cmpgt_epi64_mask(cos_q60, zero_cos);
    int32_t* dst = out + static_cast<size_t>(s) * 24;
    if (lit == 0) {  // all eight past the cut-off: E = 0
      if (!add) {
        for (int v = 0; v < 3; ++v) _mm256_storeu_si256(reinterpret_cast<__m256i*>(dst) + v, _mm256_setzero_si256());
      }
      continue;
    }
    const __m512i intensity = LidIntensity(lid_q16, lid_m, GammaFromCos(gt, cos_q60));  // >= 0
    const __m512i i = _mm512_srl_epi64(_mm512_add_epi64(intensity, Set64(k.intensity_half)), intensity_shift);
    const __m512i product = _mm512_mul_epu32(i, _mm512_srli_epi64(zg, 32));  // < 2^63
    const __m512i e = _mm512_maskz_mov_epi64(
        lit, _mm512_min_epu64(_mm512_srl_epi64(_mm512_add_epi64(product, Set64(static_cast<int64_t>(k.e_half))), e_shift),
                              max_lux));
    for (int v = 0; v < 3; ++v) {
      __m512i value = _mm512_permutexvar_epi64(spread[v], e);
      if (rho_q32 != nullptr) {
        const __m512i rho = _mm512_cvtepu32_epi64(
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rho_q32 + static_cast<size_t>(s) * 24) + v));
        // E (< 2^33) x rho modulo 2^64, as the scalar's uint64 product.
        value = _mm512_srli_epi64(_mm512_add_epi64(_mm512_mullo_epi64(value, rho), Set64(int64_t{1} << 31)), 32);
      }
      value = _mm512_min_epu64(value, max_value);
      auto* slot = reinterpret_cast<__m256i*>(dst) + v;
      if (add) value = _mm512_min_epi64(_mm512_add_epi64(value, _mm512_cvtepi32_epi64(_mm256_loadu_si256(slot))), max_value);
      _mm256_storeu_si256(slot, _mm512_cvtepi64_epi32(value));
    }
  }
  return steps * 8;
}

#else  // no AVX-512 path on this target

uint32_t DirectAimedRangeAvx512(const DirectPoint*, uint32_t, const DirectAimedCall&, const GammaTable&,
                                const int64_t*, int, const uint32_t*, bool, int32_t*) {
  return 0;
}

#endif

}  // namespace relight
