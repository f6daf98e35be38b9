// RGBA rows -> RGB rows: OSMesa hands back RGBA, every sink takes RGB.
#pragma once

#include <cstddef>
#include <cstdint>

namespace relight::render {

// Copies `pixels` RGBA pixels from `src` to `pixels` RGB pixels at `dst`,
// dropping alpha. Buffers must not overlap. Uses the widest byte shuffle the
// CPU has (SSSE3 on x86-64, NEON on aarch64); every path writes the same bytes.
void RgbaRowToRgb(const uint8_t* src, size_t pixels, uint8_t* dst);

// The portable byte loop alone (the reference the shuffles are tested against).
void RgbaRowToRgbScalar(const uint8_t* src, size_t pixels, uint8_t* dst);

}  // namespace relight::render
