#include "bounded_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace relight::hal {

Status ReadConfigFile(const std::string& path, const char* what, std::string* text, std::uint64_t max_bytes) {
  const std::string name = std::string(what) + " '" + path + "'";
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    return Status(errno == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError, name + ": " + std::strerror(errno));
  }
  struct stat st {};
  Status result = Status::Ok();
  if (fstat(fd, &st) != 0) {
    result = Status(StatusCode::kIoError, name + ": " + std::strerror(errno));
  } else if (!S_ISREG(st.st_mode)) {
    result = Status(StatusCode::kInvalidArgument, name + ": not a regular file");
  } else if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    result = Status(StatusCode::kInvalidArgument,
                    name + ": " + std::to_string(st.st_size) + " bytes, more than the limit of " +
                        std::to_string(max_bytes));
  } else {
    // The size may change under us: read at most max_bytes + 1 and judge by that.
    text->clear();
    char buf[65536];
    for (;;) {
      const ssize_t n = read(fd, buf, sizeof buf);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        result = Status(StatusCode::kIoError, name + ": " + std::strerror(errno));
        break;
      }
      if (n == 0) break;
      text->append(buf, static_cast<size_t>(n));
      if (text->size() > max_bytes) {
        result = Status(StatusCode::kInvalidArgument,
                        name + ": more than the limit of " + std::to_string(max_bytes) + " bytes");
        break;
      }
    }
  }
  close(fd);
  return result;
}

}  // namespace relight::hal
