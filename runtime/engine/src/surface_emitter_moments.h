// The source-moment terms of the emitter solve's gathers (docs/hierarchy.md
// "Bias and its fix", as the baker's hierarchy_solve.cc): a link from an
// inner node q gives its receiver f (B_q + (g_qp / f_qp) . m_q) rather than
// f B_q, m_q the first moment of q's exitance about its centre. A coarse
// link otherwise credits the receiver with q's mean exitance, and in a room
// the part of q a receiver sees best is dimmer than that mean: a dark bias
// of the interreflected light (0.33 % of peak on the Cornell wall window's
// grid, 0.013 % with the terms).
//
// Built at open (allocates); the solve takes the weights into its own
// entries for links from inner nodes (EmitterInnerSourceEntry). Integer only.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/fixed_ops.h"
#include "surface_emitter_gather_avx2.h"

namespace relight {

// Moment weights before the shift: Q36 per metre, so a weight times the
// moment view (Q20 x metres) is Q56, as a factor (UQ0.32) times the exitance
// view (Q24) is.
inline constexpr int kMomentWeightFracBits = 36;

struct EmitterMomentTable {
  // Node k's terms: entries[offsets[k] .. offsets[k + 1]), one per gather
  // entry (f_pq and f_qp both > 0) whose source is an inner node.
  std::vector<uint32_t> offsets;
  std::vector<EmitterMomentEntry> entries;
  // inner_before[k]: inner nodes before node k (an inner node's index among
  // them; entries' sources are such indices). n + 1 values.
  std::vector<uint32_t> inner_before;
  // t: the weights are stored Q(36 - t) so the largest fits int32; a gather
  // multiplies its moment sum by 2^t.
  int shift = 0;
};

// A child's exitance (or covered fraction) b, Q32, times its centre's offset
// from its parent's, Q16 metres: its share of the parent's first moment,
// Q32 x metres, rounded. In int64 where the product fits (every node of a
// real bake: below 2^47 times below 2^16), else in 128 bits: the same value
// either way. The solve's pull and adaptive refine's coverage moments both
// use it, so an unrefined link sends the moment the gathers would have.
inline int64_t OffsetMomentQ32(int64_t b, int64_t d_q16) {
  constexpr int64_t kHalf = int64_t{1} << 15;
  int64_t p = 0;
  if (!__builtin_mul_overflow(b, d_q16, &p) && p <= INT64_MAX - kHalf) return (p + kHalf) >> 16;
  return RoundShiftSat64(static_cast<Int128>(b) * d_q16, -16);
}

void BuildEmitterMoments(const BakeHierarchy& h, EmitterMomentTable* table);

// Node k's largest gather multiplier of the moment view, 2^t sum (|wu| + |wv|),
// saturated to 2^63 - 1 (the solve's overflow bound adds it to sum f).
uint64_t EmitterMomentRowSum(const EmitterMomentTable& table, uint32_t k);

}  // namespace relight
