// For a helper process a test forks (olad): its stdout and stderr go to a
// file of its own, not to the test's, which ctest reads to the end. A test
// that dies (an ASan abort) leaves such a child running; holding ctest's pipe
// it would stall the run until the test's timeout.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <string>

namespace relight::testing {

// Call in the child, between fork and exec.
inline void SendOutputTo(const std::string& path) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return;
  dup2(fd, STDOUT_FILENO);  // dup2's copies do not inherit O_CLOEXEC
  dup2(fd, STDERR_FILENO);
  close(fd);
}

}  // namespace relight::testing
