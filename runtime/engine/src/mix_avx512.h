// The AVX-512 body of MixLuminairesQ12 (mix.h), taken at the avx512vnni
// level (recombine_dispatch.h; it uses AVX-512 F and VL). Integer instructions
// only; the same values as the scalar loop and the AVX2 body (mix_avx2.h),
// bit for bit (mix_test.cc).
#pragma once

#include <cstdint>

namespace relight {

// acc[e] += (a[e] * gain[e % 3] + 2^29) >> 30 (an arithmetic shift), e in
// [0, elements), elements a multiple of 3.
// Scaling and overflow: as MixAddAvx2 (vpmuldq exact in int64, |.| <= 2^61,
// + 2^29 < 2^62), with the native 64-bit arithmetic shift (vpsraq) instead
// of AVX2's emulated one; 24 elements (eight receivers) a step so the gains'
// pattern repeats, the rest masked.
void MixAddAvx512(const int32_t* a, const int64_t gain[3], uint32_t elements, int64_t* acc);

// out[e] = acc[e] saturated to int32 (vpmovsqd), e in [0, elements).
void SaturateAvx512(const int64_t* acc, uint32_t elements, int32_t* out);

}  // namespace relight
