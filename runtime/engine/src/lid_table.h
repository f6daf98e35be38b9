// A LID that is not axisymmetric: bilinear interpolation in its (C, gamma)
// table, in the file's own angles (bake.h BakeLid), for the exact direct
// term. Integer-only, allocation-free, thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/fixed_math.h"

namespace relight {

// A view of BakeLid's table. Angles Q16.16 degrees: c from 0 to 360
// (strictly increasing), gamma strictly increasing within [0, 180].
struct LidTableView {
  const int32_t* c_deg_q16 = nullptr;
  uint32_t planes = 0;
  const int32_t* gamma_deg_q16 = nullptr;
  uint32_t gammas = 0;
  const int64_t* candela_q16 = nullptr;  // [plane * gammas + g], Q48.16 cd
};

// I(C, gamma) in Q48.16 cd; C a binary angle (a full turn is 2^32), gamma a
// binary angle in [0, 2^31] (0 to 180 degrees); 0 outside the table's gamma
// range. Scaling: angles compared as degrees x 2^32 (BAM x 360 and table
// angles x 2^16, both exact in int64); the fractions between neighbours are
// Q.16; each interpolation step forms (b - a) x fraction in 128 bits and
// rounds once, so any table of Q48.16 values is safe.
int64_t LidTableIntensityQ16(const LidTableView& table, Bam c, Bam gamma);

}  // namespace relight
