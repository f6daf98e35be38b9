// Luminance (LightQ12 cd/m^2) to 8-bit sRGB through a table built once.
// The curve: exposure so that `white` maps to 1.0, a soft shoulder above it
// (x / (1 + x/4)-style compression of highlights), then the sRGB transfer.
// Integer-only; the table is caller-owned (kToneMapEntries entries).
#pragma once

#include <cstdint>

#include "relight/fixed.h"

namespace relight {

inline constexpr int kToneMapEntries = 4096;

struct ToneMap {
  uint8_t table[kToneMapEntries];
  int32_t white_q12 = 0;      // luminance shown as display white
  int shift = 0;              // index = min(luminance >> shift, entries - 1)
};

// white_q12 > 0. Values above about 4x white saturate to 255.
void BuildToneMap(int32_t white_q12, ToneMap* out);
// rgb_q12: 3 per vertex; out: 3 bytes per vertex.
void ToneMapRgb8(const ToneMap& map, const int32_t* rgb_q12, uint32_t count, uint8_t* out);

}  // namespace relight
