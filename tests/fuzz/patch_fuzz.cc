// Fuzz target: the Modbus/GPIO patch (ParsePatch, as relightd reads
// --patch), resolved against a bake's luminaires (ResolvePatch) and turned
// into the register map (RegisterMap::Build), as relightd does at start-up.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_support.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The living room's luminaires (fixtures/living_room.toml), as a bake lists them.
  static const std::vector<relight::hal::LuminaireConsole> kLuminaires = {
      {"ceiling_wide", 540 << 16, 270 << 16}, {"ceiling_spot", 540 << 16, 270 << 16},
      {"corner_uplight", 360 << 16, 180 << 16}};
  relight::hal::Patch patch;
  if (!relight::hal::ParsePatch(relight::fuzz::AsText(data, size), "fuzz.toml", &patch).ok()) return 0;
  if (!relight::hal::ResolvePatch(kLuminaires, &patch).ok()) return 0;
  relight::hal::RegisterMap map;
  (void)relight::hal::RegisterMap::Build(patch.fixtures, &map);
  return 0;
}
