// Linux framebuffer sink: packs RGB into the device's pixel layout and
// writes it row by row at the device's line stride.
#include <fcntl.h>
#include <linux/fb.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "frame_sink.h"

namespace relight::daemon {
namespace {

struct Layout {
  int width = 0, height = 0;   // visible pixels
  int bytes_per_pixel = 4;
  size_t line_bytes = 0;       // stride
  fb_bitfield red{16, 8, 0}, green{8, 8, 0}, blue{0, 8, 0};
};

uint32_t Pack(const fb_bitfield& f, uint8_t v) {
  return (static_cast<uint32_t>(v) >> (8 - (f.length > 8 ? 8 : f.length))) << f.offset;
}

class FramebufferSink final : public FrameSink {
 public:
  FramebufferSink(std::string path, int fd, Layout layout) : path_(std::move(path)), fd_(fd), layout_(layout) {
    row_.resize(layout_.line_bytes);
  }
  ~FramebufferSink() override { close(fd_); }

  Status Write(const uint8_t* rgb, int width, int height, int64_t /*frame*/) override {
    const int w = width < layout_.width ? width : layout_.width;
    const int h = height < layout_.height ? height : layout_.height;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const uint8_t* p = rgb + (static_cast<size_t>(y) * width + x) * 3;
        const uint32_t v = Pack(layout_.red, p[0]) | Pack(layout_.green, p[1]) | Pack(layout_.blue, p[2]);
        for (int b = 0; b < layout_.bytes_per_pixel; ++b) {  // little-endian, as the kernel lays pixels out
          row_[static_cast<size_t>(x) * layout_.bytes_per_pixel + b] = static_cast<uint8_t>(v >> (8 * b));
        }
      }
      const size_t bytes = static_cast<size_t>(w) * layout_.bytes_per_pixel;
      if (pwrite(fd_, row_.data(), bytes, static_cast<off_t>(y * layout_.line_bytes)) != static_cast<ssize_t>(bytes)) {
        return Status(StatusCode::kIoError, "framebuffer " + path_ + ": " + std::strerror(errno));
      }
    }
    return Status::Ok();
  }
  std::string Describe() const override {
    return "framebuffer " + path_ + " (" + std::to_string(layout_.width) + "x" + std::to_string(layout_.height) + ", " +
           std::to_string(layout_.bytes_per_pixel * 8) + " bpp)";
  }

 private:
  std::string path_;
  int fd_;
  Layout layout_;
  std::vector<uint8_t> row_;
};

}  // namespace

Status MakeFramebufferSink(const std::string& path, int file_width, int file_height, std::unique_ptr<FrameSink>* out) {
  const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return Status(StatusCode::kIoError, "framebuffer '" + path + "': " + std::strerror(errno));
  struct stat st {};
  fstat(fd, &st);
  Layout layout;
  if (S_ISCHR(st.st_mode)) {
    fb_var_screeninfo var{};
    fb_fix_screeninfo fix{};
    if (ioctl(fd, FBIOGET_VSCREENINFO, &var) != 0 || ioctl(fd, FBIOGET_FSCREENINFO, &fix) != 0) {
      const std::string why = std::strerror(errno);
      close(fd);
      return Status(StatusCode::kInvalidArgument, "framebuffer '" + path + "': not a framebuffer device: " + why);
    }
    if (var.bits_per_pixel != 16 && var.bits_per_pixel != 24 && var.bits_per_pixel != 32) {
      close(fd);
      return Status(StatusCode::kUnsupported, "framebuffer '" + path + "': " + std::to_string(var.bits_per_pixel) +
                                                  " bits per pixel (16, 24 or 32 supported)");
    }
    layout.width = static_cast<int>(var.xres);
    layout.height = static_cast<int>(var.yres);
    layout.bytes_per_pixel = static_cast<int>(var.bits_per_pixel / 8);
    layout.line_bytes = fix.line_length;
    layout.red = var.red;
    layout.green = var.green;
    layout.blue = var.blue;
  } else {
    if (file_width <= 0 || file_height <= 0) {
      close(fd);
      return Status(StatusCode::kInvalidArgument, "framebuffer '" + path + "': not a device; give its size (--fb-size)");
    }
    layout.width = file_width;
    layout.height = file_height;
    layout.line_bytes = static_cast<size_t>(file_width) * 4;
  }
  *out = std::make_unique<FramebufferSink>(path, fd, layout);
  return Status::Ok();
}

}  // namespace relight::daemon
