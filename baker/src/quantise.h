// float64 -> the runtime's integer formats (runtime/base/include/relight/base/fixed.h,
// bake.h). Every conversion rounds to nearest and saturates at its format's
// limits; a block quantiser picks the QuantScale that maps the block's
// largest magnitude to the largest code, so its round-trip error is at most
// half a step (scale / 2).
#pragma once

#include <cstddef>
#include <cstdint>

#include "relight/base/fixed.h"

namespace relight::baker {

// The smallest representable scale >= real_per_lsb, as mantissa *
// 2^(exponent - 30) with mantissa in [2^29, 2^30) (relative excess < 2^-29);
// 0 gives the all-zero scale {0, 0}.
QuantScale MakeQuantScale(double real_per_lsb);
double QuantScaleValue(const QuantScale& scale);

// count values in[k * in_stride] -> out[k * out_stride] as int16 in
// [-32767, 32767]; returns the block's scale (real = q * scale).
QuantScale QuantiseInt16(const double* in, size_t count, size_t in_stride, int16_t* out,
                         size_t out_stride);
// Non-negative values -> uint32 in [0, 2^32 - 1]; negatives clamp to 0.
QuantScale QuantiseUint32(const double* in, size_t count, uint32_t* out);

Q16_16 ToQ16_16(double v);      // metres, degrees
Q1_14 ToQ1_14(double v);        // unit-vector components
Q1_15 ToLevelQ1_15(double v);   // dimmer, colour: clamped to [0, 1], 1.0 -> 32767
Q48_16 ToQ48_16(double v);      // candela
LightQ12 ToLightQ12(double v);  // cd/m^2, lux
uint16_t ToAlbedo(double rho);  // 65535 = 1.0, clamped to [0, 1]
// Form factors, in [0, 1]: UQ0.32, 1.0 itself takes the largest code; <= 0 and NaN give 0.
uint32_t ToUq0_32(double f);

}  // namespace relight::baker
