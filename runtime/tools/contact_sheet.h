// All frames of a sequence on one page: each frame box-filtered to half size
// and tiled 4 per row. Used by relight-render --sheet and relightd --sheet.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/status.h"

namespace relight::cli {

class ContactSheetBuilder {
 public:
  static constexpr int kColumns = 4;
  ContactSheetBuilder(int frame_width, int frame_height) : width_(frame_width), height_(frame_height) {}
  // Adds the next frame (width*height*3 bytes, top row first).
  void Add(const uint8_t* rgb);
  int frames() const { return frames_; }
  // Writes the sheet as PNG (kIoError naming the path); an empty sheet is an error.
  Status Write(const std::string& path) const;

 private:
  int width_, height_;
  int frames_ = 0;
  std::vector<std::vector<uint8_t>> tiles_;  // half-size frames
};

}  // namespace relight::cli
