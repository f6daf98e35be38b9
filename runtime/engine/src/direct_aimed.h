// The exact direct term of an axisymmetric LID, cheap per aim change.
// Receivers and luminaires do not move when a head pans, so Engine::Open
// keeps per luminaire and receiver what no aim changes: the direction from
// the luminaire as a Q1.30 unit vector (normalised once, so cos gamma is a
// plain dot product) and the geometric factor with the set's scale folded in
// (one 64 x 32-bit product per receiver gives lux). A pan, tilt, roll or zoom
// then costs per receiver: one dot product with the beam axis, gamma from
// the acos table (gamma_table.h), the LID's linear interpolation
// (lid_lookup.h, same result), and three 64-bit products for RGB.
// Integer-only, allocation-free after PrepareDirectPoints, thread-safe.
//
// Within ~1 LSB of the full path (direct.h DirectLightQ12) that computes
// gamma with a root and atan2 per receiver; direct_test.cc measures both
// against each other and against float64.
#pragma once

#include <cstdint>
#include <vector>

#include "direct.h"
#include "direct_cull.h"
#include "gamma_table.h"
#include "relight/bake/bake.h"

namespace relight {

// One receiver as the aimed kernel reads it (16 bytes, one load stream).
struct DirectPoint {
  int32_t direction_q30[3];  // unit vector luminaire -> receiver, Q1.30 (0 if none)
  uint32_t geometry;         // visibility cos / d^2 x 2^shift, in Q.12 lux per Q.16 cd
};

// A luminaire's receivers on one set, prepared at Open. Blocks of
// receivers no luminaire light reaches (kNoPoints: all geometry 0, e.g. the
// far side of the set) keep no points: 14 % of the stage's blocks.
struct DirectPoints {
  uint32_t count = 0;               // receivers
  std::vector<DirectPoint> points;  // the blocks' that have any, block after block
  std::vector<uint32_t> block_points;  // per block: its first point in `points` (none if kNoPoints)
  int shift = 0;  // E_q12 = I_q16 x geometry >> shift
  std::vector<DirectBlock> blocks;  // cones of kDirectBlockPoints receivers (direct_cull.h)
};

// Sizes and fills `out` from the bake's receivers (Open time: allocates).
// geometry = round(g x mantissa x 2^(exponent - 34 + shift)), shift the
// largest (<= 90) that keeps every receiver's value below 2^32 (>= 0: a
// factor past that saturates, i.e. > 2^20 lux from a 1/65536 cd source).
void PrepareDirectPoints(const DirectReceivers& receivers, DirectPoints* out);

// I(gamma) in Q48.16 cd, the same value as LidIntensityQ16 (lid_lookup.h)
// for gamma in [0, 2^31]: the LID samples are at most kMaxCandelaRaw
// (2^47), so (b - a) x fraction (< 2^63) needs no 128 bits.
int64_t LidIntensityFastQ16(const int64_t* candela_q16, int M, Bam gamma);

// As DirectLightQ12 (direct.h), from prepared points, skipping receivers
// past the LID's cut-off (direct_cull.h: the same values, cheaper): LightQ12 luminance
// (with reflectance_over_pi_q32) or lux (without), 3 per receiver.
// Scaling and overflow:
//   cos gamma   Q1.30 x Q1.30 dot product, Q2.60 in int64 (|.| < 2^62)
//   I           Q48.16 (<= 2^47), rounded to the LID's own 31 bits (shifted
//               by bit length of its largest sample - 31, if > 0)
//   E           I (< 2^31) x geometry (< 2^32) < 2^63 in uint64, shifted with
//               rounding to Q.12 lux, saturated to 2^33 - 1 (2 Mlux)
//   luminance   E (< 2^33) x rho/pi (Q0.32, < 2^31) < 2^64 in uint64, rounded
//               to Q12; saturated to int32 (and after kAdd's sum).
// Returns how many receivers the vector bodies did (direct_aimed_simd.h: the
// same values; 0 without AVX2), for tests.
uint32_t DirectLightAimedQ12(const DirectPoints& points, const GammaTable& gamma_table,
                             const int32_t axis_q30[3], const int64_t* lid_q16, int lid_m,
                             const uint32_t* reflectance_over_pi_q32, DirectStore store, int32_t* out);

}  // namespace relight
