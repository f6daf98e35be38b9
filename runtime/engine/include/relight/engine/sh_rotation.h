// Real-SH rotation in fixed point: the Ivanic-Ruedenberg recurrences
// (J. Phys. Chem. 1996, corrected 1998) build, band by band, the matrix
// that turns a LID's SH coefficients in the fixture frame into the world
// frame at the current aim. Control rate (a pan/tilt change), integer-only,
// allocation-free (caller-owned buffers), thread-safe. The float64 mirror is
// baker/include/relight/baker/sh_rotation.h; tests hold the two together.
#pragma once

#include <cstddef>
#include <cstdint>

#include "relight/base/fixed.h"
#include "relight/base/sh_index.h"

namespace relight {

// Values of all band matrices up to kMaxShDegree (16215 at 22).
inline constexpr size_t kShRotationValues = ShRotationBandOffset(kMaxShDegree + 1);

// The recurrence's coefficients u, v, w for every (l >= 2, m, n), Q3.29
// (|.| < 3.4 up to l = 22), with the sqrt(2) of |m| = 1 folded into v.
// Build once at start-up; share read-only.
struct ShRotationTables {
  int32_t uvw_q29[(kShRotationValues - 10) * 3];
};
void InitShRotationTables(ShRotationTables* tables);

// Band matrices D^l, l = 0..degree, of the rotation whose columns are the
// fixture frame's axes in world coordinates (r_q30 row-major, Q1.30, world =
// R local), each (2l+1)^2 values Q1.30 row-major [m + l][n + l], written to
// d_q30 (ShRotationBandOffset(degree + 1) values), so that world
// coefficients are c'_lm = sum_n D^l_mn c_ln.
// Scaling and overflow: each step forms P = R1 x D^{l-1} products in Q2.60
// (int64, |P| <= 2^61, a sum of two at most 2^62), multiplies by the Q3.29
// coefficients in 128 bits and rounds once to Q1.30 (entries |D| <= 1).
// Error: a few LSB of Q1.30 growing about linearly with l (tests: < 2e-8 at l = 16).
void ShRotationMatricesQ30(const ShRotationTables& tables, int degree, const int32_t r_q30[3][3],
                           int32_t* d_q30);

// c' = D c band by band: coefficients Q48.16 (in and out), sums in 128 bits
// (at most 33 products of |c| < 2^51 and |D| <= 2^30), rounded once.
void RotateShQ16(int degree, const int32_t* d_q30, const int64_t* in_q16, int64_t* out_q16);

}  // namespace relight
