// The DMX patch: which fixture type, in which mode, sits at which universe
// and start address. A TOML file, kept apart from the Modbus patch (patch.h)
// for now; every error names file:line.
//
//   [dmx]
//   loss_of_signal = "hold"       # or "fade" (over loss_fade_ms), "blackout" (at once)
//   loss_timeout_ms = 1000        # no frame for this long = signal lost
//   loss_fade_ms = 3000           # "fade": dimmers from their last value to 0 in this time
//
//   [[dmx_fixture]]
//   name = "spot_left"
//   type = "Martin/Martin-MAC-Aura.qxf"  # relative to the patch file, else to QLC+'s library
//   mode = "Standard"
//   universe = 1                  # OLA universe number
//   address = 1                   # start address, 1..512
#pragma once

#include <string>
#include <vector>

#include "relight/base/status.h"
#include "relight/hal/dmx/fixture_type.h"
#include "relight/hal/dmx/personality.h"

namespace relight::hal {

// What a fixture does once no frame reached it for loss_timeout_ms: keep its
// last look, fade its dimmer to 0 over loss_fade_ms, or cut it to 0.
enum class DmxLossPolicy : uint8_t { kHold, kBlackout, kFade };

struct DmxFixturePatch {
  std::string name;
  std::string type_path;               // as resolved
  std::string mode;
  int universe = 1;
  int address = 1;                     // 1-based start address
  FixtureType type;
  DmxPersonality personality;
  int line = 0;
};

struct DmxPatch {
  std::vector<DmxFixturePatch> fixtures;
  DmxLossPolicy loss_policy = DmxLossPolicy::kHold;
  int loss_timeout_ms = 1000;
  int loss_fade_ms = 3000;
  std::string where;
};

// Loads each fixture's type and builds its personality. kInvalidArgument
// "file:line: what" for bad TOML, unknown keys, an unknown type file or
// mode, a footprint past slot 512, two fixtures sharing slots of one
// universe, a name used twice. `library_dir` is where bare type paths are
// looked up after the patch's own folder (kQlcFixtureDir by default).
Status ParseDmxPatch(const std::string& text, const std::string& where, DmxPatch* out,
                     const std::string& library_dir = kQlcFixtureDir);
Status LoadDmxPatch(const std::string& path, DmxPatch* out, const std::string& library_dir = kQlcFixtureDir);

}  // namespace relight::hal
