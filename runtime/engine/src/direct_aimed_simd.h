// The vector bodies of the aimed direct term (direct_aimed.h): AVX2, four
// receivers a step (direct_aimed_avx2.cc), and AVX-512, eight
// (direct_aimed_avx512.cc), in their own files because the rest of the
// runtime is built with -mgeneral-regs-only. Integer instructions only
// (no_float_check.sh checks the object code), the scalar path's arithmetic
// lane by lane: bit-identical.
#pragma once

#include <cstdint>

#include "direct_aimed.h"
#include "gamma_table.h"

namespace relight {

// The aimed kernel's per-call constants (direct_aimed.cc fills them).
struct DirectAimedCall {
  int64_t a0, a1, a2;    // beam axis, Q1.30
  int64_t zero_cos_q60;  // cos gamma <= it: the LID gives 0 (direct_cull.h)
  int intensity_shift;   // I_q16 >> it < 2^31 for every sample of this LID
  int64_t intensity_half;
  int e_shift;           // (I >> intensity_shift) x geometry >> e_shift = E_q12
  uint64_t e_half;
};

// True when the CPU runs AVX2 (recombine_avx2.h CpuHasAvx2: honours
// RELIGHT_FORCE_SCALAR).
bool DirectAimedHasAvx2();

// True when the active level is avx512vnni (recombine_dispatch.h: honours
// the caps) and the CPU also has AVX-512 CD and DQ.
bool DirectAimedHasAvx512();

// The call's constants the vector bodies take: e_shift in [0, 63] and every
// LID sample in [0, 2^47] with lid_m >= 1 (otherwise the scalar path runs).
bool DirectAimedVectorFits(const DirectAimedCall& k, const int64_t* lid_q16, int lid_m);

// Receivers [0, count) of a block, count rounded down to a multiple of 4
// (returned; the caller does the rest): points[i] is receiver i, rho and out
// start at the block's first receiver (3 per receiver; rho nullptr: lux).
// kAdd adds to out with the scalar path's saturation.
uint32_t DirectAimedRangeAvx2(const DirectPoint* points, uint32_t count, const DirectAimedCall& k,
                              const GammaTable& gt, const int64_t* lid_q16, int lid_m, const uint32_t* rho_q32,
                              bool add, int32_t* out);
// The same, count rounded down to a multiple of 8.
uint32_t DirectAimedRangeAvx512(const DirectPoint* points, uint32_t count, const DirectAimedCall& k,
                                const GammaTable& gt, const int64_t* lid_q16, int lid_m, const uint32_t* rho_q32,
                                bool add, int32_t* out);

}  // namespace relight
