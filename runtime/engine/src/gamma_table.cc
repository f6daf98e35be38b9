// The acos table (see gamma_table.h).
#include "gamma_table.h"

namespace relight {
namespace {

// acos(1 - u) for u in Q.60 (0 .. 2^61): atan2(sqrt(u (2 - u)), 1 - u),
// the root of a Q.120 value in 128 bits (exact floor), CORDIC within 1 BAM.
Bam AcosOneMinusU(uint64_t u_q60) {
  constexpr uint64_t kOne = uint64_t{1} << 60;
  if (u_q60 >= 2 * kOne) return Bam{1} << 31;
  const UInt128 sin2 = static_cast<UInt128>(u_q60) * (2 * kOne - u_q60);
  const int64_t sin_q60 = static_cast<int64_t>(ISqrt128(sin2));
  const int64_t cos_q60 = static_cast<int64_t>(kOne) - static_cast<int64_t>(u_q60);
  return Atan2Bam(sin_q60, cos_q60);
}

struct Built {
  GammaTable table;
  Built() {
    for (int i = 0; i < kGammaEntries; ++i) {
      const int e = kGammaMinOctave + (i >> kGammaSegmentBits);
      const uint64_t m = static_cast<uint64_t>(i) & ((1u << kGammaSegmentBits) - 1);
      // u = 2^e (1 + m / 2^bits); the last entry is 2^61 (u = 2).
      const uint64_t u = ((uint64_t{1} << kGammaSegmentBits) + m) << (e - kGammaSegmentBits);
      table.bam[i] = AcosOneMinusU(u);
    }
  }
};

}  // namespace

const GammaTable& SharedGammaTable() {
  static const Built built;  // thread-safe initialisation, no heap
  return built.table;
}

}  // namespace relight
