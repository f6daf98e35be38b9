// AVX-512 VNNI accumulation for RecombineQ12: see recombine_vnni.h.
// Integer instructions only (vpdpwssd, permutes, sign extension to int64,
// masked loads and stores).
#include "recombine_vnni.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

// GCC 12's AVX-512 headers fill unused merge operands with
// _mm512_undefined_*(), a self-initialised variable that -Wmaybe-uninitialized
// reports once inlined here (a header artefact: every lane is written).
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#define RELIGHT_TARGET_AVX512_VNNI __attribute__((target("avx2,avx512f,avx512bw,avx512vl,avx512vnni")))

namespace relight {
namespace {

// The AVX2 body's pair vectors (recombine_avx2.cc PairVectors), read here as
// bytes: [lo_kh, lo_kl, hi_kh, hi_kl][phase], 32 bytes each.
constexpr int kLoKh = 0, kLoKl = 1, kHiKh = 2, kHiKl = 3;

struct Pair512 {
  __m512i v[4];  // lo_kh, lo_kl, hi_kh, hi_kl
};

// A 512-bit chunk of 32 elements at phase p (e0 % 3) is two 256-bit chunks
// at phases p and p + 16 (mod 3) = p + 1: the unpacks place the same element
// offsets in each 128-bit lane, so the 512-bit multipliers are the 256-bit
// ones of phase p joined to those of phase p + 1.
RELIGHT_TARGET_AVX512_VNNI Pair512 Widen(const TermPairVectors& pair, int phase) {
  const __m256i* v = reinterpret_cast<const __m256i*>(pair.bytes);
  Pair512 out;
  for (int which = 0; which < 4; ++which) {
    const __m256i low = _mm256_load_si256(v + which * 3 + phase);
    const __m256i high = _mm256_load_si256(v + which * 3 + (phase + 1) % 3);
    out.v[which] = _mm512_inserti64x4(_mm512_castsi256_si512(low), high, 1);
  }
  return out;
}

// unpack{lo,hi}_epi16 per 128-bit lane L: lo lane 4L + t holds element
// 8L + t, hi lane 4L + t element 8L + 4 + t. kInOrder[h] picks elements
// 16h .. 16h + 15 from (lo, hi) (vpermt2d: 16 + i is hi's lane i).
struct InOrder {
  int32_t idx[2][16];
  constexpr InOrder() : idx() {
    for (int h = 0; h < 2; ++h) {
      for (int i = 0; i < 16; ++i) {
        const int q = 16 * h + i;
        idx[h][i] = (q % 8 < 4 ? 0 : 16) + 4 * (q / 8) + q % 4;
      }
    }
  }
};
alignas(64) constexpr InOrder kInOrder;

// acc[0..8) += hi x 2^12 + lo for eight int64 lanes from eight int32 (masked: `lanes`).
RELIGHT_TARGET_AVX512_VNNI inline void AddHalves(int64_t* acc, __m256i hi, __m256i lo, __mmask8 lanes) {
  const __m512i sum = _mm512_add_epi64(_mm512_slli_epi64(_mm512_cvtepi32_epi64(hi), 12), _mm512_cvtepi32_epi64(lo));
  if (lanes == 0xFF) {
    _mm512_storeu_si512(acc, _mm512_add_epi64(_mm512_loadu_si512(acc), sum));
  } else {
    _mm512_mask_storeu_epi64(acc, lanes, _mm512_add_epi64(_mm512_maskz_loadu_epi64(lanes, acc), sum));
  }
}

constexpr int kPairsPerWiden = 4;  // 8 terms summed in int32 before widening (< 2^30)

// One pass of G term pairs over the elements [0, elements): as the AVX2
// Pass, 32 elements a step, the last step masked.
template <int G>
RELIGHT_TARGET_AVX512_VNNI inline void Pass(const int16_t* const* row_a, const int16_t* const* row_b,
                                            const Pair512 (*vec)[3], uint32_t elements, int64_t* acc) {
  const __m512i first = _mm512_load_si512(kInOrder.idx[0]), second = _mm512_load_si512(kInOrder.idx[1]);
  for (uint32_t e0 = 0, j = 0; e0 < elements; e0 += 32, ++j) {
    const int phase = static_cast<int>((2 * j) % 3);  // 32 = 2 (mod 3)
    const uint32_t left = elements - e0;
    const __mmask32 words = left >= 32 ? ~__mmask32{0} : static_cast<__mmask32>((1u << left) - 1);
    __m512i lo_h = _mm512_setzero_si512(), lo_l = lo_h, hi_h = lo_h, hi_l = lo_h;
#pragma GCC unroll 4
    for (int g = 0; g < G; ++g) {
      // Plain loads but on the last step: AMD's prefetchers follow masked
      // loads less well (measured: 2.5x slower over a basis in DRAM).
      const __m512i a = left >= 32 ? _mm512_loadu_si512(row_a[g] + e0) : _mm512_maskz_loadu_epi16(words, row_a[g] + e0);
      const __m512i b = left >= 32 ? _mm512_loadu_si512(row_b[g] + e0) : _mm512_maskz_loadu_epi16(words, row_b[g] + e0);
      const __m512i lo = _mm512_unpacklo_epi16(a, b), hi = _mm512_unpackhi_epi16(a, b);
      const __m512i* k = vec[g][phase].v;
      lo_h = _mm512_dpwssd_epi32(lo_h, lo, k[kLoKh]);
      lo_l = _mm512_dpwssd_epi32(lo_l, lo, k[kLoKl]);
      hi_h = _mm512_dpwssd_epi32(hi_h, hi, k[kHiKh]);
      hi_l = _mm512_dpwssd_epi32(hi_l, hi, k[kHiKl]);
    }
    const __m512i h0 = _mm512_permutex2var_epi32(lo_h, first, hi_h), h1 = _mm512_permutex2var_epi32(lo_h, second, hi_h);
    const __m512i l0 = _mm512_permutex2var_epi32(lo_l, first, hi_l), l1 = _mm512_permutex2var_epi32(lo_l, second, hi_l);
    const __m256i hs[4] = {_mm512_castsi512_si256(h0), _mm512_extracti64x4_epi64(h0, 1), _mm512_castsi512_si256(h1),
                           _mm512_extracti64x4_epi64(h1, 1)};
    const __m256i ls[4] = {_mm512_castsi512_si256(l0), _mm512_extracti64x4_epi64(l0, 1), _mm512_castsi512_si256(l1),
                           _mm512_extracti64x4_epi64(l1, 1)};
    for (int q = 0; q < 4; ++q) {
      const int count = static_cast<int>(left) - 8 * q;
      if (count <= 0) break;
      AddHalves(acc + e0 + 8 * q, hs[q], ls[q], count >= 8 ? __mmask8{0xFF} : static_cast<__mmask8>((1u << count) - 1));
    }
  }
}

}  // namespace

RELIGHT_TARGET_AVX512_VNNI void AccumulateTermsAvx512Vnni(const int16_t* basis, uint64_t stride,
                                                         const uint16_t* terms, uint32_t term_count,
                                                         const TermPairVectors* pairs, uint32_t elements,
                                                         int64_t* acc) {
  const uint32_t pair_count = (term_count + 1) / 2;
  for (uint32_t e = 0; e < elements; ++e) acc[e] = 0;
  for (uint32_t pass = 0; pass < pair_count; pass += kPairsPerWiden) {
    const uint32_t group = pair_count - pass < kPairsPerWiden ? pair_count - pass : kPairsPerWiden;
    const int16_t* row_a[kPairsPerWiden];
    const int16_t* row_b[kPairsPerWiden];
    Pair512 vec[kPairsPerWiden][3];  // built once a pass: 3 KiB
    for (uint32_t g = 0; g < group; ++g) {
      const uint32_t ia = 2 * (pass + g), ib = ia + 1;
      const uint16_t ta = terms[ia];
      const uint16_t tb = ib < term_count ? terms[ib] : ta;  // times zero (see BuildTermPairsAvx2)
      row_a[g] = basis + ta * stride;
      row_b[g] = basis + tb * stride;
      for (int phase = 0; phase < 3; ++phase) vec[g][phase] = Widen(pairs[pass + g], phase);
    }
    switch (group) {
      case 4: Pass<4>(row_a, row_b, vec, elements, acc); break;
      case 3: Pass<3>(row_a, row_b, vec, elements, acc); break;
      case 2: Pass<2>(row_a, row_b, vec, elements, acc); break;
      default: Pass<1>(row_a, row_b, vec, elements, acc); break;
    }
  }
}

RELIGHT_TARGET_AVX512_VNNI void FinishBlockAvx512(const int64_t* acc, uint32_t elements, int shift, int32_t* dst) {
  const __m512i half = _mm512_set1_epi64(shift > 0 ? int64_t{1} << (shift - 1) : 0);
  const __m128i count = _mm_cvtsi32_si128(shift);
  uint32_t i = 0;
  for (; i + 8 <= elements; i += 8) {
    const __m512i v = _mm512_sra_epi64(_mm512_add_epi64(_mm512_loadu_si512(acc + i), half), count);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(dst + i), _mm512_cvtsepi64_epi32(v));
  }
  if (i < elements) {
    const __mmask8 lanes = static_cast<__mmask8>((1u << (elements - i)) - 1);
    const __m512i v = _mm512_sra_epi64(_mm512_add_epi64(_mm512_maskz_loadu_epi64(lanes, acc + i), half), count);
    _mm512_mask_cvtsepi64_storeu_epi32(dst + i, lanes, v);
  }
}

}  // namespace relight

#else  // no x86-64 vector path on this target: RecombineQ12 stays scalar

namespace relight {
void FinishBlockAvx512(const int64_t*, uint32_t, int, int32_t*) {}
void AccumulateTermsAvx512Vnni(const int16_t*, uint64_t, const uint16_t*, uint32_t, const TermPairVectors*,
                               uint32_t, int64_t*) {}
}  // namespace relight

#endif
