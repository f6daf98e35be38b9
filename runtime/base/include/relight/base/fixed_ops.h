// Rounding and saturation of wide integer intermediates: the one set of
// helpers every fixed-point kernel uses to turn a 128-bit product back into a
// stored format. Integer-only, header-only, thread-safe.
#pragma once

#include <cstdint>
#include <limits>

#include "relight/base/fixed.h"

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

// v / 2^shift rounded to nearest (ties towards +inf); shift >= 1.
constexpr Int128 RoundShift(Int128 v, int shift) {
  return (v + (static_cast<Int128>(1) << (shift - 1))) >> shift;
}

// a / b rounded to nearest (ties away from zero); b > 0.
constexpr Int128 DivRound(Int128 a, Int128 b) { return a >= 0 ? (a + b / 2) / b : -((-a + b / 2) / b); }
// The same in int64, for |a| + b / 2 < 2^63.
constexpr int64_t DivRound64(int64_t a, int64_t b) { return a >= 0 ? (a + b / 2) / b : -((-a + b / 2) / b); }

// v fits int64 when its high half is the sign extension of its low half:
// one compare instead of two 128-bit ones (the emitter solve's leaf update
// and pull spent a fifth of their time in this and AddSat64).
constexpr int64_t SaturateI64(Int128 v) {
  const int64_t lo = static_cast<int64_t>(v);        // modulo 2^64 (GCC, Clang)
  const int64_t hi = static_cast<int64_t>(v >> 64);  // arithmetic shift
  if (hi == (lo >> 63)) return lo;
  return hi < 0 ? std::numeric_limits<int64_t>::min() : std::numeric_limits<int64_t>::max();
}

constexpr int32_t SaturateI32(Int128 v) {
  if (v > std::numeric_limits<int32_t>::max()) return std::numeric_limits<int32_t>::max();
  if (v < std::numeric_limits<int32_t>::min()) return std::numeric_limits<int32_t>::min();
  return static_cast<int32_t>(v);
}

// a + b and a - b saturated to int64 (no signed overflow whatever the
// inputs). They overflow only towards b's sign (a - b: away from it).
constexpr int64_t AddSat64(int64_t a, int64_t b) {
  int64_t r = 0;
  if (__builtin_add_overflow(a, b, &r))
    return b > 0 ? std::numeric_limits<int64_t>::max() : std::numeric_limits<int64_t>::min();
  return r;
}
constexpr int64_t SubSat64(int64_t a, int64_t b) {
  int64_t r = 0;
  if (__builtin_sub_overflow(a, b, &r))
    return b < 0 ? std::numeric_limits<int64_t>::max() : std::numeric_limits<int64_t>::min();
  return r;
}

// v * 2^s, rounded to nearest (halves up), saturated to int64. Valid for
// |v| < 2^126 (every caller's products are far below that).
inline int64_t RoundShiftSat64(Int128 v, int64_t s) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  if (s >= 0) {
    // Saturate before shifting: |v| * 2^s must stay below 2^63.
    if (v == 0) return 0;
    if (s >= 63 || BitLength128(Abs128(v)) + s > 63) return v > 0 ? kMax : kMin;
    return static_cast<int64_t>(v * (static_cast<Int128>(1) << s));
  }
  // A right shift needs no test for zero: (0 + 2^(n-1)) >> n is 0.
  const int64_t n = -s;
  if (n >= 127) return 0;
  return SaturateI64((v + (static_cast<Int128>(1) << (n - 1))) >> n);
}

}  // namespace relight
