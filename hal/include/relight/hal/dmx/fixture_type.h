// A DMX fixture type: maker, model, its modes (each an ordered channel list)
// and, per channel, the function relight renders from it. Read from QLC+'s
// fixture library (.qxf, XML) or from a small TOML form for a type the
// library lacks (docs/dmx.md). Channels relight does not render (gobos,
// prisms, speeds, macros...) are kept with function kIgnored so a mode's
// footprint and offsets stay right.
//
// Loading allocates and may throw nothing: errors are Status values whose
// message starts "file:line: ". Not used after start-up; not thread-safe
// beyond being const once loaded.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/status.h"

namespace relight::hal {

enum class DmxFunction : uint8_t {
  kIgnored = 0,
  kDimmer, kDimmerFine,
  kPan, kPanFine, kTilt, kTiltFine,
  kRed, kGreen, kBlue, kWhite,        // additive mixing
  kCyan, kMagenta, kYellow,           // subtractive mixing: R = 1 - C ...
  kColorWheel,                        // slots: DMX range -> filter colour
  kZoom,                              // beam angle between the lens limits
  kShutter,                           // ranges that close it; otherwise open
  kX, kY, kSize,                      // a run-time emitter's position and size: 0..255 = 0..1 of its ranges
  kCount
};

const char* DmxFunctionName(DmxFunction f);

struct Rgb8 {
  uint8_t r = 255, g = 255, b = 255;
};

// A DMX value range [min, max] of one channel.
struct DmxRange {
  uint8_t min = 0, max = 255;
};

struct WheelSlot {
  DmxRange range;
  Rgb8 color;  // what the slot lets through (white = open)
};

struct DmxChannel {
  std::string name;
  DmxFunction function = DmxFunction::kIgnored;
  std::string ignored_why;             // kIgnored: the QLC+ preset or group seen
  std::vector<WheelSlot> slots;        // kColorWheel
  std::vector<DmxRange> closed;        // kShutter: values that close it (others: open, strobe = open)
  bool zoom_big_to_small = false;      // kZoom: 0 = widest beam (BeamZoomBigSmall)
  int line = 0;                        // where it was defined
};

struct DmxMode {
  std::string name;
  std::vector<int> channels;           // indices into FixtureType::channels, DMX slot order
  // The mode's own <Physical> overrides the type's (0 = not given).
  int pan_range_deg = 0, tilt_range_deg = 0;
  int32_t beam_min_q16 = 0, beam_max_q16 = 0;  // degrees, Q16.16
  int line = 0;
};

struct FixtureType {
  std::string manufacturer;
  std::string model;
  std::string type;                    // QLC+ <Type>: "Moving Head", "Color Changer", ...
  std::vector<DmxChannel> channels;
  std::vector<DmxMode> modes;
  int pan_range_deg = 0;               // <Focus PanMax>; 0: not given
  int tilt_range_deg = 0;              // <Focus TiltMax>
  int32_t beam_min_q16 = 0;            // <Lens DegreesMin/DegreesMax>, degrees Q16.16; 0/0: not given
  int32_t beam_max_q16 = 0;
  std::string where;                   // the file

  // nullptr if there is no such mode.
  const DmxMode* FindMode(const std::string& name) const;
};

// QLC+ 4 fixture definitions (.qxf). Handles channel presets
// (<Channel Preset="PositionPan">) and the older groups
// (<Group Byte="1">Pan</Group>, <Colour>Red</Colour>).
// kNotFound / kIoError when unreadable; kInvalidArgument "file:line: what"
// for malformed XML or a definition that contradicts itself (a mode naming
// an unknown channel, a capability with Min > Max, no mode at all).
Status LoadQxf(const std::string& path, FixtureType* out);
Status ParseQxf(const std::string& text, const std::string& where, FixtureType* out);

// The TOML form (docs/dmx.md, fixtures/dmx/*.toml). Same errors.
Status LoadFixtureTypeToml(const std::string& path, FixtureType* out);
Status ParseFixtureTypeToml(const std::string& text, const std::string& where, FixtureType* out);

// The TOML form of a type, which ParseFixtureTypeToml reads back to a type
// FixtureTypeDifference() calls equal (a .qxf converted to be edited, docs/dmx.md).
// Not carried: `line`, `where`, and `ignored_why` (written as a comment).
// A string that is not UTF-8 cannot round-trip: its bytes are escaped as
// Latin-1 code points and read back different (FixtureTypeDifference shows
// it; relight-fixture-type refuses such a type).
std::string FixtureTypeToToml(const FixtureType& type);

// The first difference between two types in what they mean (everything but
// line, where and ignored_why), e.g. "channel 3 'Zoom': big_to_small true vs
// false"; empty if there is none.
std::string FixtureTypeDifference(const FixtureType& a, const FixtureType& b);

// By extension: .qxf -> LoadQxf, .toml -> LoadFixtureTypeToml.
Status LoadFixtureType(const std::string& path, FixtureType* out);

// Where Debian's qlcplus-data puts the library.
inline constexpr const char* kQlcFixtureDir = "/usr/share/qlcplus/fixtures";

}  // namespace relight::hal
