// Fuzz target: a fixture type in relight's TOML form (docs/dmx.md) read by
// ParseFixtureTypeToml, then every mode's personality built and frames decoded through
// it (fixture_type_exercise.h).
#include <cstddef>
#include <cstdint>

#include "fixture_type_exercise.h"
#include "fuzz_support.h"
#include "relight/hal/dmx/fixture_type.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  relight::hal::FixtureType type;
  if (!relight::hal::ParseFixtureTypeToml(relight::fuzz::AsText(data, size), "fuzz.toml", &type).ok()) return 0;
  relight::fuzz::ExerciseFixtureType(type);
  return 0;
}
