// Aiming as lighting consoles do it (PITFALLS.md "Conventions consoles use"):
// 16-bit pan and tilt (coarse << 8 | fine) spread over the fixture's ranges
// with home at 32768, and, to aim at a point, the choice among the pan/tilt
// pairs that reach it of one the fixture can do (inside its ranges) that is
// nearest where it points now. Integer-only, allocation-free, thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/console_value.h"
#include "relight/base/fixed.h"

namespace relight {

// Among (pan + 360 k, tilt) and (pan + 180 + 360 k, -tilt), the pair with
// |pan| <= pan_range / 2 and |tilt| <= tilt_range / 2 nearest (|d pan| +
// |d tilt|) to the current aim. Returns false when none is inside the ranges.
bool ChooseAimInRange(Q16_16 pan, Q16_16 tilt, int32_t pan_range_q16, int32_t tilt_range_q16,
                      Q16_16 current_pan, Q16_16 current_tilt, Q16_16* out_pan, Q16_16* out_tilt);

}  // namespace relight
