// The patch: which Modbus register or GPIO line drives which fixture
// parameter, with each fixture's ranges, dimmer curve and fade time, and
// which input backends relightd starts. A TOML file (docs/modbus.md shows a
// full example); every error names file:line and what was expected.
//
//   [[fixture]]
//   name = "ceiling_spot"
//   modbus_base = 0        # first holding register, PDU (0-based) address
//   registers = ["dimmer", "pan", "pan_fine", "tilt", "tilt_fine", "roll"]  # default: the standard 8
//   pan_range_deg = 540    # 16-bit pan spans this, 32768 = 0 degrees (default: the bake's)
//   tilt_range_deg = 270   # (default: the bake's)
//   roll_range_deg = 360   # (default 360)
//   dimmer_curve = "square"
//   fade_ms = 200
//
//   [[emitter]]            # a run-time light source on a surface (docs/modbus.md "Emitters")
//   name = "panel"
//   surface = "room/+z"
//   centre = [3.0, 2.0, 2.7]   # a rectangle: centre (metres, on the surface), width along
//   width = 1.0                # the surface's u axis, height along v; or polygon = [[x,y,z], ...]
//   height = 0.6
//   luminance = 3000       # cd/m^2 at dimmer 1, or [R, G, B]
//   x_range_m = [-1, 1]    # parameter x 0..1 moves it this far along u (y_range_m: along v)
//   size_range = [0.5, 1]  # parameter size 0..1 scales it so
//
//   [modbus_tcp]
//   port = 1502            # listens on 127.0.0.1 unless `listen` says otherwise
//
// A section ([modbus_tcp], [modbus_rtu], [modbus_poller], [[gpio_button]],
// [[gpio_encoder]], [replay]) present = that backend is started.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/param.h"
#include "relight/hal/param_text.h"
#include "relight/hal/register_layout.h"
#include "relight/base/status.h"

namespace relight::hal {

enum class DimmerCurve : uint8_t { kLinear, kSquare };

struct FixturePatch {
  std::string name;
  int modbus_base = -1;                // first of its holding registers (PDU address); -1: next free block
  RegisterLayout layout;               // what each register from modbus_base means (default: the standard 8)
  // Degrees (Q16.16) spanned by the 16-bit pan, tilt and roll values, 32768 = 0.
  // Pan and tilt 0: the luminaire's own console ranges (bake.h), which
  // ResolvePatch fills in, so registers mean what Engine::SetPanTilt16 means.
  int32_t pan_range_q16 = 0;
  int32_t tilt_range_q16 = 0;
  int32_t roll_range_q16 = 360 << 16;
  DimmerCurve dimmer_curve = DimmerCurve::kLinear;
  int32_t fade_ms = 0;                 // linear ramp to each new value; 0 = jump
  int line = 0;                        // where it was declared (0: not from a file)
  // >= 0: this entry is Patch::emitters[emitter] (appended by ResolvePatch),
  // not a luminaire of the bake.
  int emitter = -1;
};

// What the engine can hold at once (relight/engine/surface_emitter.h
// kMaxSurfaceEmitters; the control stage checks the two agree).
inline constexpr int kMaxPatchEmitters = 8;
inline constexpr int kMaxPatchEmitterCorners = 8;  // kMaxSurfaceEmitterCorners

// A run-time light source on a surface of the bake ([[emitter]]): hal reads
// its numbers and treats its parameters as a fixture's (dimmer, r, g, b and
// the levels x, y, size, relight/base/param.h); what they mean on the
// surface is the control stage's (relight/control/emitter_binding.h).
struct EmitterPatch {
  std::string surface;                 // the bake's surface name, e.g. "room/+z"
  // The shape at offset 0 and scale 1: a rectangle (centre, width along the
  // surface's u axis, height along v), or a convex polygon (corners, when
  // `polygon` is not empty). Q16.16 metres.
  std::array<int32_t, 3> centre_q16 = {};
  int32_t width_q16 = 0, height_q16 = 0;
  std::vector<std::array<int32_t, 3>> polygon_q16;
  int32_t luminance_q12[3] = {0, 0, 0};  // LightQ12 cd/m^2 per channel at dimmer 1, colour 1, 1, 1
  // Offsets along u and v (Q16.16 metres) for x, y = 0 and 1; scale (Q16.16) for size = 0 and 1.
  int32_t x_range_q16[2] = {0, 0};
  int32_t y_range_q16[2] = {0, 0};
  int32_t size_range_q16[2] = {65536, 65536};
  // Levels (Q1.15) at start: dimmer, x, y, size, and the colour.
  int32_t dimmer_q15 = 32767, x_q15 = 0, y_q15 = 0, size_q15 = 32767;
  int32_t rgb_q15[3] = {32767, 32767, 32767};
  FixturePatch control;                // name, Modbus block, curve, fade: as a fixture's
};

struct ModbusTcpConfig {
  bool enabled = false;
  std::string listen = "127.0.0.1";   // an IPv4 address; "0.0.0.0" = every interface
  int port = 1502;                     // 0: any free port (tests)
  std::vector<std::string> allow;      // client IPv4 addresses; empty = any
  int max_clients = 16;
  int idle_timeout_ms = 60000;         // a client silent this long is closed
  int request_timeout_ms = 5000;       // a request begun must be whole this soon (slow senders are closed)
};

struct ModbusRtuConfig {
  bool enabled = false;
  std::string device;                  // e.g. /dev/ttyUSB0
  int baud = 19200;
  char parity = 'N';                   // N, E or O
  int data_bits = 8;
  int stop_bits = 1;
  int unit_id = 1;                     // our slave address, 1..247
};

// One register of the polled peer and what it drives: the fixture's
// register for `channel` (which its layout must have). Values are read as
// that register of our own map is (docs/modbus.md); bytes above 255 clamp.
struct PollEntry {
  int peer_register = 0;               // PDU address on the peer
  std::string fixture;
  Channel channel = Channel::kDimmer;  // not profile or flags
  int line = 0;
};

struct ModbusPollerConfig {
  bool enabled = false;
  std::string host = "127.0.0.1";
  int port = 502;
  int unit_id = 1;
  int rate_hz = 10;
  int timeout_ms = 500;                // per request
  int backoff_max_ms = 5000;           // reconnect delay doubles up to this
  std::vector<PollEntry> map;
};

enum class ButtonAction : uint8_t { kToggle, kPreset };

struct GpioButtonConfig {
  std::string chip;                    // "gpiochip0", a path or a label
  int line = 0;                        // offset on the chip
  bool active_low = true;              // pressed pulls the line low
  int debounce_ms = 20;
  ButtonAction action = ButtonAction::kToggle;
  std::string fixture;                 // kToggle: the fixture switched on/off
  int32_t on_level_q15 = 32767;        // kToggle: dimmer when on
  std::vector<NamedChange> preset;     // kPreset: the changes recalled (names resolved by the sources)
  int config_line = 0;
};

struct GpioEncoderConfig {
  std::string chip;
  int line_a = 0, line_b = 0;
  std::string fixture;
  Param param = Param::kDimmer;
  int32_t step = 327;                  // per quadrature count: Q1.15 level, or Q16.16 degrees for pan/tilt/roll/zoom
  int32_t start = 0;                   // value before the first turn (same format; zoom: required, a beam angle)
  int config_line = 0;
};

struct Patch {
  std::vector<FixturePatch> fixtures;  // after ResolvePatch: the luminaires, then the emitters
  std::vector<EmitterPatch> emitters;
  ModbusTcpConfig modbus_tcp;
  ModbusRtuConfig modbus_rtu;
  ModbusPollerConfig modbus_poller;
  std::vector<GpioButtonConfig> buttons;
  std::vector<GpioEncoderConfig> encoders;
  std::string replay_script;           // [replay] script = "..."; empty = none
  std::string where;                   // the file, for messages
};

// kInvalidArgument with "file:line: what" for bad TOML, unknown keys, values
// out of range; kNotFound / kIoError if the file cannot be read.
Status ParsePatch(const std::string& text, const std::string& where, Patch* out);
Status LoadPatch(const std::string& path, Patch* out);

// What ResolvePatch needs of a bake's luminaire: its name and the console
// ranges of its 16-bit pan and tilt (BakeLuminaire::pan_range, tilt_range).
struct LuminaireConsole {
  std::string name;
  int32_t pan_range_q16 = 540 << 16;
  int32_t tilt_range_q16 = 270 << 16;
};

// Checks the patch against the bake's luminaires and completes it: every
// fixture named must exist; luminaires the patch does not name are appended
// with default settings; pan and tilt ranges the patch leaves out become the
// luminaire's; fixtures without modbus_base get the next free block (as many
// registers as their layout); blocks must not overlap or pass 65535. Buttons,
// encoders and the poller map must name known fixtures, and poller entries a
// register the fixture's layout has. Emitters (at most kMaxPatchEmitters,
// names unique among luminaires and emitters) are appended to `fixtures`
// after the luminaires, with `emitter` set, so every input addresses them
// as fixtures. Errors name file:line.
Status ResolvePatch(const std::vector<LuminaireConsole>& luminaires, Patch* patch);

}  // namespace relight::hal
