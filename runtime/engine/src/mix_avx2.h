// The AVX2 body of MixLuminairesQ12 (mix.h), apart because the rest of the
// runtime is built with -mgeneral-regs-only. Integer instructions only
// (tests/runtime/no_float_check.sh checks the object code); the same
// values as the scalar loop, bit for bit (mix_test.cc, both paths).
#pragma once

#include <cstdint>

namespace relight {

// acc[e] += (a[e] * gain[e % 3] + 2^29) >> 30 (an arithmetic shift), e in
// [0, elements), elements a multiple of 3.
// Scaling and overflow: a int32, gain 0 .. 2^30 (int32): the product by
// _mm256_mul_epi32 is exact in int64 (|.| <= 2^61); + 2^29 stays below 2^62;
// the shift is emulated (AVX2 has no 64-bit arithmetic shift) as a logical
// one with the sign bits put back; acc as in mix.h (< 2^63).
void MixAddAvx2(const int32_t* a, const int64_t gain[3], uint32_t elements, int64_t* acc);

// out[e] = acc[e] saturated to int32, e in [0, elements).
void SaturateAvx2(const int64_t* acc, uint32_t elements, int32_t* out);

}  // namespace relight
