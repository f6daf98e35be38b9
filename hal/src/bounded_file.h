// Reading a configuration file named on the command line or by another file
// (a patch, a DMX patch, a replay script or DMX recording): only a regular file, only up to a size limit, so
// `--patch /dev/zero`, a FIFO or a directory is a clear error instead of a
// hang or memory growing without end (issue 17; the baker's twin is
// baker/src/bounded_read.h).
#pragma once

#include <cstdint>
#include <string>

#include "relight/base/status.h"

namespace relight::hal {

// Patches and DMX patches are a few kB; this is far above any real one.
inline constexpr std::uint64_t kMaxConfigFileBytes = 4ull << 20;
// Recorded input: replay scripts and DMX recordings (a 24 s 48-head show is ~1 MB).
inline constexpr std::uint64_t kMaxReplayScriptBytes = 64ull << 20;
inline constexpr std::uint64_t kMaxDmxRecordingBytes = 256ull << 20;

// Reads all of `path` into *text. `what` names the file in messages
// ("patch", "DMX patch"). kNotFound when it does not exist, kIoError when it
// cannot be opened or read, kInvalidArgument when it is not a regular file
// or is larger than max_bytes. Opened without blocking and checked through
// the open descriptor, so a FIFO cannot stall it.
Status ReadConfigFile(const std::string& path, const char* what, std::string* text,
                      std::uint64_t max_bytes = kMaxConfigFileBytes);

}  // namespace relight::hal
