#include "relight/render/compiler_pages.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>

namespace relight::render {
namespace {

#ifndef MADV_PAGEOUT
#define MADV_PAGEOUT 21  // linux/mman.h since 5.4
#endif

// One /proc/self/maps line: "start-end perms offset dev inode   path".
// Advises the mapping if it is read-only and its path contains path_part.
// Returns false when the kernel refused the advice as unknown (EINVAL).
bool AdviseLine(const char* line, const char* path_part, PagesReleased* released) {
  uintmax_t start = 0, end = 0;
  char perms[8] = {};
  int path_at = 0;
  if (std::sscanf(line, "%jx-%jx %7s %*s %*s %*s %n", &start, &end, perms, &path_at) != 3) return true;
  if (path_at <= 0 || std::strstr(line + path_at, path_part) == nullptr) return true;
  if (perms[0] != 'r' || perms[1] == 'w' || end <= start) return true;
  // The address comes from the kernel's own list of this process's mappings.
  void* addr = reinterpret_cast<void*>(static_cast<uintptr_t>(start));  // NOLINT(performance-no-int-to-ptr)
  if (madvise(addr, static_cast<size_t>(end - start), MADV_PAGEOUT) != 0) return errno != EINVAL;
  released->bytes += end - start;
  ++released->mappings;
  return true;
}

}  // namespace

Status ReleaseMappedFilePages(const char* path_part, PagesReleased* released) {
  *released = PagesReleased{};
  if (path_part == nullptr || path_part[0] == '\0') {
    return Status(StatusCode::kInvalidArgument, "ReleaseMappedFilePages: empty path part");
  }
  const int fd = open("/proc/self/maps", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Status(StatusCode::kIoError, std::string("/proc/self/maps: ") + std::strerror(errno));
  // Lines are read whole into `buf`; a line longer than the buffer (a path
  // of over 4000 bytes) is skipped.
  char buf[4096 + 1];
  size_t have = 0;
  bool skipping = false, supported = true;
  for (;;) {
    const ssize_t got = read(fd, buf + have, sizeof buf - 1 - have);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    have += static_cast<size_t>(got);
    size_t from = 0;
    for (size_t i = 0; i < have; ++i) {
      if (buf[i] != '\n') continue;
      buf[i] = '\0';
      if (!skipping && supported) supported = AdviseLine(buf + from, path_part, released);
      skipping = false;
      from = i + 1;
    }
    if (from == 0 && have == sizeof buf - 1) {  // no newline in a full buffer
      skipping = true;
      have = 0;
      continue;
    }
    std::memmove(buf, buf + from, have - from);
    have -= from;
  }
  close(fd);
  if (!supported) {
    return Status(StatusCode::kUnsupported, "this kernel has no MADV_PAGEOUT (Linux 5.4 or later has it)");
  }
  return Status();
}

Status ReleaseShaderCompilerPages(PagesReleased* released) { return ReleaseMappedFilePages("libLLVM", released); }

}  // namespace relight::render
