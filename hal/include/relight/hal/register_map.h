// The Modbus register map (docs/modbus.md), shared by the TCP and RTU
// servers, the client poller and the mock. Addresses are PDU addresses,
// 0-based, everywhere in code.
//
// Holding registers: a block per fixture from its modbus_base, laid out as
// its RegisterLayout says (register_layout.h). The standard 8 (kReg*):
//   +0 dimmer   0..65535 = 0..1 (before the dimmer curve)
//   +1 pan      0..65535 over the fixture's pan range, 32768 = 0 degrees
//   +2 tilt     0..65535 over the tilt range, 32768 = 0 degrees
//   +3 red      0..255      +4 green 0..255      +5 blue 0..255
//   +6 profile  beam/profile index: 0 (bakes carry one profile per luminaire)
//   +7 flags    bit 0: on (0 = off, dimmer output 0); other bits must be 0
// A layout may add roll (0..65535 over the roll range, 32768 = 0 degrees) and
// zoom (the beam angle in 0.01 degrees, 0..18000), an emitter x, y and size
// (0..65535 = 0..1 of its declared ranges) and split pan, tilt or roll
// into coarse and fine bytes.
// Input registers (status), see kStatus*.
//
// Thread safety: a RegisterMap is immutable after Build(); share it freely.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "relight/base/fixture_state.h"
#include "relight/base/param.h"
#include "relight/hal/patch.h"
#include "relight/base/status.h"

namespace relight::hal {

// The standard layout: its size and offsets.
inline constexpr int kRegistersPerFixture = 8;
enum RegisterOffset : int {
  kRegDimmer = 0, kRegPan = 1, kRegTilt = 2, kRegRed = 3, kRegGreen = 4, kRegBlue = 5,
  kRegProfile = 6, kRegFlags = 7,
};
inline constexpr uint16_t kFlagOn = 1;

// Input registers (function 0x04): status, updated by the daemon each frame.
enum StatusRegister : int {
  kStatusFrameHigh = 0,      // frames written, 32-bit, high word first
  kStatusFrameLow = 1,
  kStatusLatencyHigh = 2,    // arrival of the newest write shown -> that frame out, microseconds, 32-bit
  kStatusLatencyLow = 3,
  kStatusIllegalAddress = 4, // exceptions 0x02 sent (counters are mod 65536)
  kStatusIllegalValue = 5,   // exceptions 0x03 sent
  kStatusBadFrames = 6,      // malformed frames, CRC errors, partial requests dropped
  kStatusRefused = 7,        // connections refused (allow-list, too many clients)
  kStatusClients = 8,        // clients connected now
  kStatusFixtures = 9,       // fixtures in the map
  kStatusRegisterCount = 16, // input registers served
};

// Modbus exception codes we send.
inline constexpr uint8_t kExceptionIllegalFunction = 0x01;
inline constexpr uint8_t kExceptionIllegalAddress = 0x02;
inline constexpr uint8_t kExceptionIllegalValue = 0x03;

// Register value <-> parameter, integer-only, round to nearest. Angles are
// relight/base/console_value.h's, the engine's own 16-bit conversion.
int32_t AngleQ16FromRegister(uint16_t reg, int32_t range_q16);  // Q16.16 degrees
uint16_t RegisterFromAngleQ16(int32_t deg_q16, int32_t range_q16);  // clamps to 0..65535
int32_t LevelQ15FromRegister16(uint16_t reg);  // 0..65535 -> 0..32767
uint16_t Register16FromLevelQ15(int32_t level_q15);
int32_t LevelQ15FromByte(uint16_t reg);  // 0..255 -> 0..32767
uint16_t ByteFromLevelQ15(int32_t level_q15);
inline constexpr uint16_t kZoomRegisterMax = 18000;  // 180 degrees in 0.01 degrees
int32_t ZoomQ16FromRegister(uint16_t reg);           // 0.01 degrees -> Q16.16 degrees
uint16_t RegisterFromZoomQ16(int32_t deg_q16);       // clamps to 0..kZoomRegisterMax
class RegisterMap {
 public:
  // From a resolved patch (every fixture has a modbus_base and its ranges).
  static Status Build(const std::vector<FixturePatch>& fixtures, RegisterMap* out);

  int holding_count() const { return static_cast<int>(owner_.size()); }  // one past the highest mapped address
  int fixture_count() const { return static_cast<int>(fixtures_.size()); }
  const FixturePatch& fixture(int index) const { return fixtures_[index]; }
  // Fixture index whose block holds `addr` (and the offset in it), or -1.
  int FixtureAt(int addr, int* offset) const;
  // 0 if `value` may be written at `addr`, else the exception code to send:
  // kExceptionIllegalAddress outside every block, kExceptionIllegalValue for a
  // value the register does not take (a byte above 255, profile not 0,
  // flags other than 0 or 1, a zoom above 18000).
  uint8_t CheckWrite(int addr, uint16_t value) const;
  // The fixture's registers (layout().size() of them) that show `state`
  // (flags = on, profile 0).
  void Encode(const FixtureState& state, int fixture, uint16_t* out) const;
  // Parameter changes between two register images of one fixture's block
  // (layout().size() registers each): only the parameters whose value
  // differs, in the order dimmer, pan, tilt, roll, r, g, b, zoom, x, y, size, each naming the
  // fixture by its index `fixture`. Returns how many (<= kParamCount).
  size_t DecodeChanges(int fixture, const uint16_t* before, const uint16_t* after, int64_t time_us,
                       ParamChange out[kParamCount]) const;

 private:
  std::vector<FixturePatch> fixtures_;
  std::vector<int16_t> owner_;  // per holding address: fixture index or -1
};

}  // namespace relight::hal
