#include "console_aim.h"

namespace relight {

Q16_16 ConsoleToDegrees(uint16_t value, int32_t range_deg_q16) {
  // |value - 32768| <= 2^15 and range < 2^26: the product fits int64 easily.
  const int64_t p = (static_cast<int64_t>(value) - 32768) * range_deg_q16;
  const int64_t rounded = p >= 0 ? (p + 32768) >> 16 : -((-p + 32768) >> 16);
  return Q16_16::FromRaw(static_cast<int32_t>(rounded));
}

uint16_t DegreesToConsole(Q16_16 degrees, int32_t range_deg_q16) {
  if (range_deg_q16 <= 0) return 32768;
  const int64_t num = static_cast<int64_t>(degrees.raw()) * 65536;
  const int64_t half = range_deg_q16 / 2;
  const int64_t q = (num >= 0 ? num + half : num - half) / range_deg_q16;
  int64_t v = q + 32768;
  if (v < 0) v = 0;
  if (v > 65535) v = 65535;
  return static_cast<uint16_t>(v);
}

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
