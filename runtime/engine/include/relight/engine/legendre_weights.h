// Legendre weights of a rotationally symmetric beam in fixed point (Dobashi
// Eq. 19), and their incremental update when one control point moves (Eq. 21).
// The beam is M+1 samples at gamma_k = k * 180 / M degrees, candela in Q48.16.
// Integer-only, allocation-free (caller-owned spans), thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/fixed.h"
#include "relight/base/status.h"

namespace relight {

// f_l(gamma_k) = P_l(cos gamma_k) sin(gamma_k), Q1.30, laid out [l][k] with
// (degree+1) * (M+1) entries (Dobashi Eq. 20, the table the paper suggests
// storing). dgamma = pi/M is applied by the functions below at 128 bits: a
// table of f_l * dgamma would waste log2(M/pi) bits of Q1.30 (~6 at M = 180).
// Returns kInvalidArgument if M < 2 or degree outside [0, kMaxShDegree].
Status BuildLegendreTableQ30(int degree, int M, int32_t* table_q30);

// w_l, l = 0..degree, in Q48.16 candela (Eq. 19), from the table above.
void LegendreWeightsQ16(const int32_t* table_q30, int degree, int M, const int64_t* candela_q16,
                        int64_t* weights_q16);

// Sample k moves from old to new candela: w_l += t_k (new - old) f_l dgamma (2l+1)/2 (Eq. 21).
void UpdateLegendreWeightsQ16(const int32_t* table_q30, int degree, int M, int k,
                              int64_t old_candela_q16, int64_t new_candela_q16,
                              int64_t* weights_q16);

}  // namespace relight
