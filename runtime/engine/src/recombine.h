// The hot kernel: basis luminances (int16, term-major) times per-term
// multipliers (int32, from weights.h), summed into LightQ12 outputs.
// Dobashi Eq. 18 with the weights and the bake's quantisation scales folded
// into one integer multiplier per (term, channel).
// Integer-only, allocation-free (caller-owned spans), thread-safe.
#pragma once

#include <cstdint>

namespace relight {

// Receivers per pass over the terms: the int64 accumulators of one block
// (48 KiB scalar, 2 x 24 KiB on the vector path) stay in L1/L2 while every
// term streams past them; larger blocks mean fewer switches between the
// terms' rows, which keeps the hardware prefetchers streaming
// (runtime/bench/recombine_bench: 2048 beat 512 at 100k receivers).
inline constexpr uint32_t kRecombineBlockReceivers = 2048;

// out[r*3 + c] = sat32(round((sum_t basis[(t*count + r)*3 + c] * k[t*3 + c]) / 2^shift))
//
// Scaling and overflow:
//   basis  int16 q, |q| <= 2^15 (the whole int16 range is safe)
//   k      int32, |k| < 2^31 (ChannelMultipliersQ12 guarantees it)
//   acc    int64: each product < 2^15 * 2^31 = 2^46; at most 529 terms
//          (kMaxShDegree = 22) < 2^10, so |sum| < 2^56: 7 guard bits, no
//          overflow possible for any input.
//   out    LightQ12 int32: the sum shifted right by `shift` (0..62) with
//          round-to-nearest (halves up), then saturated to [INT32_MIN,
//          INT32_MAX]; never wraps.
// Terms whose three multipliers are all zero are skipped (e.g. m != 0 terms
// of a beam aimed straight down). scratch: scratch_len >= 3 int64, used in
// blocks of min(scratch_len / 3, count) receivers. Returns the number of
// terms accumulated.
uint32_t RecombineQ12(const int16_t* basis, uint32_t term_count, uint32_t receiver_count,
                      const int32_t* k, int shift, int64_t* scratch, uint32_t scratch_len,
                      int32_t* out);

}  // namespace relight
