// File I/O of the bake layer, apart from the format: reads of a byte range
// of an open file, and atomic writes (temporary file beside the target, fsync, rename, directory
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

// An open regular file and its size; closes itself.
class ReadOnlyFile {
 public:
  ReadOnlyFile() = default;
  ~ReadOnlyFile();
  ReadOnlyFile(const ReadOnlyFile&) = delete;
  ReadOnlyFile& operator=(const ReadOnlyFile&) = delete;

  // The regular file at `path`. kNotFound, kIoError ("bake 'path': why").
  Status Open(const std::string& path);
  size_t size() const { return size_; }
  // Exactly `n` bytes at `offset` into `dst`; "" or why not (e.g. the file
  // shrank since Open).
  std::string ReadAt(uint64_t offset, size_t n, uint8_t* dst) const;

 private:
  int fd_ = -1;
  size_t size_ = 0;
};

// Creates a temporary file beside `path`, lets `write` fill it (false with
// errno set on failure), fsyncs it and renames it over `path`. Any failure
// removes the temporary file and leaves `path` as it was: kIoError.
Status WriteFileAtomically(const std::string& path, const std::function<bool(int fd)>& write);

}  // namespace relight::bake_format
