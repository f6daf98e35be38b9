#include "relight/base/console_value.h"

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

}  // namespace relight
