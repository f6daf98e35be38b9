// Fixed-point real spherical harmonics, A_lm and the sigma factor: the
// control-rate part of turning a fixture's aim into per-term weights. Same
// conventions as sh_index.h and the baker's float64 photometry.h.
// Integer-only, allocation-free, thread-safe (tables are caller-owned).
#pragma once

#include <cstdint>

#include "relight/fixed.h"
#include "relight/sh_index.h"
#include "relight/status.h"

namespace relight {

// Recurrence constants for real SH up to kMaxShDegree, computed once (integer
// square roots of rationals). Build it at start-up; share it read-only.
struct ShTables {
  // Internal layout; filled by InitShTables.
  int32_t k_mm[kMaxShDegree + 1];                      // normalisation seeds, Q1.30
  int32_t a_lm[kMaxShDegree + 1][kMaxShDegree + 1];    // Q4.27
  int32_t b_lm[kMaxShDegree + 1][kMaxShDegree + 1];    // Q4.27
};
void InitShTables(ShTables* tables);

// Y_t(dir) for t < (degree+1)^2, dir a unit vector in Q1.30, out in Q1.30
// (|Y_lm| <= sqrt((2l+1)/4pi) < 1.63 for l <= 16). Max error a few LSB
// times degree.
void EvalShQ30(const ShTables& tables, int degree, const int32_t dir_q30[3], int32_t* out_q30);

// A_lm(aim) = 4 pi/(2l+1) Y_lm(aim), Dobashi Eq. 10, in Q34.30 (int64).
void AimCoefficientsQ30(const ShTables& tables, int degree, const int32_t aim_q30[3],
                        int64_t* out_q30);

// sigma(N, l), Dobashi Eq. 13, Q1.30.
Q1_30 SigmaQ30(int degree, int l);

}  // namespace relight
