// How many frames `relight-render --replay` renders for a script: bounded
// before the loop starts, in 64-bit arithmetic, so a script time of 1e7 s or
// a high --fps is a clear error instead of tens of millions of frames (or an
// int overflow at --fps 240).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace relight::cli {

inline constexpr double kMaxReplayFps = 240.0;       // --fps range: 0.1 .. 240
inline constexpr double kMinReplayFps = 0.1;
inline constexpr int64_t kMaxReplayFrames = 100000;  // ~55 min at 30 fps

struct ReplayPlan {
  int64_t frame_us = 0;  // script time between frames
  int64_t frames = 0;    // frame 0 at t = 0 to the last change, inclusive
};

// False with *error set when fps is out of range or the script would need
// more than kMaxReplayFrames frames.
inline bool PlanReplayFrames(int64_t duration_us, double fps, ReplayPlan* plan,
                             std::string* error) {
  char fps_text[32];
  std::snprintf(fps_text, sizeof fps_text, "%g", fps);
  if (!(fps >= kMinReplayFps && fps <= kMaxReplayFps)) {
    *error = std::string("--fps must be in 0.1..240, got ") + fps_text;
    return false;
  }
  if (duration_us < 0) {
    *error = "the script's times must be 0 or more";
    return false;
  }
  plan->frame_us = std::llround(1e6 / fps);  // >= 4167 in range
  plan->frames = duration_us / plan->frame_us + 1;
  if (plan->frames > kMaxReplayFrames) {
    *error = "the script runs " + std::to_string(duration_us / 1000000) + " s: at " +
             fps_text + " fps that is " + std::to_string(plan->frames) +
             " frames, more than the limit of " + std::to_string(kMaxReplayFrames) +
             " (shorten the script or lower --fps)";
    return false;
  }
  return true;
}

}  // namespace relight::cli
