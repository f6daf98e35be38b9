// Fixed-point real spherical harmonics, A_lm and the sigma factor: the
// control-rate part of turning a fixture's aim into per-term weights. Same
// conventions as sh_index.h and the baker's float64 photometry.h.
// Integer-only, allocation-free, thread-safe (tables are caller-owned).
#pragma once

#include <cstdint>

#include "relight/base/fixed.h"
#include "relight/base/sh_index.h"
#include "relight/base/status.h"

namespace relight {

// Recurrence constants for real SH up to kMaxShDegree, computed once (integer
// square roots of rationals). Build it at start-up; share it read-only.
// Internal layout, filled by InitShTables. Q3.60 so the recurrence keeps ~50
// bits and the Q1.30 results round only once (Q4.27 lost several LSB at l = 16).
// With q_l^m = sqrt(2) K_lm P_l^m(z) / sin^m(theta) (no sqrt(2) for m = 0):
//   q_m^m = seed[m],  q_l^m = a[l][m] (z q_{l-1}^m - b[l][m] q_{l-2}^m).
struct ShTables {
  int64_t seed_q60[kMaxShDegree + 1];                    // q_m^m, |.| < 1
  int64_t a_q60[kMaxShDegree + 1][kMaxShDegree + 1];     // [l][m], < sqrt(45)
  int64_t b_q60[kMaxShDegree + 1][kMaxShDegree + 1];     // [l][m], < 1
  int64_t four_pi_over_q58[kMaxShDegree + 1];            // 4 pi/(2l+1), Q5.58 (Eq. 10)
};
void InitShTables(ShTables* tables);

// Y_t(dir) for t < (degree+1)^2, dir a unit vector in Q1.30, out in Q1.30
// (|Y_lm| <= sqrt((2l+1)/4pi) < 1.90 for l <= 22). Max error 1 LSB at every
// degree (the recurrence runs at Q50-Q60 and rounds once; tests measure 0.5).
// Precondition: |dir| = 1 within a few LSB (NormaliseQ30's output); other
// inputs give meaningless but well-defined (saturated) values.
void EvalShQ30(const ShTables& tables, int degree, const int32_t dir_q30[3], int32_t* out_q30);

// A_lm(aim) = 4 pi/(2l+1) Y_lm(aim), Dobashi Eq. 10, in Q34.30 (int64).
void AimCoefficientsQ30(const ShTables& tables, int degree, const int32_t aim_q30[3],
                        int64_t* out_q30);

// sigma(N, l), Dobashi Eq. 13, Q1.30.
Q1_30 SigmaQ30(int degree, int l);

}  // namespace relight
