// File I/O of the bake layer, apart from the format: whole-file reads and
// atomic writes (temporary file beside the target, fsync, rename, directory
// fsync). Private to the bake layer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "relight/base/status.h"

namespace relight::bake_format {

// pwrite() until done (it may write less than asked or be interrupted).
// Returns false with errno set.
bool WriteAt(int fd, const uint8_t* data, size_t size, uint64_t offset);

// The whole regular file at `path`. kNotFound, kIoError ("bake 'path': why").
Status ReadWholeFile(const std::string& path, std::vector<uint8_t>* bytes);

// Creates a temporary file beside `path`, lets `write` fill it (false with
// errno set on failure), fsyncs it and renames it over `path`. Any failure
// removes the temporary file and leaves `path` as it was: kIoError.
Status WriteFileAtomically(const std::string& path, const std::function<bool(int fd)>& write);

}  // namespace relight::bake_format
