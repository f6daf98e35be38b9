// Console 16-bit angle values (coarse << 8 | fine, as lighting consoles send
// pan and tilt) <-> degrees: the value spreads over a range centred on 0, so
// 32768 is home. The engine's SetPanTilt16 and the hal's register decoding
// both go through these. Integer-only, allocation-free, thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/fixed.h"

namespace relight {

// (value - 32768) / 65536 x range, Q16.16 degrees, rounded to nearest.
Q16_16 ConsoleToDegrees(uint16_t value, int32_t range_deg_q16);
// The inverse, rounded and clamped to 0..65535.
uint16_t DegreesToConsole(Q16_16 degrees, int32_t range_deg_q16);

}  // namespace relight
