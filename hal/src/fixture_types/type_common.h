// What the fixture-type readers share.
#pragma once

#include <string>

#include "relight/base/status.h"

namespace relight::hal {

// Reads a whole file; refuses non-regular files (a FIFO, /dev/zero) and files
// over 4 MiB (the largest .qxf in QLC+'s library is ~100 kB).
Status ReadTypeFile(const std::string& path, std::string* text);

// DmxChannel::ignored_why of an "ignored" channel read from the TOML form
// (the writer leaves it out rather than comment every such channel with it).
inline constexpr const char* kTomlIgnoredWhy = "ignored in the TOML type";

}  // namespace relight::hal
