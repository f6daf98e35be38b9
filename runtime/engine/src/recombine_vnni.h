// The AVX-512 VNNI body of RecombineQ12 (recombine.h), apart because the
// rest of the runtime is built with -mgeneral-regs-only. Integer
// instructions only; bit-identical to the scalar path and to the AVX2 body
// (recombine_avx2.h), whose multiplier split and bounds it keeps.
#pragma once

#include <cstdint>

#include "recombine_avx2.h"

namespace relight {

// Same contract as AccumulateTermsAvx2 (acc[e] for e in [0, elements), the
// pairs from BuildTermPairsAvx2), 32 elements a step in 512-bit registers,
// the last step with masked loads and stores (no scalar tail).
//
// Scaling and overflow: as AccumulateTermsAvx2. vpdpwssd (not the
// saturating vpdpwssds) is vpmaddwd + vpaddd in one instruction, wrapping
// as vpaddd does; each pair adds < 2 x 2^15 x 2^12 = 2^28 and four pairs
// (8 terms) stay < 2^30 in int32 before they are widened to int64 as
// hi x 2^12 + lo, so nothing wraps.
void AccumulateTermsAvx512Vnni(const int16_t* basis, uint64_t stride, const uint16_t* terms,
                               uint32_t term_count, const TermPairVectors* pairs, uint32_t elements,
                               int64_t* acc);

// dst[i] = SaturateI32((acc[i] + half) >> shift), half = 2^(shift - 1) (0 for
// shift 0), for i in [0, elements): FinishBlock's (recombine.cc) integers,
// 8 a step (vpsraq, then vpmovsqd, which clamps to int32 as SaturateI32
// does). |acc| < 2^55 (recombine.h), so acc + half cannot overflow.
void FinishBlockAvx512(const int64_t* acc, uint32_t elements, int shift, int32_t* dst);

}  // namespace relight
