// LID table lookup with linear interpolation (see lid_lookup.h).
#include "lid_lookup.h"

#include "relight/base/fixed_ops.h"

namespace relight {

int64_t LidIntensityQ16(const int64_t* candela_q16, int M, Bam gamma) {
  constexpr uint32_t kHalfTurn = uint32_t{1} << 31;
  if (gamma > kHalfTurn) gamma = 0u - gamma;  // 360 - gamma
  // Samples from the axis, Q.16: gamma / 2^31 * M, rounded.
  constexpr int kDrop = 31 - kLidFractionBits;
  const uint64_t pos = (static_cast<uint64_t>(gamma) * static_cast<uint64_t>(M) +
                        (uint64_t{1} << (kDrop - 1))) >> kDrop;
  const uint64_t index = pos >> kLidFractionBits;
  if (index >= static_cast<uint64_t>(M)) return candela_q16[M];
  const int64_t fraction = static_cast<int64_t>(pos & ((uint64_t{1} << kLidFractionBits) - 1));
  const int64_t a = candela_q16[index];
  const int64_t b = candela_q16[index + 1];
  const Int128 step = (static_cast<Int128>(b) - a) * fraction;
  const Int128 value = static_cast<Int128>(a) + RoundShiftSat64(step, -kLidFractionBits);
  return RoundShiftSat64(value, 0);
}

}  // namespace relight
