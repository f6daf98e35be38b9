// AVX2 accumulation for RecombineQ12: see recombine_avx2.h. Integer
// instructions only (no float): madd of int16 pairs, int32 adds, sign
// extension to int64.
#include "recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define RELIGHT_HAVE_AVX2_PATH 1
#endif

namespace relight {

#ifdef RELIGHT_HAVE_AVX2_PATH

namespace {

// Two terms' 12-bit halves packed per int32 lane as (term a in the low 16
// bits, term b in the high 16 bits), the order _mm256_unpack*_epi16 puts
// their basis values in, for the channel of each lane.
inline int32_t Pack(int32_t a, int32_t b) {
  return static_cast<int32_t>((static_cast<uint32_t>(b) << 16) | (static_cast<uint32_t>(a) & 0xFFFFu));
}

// For a 16-element chunk starting at element e0 with e0 % 3 == phase:
// unpacklo lanes hold elements e0 + {0,1,2,3 | 8,9,10,11}, unpackhi
// e0 + {4,5,6,7 | 12,13,14,15} (AVX2 unpacks work within 128-bit halves).
constexpr int kLoOffsets[8] = {0, 1, 2, 3, 8, 9, 10, 11};
constexpr int kHiOffsets[8] = {4, 5, 6, 7, 12, 13, 14, 15};

struct PairVectors {
  __m256i lo_kh[3], lo_kl[3], hi_kh[3], hi_kl[3];  // [phase]
};
static_assert(sizeof(PairVectors) == sizeof(TermPairVectors), "opaque storage fits");
static_assert(alignof(PairVectors) <= alignof(TermPairVectors), "opaque storage aligned");

// The channel each lane carries, per phase: lo lane i element e0 +
// kLoOffsets[i], so channel (phase + kLoOffsets[i]) % 3 (hi likewise).
struct LaneChannels {
  int32_t lo[3][8], hi[3][8];
  constexpr LaneChannels() : lo(), hi() {
    for (int phase = 0; phase < 3; ++phase) {
      for (int i = 0; i < 8; ++i) {
        lo[phase][i] = (phase + kLoOffsets[i]) % 3;
        hi[phase][i] = (phase + kHiOffsets[i]) % 3;
      }
    }
  }
};
alignas(32) constexpr LaneChannels kLaneChannels;

// Each lane's packed halves are one of three per channel: packed once, then
// spread over the lanes by a permute per vector (this runs per term pair and
// per call, twice per moved luminaire; the per-lane modulo loop it replaced
// was 4 % of a stage frame).
__attribute__((target("avx2"))) void MakePair(const int32_t* ka, const int32_t* kb,
                                              PairVectors* v) {
  // Arithmetic shift: kh = floor(k / 2^12); kl = k - kh * 2^12 in [0, 2^12).
  const __m256i kh =
      _mm256_setr_epi32(Pack(ka[0] >> 12, kb[0] >> 12), Pack(ka[1] >> 12, kb[1] >> 12),
                        Pack(ka[2] >> 12, kb[2] >> 12), 0, 0, 0, 0, 0);
  const __m256i kl =
      _mm256_setr_epi32(Pack(ka[0] & 0xFFF, kb[0] & 0xFFF), Pack(ka[1] & 0xFFF, kb[1] & 0xFFF),
                        Pack(ka[2] & 0xFFF, kb[2] & 0xFFF), 0, 0, 0, 0, 0);
  for (int phase = 0; phase < 3; ++phase) {
    const __m256i lo = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLaneChannels.lo[phase]));
    const __m256i hi = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLaneChannels.hi[phase]));
    v->lo_kh[phase] = _mm256_permutevar8x32_epi32(kh, lo);
    v->lo_kl[phase] = _mm256_permutevar8x32_epi32(kl, lo);
    v->hi_kh[phase] = _mm256_permutevar8x32_epi32(kh, hi);
    v->hi_kl[phase] = _mm256_permutevar8x32_epi32(kl, hi);
  }
}

// Widens four int32 lanes (the low or high 128 bits of s) to int64.
__attribute__((target("avx2"))) inline __m256i Widen(__m128i s) { return _mm256_cvtepi32_epi64(s); }

// acc += hi * 2^12 + lo for four int64 lanes, from four int32 lanes each.
__attribute__((target("avx2"))) inline __m256i AddHalves(__m256i acc, __m128i hi, __m128i lo) {
  return _mm256_add_epi64(acc, _mm256_add_epi64(_mm256_slli_epi64(Widen(hi), 12), Widen(lo)));
}

constexpr int kPairsPerWiden = 4;  // 8 terms summed in int32 before widening (< 2^30)

}  // namespace

__attribute__((target("avx2"))) void BuildTermPairsAvx2(const uint16_t* terms, uint32_t term_count,
                                                        const int32_t* k, TermPairVectors* pairs) {
  static const int32_t kZero[3] = {0, 0, 0};
  for (uint32_t p = 0; 2 * p < term_count; ++p) {
    const uint32_t ia = 2 * p, ib = ia + 1;
    // An odd term count pairs the last term with itself times zero.
    const int32_t* kb = ib < term_count ? k + 3 * terms[ib] : kZero;
    MakePair(k + 3 * terms[ia], kb, reinterpret_cast<PairVectors*>(pairs[p].bytes));
  }
}

// One pass of G term pairs (G <= 4, 8 terms: the int32 sums cannot overflow)
// over all 16-element chunks: multiply-adds unrolled over the pairs, then the
// int32 sums widened as hi * 2^12 + lo and added to acc. The rows of a pass
// are read side by side, a handful of streams the hardware prefetcher keeps up with.
template <int G>
__attribute__((target("avx2"), always_inline)) inline void Pass(const int16_t* const* row_a,
                                                                const int16_t* const* row_b,
                                                                const PairVectors* vec, uint32_t chunks,
                                                                int64_t* acc) {
  for (uint32_t j = 0; j < chunks; ++j) {
    const uint32_t e0 = 16 * j;
    const int phase = static_cast<int>(j % 3);  // 16 = 1 (mod 3)
    __m256i lo_h = _mm256_setzero_si256(), lo_l = lo_h, hi_h = lo_h, hi_l = lo_h;
#pragma GCC unroll 4
    for (int g = 0; g < G; ++g) {
      const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row_a[g] + e0));
      const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row_b[g] + e0));
      const __m256i lo = _mm256_unpacklo_epi16(a, b);
      const __m256i hi = _mm256_unpackhi_epi16(a, b);
      lo_h = _mm256_add_epi32(lo_h, _mm256_madd_epi16(lo, vec[g].lo_kh[phase]));
      lo_l = _mm256_add_epi32(lo_l, _mm256_madd_epi16(lo, vec[g].lo_kl[phase]));
      hi_h = _mm256_add_epi32(hi_h, _mm256_madd_epi16(hi, vec[g].hi_kh[phase]));
      hi_l = _mm256_add_epi32(hi_l, _mm256_madd_epi16(hi, vec[g].hi_kl[phase]));
    }
    // Lanes: lo holds elements e0 + {0..3 | 8..11}, hi e0 + {4..7 | 12..15}.
    __m256i* out = reinterpret_cast<__m256i*>(acc + e0);
    _mm256_storeu_si256(out + 0, AddHalves(_mm256_loadu_si256(out + 0), _mm256_castsi256_si128(lo_h),
                                           _mm256_castsi256_si128(lo_l)));
    _mm256_storeu_si256(out + 1, AddHalves(_mm256_loadu_si256(out + 1), _mm256_castsi256_si128(hi_h),
                                           _mm256_castsi256_si128(hi_l)));
    _mm256_storeu_si256(out + 2, AddHalves(_mm256_loadu_si256(out + 2), _mm256_extracti128_si256(lo_h, 1),
                                           _mm256_extracti128_si256(lo_l, 1)));
    _mm256_storeu_si256(out + 3, AddHalves(_mm256_loadu_si256(out + 3), _mm256_extracti128_si256(hi_h, 1),
                                           _mm256_extracti128_si256(hi_l, 1)));
  }
}

__attribute__((target("avx2"))) void AccumulateTermsAvx2(const int16_t* basis, uint64_t stride,
                                                         const uint16_t* terms, uint32_t term_count,
                                                         const int32_t* k, const TermPairVectors* pairs,
                                                         uint32_t elements, int64_t* acc) {
  const uint32_t chunks = elements / 16;
  const uint32_t pair_count = (term_count + 1) / 2;
  const PairVectors* vec = reinterpret_cast<const PairVectors*>(pairs);
  for (uint32_t e = 0; e < chunks * 16; ++e) acc[e] = 0;
  for (uint32_t pass = 0; pass < pair_count; pass += kPairsPerWiden) {
    const uint32_t group = pair_count - pass < kPairsPerWiden ? pair_count - pass : kPairsPerWiden;
    const int16_t* row_a[kPairsPerWiden];
    const int16_t* row_b[kPairsPerWiden];
    for (uint32_t g = 0; g < group; ++g) {
      const uint32_t ia = 2 * (pass + g), ib = ia + 1;
      const uint16_t ta = terms[ia];
      const uint16_t tb = ib < term_count ? terms[ib] : ta;  // times zero (see BuildTermPairsAvx2)
      row_a[g] = basis + ta * stride;
      row_b[g] = basis + tb * stride;
    }
    switch (group) {
      case 4: Pass<4>(row_a, row_b, vec + pass, chunks, acc); break;
      case 3: Pass<3>(row_a, row_b, vec + pass, chunks, acc); break;
      case 2: Pass<2>(row_a, row_b, vec + pass, chunks, acc); break;
      default: Pass<1>(row_a, row_b, vec + pass, chunks, acc); break;
    }
  }
  // Tail elements (fewer than 16): exact scalar products.
  for (uint32_t e = chunks * 16; e < elements; ++e) {
    int64_t sum = 0;
    for (uint32_t i = 0; i < term_count; ++i) {
      sum += static_cast<int64_t>(basis[terms[i] * stride + e]) * k[3 * terms[i] + e % 3];
    }
    acc[e] = sum;
  }
}

#else  // no AVX2 path on this target: RecombineQ12 stays scalar

void BuildTermPairsAvx2(const uint16_t*, uint32_t, const int32_t*, TermPairVectors*) {}
void AccumulateTermsAvx2(const int16_t*, uint64_t, const uint16_t*, uint32_t, const int32_t*,
                         const TermPairVectors*, uint32_t, int64_t*) {}

#endif

}  // namespace relight
