// Receivers a beam cannot reach, skipped cheaply by the aimed direct term
// (direct_aimed.h; issue 13). A zoom LID is cut to 0 past its field
// (docs/scene-format.md "beam"), so a head lights a cone, and most of the
// stage lies outside it. Two tests, both exact (the skipped receivers get
// the 0 the full computation would give, bit for bit):
//  - per LID: the angle g_zero from which the LID lookup (lid_lookup.h,
//    LidIntensityFastQ16) is 0 for every larger angle, and the cosine T at
//    and below which the acos table (gamma_table.h, monotonic) gives an
//    angle >= g_zero: a receiver with cos <= T costs a dot product;
//  - per block of consecutive receivers (the mesher's order is spatially
//    coherent): at Open the cone round them (a centre direction and a half
//    angle); per aim the block is skipped when the angle to its centre
//    exceeds g_zero + its half angle + a margin for the rounding of the Q1.30
//    vectors and the table (a receiver's angle is then >= g_zero, triangle
//    inequality on the sphere).
// Integer-only, allocation-free after PrepareDirectBlocks, thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "gamma_table.h"

namespace relight {

struct DirectPoint;

// Receivers per block.
inline constexpr uint32_t kDirectBlockPoints = 32;

// One block's cone (16 bytes).
struct DirectBlock {
  int32_t centre_q30[3];  // unit vector, Q1.30
  uint32_t half_angle;    // BAM; kNoPoints: no receiver in it has geometry
};
inline constexpr uint32_t kNoPoints = 0xffffffffu;

// Margin of the block test, BAM (2^21 = 0.18 degrees): the angles between
// Q1.30 vectors of norm 1 +- 2^-29 through the table are within ~6e4 BAM
// of the true ones (sqrt(2 x 3 x 2^-30) rad at worst, near 0), three of
// them in the inequality.
inline constexpr uint64_t kBlockMarginBam = uint64_t{1} << 21;

// Open time (allocates): the cones of points[0 .. count) in blocks of
// kDirectBlockPoints (the last one shorter).
void PrepareDirectBlocks(const DirectPoint* points, uint32_t count, const GammaTable& gt,
                         std::vector<DirectBlock>* blocks);

// The smallest angle g such that LidIntensityFastQ16(lid, M, gamma) is 0 for
// every gamma in [g, 2^31]: past the last non-zero sample. 2^32 if the last
// sample (180 degrees) is not 0, i.e. no angle.
uint64_t LidZeroFromBam(const int64_t* lid_q16, int M);

// The largest cos_q60 with GammaFromCosQ60(gt, cos_q60) >= g_zero (INT64_MIN
// if none): every cos <= it gives an angle >= g_zero. A binary search over
// the table's monotonic map, 64 lookups.
int64_t ZeroCosQ60(const GammaTable& gt, uint64_t g_zero);

// True when no receiver of `block` can be lit by a beam along axis_q30
// whose LID is 0 from g_zero on.
inline bool BlockOutsideBeam(const DirectBlock& block, const GammaTable& gt,
                             const int32_t axis_q30[3], uint64_t g_zero) {
  if (block.half_angle == kNoPoints) return true;
  const int64_t cos_q60 = int64_t{block.centre_q30[0]} * axis_q30[0] +
                          int64_t{block.centre_q30[1]} * axis_q30[1] +
                          int64_t{block.centre_q30[2]} * axis_q30[2];
  return GammaFromCosQ60(gt, cos_q60) >= g_zero + block.half_angle + kBlockMarginBam;
}

}  // namespace relight
