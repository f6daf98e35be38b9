// The emitter solve's final extrapolation (surface_emitter_extrapolate.h).
//
// Scaling: the sums are Int128 (|change| < 2^63 over < 2^32 leaves); both
// are shifted until the earlier fits 31 bits, so num < 2^31 and
// delta (< 2^63) x num < 2^94.
#include "surface_emitter_extrapolate.h"

#include <cstddef>

#include "relight/base/fixed_ops.h"

namespace relight {

void ExtrapolationRatios(const Int128 l1[3], const Int128 l1_before[3], Int128 num[3], Int128 den[3]) {
  for (int ch = 0; ch < 3; ++ch) {
    num[ch] = 0, den[ch] = 1;
    if (l1[ch] <= 0 || l1[ch] >= l1_before[ch]) continue;  // not contracting
    if (l1[ch] * 10 > l1_before[ch] * 9) {  // r > 0.9: 0.9 / 0.1
      num[ch] = 9;
      continue;
    }
    int shift = 0;
    while ((l1_before[ch] >> shift) > INT32_MAX) ++shift;
    num[ch] = l1[ch] >> shift;
    den[ch] = (l1_before[ch] >> shift) - num[ch];
    if (den[ch] <= 0) num[ch] = 0, den[ch] = 1;
  }
}

void ExtrapolateLeaves(uint32_t nodes, const uint8_t* child_count, const int64_t* delta, const Int128 num[3],
                       const Int128 den[3], int64_t* b) {
  // num, den < 2^31 (ExtrapolationRatios), so a change below 2^31 makes a
  // product below 2^62 and the rounded quotient is the same in int64, where
  // the division is several times cheaper than the 128-bit one.
  int64_t num64[3], den64[3];
  for (int ch = 0; ch < 3; ++ch) num64[ch] = static_cast<int64_t>(num[ch]), den64[ch] = static_cast<int64_t>(den[ch]);
  constexpr int64_t kNarrow = int64_t{1} << 31;
  for (uint32_t k = 0; k < nodes; ++k) {
    if (child_count[k] != 0) continue;
    for (int ch = 0; ch < 3; ++ch) {
      const size_t i = 3 * size_t{k} + ch;
      if (num64[ch] == 0) continue;
      const int64_t d = delta[i];
      const int64_t add = d > -kNarrow && d < kNarrow
                              ? DivRound64(d * num64[ch], den64[ch])
                              : SaturateI64(DivRound(Int128{d} * num[ch], den[ch]));
      b[i] = AddSat64(b[i], add);
    }
  }
}

bool FirstSweepSuffices(int64_t change, int64_t peak, const SweepContraction& hint, int tolerance_log2) {
  int64_t first = hint.change[0], second = hint.change[1];
  // first < 2^55 and change < 2^55 (the caller) keep both products below 2^127.
  if (first <= 0 || second <= 0 || second >= first || first >= (int64_t{1} << 55)) return false;
  if (second < first / 8) second = first / 8;
  const Int128 lhs = static_cast<Int128>(change) << tolerance_log2;
  return lhs * second < static_cast<Int128>(peak) * (first - second);
}

}  // namespace relight
