#include "fixture_type_exercise.h"

#include <cstdint>

#include "relight/hal/dmx/personality.h"

namespace relight::fuzz {

void ExerciseFixtureType(const hal::FixtureType& type) {
  static uint8_t zeros[512] = {};
  static uint8_t ramp[512];
  for (int i = 0; i < 512; ++i) ramp[i] = static_cast<uint8_t>(i * 7);
  for (const hal::DmxMode& mode : type.modes) {
    hal::DmxPersonality p;
    if (!hal::BuildPersonality(type, mode.name, &p).ok()) continue;
    hal::DmxFixtureValues values;
    (void)hal::DecodeDmxFrame(p, 1, 0, zeros, sizeof zeros, &values);
    (void)hal::DecodeDmxFrame(p, 1, 0, ramp, sizeof ramp, &values);
  }
}

}  // namespace relight::fuzz
