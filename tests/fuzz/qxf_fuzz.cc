// Fuzz target: a QLC+ fixture definition (.qxf, XML) read by
// ParseQxf, then every mode's personality built and frames decoded through
// it (fixture_type_exercise.h).
#include <cstddef>
#include <cstdint>

#include "fixture_type_exercise.h"
#include "fuzz_support.h"
#include "relight/hal/dmx/fixture_type.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  relight::hal::FixtureType type;
  if (!relight::hal::ParseQxf(relight::fuzz::AsText(data, size), "fuzz.qxf", &type).ok()) return 0;
  relight::fuzz::ExerciseFixtureType(type);
  return 0;
}
