// PPM / raw RGB frame stream on stdout or a FIFO.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "frame_sink.h"

namespace relight::daemon {
namespace {

class StreamSink final : public FrameSink {
 public:
  StreamSink(std::string path, int fd, bool raw) : path_(std::move(path)), fd_(fd), raw_(raw) {}
  ~StreamSink() override {
    if (fd_ != STDOUT_FILENO) close(fd_);
  }

  Status Write(const uint8_t* rgb, int width, int height, int64_t /*frame*/) override {
    if (!raw_) {
      char header[64];
      const int n = std::snprintf(header, sizeof header, "P6\n%d %d\n255\n", width, height);
      RELIGHT_RETURN_IF_ERROR(WriteAll(reinterpret_cast<const uint8_t*>(header), static_cast<size_t>(n)));
    }
    return WriteAll(rgb, static_cast<size_t>(width) * height * 3);
  }
  std::string Describe() const override { return std::string(raw_ ? "raw RGB" : "PPM") + " stream to " + path_; }

 private:
  Status WriteAll(const uint8_t* data, size_t size) {
    while (size > 0) {
      const ssize_t n = write(fd_, data, size);
      if (n < 0) {
        if (errno == EINTR) continue;
        return Status(StatusCode::kIoError, "frame stream " + path_ + ": " + std::strerror(errno));
      }
      data += n;
      size -= static_cast<size_t>(n);
    }
    return Status::Ok();
  }

  std::string path_;
  int fd_;
  bool raw_;
};

}  // namespace

Status MakeStreamSink(const std::string& path, bool raw, std::unique_ptr<FrameSink>* out) {
  int fd = STDOUT_FILENO;
  if (path != "-") {
    fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return Status(StatusCode::kIoError, "frame stream '" + path + "': " + std::strerror(errno));
  }
  *out = std::make_unique<StreamSink>(path == "-" ? "stdout" : path, fd, raw);
  return Status::Ok();
}

}  // namespace relight::daemon
