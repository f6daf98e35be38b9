#include "console_aim.h"

namespace relight {

bool ChooseAimInRange(Q16_16 pan, Q16_16 tilt, int32_t pan_range_q16, int32_t tilt_range_q16,
                      Q16_16 current_pan, Q16_16 current_tilt, Q16_16* out_pan, Q16_16* out_tilt) {
  constexpr int64_t kTurn = int64_t{360} << 16, kHalf = int64_t{180} << 16;
  const int64_t pan_limit = pan_range_q16 / 2, tilt_limit = tilt_range_q16 / 2;
  bool found = false;
  int64_t best = 0;
  for (int flip = 0; flip < 2; ++flip) {
    const int64_t t = flip ? -static_cast<int64_t>(tilt.raw()) : tilt.raw();
    if (t > tilt_limit || t < -tilt_limit) continue;
    for (int k = -2; k <= 2; ++k) {
      const int64_t p = pan.raw() + (flip ? kHalf : 0) + k * kTurn;
      if (p > pan_limit || p < -pan_limit) continue;
      const int64_t dp = p - current_pan.raw(), dt = t - current_tilt.raw();
      const int64_t cost = (dp < 0 ? -dp : dp) + (dt < 0 ? -dt : dt);
      if (!found || cost < best) {
        found = true;
        best = cost;
        *out_pan = Q16_16::FromRaw(static_cast<int32_t>(p));
        *out_tilt = Q16_16::FromRaw(static_cast<int32_t>(t));
      }
    }
  }
  return found;
}

}  // namespace relight
