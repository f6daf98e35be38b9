// Fuzz target: the DMX patch (ParseDmxPatch, as relightd reads a DMX patch):
// TOML, then each fixture's type file loaded and its personality built.
// Type files are looked up in fixtures/dmx (the library the seeds name), so
// the fuzzer reaches the fixture-type readers and BuildPersonality too.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "relight/hal/dmx/dmx_patch.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kLibrary = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx";
  relight::hal::DmxPatch patch;
  (void)relight::hal::ParseDmxPatch(relight::fuzz::AsText(data, size), kLibrary + "/fuzz.toml", &patch, kLibrary);
  return 0;
}
