// Fuzz target: a whole bake file from bytes (ParseBake, as Engine::Open reads
// a file), then the engine opened on whatever passed validation and one
// frame computed with a run-time surface emitter placed: a bake that
// validates must not overflow anything downstream (issue 17 item 5).
// Checksums are as the bytes have them, so this target mostly exercises the
// header and table of contents; bake_sections_fuzz reaches the sections.
#include <cstddef>
#include <cstdint>

#include "bake_exercise.h"
#include "relight/bake/bake.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  relight::Bake bake;
  if (!relight::ParseBake(data, size, &bake).ok()) return 0;
  relight::fuzz::ExerciseBake(std::move(bake));
  return 0;
}
