// Private helpers shared by fixed_math.cc, sh_eval.cc and legendre_weights.cc:
// pi and sin/cos at Q2.61 (well beyond the Q1.30 the API returns, so the
// public results round only once), and 128-bit rounding primitives.
// Integer-only (built with -mgeneral-regs-only).
#pragma once

#include <cstdint>
#include <limits>

namespace relight::internal {

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

// round(pi * 2^61) = 7244019458077122842 (0x6487ED5110B4611A).
inline constexpr int64_t kPiQ61 = 7244019458077122842;
inline constexpr int64_t kOneQ61 = int64_t{1} << 61;
inline constexpr int64_t kOneQ60 = int64_t{1} << 60;

// v / 2^shift rounded to nearest (ties towards +inf); shift >= 1.
constexpr i128 RoundShift(i128 v, int shift) {
  return (v + (static_cast<i128>(1) << (shift - 1))) >> shift;
}

// a / b rounded to nearest (ties away from zero); b > 0.
constexpr i128 DivRound(i128 a, i128 b) { return a >= 0 ? (a + b / 2) / b : -((-a + b / 2) / b); }

constexpr int64_t SaturateI64(i128 v) {
  if (v > std::numeric_limits<int64_t>::max()) return std::numeric_limits<int64_t>::max();
  if (v < std::numeric_limits<int64_t>::min()) return std::numeric_limits<int64_t>::min();
  return static_cast<int64_t>(v);
}

constexpr int32_t SaturateI32(i128 v) {
  if (v > std::numeric_limits<int32_t>::max()) return std::numeric_limits<int32_t>::max();
  if (v < std::numeric_limits<int32_t>::min()) return std::numeric_limits<int32_t>::min();
  return static_cast<int32_t>(v);
}

// sin and cos of the angle 2 pi num/den (num/den of a full turn), Q2.61.
// 1 <= den <= 2^32, any num. Error below 2^-58 (a few Q61 ulps).
void SinCosTurnQ61(uint64_t num, uint64_t den, int64_t* sin_q61, int64_t* cos_q61);

}  // namespace relight::internal
