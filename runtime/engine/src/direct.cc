// The exact direct term (see direct.h).
#include "direct.h"

#include <cstddef>

#include "lid_lookup.h"
#include "lid_table.h"
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

// atan2(sqrt(sin2), cos) for sin2 >= 0 (up to 128 bits) and cos at the same
// scale: both are scaled down together so the root is a 64-bit one (~31
// significant bits, far beyond the ~14 bits of a Q1.14 direction), and the
// angle comes from the interpolated atan table (within 5 BAM).
Bam AngleFromSinSquared(UInt128 sin2, int64_t cos) {
  const uint64_t high = static_cast<uint64_t>(sin2 >> 64);
  const int bits = high != 0 ? 128 - __builtin_clzll(high) : 64 - __builtin_clzll(static_cast<uint64_t>(sin2) | 1);
  const int shift = bits > 62 ? (bits - 62 + 1) & ~1 : 0;  // even, so the root scales by 2^(shift/2)
  const int64_t sin_scaled = ISqrt64(static_cast<uint64_t>(sin2 >> shift));
  return Atan2BamFast(sin_scaled, cos >> (shift / 2));
}

}  // namespace

void ReflectanceOverPiQ32(const uint16_t* albedo, uint32_t value_count, uint32_t* out_q32) {
  for (uint32_t i = 0; i < value_count; ++i) {
    // albedo / 65535 * 2^32 / pi, rounded; < 2^47 before the division.
    const uint64_t num = static_cast<uint64_t>(albedo[i]) * kInvPiQ32;
    out_q32[i] = static_cast<uint32_t>((num + 65535 / 2) / 65535);
  }
}

int64_t DirectIlluminanceQ20(const int16_t direction_q14[3], uint32_t geometry,
                             QuantScale geometry_scale, const int32_t axis_q30[3],
                             const int64_t* lid_q16, int lid_m) {
  if (geometry == 0 || geometry_scale.mantissa == 0) return 0;
  int64_t d[3];
  for (int i = 0; i < 3; ++i) d[i] = static_cast<int64_t>(direction_q14[i]) * (int64_t{1} << 16);
  const int64_t a[3] = {axis_q30[0], axis_q30[1], axis_q30[2]};
  if ((d[0] | d[1] | d[2]) == 0) return 0;
  // Q2.60: each product <= 2^60 (+ a few LSB of the axis), the sum < 2^62.
  const int64_t cos_q60 = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
  const int64_t cx = d[1] * a[2] - d[2] * a[1];
  const int64_t cy = d[2] * a[0] - d[0] * a[2];
  const int64_t cz = d[0] * a[1] - d[1] * a[0];
  const UInt128 cross2 = static_cast<UInt128>(static_cast<Int128>(cx) * cx) +
                         static_cast<UInt128>(static_cast<Int128>(cy) * cy) +
                         static_cast<UInt128>(static_cast<Int128>(cz) * cz);
  const Bam gamma = AngleFromSinSquared(cross2, cos_q60);  // 0 .. 2^31, sin >= 0
  return IlluminanceQ20(LidIntensityQ16(lid_q16, lid_m, gamma), geometry, geometry_scale);
}

int64_t IlluminanceQ20(int64_t intensity_q16, uint32_t geometry, QuantScale geometry_scale) {
  // Q48.16 cd x g x mantissa x 2^(exponent - 30) = Q.16 lux; x 2^4 -> Q.20.
  const Int128 p = static_cast<Int128>(intensity_q16) * geometry * geometry_scale.mantissa;
  return RoundShiftSat64(p, static_cast<int64_t>(geometry_scale.exponent) - 26);
}

int64_t DirectIlluminanceTableQ20(const int16_t direction_q14[3], uint32_t geometry,
                                  QuantScale geometry_scale, const FixtureFrameQ30& frame,
                                  const LidTableView& table) {
  if (geometry == 0 || geometry_scale.mantissa == 0) return 0;
  const int64_t d[3] = {direction_q14[0], direction_q14[1], direction_q14[2]};
  if ((d[0] | d[1] | d[2]) == 0) return 0;
  // Q1.14 x Q1.30 = Q2.44; three products < 2^46.
  const auto dot = [&](const int32_t v[3]) { return d[0] * v[0] + d[1] * v[1] + d[2] * v[2]; };
  const int64_t x = dot(frame.c0), y = dot(frame.c90), z = dot(frame.axis);
  const UInt128 r2 = static_cast<UInt128>(static_cast<Int128>(x) * x) +
                     static_cast<UInt128>(static_cast<Int128>(y) * y);
  const Bam gamma = AngleFromSinSquared(r2, z);  // 0 .. 2^31
  const Bam c = Atan2BamFast(y, x);              // a full turn
  return IlluminanceQ20(LidTableIntensityQ16(table, c, gamma), geometry, geometry_scale);
}

namespace {

// Illuminance e(r) (Q.20 lux) of each receiver to LightQ12 luminance or lux.
template <typename Illuminance>
void StoreDirect(const DirectReceivers& receivers, const uint32_t* reflectance_over_pi_q32,
                 DirectStore store, int32_t* out, Illuminance illuminance_q20) {
  for (uint32_t r = 0; r < receivers.count; ++r) {
    const int64_t e_q20 = illuminance_q20(r);
    int32_t* dst = out + static_cast<size_t>(r) * 3;
    for (int c = 0; c < 3; ++c) {
      int64_t v = 0;
      if (reflectance_over_pi_q32 != nullptr) {
        // Q.20 lux x Q0.32 = Q.52, to Q12 cd/m^2.
        const Int128 p =
            static_cast<Int128>(e_q20) * reflectance_over_pi_q32[static_cast<size_t>(r) * 3 + c];
        v = RoundShiftSat64(p, -40);
      } else {
        v = RoundShiftSat64(e_q20, -8);
      }
      int64_t value = SaturateI32(v);
      if (store == DirectStore::kAdd) value += dst[c];  // two int32: no int64 overflow
      dst[c] = SaturateI32(value);
    }
  }
}

}  // namespace

void DirectLightQ12(const DirectReceivers& receivers, const int32_t axis_q30[3],
                    const int64_t* lid_q16, int lid_m, const uint32_t* reflectance_over_pi_q32,
                    DirectStore store, int32_t* out) {
  StoreDirect(receivers, reflectance_over_pi_q32, store, out, [&](uint32_t r) {
    return DirectIlluminanceQ20(receivers.direction_q14 + static_cast<size_t>(r) * 3,
                                receivers.geometry[r], receivers.geometry_scale, axis_q30, lid_q16,
                                lid_m);
  });
}

void DirectLightTableQ12(const DirectReceivers& receivers, const FixtureFrameQ30& frame,
                         const LidTableView& table, const uint32_t* reflectance_over_pi_q32,
                         DirectStore store, int32_t* out) {
  StoreDirect(receivers, reflectance_over_pi_q32, store, out, [&](uint32_t r) {
    return DirectIlluminanceTableQ20(receivers.direction_q14 + static_cast<size_t>(r) * 3,
                                     receivers.geometry[r], receivers.geometry_scale, frame, table);
  });
}

}  // namespace relight
