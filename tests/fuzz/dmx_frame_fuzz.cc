// Fuzz target: the DMX frame decoder (DecodeDmxFrame, as the OLA backend
// decodes each frame olad delivers) for the test fixture types in
// fixtures/dmx (a spot with 16-bit pan/tilt, wheel, zoom and shutter; an
// RGBW par). Bytes: start code, start address (2 bytes, any value: the
// decoder must refuse what is out of 1..512), then the slots (at most 512;
// shorter frames occur).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "relight/hal/dmx/fixture_type.h"
#include "relight/hal/dmx/personality.h"

namespace {

std::vector<relight::hal::DmxPersonality> LoadPersonalities() {
  std::vector<relight::hal::DmxPersonality> out;
  for (const char* file : {"relight-test-spot.toml", "relight-test-rgbw.toml"}) {
    relight::hal::FixtureType type;
    if (!relight::hal::LoadFixtureType(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/" + file, &type).ok()) std::abort();
    for (const relight::hal::DmxMode& mode : type.modes) {
      out.emplace_back();
      if (!relight::hal::BuildPersonality(type, mode.name, &out.back()).ok()) std::abort();
    }
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<relight::hal::DmxPersonality> personalities = LoadPersonalities();
  if (size < 3) return 0;
  const uint8_t start_code = data[0];
  const int start_address = static_cast<int16_t>((data[1] << 8) | data[2]);
  size_t count = size - 3;
  if (count > 512) count = 512;
  for (const relight::hal::DmxPersonality& p : personalities) {
    relight::hal::DmxFixtureValues values;
    (void)relight::hal::DecodeDmxFrame(p, start_address, start_code, data + 3, count, &values);
  }
  return 0;
}
