// Bake file I/O (see bake_file_io.h).
#include "bake_file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "bake_container.h"

namespace relight::bake_format {
namespace {

Status IoError(const std::string& path, const char* what, int err) {
  return Status(StatusCode::kIoError,
                StrFormat("bake '%s': %s: %s", path.c_str(), what, std::strerror(err)));
}

// Makes the rename itself durable. Best effort: the new file is already in
// place when this runs, so a failure here is not reported as one.
void SyncDirectoryOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "."
                          : slash == 0               ? "/"
                                                     : path.substr(0, slash);
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

}  // namespace

bool WriteAt(int fd, const uint8_t* data, size_t size, uint64_t offset) {
  while (size > 0) {
    const size_t chunk = size < (size_t{1} << 30) ? size : (size_t{1} << 30);
    const ssize_t n = ::pwrite(fd, data, chunk, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) errno = EIO;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
    offset += static_cast<uint64_t>(n);
  }
  return true;
}

ReadOnlyFile::~ReadOnlyFile() {
  if (fd_ >= 0) ::close(fd_);
}

Status ReadOnlyFile::Open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    const StatusCode code = err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError;
    return Status(code, StrFormat("bake '%s': %s", path.c_str(), std::strerror(err)));
  }
  struct stat st;
  std::string error;
  if (::fstat(fd, &st) != 0) {
    error = std::strerror(errno);
  } else if (!S_ISREG(st.st_mode)) {
    error = "not a regular file";
  } else if (st.st_size < 0 || !FitsSizeT(st.st_size)) {
    error = "too large for this machine's address space";
  }
  if (!error.empty()) {
    ::close(fd);
    return Status(StatusCode::kIoError, StrFormat("bake '%s': %s", path.c_str(), error.c_str()));
  }
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
  size_ = static_cast<size_t>(st.st_size);
  return Status::Ok();
}

std::string ReadOnlyFile::ReadAt(uint64_t offset, size_t n, uint8_t* dst) const {
  size_t done = 0;
  while (done < n) {
    const ssize_t got = ::pread(fd_, dst + done, n - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return std::strerror(errno);
    if (got == 0) return "the file shrank while being read";
    done += static_cast<size_t>(got);
  }
  return "";
}

Status WriteFileAtomically(const std::string& path, const std::function<bool(int fd)>& write) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return IoError(path, ("cannot create '" + tmp + "'").c_str(), errno);

  const char* failed = nullptr;
  if (!write(fd)) {
    failed = "write failed";
  } else if (::fsync(fd) != 0) {
    failed = "fsync failed";
  }
  int err = failed ? errno : 0;
  if (::close(fd) != 0 && !failed) {
    failed = "close failed";
    err = errno;
  }
  if (!failed && ::rename(tmp.c_str(), path.c_str()) != 0) {
    failed = "rename failed";
    err = errno;
  }
  if (failed) {
    ::unlink(tmp.c_str());
    return IoError(path, failed, err);
  }
  SyncDirectoryOf(path);
  return Status::Ok();
}

}  // namespace relight::bake_format
