// The emitter solve's last step (surface_emitter_solve.h): where the sweeps
// stop, each channel's changes shrink by about r = (sum over the leaves of
// |change|) / (the same a sweep before), the slowest mode -- the room's
// ambient light -- dominating them, so the rest of the series is the last
// change x r / (1 - r): Aitken's extrapolation with one ratio per channel.
// It lets the sweeps stop at 2^-11 of peak instead of 2^-15 with the grids
// as accurate (docs/hierarchy.md "Fewer sweeps").
//
// The sum, not the largest change: the largest is the emitter's near field,
// which dies out faster, and its ratio under-corrects the ambient light the
// grids read (Cornell ceiling panel, FE, floor grid, 5 sweeps: 0.152 % of
// peak mean error with the largest change's ratio, 0.117 % with the sums').
// Integer only.
#pragma once

#include <cstdint>

#include "relight/base/fixed.h"

namespace relight {

// r / (1 - r) as num / den per channel from the two sweeps' sums of |change|
// (Q32, >= 0); 0 / 1 (no extrapolation) unless the sums shrink; r at most 0.9.
void ExtrapolationRatios(const Int128 l1[3], const Int128 l1_before[3], Int128 num[3], Int128 den[3]);

// b[3 k + c] += delta[3 k + c] x num[c] / den[c] for every k with leaf[k]
// (rounded, saturated to int64).
void ExtrapolateLeaves(uint32_t nodes, const uint8_t* child_count, const int64_t* delta, const Int128 num[3],
                       const Int128 den[3], int64_t* b);

}  // namespace relight
