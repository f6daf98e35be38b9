// Luminance (LightQ12 cd/m^2) to 8-bit sRGB through tables built once.
// The curve: exposure x = L / white, Reinhard's shoulder y = x (1 + x/16) / (1 + x),
// so `white` (a diffuse white) shows as sRGB 193 and highlights roll off up to
// 4x white (255); then the sRGB transfer. Two tables: a coarse one over
// [0, 4x white) and a fine one over its first 1/16, where sRGB is steepest,
// so dark areas do not band. Integer-only; the tables are caller-owned.
#pragma once

#include <cstdint>

#include "relight/base/light_view.h"

#include "relight/base/fixed.h"

namespace relight {

inline constexpr int kToneMapEntries = 4096;

struct ToneMap {
  uint8_t table[kToneMapEntries];  // coarse: index = min(L >> shift, entries - 1)
  uint8_t fine[kToneMapEntries];   // fine: index = L >> fine_shift, used while < entries
  int32_t white_q12 = 0;           // luminance shown as diffuse white (sRGB 193)
  int shift = 0;
  int fine_shift = 0;              // shift - 4 (or 0)
};

// white_q12 > 0. Values above about 4x white saturate to 255.
void BuildToneMap(int32_t white_q12, ToneMap* out);
// out: 3 bytes (sRGB r, g, b) per vertex of `luminance`.
void ToneMapRgb8(const ToneMap& map, LuminanceView luminance, uint8_t* out);

}  // namespace relight
