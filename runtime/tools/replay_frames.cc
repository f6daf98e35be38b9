#include "replay_frames.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "relight/hal/replay_source.h"
#include "relight/osmesa_frame.h"
#include "set_args.h"

namespace relight::cli {
namespace {

bool PatternHasOneNumber(const std::string& pattern) {
  const size_t pct = pattern.find('%');
  if (pct == std::string::npos || pattern.find('%', pct + 1) != std::string::npos) return false;
  const size_t d = pattern.find('d', pct);
  return d != std::string::npos && pattern.find_first_not_of("0123456789", pct + 1) == d;
}

constexpr int kSheetColumns = 4;

// Box-filters frame `rgb` to half size into tile `index` of the sheet.
void AddTile(const uint8_t* rgb, int width, int height, int index, int columns, std::vector<uint8_t>* sheet) {
  const int tw = width / 2, th = height / 2;
  const int sheet_w = tw * columns;
  const int x0 = (index % columns) * tw, y0 = (index / columns) * th;
  for (int y = 0; y < th; ++y) {
    for (int x = 0; x < tw; ++x) {
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) sum += rgb[((2 * y + dy) * width + 2 * x + dx) * 3 + c];
        }
        (*sheet)[((y0 + y) * static_cast<size_t>(sheet_w) + x0 + x) * 3 + c] = static_cast<uint8_t>((sum + 2) / 4);
      }
    }
  }
}

}  // namespace

int RenderReplay(Engine& engine, const std::string& script_path, double fps, const std::string& pattern,
                 const std::function<int(const std::string&)>& render_to, const ContactSheet& sheet) {
  if (!PatternHasOneNumber(pattern)) {
    std::fprintf(stderr, "relight-render: error: with --replay, -o needs one %%d (e.g. frame_%%04d.png), got '%s'\n",
                 pattern.c_str());
    return 2;
  }
  hal::ReplaySource source(script_path);
  if (Status st = source.Start(); !st.ok()) {
    std::fprintf(stderr, "relight-render: error: %s\n", st.ToString().c_str());
    return 2;
  }
  const int64_t frame_us = std::llround(1e6 / fps);
  const int frames = static_cast<int>(source.duration_us() / frame_us) + 1;
  std::vector<hal::ParamChange> changes(256);
  const int columns = frames < kSheetColumns ? frames : kSheetColumns;
  const int rows = (frames + kSheetColumns - 1) / kSheetColumns;
  std::vector<uint8_t> sheet_rgb;
  if (!sheet.path.empty()) sheet_rgb.assign(static_cast<size_t>(sheet.width / 2) * columns * (sheet.height / 2) * rows * 3, 0);
  const bool tty = isatty(STDOUT_FILENO) != 0;
  for (int i = 0; i < frames; ++i) {
    const int64_t now_us = static_cast<int64_t>(i) * frame_us;
    size_t n;
    while ((n = source.Poll(now_us, changes.data(), changes.size())) > 0) {
      for (size_t k = 0; k < n; ++k) {
        std::string error;
        if (!ApplyChange(engine, changes[k], &error)) {
          std::fprintf(stderr, "relight-render: error: %s at %.3f s: %s\n", script_path.c_str(),
                       static_cast<double>(changes[k].time_us) / 1e6, error.c_str());
          return 2;
        }
      }
    }
    char path[4096];
    std::snprintf(path, sizeof path, pattern.c_str(), i);
    if (int rc = render_to(path); rc != 0) return rc;
    if (!sheet.path.empty()) AddTile(sheet.frame_rgb, sheet.width, sheet.height, i, columns, &sheet_rgb);
    std::printf("%srelight-render: frame %d/%d (t = %.2f s) -> %s%s", tty ? "\r" : "", i + 1, frames,
                static_cast<double>(now_us) / 1e6, path, tty ? "" : "\n");
    std::fflush(stdout);
  }
  std::printf("%srelight-render: wrote %d frames from %s\n", tty ? "\n" : "", frames, script_path.c_str());
  if (!sheet.path.empty()) {
    if (Status st = WritePngRgb8(sheet.path, sheet_rgb.data(), sheet.width / 2 * columns, sheet.height / 2 * rows);
        !st.ok()) {
      std::fprintf(stderr, "relight-render: error: %s\n", st.ToString().c_str());
      return 1;
    }
    std::printf("relight-render: contact sheet %s\n", sheet.path.c_str());
  }
  return 0;
}

}  // namespace relight::cli
