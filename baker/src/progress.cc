#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace relight::baker {
namespace {

constexpr auto kRedrawInterval = std::chrono::milliseconds(100);
constexpr int kBarWidth = 30;

}  // namespace

Progress::Progress(bool enabled) : drawing_(enabled && isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() { End(); }

void Progress::Begin(const std::string& stage, size_t total) {
  End();
  stage_ = stage;
  total_ = total;
  done_ = 0;
  start_ = std::chrono::steady_clock::now();
  last_draw_ = start_ - kRedrawInterval;
  Draw(0, true);
}

void Progress::Advance(size_t n) {
  const size_t done = done_ += n;
  if (!drawing_) return;
  Draw(done, false);
}

void Progress::End() {
  if (!drawing_ || !open_line_) return;
  Draw(total_, true);
  std::fputc('\n', stderr);
  std::fflush(stderr);
  open_line_ = false;
}

void Progress::Draw(size_t done, bool force) {
  if (!drawing_) return;
  std::unique_lock<std::mutex> lock(draw_mutex_, std::defer_lock);
  if (force) {
    lock.lock();
  } else if (!lock.try_lock()) {
    return;  // another thread is drawing; this update is not needed
  }
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < kRedrawInterval) return;
  last_draw_ = now;
  const double fraction =
      total_ == 0 ? 1.0 : static_cast<double>(std::min(done, total_)) / static_cast<double>(total_);
  const int filled = static_cast<int>(fraction * kBarWidth);
  char bar[kBarWidth + 1];
  for (int k = 0; k < kBarWidth; ++k) bar[k] = k < filled ? '#' : '.';
  bar[kBarWidth] = '\0';
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  char eta[32] = "  --:--";
  if (fraction > 0.01 && fraction < 1.0) {
    const long left = static_cast<long>(elapsed * (1.0 - fraction) / fraction + 0.5);
    std::snprintf(eta, sizeof eta, "%4ld:%02ld", left / 60, left % 60);
  } else if (fraction >= 1.0) {
    std::snprintf(eta, sizeof eta, "   done");
  }
  std::fprintf(stderr, "\r%-22s [%s] %3d%%  left %s ", stage_.c_str(), bar,
               static_cast<int>(fraction * 100.0), eta);
  std::fflush(stderr);
  open_line_ = true;
}

}  // namespace relight::baker
