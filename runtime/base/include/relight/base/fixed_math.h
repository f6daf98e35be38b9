// Integer-only elementary functions for the runtime: square root, sine and
// cosine, atan2. Angles are binary angles (BAM): a uint32 where 2^32 is one
// full turn, so wrap-around is free. All functions are exact integer code
// (no float anywhere) and deterministic across platforms. Thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/fixed.h"

namespace relight {

using Bam = uint32_t;  // 2^32 = 360 degrees

// floor(sqrt(v)).
uint32_t ISqrt64(uint64_t v);
uint64_t ISqrt128(UInt128 v);

// Degrees (Q16.16) to a binary angle, rounded; any value wraps.
Bam DegreesToBam(Q16_16 degrees);
// A binary angle to degrees in (-180, 180], Q16.16.
Q16_16 BamToDegrees(Bam angle);

// sin and cos of a binary angle, max error 2 LSB of Q1.30.
void SinCosQ30(Bam angle, Q1_30* sin_out, Q1_30* cos_out);
// atan2(y, x) as a binary angle; y, x any scale (same for both), not both 0.
// CORDIC, within 1 BAM of the exact angle.
Bam Atan2Bam(int64_t y, int64_t x);
// The same from a 4096-segment table with linear interpolation and one
// 64-bit division: within kAtan2FastMaxErrorBam of the exact angle, about
// ten times cheaper. For per-vertex work, where inputs carry far less
// precision than that (a Q1.14 direction is good to ~2e4 BAM).
inline constexpr uint32_t kAtan2FastMaxErrorBam = 5;
Bam Atan2BamFast(int64_t y, int64_t x);

// Constants and the wide sine/cosine behind the functions above, for the
// kernels that need more than Q1.30 (SH evaluation, Legendre weights):
// pi at Q2.61 so that their public results round only once.
// round(pi * 2^61) = 7244019458077122842 (0x6487ED5110B4611A).
inline constexpr int64_t kPiQ61 = 7244019458077122842;
inline constexpr int64_t kOneQ61 = int64_t{1} << 61;
inline constexpr int64_t kOneQ60 = int64_t{1} << 60;
// sin and cos of the angle 2 pi num/den (num/den of a full turn), Q2.61.
// 1 <= den <= 2^32, any num. Error below 2^-58 (a few Q61 ulps).
void SinCosTurnQ61(uint64_t num, uint64_t den, int64_t* sin_q61, int64_t* cos_q61);

// Unit vector (Q1.30) of an integer vector of any scale, not all zero.
void NormaliseQ30(const int64_t v[3], int32_t out_q30[3]);

}  // namespace relight
