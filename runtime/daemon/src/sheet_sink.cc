// Contact sheet sink: every frame as a half-size tile of one PNG.
#include <memory>

#include "contact_sheet.h"
#include "frame_sink.h"

namespace relight::daemon {
namespace {

class ContactSheetSink final : public FrameSink {
 public:
  explicit ContactSheetSink(std::string path) : path_(std::move(path)) {}
  Status Write(const uint8_t* rgb, int width, int height, int64_t /*frame*/) override {
    if (!builder_) builder_ = std::make_unique<cli::ContactSheetBuilder>(width, height);
    builder_->Add(rgb);
    return Status::Ok();
  }
  Status Finish() override { return builder_ ? builder_->Write(path_) : Status::Ok(); }
  std::string Describe() const override { return "contact sheet " + path_; }

 private:
  std::string path_;
  std::unique_ptr<cli::ContactSheetBuilder> builder_;
};

}  // namespace

Status MakeContactSheetSink(const std::string& path, std::unique_ptr<FrameSink>* out) {
  *out = std::make_unique<ContactSheetSink>(path);
  return Status::Ok();
}

}  // namespace relight::daemon
