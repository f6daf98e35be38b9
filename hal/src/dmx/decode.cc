// DMX frame -> DmxFixtureValues for one fixture. Pure integer code, no heap.
//
// Scaling and overflow: 8-bit levels widen to 16 bits (v * 257) and then to
// Q1.15 as round(v16 * 32767 / 65535) in 32-bit arithmetic (max product
// 65535 * 32767 < 2^31). Additive W adds to each primary, saturating at
// 32767. Wheel filters multiply in 32 bits (32767 * 255 < 2^23). The beam
// interpolation multiplies a Q16.16 span (< 3600 * 2^16) by v <= 255 in 64
// bits.
#include "relight/hal/dmx/personality.h"

namespace relight::hal {
namespace {

int32_t Level16ToQ15(uint32_t v16) { return static_cast<int32_t>((v16 * 32767u + 32767u) / 65535u); }
int32_t Level8ToQ15(uint8_t v) { return Level16ToQ15(uint32_t{v} * 257u); }

class Frame {
 public:
  Frame(const DmxPersonality& p, int start_address, const uint8_t* slots, size_t count)
      : p_(p), base_(start_address - 1), slots_(slots), count_(count) {}

  // The byte for a function, if the mode has it and the frame reaches it.
  bool Get(DmxFunction f, uint8_t* v) const {
    const int off = p_.Offset(f);
    if (off < 0) return false;
    const size_t at = static_cast<size_t>(base_ + off);
    if (at >= count_) return false;
    *v = slots_[at];
    return true;
  }
  bool Has(DmxFunction f) const { return p_.Offset(f) >= 0; }

  // A 16-bit value: coarse << 8 | fine when both arrived, coarse * scale8
  // without a fine channel; false (keep the previous) otherwise.
  bool Get16(DmxFunction coarse, DmxFunction fine, uint32_t scale8, uint32_t* v16) const {
    uint8_t c = 0, f = 0;
    if (!Get(coarse, &c)) return false;
    if (!Has(fine)) {
      *v16 = scale8 == 257 ? uint32_t{c} * 257u : uint32_t{c} << 8;
      return true;
    }
    if (!Get(fine, &f)) return false;
    *v16 = (uint32_t{c} << 8) | f;
    return true;
  }

 private:
  const DmxPersonality& p_;
  int base_;
  const uint8_t* slots_;
  size_t count_;
};

int16_t Sat15(int32_t v) { return static_cast<int16_t>(v > 32767 ? 32767 : (v < 0 ? 0 : v)); }

}  // namespace

bool DecodeDmxFrame(const DmxPersonality& p, int start_address, uint8_t start_code, const uint8_t* slots,
                    size_t count, DmxFixtureValues* values) {
  if (start_code != kDmxNullStartCode) return false;
  if (start_address < 1 || start_address > kDmxSlots) return false;
  if (count > static_cast<size_t>(kDmxSlots)) count = kDmxSlots;
  if (count < static_cast<size_t>(start_address)) return false;
  const Frame f(p, start_address, slots, count);
  DmxFixtureValues& out = *values;

  uint32_t v16 = 0;
  if (!f.Has(DmxFunction::kDimmer)) {
    out.dimmer = Q1_15::FromRaw(32767);
  } else if (f.Get16(DmxFunction::kDimmer, DmxFunction::kDimmerFine, 257, &v16)) {
    out.dimmer = Q1_15::FromRaw(static_cast<int16_t>(Level16ToQ15(v16)));
  }
  if (f.Get16(DmxFunction::kPan, DmxFunction::kPanFine, 256, &v16)) out.pan16 = static_cast<uint16_t>(v16);
  if (f.Get16(DmxFunction::kTilt, DmxFunction::kTiltFine, 256, &v16)) out.tilt16 = static_cast<uint16_t>(v16);

  // Colour: start from the mixing system's result (or the previous one if
  // this frame does not reach every byte of it), then the wheel filter.
  const bool additive = f.Has(DmxFunction::kRed) || f.Has(DmxFunction::kGreen) || f.Has(DmxFunction::kBlue);
  const bool subtractive = f.Has(DmxFunction::kCyan) || f.Has(DmxFunction::kMagenta) || f.Has(DmxFunction::kYellow);
  int32_t rgb[3] = {32767, 32767, 32767};
  bool colour_complete = true;
  if (additive) {
    static constexpr DmxFunction kPrimaries[3] = {DmxFunction::kRed, DmxFunction::kGreen, DmxFunction::kBlue};
    int32_t white = 0;
    uint8_t w = 0;
    if (f.Has(DmxFunction::kWhite)) {
      if (f.Get(DmxFunction::kWhite, &w)) white = Level8ToQ15(w);
      else colour_complete = false;
    }
    for (int i = 0; i < 3; ++i) {
      uint8_t v = 0;
      if (!f.Has(kPrimaries[i])) {
        rgb[i] = white;
      } else if (f.Get(kPrimaries[i], &v)) {
        rgb[i] = Sat15(Level8ToQ15(v) + white);
      } else {
        colour_complete = false;
      }
    }
  } else if (subtractive) {
    static constexpr DmxFunction kFilters[3] = {DmxFunction::kCyan, DmxFunction::kMagenta, DmxFunction::kYellow};
    for (int i = 0; i < 3; ++i) {
      uint8_t v = 0;
      if (!f.Has(kFilters[i])) continue;  // no such flag: that primary passes
      if (f.Get(kFilters[i], &v)) rgb[i] = 32767 - Level8ToQ15(v);
      else colour_complete = false;
    }
  } else if (f.Has(DmxFunction::kWhite)) {
    uint8_t w = 0;
    if (f.Get(DmxFunction::kWhite, &w)) rgb[0] = rgb[1] = rgb[2] = Level8ToQ15(w);
    else colour_complete = false;
  }
  if (p.has_wheel) {
    uint8_t v = 0;
    if (f.Get(DmxFunction::kColorWheel, &v)) {
      const auto& filter = p.wheel[v];
      for (int i = 0; i < 3; ++i) rgb[i] = (rgb[i] * filter[static_cast<size_t>(i)] + 127) / 255;
    } else {
      colour_complete = false;
    }
  }
  if (colour_complete) {
    out.r = Q1_15::FromRaw(Sat15(rgb[0]));
    out.g = Q1_15::FromRaw(Sat15(rgb[1]));
    out.b = Q1_15::FromRaw(Sat15(rgb[2]));
  }

  uint8_t v = 0;
  if (f.Get(DmxFunction::kZoom, &v) && p.beam_max_q16 > 0) {
    const int64_t span = int64_t{p.beam_max_q16} - p.beam_min_q16;
    const int64_t t = p.zoom_big_to_small ? 255 - v : v;
    out.beam_angle = Q16_16::FromRaw(static_cast<int32_t>(p.beam_min_q16 + (span * t + 127) / 255));
  }
  if (f.Get(DmxFunction::kShutter, &v)) out.shutter_open = !p.has_shutter_ranges || p.shutter_open[v] != 0;
  if (f.Get(DmxFunction::kX, &v)) out.x = Q1_15::FromRaw(static_cast<int16_t>(Level8ToQ15(v)));
  if (f.Get(DmxFunction::kY, &v)) out.y = Q1_15::FromRaw(static_cast<int16_t>(Level8ToQ15(v)));
  if (f.Get(DmxFunction::kSize, &v)) out.size = Q1_15::FromRaw(static_cast<int16_t>(Level8ToQ15(v)));
  ++out.frames;
  return true;
}

}  // namespace relight::hal
