// A progress bar on stderr for the long stages of a bake: stage name,
// percent and estimated time left, redrawn at most ten times a second, and
// only when asked for and stderr is a terminal (never in logs or pipes).
// Advance() is thread-safe; Begin()/End() are called from one thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace relight::baker {

class Progress {
 public:
  explicit Progress(bool enabled);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void Begin(const std::string& stage, size_t total);
  void Advance(size_t n = 1);
  void End();
  bool drawing() const { return drawing_; }

 private:
  void Draw(size_t done, bool force);

  bool drawing_;
  std::string stage_;
  size_t total_ = 0;
  std::atomic<size_t> done_{0};
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex draw_mutex_;
  bool open_line_ = false;
};

// Seconds since construction, for BakeReport timings.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace relight::baker
