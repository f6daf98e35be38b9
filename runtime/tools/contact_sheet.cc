#include "contact_sheet.h"

#include <algorithm>

#include "relight/render/osmesa_frame.h"

namespace relight::cli {

void ContactSheetBuilder::Add(const uint8_t* rgb) {
  const int tw = width_ / 2, th = height_ / 2;
  std::vector<uint8_t> tile(static_cast<size_t>(tw) * th * 3);
  for (int y = 0; y < th; ++y) {
    for (int x = 0; x < tw; ++x) {
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) sum += rgb[((2 * y + dy) * static_cast<size_t>(width_) + 2 * x + dx) * 3 + c];
        }
        tile[(static_cast<size_t>(y) * tw + x) * 3 + c] = static_cast<uint8_t>((sum + 2) / 4);
      }
    }
  }
  tiles_.push_back(std::move(tile));
  ++frames_;
}

Status ContactSheetBuilder::Write(const std::string& path) const {
  if (frames_ == 0) return Status(StatusCode::kInvalidArgument, "contact sheet '" + path + "': no frames");
  const int tw = width_ / 2, th = height_ / 2;
  const int columns = frames_ < kColumns ? frames_ : kColumns;
  const int rows = (frames_ + kColumns - 1) / kColumns;
  const size_t sheet_w = static_cast<size_t>(tw) * columns;
  std::vector<uint8_t> sheet(sheet_w * th * rows * 3, 0);
  for (int i = 0; i < frames_; ++i) {
    const size_t x0 = static_cast<size_t>(i % kColumns) * tw, y0 = static_cast<size_t>(i / kColumns) * th;
    for (int y = 0; y < th; ++y) {
      const uint8_t* src = &tiles_[static_cast<size_t>(i)][static_cast<size_t>(y) * tw * 3];
      std::copy(src, src + static_cast<size_t>(tw) * 3, &sheet[((y0 + y) * sheet_w + x0) * 3]);
    }
  }
  return WritePngRgb8(path, sheet.data(), tw * columns, th * rows);
}

}  // namespace relight::cli
