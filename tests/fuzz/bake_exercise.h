// What the bake fuzz targets do with a bake that passed validation: open the
// engine on it, compute a frame, move a luminaire and place a run-time
// surface emitter on the first surface of a hierarchical bake, compute again.
// Errors are fine; a crash or a sanitizer report is not.
#pragma once

#include "relight/bake/bake.h"

namespace relight::fuzz {

void ExerciseBake(Bake bake);

}  // namespace relight::fuzz
