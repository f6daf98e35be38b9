// Fuzz target: the EULUMDAT reader (ParseEulumdat, as relight-bake and relight-lid read a
// luminaire file), then MakeLid on what it accepts. SceneError ("file:line:
// what") is the reader's answer to bad input; anything else escaping, or a
// sanitizer report, is a bug.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kPath = relight::fuzz::ScratchDir() + "/fuzz.ldt";
  try {
    relight::baker::MakeLid(relight::baker::ParseEulumdat(relight::fuzz::AsText(data, size), kPath));
  } catch (const relight::baker::SceneError&) {
  }
  return 0;
}
