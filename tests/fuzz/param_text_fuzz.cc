// Fuzz target: the parameter syntax of --set, replay lines and patch presets
// (ParseParamText: "FIXTURE.PARAM=VALUE").
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "relight/hal/param_text.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  relight::hal::NamedChange out[3];
  std::string error;
  (void)relight::hal::ParseParamText(relight::fuzz::AsText(data, size), 0, out, &error);
  return 0;
}
