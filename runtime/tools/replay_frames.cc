#include "replay_frames.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "relight/control/engine_binding.h"
#include "relight/hal/replay_source.h"
#include "relight/render/osmesa_frame.h"
#include "contact_sheet.h"
#include "replay_plan.h"
#include "replay_step.h"

namespace relight::cli {
namespace {

bool PatternHasOneNumber(const std::string& pattern) {
  const size_t pct = pattern.find('%');
  if (pct == std::string::npos || pattern.find('%', pct + 1) != std::string::npos) return false;
  const size_t d = pattern.find('d', pct);
  return d != std::string::npos && pattern.find_first_not_of("0123456789", pct + 1) == d;
}

}  // namespace

int RenderReplay(Engine& engine, const std::string& script_path, double fps, const std::string& pattern,
                 const std::function<int(const std::string&)>& render_to, const ContactSheet& sheet) {
  if (!PatternHasOneNumber(pattern)) {
    std::fprintf(stderr, "relight-render: error: with --replay, -o needs one %%d (e.g. frame_%%04d.png), got '%s'\n",
                 pattern.c_str());
    return 2;
  }
  hal::ReplaySource source(script_path, control::LuminaireNames(engine));
  if (Status st = source.Start(); !st.ok()) {
    std::fprintf(stderr, "relight-render: error: %s\n", st.ToString().c_str());
    return 2;
  }
  ReplayPlan plan;
  std::string plan_error;
  if (!PlanReplayFrames(source.duration_us(), fps, &plan, &plan_error)) {
    std::fprintf(stderr, "relight-render: error: %s: %s\n", script_path.c_str(), plan_error.c_str());
    return 2;
  }
  const int64_t frame_us = plan.frame_us;
  const int frames = static_cast<int>(plan.frames);  // <= kMaxReplayFrames
  std::vector<ParamChange> changes(256);
  ContactSheetBuilder sheet_builder(sheet.width, sheet.height);
  const bool tty = isatty(STDOUT_FILENO) != 0;
  for (int i = 0; i < frames; ++i) {
    const int64_t now_us = static_cast<int64_t>(i) * frame_us;
    if (std::string error; !ApplyDueReplayChanges(source, script_path, now_us, engine, &changes, &error)) {
      std::fprintf(stderr, "relight-render: error: %s\n", error.c_str());
      return 2;
    }
    char path[4096];
    std::snprintf(path, sizeof path, pattern.c_str(), i);
    if (int rc = render_to(path); rc != 0) return rc;
    if (!sheet.path.empty()) sheet_builder.Add(sheet.frame_rgb);
    std::printf("%srelight-render: frame %d/%d (t = %.2f s) -> %s%s", tty ? "\r" : "", i + 1, frames,
                static_cast<double>(now_us) / 1e6, path, tty ? "" : "\n");
    std::fflush(stdout);
  }
  std::printf("%srelight-render: wrote %d frames from %s\n", tty ? "\n" : "", frames, script_path.c_str());
  if (!sheet.path.empty()) {
    if (Status st = sheet_builder.Write(sheet.path); !st.ok()) {
      std::fprintf(stderr, "relight-render: error: %s\n", st.ToString().c_str());
      return 1;
    }
    std::printf("relight-render: contact sheet %s\n", sheet.path.c_str());
  }
  return 0;
}

}  // namespace relight::cli
