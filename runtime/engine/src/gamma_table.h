// The angle from the beam axis without a square root or atan2 per receiver:
// gamma = acos(cos gamma) from a table, for the aimed direct term
// (direct_aimed.h). Built once per process (Engine::Open); integer-only,
// allocation-free, thread-safe after it is built.
#pragma once

#include <cstdint>

#include "relight/base/fixed_math.h"

namespace relight {

// u = 1 - cos gamma in Q.60, u in [0, 1]: acos(1 - u) ~ sqrt(2u) near the
// axis, so the table is piecewise linear over octaves of u (64 segments an
// octave; within an octave acos(1 - u) is sqrt-like and a segment is 1/128 of
// its start: relative error < 2e-6, at most ~1e3 BAM (1e-4 degrees) at
// gamma = 90, below the ~2e4 BAM a Q1.14 bake direction is good to). Below
// 2^-37 (gamma < 8e-6 rad) the first entry is scaled linearly.
inline constexpr int kGammaSegmentBits = 7;
inline constexpr int kGammaMinOctave = 16 + kGammaSegmentBits;  // u >= 2^23 (Q.60): the table
inline constexpr int kGammaMaxOctave = 60;  // u = 2^60 (cos 0) is the top
inline constexpr int kGammaEntries =
    ((kGammaMaxOctave - kGammaMinOctave + 1) << kGammaSegmentBits) + 1;

struct GammaTable {
  Bam bam[kGammaEntries];  // gamma at u = 2^e (1 + m / 128), 20 kB
};

// The process's table (a function-local static: built by the first caller,
// Engine::Open, with CORDIC atan2 and a 128-bit root per entry).
const GammaTable& SharedGammaTable();

// acos(1 - u) in BAM for u in [0, 2^60] (Q.60), 0 .. 2^30 (90 degrees).
// Scaling: the fraction within a segment is Q.16; (b - a) < 2^31 times it
// stays below 2^47 in uint64.
inline Bam GammaFromUQ60(const GammaTable& t, uint64_t u_q60) {
  constexpr uint64_t kTableStart = uint64_t{1} << kGammaMinOctave;
  if (u_q60 < kTableStart) {
    return static_cast<Bam>((static_cast<uint64_t>(t.bam[0]) * u_q60) >> kGammaMinOctave);
  }
  const int e = 63 - __builtin_clzll(u_q60);
  const uint32_t m = static_cast<uint32_t>(u_q60 >> (e - kGammaSegmentBits)) & ((1u << kGammaSegmentBits) - 1);
  const uint64_t frac = (u_q60 >> (e - kGammaSegmentBits - 16)) & 0xffff;
  const uint32_t i = (static_cast<uint32_t>(e - kGammaMinOctave) << kGammaSegmentBits) + m;
  const uint64_t a = t.bam[i], b = t.bam[i + 1];
  return static_cast<Bam>(a + (((b - a) * frac + 0x8000) >> 16));
}

// gamma in [0, 2^31] (0 .. 180 degrees) from cos gamma in Q2.60 (clamped to
// [-2^60, 2^60]): the table on 1 - |cos|, mirrored for a backward direction
// (so the square-root end of acos at 180 degrees is as fine as at 0).
inline Bam GammaFromCosQ60(const GammaTable& t, int64_t cos_q60) {
  constexpr int64_t kOne = int64_t{1} << 60;
  const int64_t sign = cos_q60 >> 63;                // 0 or -1
  const int64_t magnitude = (cos_q60 ^ sign) - sign;  // |cos|: cos_q60 > -2^63
  const int64_t u = kOne - magnitude;
  const Bam g = GammaFromUQ60(t, static_cast<uint64_t>(u < 0 ? 0 : u));
  return sign != 0 ? (Bam{1} << 31) - g : g;
}

}  // namespace relight
