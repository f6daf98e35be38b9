// AVX2 body of the aimed direct term: see direct_aimed_simd.h. Per step four
// receivers in int64 lanes, each lane the scalar PointLuxQ12 (direct_aimed.cc)
// and AimedRange's RGB step:
//   cos gamma   _mm256_mul_epi32 of the Q1.30 components, summed in int64
//   octave of u 64-bit bit length by a six-step binary search (AVX2 has no
//               64-bit lzcnt), then the table's two entries in one 8-byte load
//   LID         its two samples in one 16-byte load; (b - a) x fraction as the 64 x 16-bit
//               product from two 32-bit multiplies (|.| < 2^63, as the scalar's)
//   RGB         the 12 values of 4 receivers in three vectors of 4 lanes; the
//               33 x 32-bit luminance product from two 32-bit multiplies
// Shifts of signed values use the identity x >> n = ~(~x >>> n) for x < 0
// (AVX2 has no 64-bit arithmetic shift).
#include "direct_aimed_simd.h"

#include <cstddef>

#include "recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define RELIGHT_HAVE_AVX2_PATH 1
#endif

namespace relight {

bool DirectAimedHasAvx2() { return CpuHasAvx2(); }

bool DirectAimedVectorFits(const DirectAimedCall& k, const int64_t* lid_q16, int lid_m) {
  if (k.e_shift < 0 || k.e_shift > 63 || lid_m < 1) return false;
  if (k.intensity_shift < 0 || k.intensity_shift > 63) return false;
  for (int i = 0; i <= lid_m; ++i) {
    // Non-negative samples give a non-negative interpolation, so the
    // intensity's rounding shift can be a logical one.
    if (lid_q16[i] < 0 || lid_q16[i] > (int64_t{1} << 47)) return false;
  }
  return true;
}

#ifdef RELIGHT_HAVE_AVX2_PATH

namespace {

#define RELIGHT_AVX2 __attribute__((target("avx2"), always_inline)) inline

RELIGHT_AVX2 __m256i Set64(int64_t v) { return _mm256_set1_epi64x(v); }

// a > b ? c : a, lane by lane (signed 64-bit compare).
RELIGHT_AVX2 __m256i MinSigned(__m256i a, __m256i b) {
  return _mm256_blendv_epi8(a, b, _mm256_cmpgt_epi64(a, b));
}

// The arithmetic shift right by 16 of int64 lanes.
RELIGHT_AVX2 __m256i ShiftRightSigned16(__m256i x) {
  const __m256i s = _mm256_cmpgt_epi64(_mm256_setzero_si256(), x);
  return _mm256_xor_si256(_mm256_srli_epi64(_mm256_xor_si256(x, s), 16), s);
}

// One step of the bit-length search: where v >> kStep is not 0, v >>= kStep
// and e += kStep.
template <int kStep>
RELIGHT_AVX2 void LengthStep(__m256i* v, __m256i* e) {
  const __m256i t = _mm256_srli_epi64(*v, kStep);
  const __m256i m = _mm256_cmpgt_epi64(t, _mm256_setzero_si256());  // t < 2^62: signed is fine
  *v = _mm256_blendv_epi8(*v, t, m);
  *e = _mm256_add_epi64(*e, _mm256_and_si256(m, Set64(kStep)));
}

// floor(log2 v) for 1 <= v < 2^62.
RELIGHT_AVX2 __m256i FloorLog2(__m256i v) {
  __m256i e = _mm256_setzero_si256();
  LengthStep<32>(&v, &e);
  LengthStep<16>(&v, &e);
  LengthStep<8>(&v, &e);
  LengthStep<4>(&v, &e);
  LengthStep<2>(&v, &e);
  LengthStep<1>(&v, &e);
  return e;
}

// Unaligned 8 and 16-byte loads (table reads with a lane's index: four
// plain loads are cheaper than a gather on the CPUs measured).
RELIGHT_AVX2 __m128i Load8(const void* p) { return _mm_loadl_epi64(static_cast<const __m128i*>(p)); }
RELIGHT_AVX2 __m128i Load16(const void* p) { return _mm_loadu_si128(static_cast<const __m128i*>(p)); }

// Four 64-bit values (each in the low half of its argument) as lanes 0 .. 3.
RELIGHT_AVX2 __m256i Pairs(__m128i v0, __m128i v1, __m128i v2, __m128i v3) {
  return _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_unpacklo_epi64(v0, v1)), _mm_unpacklo_epi64(v2, v3), 1);
}

// x (< 2^64) times y (< 2^32 in each lane's low half) modulo 2^64.
RELIGHT_AVX2 __m256i MulU64ByU32(__m256i x, __m256i y) {
  const __m256i lo = _mm256_mul_epu32(x, y);
  const __m256i hi = _mm256_mul_epu32(_mm256_srli_epi64(x, 32), y);
  return _mm256_add_epi64(lo, _mm256_slli_epi64(hi, 32));
}

// GammaFromCosQ60 (gamma_table.h), four lanes.
RELIGHT_AVX2 __m256i GammaFromCos(const GammaTable& gt, __m256i cos_q60) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i sign = _mm256_cmpgt_epi64(zero, cos_q60);
  const __m256i magnitude = _mm256_sub_epi64(_mm256_xor_si256(cos_q60, sign), sign);
  __m256i u = _mm256_sub_epi64(Set64(int64_t{1} << 60), magnitude);
  u = _mm256_andnot_si256(_mm256_cmpgt_epi64(zero, u), u);  // u < 0 -> 0
  const __m256i table_start = Set64(int64_t{1} << kGammaMinOctave);
  const __m256i small = _mm256_cmpgt_epi64(table_start, u);
  // Below the table: bam[0] u >> 23 (u < 2^23). The table lanes' u is at
  // least 2^23, so their octave and index stay in the table.
  const __m256i g_small =
      _mm256_srli_epi64(_mm256_mul_epu32(Set64(gt.bam[0]), u), kGammaMinOctave);
  const __m256i ut = _mm256_blendv_epi8(u, table_start, small);
  const __m256i e = FloorLog2(ut);
  const __m256i m = _mm256_and_si256(_mm256_srlv_epi64(ut, _mm256_sub_epi64(e, Set64(kGammaSegmentBits))),
                                     Set64((1 << kGammaSegmentBits) - 1));
  const __m256i frac = _mm256_and_si256(
      _mm256_srlv_epi64(ut, _mm256_sub_epi64(e, Set64(kGammaSegmentBits + 16))), Set64(0xffff));
  const __m256i index = _mm256_add_epi64(
      _mm256_slli_epi64(_mm256_sub_epi64(e, Set64(kGammaMinOctave)), kGammaSegmentBits), m);
  // bam[i] and bam[i + 1] in one 8-byte read (i + 1 < kGammaEntries).
  alignas(32) int64_t at[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at), index);
  const __m256i ab = Pairs(Load8(gt.bam + at[0]), Load8(gt.bam + at[1]), Load8(gt.bam + at[2]), Load8(gt.bam + at[3]));
  const __m256i a = _mm256_and_si256(ab, Set64(0xffffffff));
  const __m256i b = _mm256_srli_epi64(ab, 32);
  // The table rises (acos(1 - u) grows with u), so b - a < 2^31.
  const __m256i g_table = _mm256_add_epi64(
      a, _mm256_srli_epi64(_mm256_add_epi64(_mm256_mul_epu32(_mm256_sub_epi64(b, a), frac), Set64(0x8000)), 16));
  const __m256i g = _mm256_blendv_epi8(g_table, g_small, small);
  return _mm256_blendv_epi8(g, _mm256_sub_epi64(Set64(int64_t{1} << 31), g), sign);
}

// LidIntensityFastQ16 (direct_aimed.h), four lanes, gamma in [0, 2^31].
RELIGHT_AVX2 __m256i LidIntensity(const int64_t* lid_q16, int lid_m, __m256i gamma) {
  const __m256i pos = _mm256_srli_epi64(
      _mm256_add_epi64(_mm256_mul_epu32(gamma, Set64(lid_m)), Set64(int64_t{1} << 14)), 15);
  const __m256i index = _mm256_srli_epi64(pos, 16);
  const __m256i top = _mm256_cmpgt_epi64(index, Set64(lid_m - 1));  // index >= M: the last sample
  alignas(32) int64_t at[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at), _mm256_blendv_epi8(index, Set64(lid_m - 1), top));
  // Samples i and i + 1 of each lane in one 16-byte read.
  const __m256i s02 = _mm256_inserti128_si256(_mm256_castsi128_si256(Load16(lid_q16 + at[0])), Load16(lid_q16 + at[2]), 1);
  const __m256i s13 = _mm256_inserti128_si256(_mm256_castsi128_si256(Load16(lid_q16 + at[1])), Load16(lid_q16 + at[3]), 1);
  const __m256i a = _mm256_unpacklo_epi64(s02, s13);
  const __m256i b = _mm256_unpackhi_epi64(s02, s13);
  const __m256i fraction = _mm256_and_si256(pos, Set64(0xffff));
  // (b - a) x fraction: the signed high half's product shifted up plus the
  // unsigned low half's, modulo 2^64 (the exact value is below 2^63).
  const __m256i d = _mm256_sub_epi64(b, a);
  const __m256i step = _mm256_add_epi64(_mm256_mul_epu32(d, fraction),
                                        _mm256_slli_epi64(_mm256_mul_epi32(_mm256_srli_epi64(d, 32), fraction), 32));
  const __m256i value = _mm256_add_epi64(a, ShiftRightSigned16(_mm256_add_epi64(step, Set64(int64_t{1} << 15))));
  return _mm256_blendv_epi8(value, Set64(lid_q16[lid_m]), top);
}

// The low 32 bits of each int64 lane, packed into 128 bits.
RELIGHT_AVX2 __m128i PackLow32(__m256i v) {
  return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6)));
}

}  // namespace

__attribute__((target("avx2"))) uint32_t DirectAimedRangeAvx2(const DirectPoint* points, uint32_t count,
                                                              const DirectAimedCall& k, const GammaTable& gt,
                                                              const int64_t* lid_q16, int lid_m,
                                                              const uint32_t* rho_q32, bool add, int32_t* out) {
  const uint32_t steps = count / 4;
  const __m256i a0 = Set64(k.a0), a1 = Set64(k.a1), a2 = Set64(k.a2);
  const __m256i zero_cos = Set64(k.zero_cos_q60);
  const __m128i intensity_shift = _mm_cvtsi32_si128(k.intensity_shift);
  const __m128i e_shift = _mm_cvtsi32_si128(k.e_shift);
  const __m256i max_lux = Set64((int64_t{1} << 33) - 1);
  const __m256i max_value = Set64(0x7fffffff);
  // Receiver k's E sits in 32-bit slots 2k, 2k + 1; the 12 values of four
  // receivers (3 each) are lanes of these three patterns.
  const __m256i spread[3] = {_mm256_setr_epi32(0, 1, 0, 1, 0, 1, 2, 3), _mm256_setr_epi32(2, 3, 2, 3, 4, 5, 4, 5),
                             _mm256_setr_epi32(4, 5, 6, 7, 6, 7, 6, 7)};
  for (uint32_t s = 0; s < steps; ++s) {
    const DirectPoint* p = points + static_cast<size_t>(s) * 4;
    const auto* raw = reinterpret_cast<const __m128i*>(p);
    const __m256i p02 = _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_loadu_si128(raw)),
                                                _mm_loadu_si128(raw + 2), 1);
    const __m256i p13 = _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_loadu_si128(raw + 1)),
                                                _mm_loadu_si128(raw + 3), 1);
    const __m256i xy = _mm256_unpacklo_epi64(p02, p13);  // lanes: receivers 0 .. 3
    const __m256i zg = _mm256_unpackhi_epi64(p02, p13);
    const __m256i cos_q60 =
        _mm256_add_epi64(_mm256_add_epi64(_mm256_mul_epi32(xy, a0), _mm256_mul_epi32(_mm256_srli_epi64(xy, 32), a1)),
                         _mm256_mul_epi32(zg, a2));
    const __m256i lit = _mm256_cmpgt_epi64(cos_q60, zero_cos);
    int32_t* dst = out + static_cast<size_t>(s) * 12;
    if (_mm256_movemask_epi8(lit) == 0) {  // all four past the cut-off: E = 0
      if (!add) {
        for (int v = 0; v < 3; ++v) _mm_storeu_si128(reinterpret_cast<__m128i*>(dst) + v, _mm_setzero_si128());
      }
      continue;
    }
    const __m256i gamma = GammaFromCos(gt, cos_q60);
    const __m256i intensity = LidIntensity(lid_q16, lid_m, gamma);  // >= 0: DirectAimedVectorFits
    const __m256i i = _mm256_srl_epi64(_mm256_add_epi64(intensity, Set64(k.intensity_half)), intensity_shift);
    const __m256i product = _mm256_mul_epu32(i, _mm256_srli_epi64(zg, 32));  // < 2^63
    __m256i e = _mm256_srl_epi64(_mm256_add_epi64(product, Set64(static_cast<int64_t>(k.e_half))), e_shift);
    e = _mm256_and_si256(MinSigned(e, max_lux), lit);
    for (int v = 0; v < 3; ++v) {
      __m256i value = _mm256_permutevar8x32_epi32(e, spread[v]);
      if (rho_q32 != nullptr) {
        const __m256i rho = _mm256_cvtepu32_epi64(
            _mm_loadu_si128(reinterpret_cast<const __m128i*>(rho_q32 + static_cast<size_t>(s) * 12) + v));
        value = _mm256_srli_epi64(_mm256_add_epi64(MulU64ByU32(value, rho), Set64(int64_t{1} << 31)), 32);
      }
      value = MinSigned(value, max_value);
      auto* slot = reinterpret_cast<__m128i*>(dst) + v;
      if (add) value = MinSigned(_mm256_add_epi64(value, _mm256_cvtepi32_epi64(_mm_loadu_si128(slot))), max_value);
      _mm_storeu_si128(slot, PackLow32(value));
    }
  }
  return steps * 4;
}

#else  // no AVX2 path on this target: the scalar path does every receiver

uint32_t DirectAimedRangeAvx2(const DirectPoint*, uint32_t, const DirectAimedCall&, const GammaTable&,
                              const int64_t*, int, const uint32_t*, bool, int32_t*) {
  return 0;
}

#endif

}  // namespace relight
