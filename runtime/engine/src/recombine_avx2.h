// The AVX2 body of RecombineQ12 (recombine.h), in its own file because the
// rest of the runtime is built with -mgeneral-regs-only. It uses integer
// instructions only; tests/runtime/no_float_test checks its object code for
// floating-point instructions. Results are bit-identical to the scalar path.
#pragma once

#include <cstdint>

#include "relight/base/sh_index.h"

namespace relight {

// Multipliers the vector path accepts: |k| < 2^kVectorMultiplierBits (each k
// is split into a signed high and an unsigned low 12-bit half for 16-bit
// multiply-adds). RecombineQ12 falls back to the scalar path otherwise.
inline constexpr int kVectorMultiplierBits = 24;

// True when the active level (recombine_dispatch.h: the CPU's, capped by
// RELIGHT_FORCE_SCALAR, RELIGHT_SIMD or SetSimdLevelCap) is AVX2 or above.
bool CpuHasAvx2();

// The multiplier vectors of one term pair, built once per call and reused for
// every block of receivers (opaque here: AVX2 registers in the .cc).
struct alignas(32) TermPairVectors {
  uint8_t bytes[12 * 32];
};
inline constexpr uint32_t kMaxTermPairs = (ShTermCount(kMaxShDegree) + 1) / 2;

// Builds (term_count + 1) / 2 pair vectors for the given terms and multipliers.
void BuildTermPairsAvx2(const uint16_t* terms, uint32_t term_count, const int32_t* k, TermPairVectors* pairs);

// acc[e] = sum over the given terms of q_t[e] * k[t*3 + e % 3], exactly, for
// e in [0, elements), where q_t = basis + t * stride (int16 elements). The
// term list holds indices into the rows/multipliers; |k| < 2^24 for those.
//
// Scaling and overflow: each k = kh * 2^12 + kl, kh in [-2^12, 2^12),
// kl in [0, 2^12). _mm256_madd_epi16 forms q_a*kh_a + q_b*kh_b for a term
// pair in int32 (< 2 * 2^15 * 2^12 = 2^28); four pairs (8 terms) are summed
// in int32 (< 2^30) before widening to int64 as hi * 2^12 + lo; the total
// stays below 529 * 2^27 * 2^12 * 2 < 2^50 (529 terms at kMaxShDegree = 22).
void AccumulateTermsAvx2(const int16_t* basis, uint64_t stride, const uint16_t* terms, uint32_t term_count,
                         const int32_t* k, const TermPairVectors* pairs, uint32_t elements, int64_t* acc);

}  // namespace relight
