// Helpers shared by the fuzz targets (tests/fuzz/): the fuzzer's bytes as
// text, a scratch folder for readers that only take a path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace relight::fuzz {

inline std::string AsText(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A folder of this process's own under $TMPDIR (or /tmp), made on first use
// and kept for the process's life (the fuzzer calls a target millions of
// times: one folder, overwritten).
const std::string& ScratchDir();

// Writes `size` bytes to ScratchDir()/name and returns the path.
std::string WriteScratchFile(const std::string& name, const uint8_t* data, size_t size);

}  // namespace relight::fuzz
