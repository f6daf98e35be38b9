// What the fixture-type fuzz targets do with a type that was read: build the
// personality of every mode and decode two frames through it (all slots 0,
// then a ramp), as the DMX backend does with each frame from olad.
#pragma once

#include "relight/hal/dmx/fixture_type.h"

namespace relight::fuzz {

void ExerciseFixtureType(const hal::FixtureType& type);

}  // namespace relight::fuzz
