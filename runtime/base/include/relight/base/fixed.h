// Fixed-point number formats as types. A Q<I>.<F> value is stored in an
// integer of width I+F (sign included in I) and means raw / 2^F. Formats do
// not mix silently: converting between them is an explicit call that says
// how it rounds and where it saturates.
//
// Formats used across the runtime (each kernel names its formats):
//   Q1_30  int32  unit vectors, cosines, SH values |Y| < 2, sigma factors
//   Q16_16 int32  angles in degrees, positions in metres
//   Q1_14  int16  unit vectors stored in the bake
//   Q1_15  int16  dimmer and colour levels (32767 ~ 1.0, clamped to [0,1])
//   Q48_16 int64  candela, Legendre weights, per-term coefficients
// Output luminance: int32 in units of 1/4096 cd/m^2 (LuminanceQ12).
#pragma once

#include <cstdint>
#include <limits>
#include <type_traits>

namespace relight {

// 128-bit integers for control-rate products (GCC/Clang on 64-bit targets).
// __extension__ keeps -Wpedantic quiet; use these names, not __int128.
__extension__ typedef __int128 Int128;
__extension__ typedef unsigned __int128 UInt128;

template <typename Int, int Frac>
class Fixed {
  static_assert(std::is_integral<Int>::value && std::is_signed<Int>::value, "signed storage");
  static_assert(Frac >= 0 && Frac < static_cast<int>(sizeof(Int) * 8), "fraction bits fit");

 public:
  using Storage = Int;
  static constexpr int kFracBits = Frac;
  static constexpr Int kOneRaw = static_cast<Int>(Frac == static_cast<int>(sizeof(Int) * 8) - 1
                                                      ? std::numeric_limits<Int>::max()
                                                      : (Int{1} << Frac));

  constexpr Fixed() = default;
  static constexpr Fixed FromRaw(Int raw) {
    Fixed f;
    f.raw_ = raw;
    return f;
  }
  // Exact for integers whose value fits; saturates otherwise.
  static constexpr Fixed FromInt(int64_t v) {
    constexpr int64_t kMax = static_cast<int64_t>(std::numeric_limits<Int>::max()) >> Frac;
    constexpr int64_t kMin = static_cast<int64_t>(std::numeric_limits<Int>::min()) >> Frac;
    if (v > kMax) return FromRaw(std::numeric_limits<Int>::max());
    if (v < kMin) return FromRaw(std::numeric_limits<Int>::min());
    return FromRaw(static_cast<Int>(static_cast<int64_t>(v) * (int64_t{1} << Frac)));
  }
  // a / b as a rational, rounded to nearest; b != 0.
  static constexpr Fixed FromRatio(int64_t num, int64_t den) {
    const Int128 scaled = static_cast<Int128>(num) * (static_cast<Int128>(1) << Frac);
    const Int128 half = (den > 0 ? den : -den) / 2;
    const bool negative = (scaled < 0) != (den < 0);
    const Int128 q = (scaled + (negative == (den > 0) ? -half : half)) / den;
    return FromRaw(SaturateRaw(q));
  }

  constexpr Int raw() const { return raw_; }

  // Re-express in another format: shifts with round-to-nearest, saturates.
  template <typename Int2, int Frac2>
  constexpr Fixed<Int2, Frac2> To() const {
    Int128 v = raw_;
    if (Frac2 >= Frac) {
      v *= static_cast<Int128>(1) << (Frac2 - Frac);
    } else {
      const int sh = Frac - Frac2;
      v = (v + (static_cast<Int128>(1) << (sh - 1))) >> sh;
    }
    return Fixed<Int2, Frac2>::FromRaw(Fixed<Int2, Frac2>::SaturateRaw(v));
  }

  static constexpr Int SaturateRaw(Int128 v) {
    if (v > std::numeric_limits<Int>::max()) return std::numeric_limits<Int>::max();
    if (v < std::numeric_limits<Int>::min()) return std::numeric_limits<Int>::min();
    return static_cast<Int>(v);
  }

  friend constexpr bool operator==(Fixed a, Fixed b) { return a.raw_ == b.raw_; }
  friend constexpr bool operator!=(Fixed a, Fixed b) { return a.raw_ != b.raw_; }
  friend constexpr bool operator<(Fixed a, Fixed b) { return a.raw_ < b.raw_; }
  friend constexpr bool operator>(Fixed a, Fixed b) { return a.raw_ > b.raw_; }
  friend constexpr bool operator<=(Fixed a, Fixed b) { return a.raw_ <= b.raw_; }
  friend constexpr bool operator>=(Fixed a, Fixed b) { return a.raw_ >= b.raw_; }
  // Same-format add/subtract saturate.
  friend constexpr Fixed operator+(Fixed a, Fixed b) {
    return FromRaw(SaturateRaw(static_cast<Int128>(a.raw_) + b.raw_));
  }
  friend constexpr Fixed operator-(Fixed a, Fixed b) {
    return FromRaw(SaturateRaw(static_cast<Int128>(a.raw_) - b.raw_));
  }
  constexpr Fixed operator-() const { return FromRaw(SaturateRaw(-static_cast<Int128>(raw_))); }

 private:
  Int raw_ = 0;
};

// Product of two fixed values, rounded to nearest, in the format of the
// result type R. The intermediate is 128-bit, so no operand combination
// overflows before the final saturation.
template <typename R, typename A, typename B>
constexpr R MulFixed(A a, B b) {
  const Int128 p = static_cast<Int128>(a.raw()) * b.raw();
  const int sh = A::kFracBits + B::kFracBits - R::kFracBits;
  // One initialised value (a constexpr function may not leave it unset: clang).
  const Int128 v = sh > 0 ? (p + (static_cast<Int128>(1) << (sh - 1))) >> sh
                          : p * (static_cast<Int128>(1) << (-sh));
  return R::FromRaw(R::SaturateRaw(v));
}

using Q1_30 = Fixed<int32_t, 30>;
using Q2_29 = Fixed<int32_t, 29>;
using Q16_16 = Fixed<int32_t, 16>;
using Q1_14 = Fixed<int16_t, 14>;
using Q1_15 = Fixed<int16_t, 15>;
using Q48_16 = Fixed<int64_t, 16>;
using Q34_30 = Fixed<int64_t, 30>;

// Output luminance (cd/m^2) and illuminance (lux): int32, 1 LSB = 1/4096.
inline constexpr int kLightFracBits = 12;
using LightQ12 = Fixed<int32_t, kLightFracBits>;

// A quantisation scale as stored in the bake: real = q * mantissa * 2^(exponent - 30),
// mantissa in [2^29, 2^30) for a non-zero scale, 0 for an all-zero block.
struct QuantScale {
  int32_t mantissa = 0;
  int32_t exponent = 0;
};

}  // namespace relight
