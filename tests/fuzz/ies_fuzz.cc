// Fuzz target: the IES reader (ParseIes, as relight-bake and relight-lid read a
// luminaire file), then MakeLid on what it accepts. SceneError ("file:line:
// what") is the reader's answer to bad input; anything else escaping, or a
// sanitizer report, is a bug. The text is named inside a scratch folder, so
// a TILT= file resolves there (to nothing, unless absolute).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kPath = relight::fuzz::ScratchDir() + "/fuzz.ies";
  try {
    relight::baker::MakeLid(relight::baker::ParseIes(relight::fuzz::AsText(data, size), kPath));
  } catch (const relight::baker::SceneError&) {
  }
  return 0;
}
