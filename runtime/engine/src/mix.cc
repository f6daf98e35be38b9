// Mixing cached luminaire results (see mix.h).
#include "mix.h"

#include <cstddef>

#include "mix_avx2.h"
#include "mix_avx512.h"
#include "recombine_dispatch.h"
#include "relight/base/fixed_ops.h"
#include "relight/base/status.h"

namespace relight {

Q1_30 GainQ30(Q1_15 dimmer, Q1_15 colour) {
  constexpr int64_t kFull = 32767;
  const int64_t d = dimmer.raw() < 0 ? 0 : dimmer.raw();
  const int64_t c = colour.raw() < 0 ? 0 : colour.raw();
  // d c / 32767^2 in Q2.30, rounded: at most 2^30 exactly.
  const int64_t den = kFull * kFull;
  return Q1_30::FromRaw(static_cast<int32_t>((d * c * kUnityGainQ30 + den / 2) / den));
}

void MixLuminairesQ12(const MixSource* sources, uint32_t source_count, uint32_t receiver_count,
                      int64_t* scratch, uint32_t scratch_len, int32_t* out) {
  RELIGHT_CHECK(scratch_len >= 3);
  const uint32_t block = scratch_len / 3;
  constexpr int64_t kHalf = int64_t{1} << 29;
  const SimdLevel level = ActiveSimdLevel();  // the same values on every path
  const bool avx512 = level == SimdLevel::kAvx512Vnni, avx2 = level >= SimdLevel::kAvx2;
  for (uint32_t r0 = 0; r0 < receiver_count; r0 += block) {
    const uint32_t n = receiver_count - r0 < block ? receiver_count - r0 : block;
    const size_t base = static_cast<size_t>(r0) * 3;
    for (uint32_t i = 0; i < 3 * n; ++i) scratch[i] = 0;
    for (uint32_t l = 0; l < source_count; ++l) {
      const MixSource& s = sources[l];
      const int64_t g[3] = {s.gain[0].raw(), s.gain[1].raw(), s.gain[2].raw()};
      if ((g[0] | g[1] | g[2]) == 0) continue;
      const int32_t* a = s.a + base;
      const int32_t* b = s.b != nullptr ? s.b + base : nullptr;
      if (avx2 && b == nullptr) {  // a + b may pass int32: only a alone in vectors
        if (avx512) {
          MixAddAvx512(a, g, 3 * n, scratch);
        } else {
          MixAddAvx2(a, g, 3 * n, scratch);
        }
        continue;
      }
      for (uint32_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
          const int64_t light = static_cast<int64_t>(a[3 * i + c]) + (b ? b[3 * i + c] : 0);
          scratch[3 * i + c] += (light * g[c] + kHalf) >> 30;
        }
      }
    }
    if (avx512) {
      SaturateAvx512(scratch, 3 * n, out + base);
    } else if (avx2) {
      SaturateAvx2(scratch, 3 * n, out + base);
    } else {
      for (uint32_t i = 0; i < 3 * n; ++i) out[base + i] = SaturateI32(scratch[i]);
    }
  }
}

}  // namespace relight
