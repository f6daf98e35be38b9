// Rounded, saturating power-of-two scaling of 128-bit intermediates: the one
// place the engine turns a wide product back into a stored format.
// Integer-only, header-only, thread-safe.
#pragma once

#include <cstdint>
#include <limits>

#include "relight/fixed.h"

namespace relight {

// Number of significant bits of |v| (0 for v == 0).
inline int BitLength128(UInt128 v) {
  const uint64_t hi = static_cast<uint64_t>(v >> 64);
  const uint64_t lo = static_cast<uint64_t>(v);
  if (hi != 0) return 128 - __builtin_clzll(hi);
  if (lo != 0) return 64 - __builtin_clzll(lo);
  return 0;
}

inline UInt128 Abs128(Int128 v) {
  return v < 0 ? static_cast<UInt128>(0) - static_cast<UInt128>(v) : static_cast<UInt128>(v);
}

// v * 2^s, rounded to nearest (halves up), saturated to int64. Valid for
// |v| < 2^126 (every caller's products are far below that).
inline int64_t RoundShiftSat64(Int128 v, int64_t s) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  if (v == 0) return 0;
  if (s >= 0) {
    // Saturate before shifting: |v| * 2^s must stay below 2^63.
    if (s >= 63 || BitLength128(Abs128(v)) + s > 63) return v > 0 ? kMax : kMin;
    return static_cast<int64_t>(v * (static_cast<Int128>(1) << s));
  }
  const int64_t n = -s;
  if (n >= 127) return 0;
  const Int128 r = (v + (static_cast<Int128>(1) << (n - 1))) >> n;
  if (r > kMax) return kMax;
  if (r < kMin) return kMin;
  return static_cast<int64_t>(r);
}

inline int32_t SaturateToInt32(int64_t v) {
  if (v > std::numeric_limits<int32_t>::max()) return std::numeric_limits<int32_t>::max();
  if (v < std::numeric_limits<int32_t>::min()) return std::numeric_limits<int32_t>::min();
  return static_cast<int32_t>(v);
}

}  // namespace relight
