// PNG sequence sink: one file per frame.
#include <cstdio>

#include "frame_sink.h"
#include "relight/render/osmesa_frame.h"

namespace relight::daemon {
namespace {

bool HasOneIntConversion(const std::string& pattern) {
  size_t count = 0, pos = 0;
  bool ok = false;
  while ((pos = pattern.find('%', pos)) != std::string::npos) {
    if (pos + 1 < pattern.size() && pattern[pos + 1] == '%') {
      pos += 2;
      continue;
    }
    ++count;
    const size_t d = pattern.find_first_not_of("0123456789", pos + 1);
    ok = d != std::string::npos && pattern[d] == 'd';
    pos = pos + 1;
  }
  return count == 1 && ok;
}

class PngSequenceSink final : public FrameSink {
 public:
  explicit PngSequenceSink(std::string pattern) : pattern_(std::move(pattern)) {}
  Status Write(const uint8_t* rgb, int width, int height, int64_t frame) override {
    char path[4096];
    std::snprintf(path, sizeof path, pattern_.c_str(), static_cast<int>(frame));
    return WritePngRgb8(path, rgb, width, height);
  }
  std::string Describe() const override { return "PNG files " + pattern_; }

 private:
  std::string pattern_;
};

}  // namespace

Status MakePngSequenceSink(const std::string& pattern, std::unique_ptr<FrameSink>* out) {
  if (!HasOneIntConversion(pattern)) {
    return Status(StatusCode::kInvalidArgument,
                  "--png '" + pattern + "': needs exactly one %d for the frame number, e.g. frames/f_%04d.png");
  }
  *out = std::make_unique<PngSequenceSink>(pattern);
  return Status::Ok();
}

}  // namespace relight::daemon
