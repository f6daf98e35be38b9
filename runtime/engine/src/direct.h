// The exact direct term (DESIGN.md "split direct from indirect"): per
// receiver, the angle between the stored direction from the luminaire and
// the beam axis, the LID at that angle, times the stored geometric factor.
// Integer-only, allocation-free, thread-safe.
#pragma once

#include <cstdint>

#include "fixture_frame.h"
#include "lid_table.h"
#include "relight/bake/bake.h"
#include "relight/base/fixed.h"

namespace relight {

// 1/pi in Q0.32: round(2^32 / pi) = round(1367130551.15).
inline constexpr uint32_t kInvPiQ32 = 1367130551u;

// One luminaire's direct data on one receiver set (views into the bake).
struct DirectReceivers {
  const int16_t* direction_q14 = nullptr;  // 3 per receiver, luminaire -> receiver
  const uint32_t* geometry = nullptr;      // 1 per receiver, visibility cos / d^2
  QuantScale geometry_scale;               // m^-2 per LSB
  uint32_t count = 0;
};

// A luminaire's bake receivers on one set as a DirectReceivers view.
inline DirectReceivers DirectReceiversOf(const BakeLightReceivers& rx, uint32_t count) {
  DirectReceivers d;
  d.direction_q14 = rx.direction.data();
  d.geometry = rx.geometry.data();
  d.geometry_scale = rx.geometry_scale;
  d.count = count;
  return d;
}

// rho_c / pi per vertex and channel, Q0.32, from the bake's albedo
// (65535 = 1): the Lambertian factor from illuminance to luminance.
void ReflectanceOverPiQ32(const uint16_t* albedo, uint32_t value_count, uint32_t* out_q32);

// Illuminance E = I(gamma) * G at each receiver, in Q43.20 lux (int64):
//   cos gamma = dir . axis, sin gamma = |dir x axis| (dir Q1.14 -> Q1.30,
//   products Q2.60 in int64 / 128 bits), gamma = atan2 (BAM, the table
//   atan within 5 BAM, root of sin^2 to ~31 bits), I from
//   LidIntensityQ16; E = I_q16 * g * mantissa * 2^(exponent - 26), formed in
//   128 bits (< 2^125) and rounded once, saturating to int64.
int64_t DirectIlluminanceQ20(const int16_t direction_q14[3], uint32_t geometry,
                             QuantScale geometry_scale, const int32_t axis_q30[3],
                             const int64_t* lid_q16, int lid_m);

// E = I * g * mantissa * 2^(exponent - 26) in Q43.20 lux: the common tail
// of both direct terms (128-bit product < 2^125, rounded once, saturated).
int64_t IlluminanceQ20(int64_t intensity_q16, uint32_t geometry, QuantScale geometry_scale);

// The same for a LID given as a (C, gamma) table (a luminaire that is not
// axisymmetric): the direction into the fixture frame (Q1.14 x Q1.30 = Q2.44
// dot products with c0, c90 and the axis), gamma = atan2(|(x, y)|, z),
// C = atan2(y, x) (binary angles), I from LidTableIntensityQ16.
int64_t DirectIlluminanceTableQ20(const int16_t direction_q14[3], uint32_t geometry,
                                  QuantScale geometry_scale, const FixtureFrameQ30& frame,
                                  const LidTableView& table);

enum class DirectStore { kWrite, kAdd };

// The direct light of one luminaire on a receiver set, LightQ12, 3 per
// receiver. With reflectance_over_pi_q32 (vertices): luminance
// L_c = E rho_c / pi in cd/m^2; without (grids): E in lux on all three
// channels. kAdd adds to `out` (saturating) instead of overwriting it.
// Rounded to nearest, saturated to int32.
void DirectLightQ12(const DirectReceivers& receivers, const int32_t axis_q30[3],
                    const int64_t* lid_q16, int lid_m, const uint32_t* reflectance_over_pi_q32,
                    DirectStore store, int32_t* out);
// The same for a (C, gamma) table LID.
void DirectLightTableQ12(const DirectReceivers& receivers, const FixtureFrameQ30& frame,
                         const LidTableView& table, const uint32_t* reflectance_over_pi_q32,
                         DirectStore store, int32_t* out);

}  // namespace relight
