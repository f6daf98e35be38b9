#include "quantise.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace relight::baker {
namespace {

constexpr double kTwo30 = 1073741824.0;  // 2^30

// Rounds to nearest and saturates into [lo, hi].
template <typename Int>
Int RoundSaturate(double v, double lo, double hi) {
  if (std::isnan(v)) throw std::runtime_error("quantise: NaN value");
  return static_cast<Int>(std::llround(std::clamp(v, lo, hi)));
}

template <typename F>
F FromReal(double v) {
  using Int = typename F::Storage;
  const double scaled = std::ldexp(v, F::kFracBits);
  // The bounds are exact in a double for every format up to 53 bits; the
  // int64 format clamps 2^10 below its limit so llround cannot overflow.
  const double hi =
      std::min(static_cast<double>(std::numeric_limits<Int>::max()), 9.2233720368547e18);
  const double lo =
      std::max(static_cast<double>(std::numeric_limits<Int>::min()), -9.2233720368547e18);
  return F::FromRaw(RoundSaturate<Int>(scaled, lo, hi));
}

}  // namespace

QuantScale MakeQuantScale(double real_per_lsb) {
  if (!(real_per_lsb > 0) || !std::isfinite(real_per_lsb)) return QuantScale{};
  int e = 0;
  const double fr = std::frexp(real_per_lsb, &e);  // real = fr * 2^e, fr in [0.5, 1)
  // Rounded up: the stored step is never smaller than asked for, so the
  // block's largest value never lands above the top code (for uint32 codes a
  // rounded-down step could push it several codes past 2^32 - 1).
  long long m = static_cast<long long>(std::ceil(fr * kTwo30));
  if (m == (1LL << 30)) {
    m = 1LL << 29;
    ++e;
  }
  return QuantScale{static_cast<int32_t>(m), static_cast<int32_t>(e)};
}

double QuantScaleValue(const QuantScale& scale) {
  return std::ldexp(static_cast<double>(scale.mantissa), scale.exponent - 30);
}

QuantScale QuantiseInt16(const double* in, size_t count, size_t in_stride, int16_t* out,
                         size_t out_stride) {
  constexpr double kMaxCode = 32767.0;
  double max_abs = 0;
  for (size_t k = 0; k < count; ++k) {
    const double v = in[k * in_stride];
    if (!std::isfinite(v)) throw std::runtime_error("quantise: non-finite basis value");
    max_abs = std::max(max_abs, std::abs(v));
  }
  const QuantScale scale = MakeQuantScale(max_abs / kMaxCode);
  const double step = QuantScaleValue(scale);
  for (size_t k = 0; k < count; ++k) {
    out[k * out_stride] =
        step > 0 ? RoundSaturate<int16_t>(in[k * in_stride] / step, -kMaxCode, kMaxCode) : 0;
  }
  return scale;
}

QuantScale QuantiseUint32(const double* in, size_t count, uint32_t* out) {
  constexpr double kMaxCode = 4294967295.0;
  double max_v = 0;
  for (size_t k = 0; k < count; ++k) {
    if (!std::isfinite(in[k])) throw std::runtime_error("quantise: non-finite geometry value");
    max_v = std::max(max_v, in[k]);
  }
  const QuantScale scale = MakeQuantScale(max_v / kMaxCode);
  const double step = QuantScaleValue(scale);
  for (size_t k = 0; k < count; ++k) {
    out[k] = step > 0 ? RoundSaturate<uint32_t>(in[k] / step, 0.0, kMaxCode) : 0;
  }
  return scale;
}

Q16_16 ToQ16_16(double v) { return FromReal<Q16_16>(v); }
Q1_14 ToQ1_14(double v) { return FromReal<Q1_14>(v); }
Q1_15 ToLevelQ1_15(double v) { return FromReal<Q1_15>(std::clamp(v, 0.0, 1.0)); }
Q48_16 ToQ48_16(double v) { return FromReal<Q48_16>(v); }
LightQ12 ToLightQ12(double v) { return FromReal<LightQ12>(v); }
uint16_t ToAlbedo(double rho) {
  return RoundSaturate<uint16_t>(std::clamp(rho, 0.0, 1.0) * 65535.0, 0.0, 65535.0);
}

uint32_t ToUq0_32(double f) {
  constexpr double kTwo32 = 4294967296.0;
  if (!(f > 0)) return 0;
  const double q = std::round(f * kTwo32);
  return q >= kTwo32 ? std::numeric_limits<uint32_t>::max() : static_cast<uint32_t>(q);
}

}  // namespace relight::baker
