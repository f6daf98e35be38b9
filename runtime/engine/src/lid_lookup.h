// The luminaire's luminous intensity at an angle from its beam axis: linear
// interpolation in the bake's LID table (M+1 uniform samples, gamma 0..180
// degrees). Integer-only, allocation-free, thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/fixed_math.h"

namespace relight {

// Fraction bits of the position between two samples.
inline constexpr int kLidFractionBits = 16;

// I(gamma) in Q48.16 cd. gamma is a binary angle from the beam axis, 0 ..
// 2^31 (= 180 degrees); angles past 180 degrees fold back (the LID is
// rotationally symmetric, so gamma and 360 - gamma are the same direction
// cone). candela_q16 has M+1 entries, M >= 1.
// Scaling: position = gamma * M / 2^31 samples, rounded to 16 fraction
// bits; the difference of neighbouring samples times the fraction is formed
// in 128 bits, so any Q48.16 table is safe.
int64_t LidIntensityQ16(const int64_t* candela_q16, int M, Bam gamma);

}  // namespace relight
