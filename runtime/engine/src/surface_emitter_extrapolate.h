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

// How fast a solve's sweeps contracted: the largest change of its first two
// sweeps and their sums of |change| per channel. A drag (an emitter moved a
// few centimetres at a time) repeats the same contraction from solve to
// solve, so the next solve can stop after one sweep where this one needed
// two (SolveRgb's `hint`).
// A one-sweep solve hands its hint on with `reused` one more; a hint reused
// kMaxContractionReuse times is not taken, so a long drag measures again
// every few solves.
inline constexpr int kMaxContractionReuse = 3;
struct SweepContraction {
  bool valid = false;
  int reused = 0;
  int64_t change[2] = {0, 0};
  Int128 l1[2][3] = {{0, 0, 0}, {0, 0, 0}};
};

// The stopping rule after a first sweep whose largest change is `change`
// (< 2^55), with the hint's ratio r of its first two sweeps' largest changes
// (at least 1/8, so a hint that saw a very fast drop cannot stop a solve
// whose first change is large): true when change x r / (1 - r) is below
// 2^-tolerance_log2 of `peak`.
bool FirstSweepSuffices(int64_t change, int64_t peak, const SweepContraction& hint, int tolerance_log2);

}  // namespace relight
