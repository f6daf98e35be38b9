// A DMX personality: a fixture type's mode compiled into slot offsets and
// 256-entry lookup tables, and the decoder that turns a DMX frame into the
// values relight renders. Building a personality allocates nothing either
// (fixed arrays) but runs at start-up; decoding is pure, integer-only and
// heap-free, so it may run on a receive thread at frame rate.
//
// Scaling:
//   dimmer   Q1.15: v16 = coarse << 8 | fine (coarse * 257 without a fine
//            channel, so 255 = full); Q1.15 = round(v16 * 32767 / 65535).
//            No dimmer channel: full (an RGB par's level is its colour).
//   pan/tilt 16-bit console values, coarse << 8 | fine (coarse << 8 without
//            a fine channel, so 128 = 32768 = home).
//   rgb      Q1.15 each: additive R,G,B (+W added to each, saturating at
//            1.0); subtractive R = 1 - C, G = 1 - M, B = 1 - Y; a colour
//            wheel slot's colour multiplies (filters in series). Nothing:
//            white.
//   beam     degrees Q16.16: min + (max - min) * v / 255 for a small->big
//            zoom (reversed for big->small), 64-bit product; 0 when the
//            type gives no lens range.
//   shutter  open unless the value lies in a range the type marks closed.
//   x, y, size  an emitter's levels, Q1.15 = round(v * 32767 / 255).
// A 16-bit value (dimmer, pan, tilt) changes only when both of its bytes are
// in the frame: a frame that stops between coarse and fine keeps the
// previous value. 8-bit values absent from a short frame keep theirs too.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "relight/base/fixed.h"
#include "relight/base/status.h"
#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {

inline constexpr int kDmxSlots = 512;
inline constexpr uint8_t kDmxNullStartCode = 0x00;  // dimmer levels; 0xCC RDM, 0x17 text, ... are not

struct DmxFixtureValues {
  Q1_15 dimmer = Q1_15::FromRaw(0);
  uint16_t pan16 = 32768;
  uint16_t tilt16 = 32768;
  Q1_15 r = Q1_15::FromRaw(32767), g = Q1_15::FromRaw(32767), b = Q1_15::FromRaw(32767);
  Q16_16 beam_angle = Q16_16::FromRaw(0);  // degrees; 0: the bake's own
  bool shutter_open = true;
  Q1_15 x = Q1_15::FromRaw(0), y = Q1_15::FromRaw(0), size = Q1_15::FromRaw(0);  // an emitter's levels
  uint32_t frames = 0;                     // frames decoded into these values
};

struct DmxPersonality {
  uint16_t footprint = 0;                  // slots the mode occupies
  // Offset from the start address of the first channel with each function;
  // -1: the mode has none.
  std::array<int16_t, static_cast<size_t>(DmxFunction::kCount)> offset{};
  bool has_wheel = false;
  std::array<std::array<uint8_t, 3>, 256> wheel{};  // per DMX value: filter RGB, 8 bit
  bool has_shutter_ranges = false;
  std::array<uint8_t, 256> shutter_open{};          // per DMX value: 1 = open
  bool zoom_big_to_small = false;
  int32_t beam_min_q16 = 0, beam_max_q16 = 0;       // degrees
  int pan_range_deg = 0, tilt_range_deg = 0;        // 0: the type gives none

  int Offset(DmxFunction f) const { return offset[static_cast<size_t>(f)]; }
};

// kNotFound if the type has no such mode. Later channels with a function
// already taken (the second cell of a multi-cell bar) are not rendered.
Status BuildPersonality(const FixtureType& type, const std::string& mode, DmxPersonality* out);

// Decodes one frame for the fixture whose first slot is `start_address`
// (1..512) into *values, which holds the previous values on entry.
// `slots` are the frame's data slots (slot 1 first), `count` of them
// (0..512). Returns false, changing nothing, if start_code is not 0x00 or
// the frame ends before the fixture's first slot.
bool DecodeDmxFrame(const DmxPersonality& p, int start_address, uint8_t start_code, const uint8_t* slots,
                    size_t count, DmxFixtureValues* values);

}  // namespace relight::hal
