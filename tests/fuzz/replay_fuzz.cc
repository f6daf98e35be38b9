// Fuzz target: a replay script (ParseReplayScript, as the replay backend and
// relight-render --replay read one: times, then FIXTURE.PARAM=VALUE
// changes), then relight-render's frame plan for it at 2 and 240 fps
// (bounded, issue 17 item 3).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "relight/hal/replay_source.h"
#include "replay_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The living room's luminaires (the seeds' script names them) and two more.
  static const std::vector<std::string> kFixtures = {"ceiling_wide", "ceiling_spot", "corner_uplight", "a", "b"};
  std::vector<relight::ParamChange> changes;
  if (!relight::hal::ParseReplayScript(relight::fuzz::AsText(data, size), "fuzz.replay", kFixtures, &changes).ok()) {
    return 0;
  }
  const int64_t duration_us = changes.empty() ? 0 : changes.back().time_us;
  for (const double fps : {2.0, 240.0}) {
    relight::cli::ReplayPlan plan;
    std::string error;
    (void)relight::cli::PlanReplayFrames(duration_us, fps, &plan, &error);
  }
  return 0;
}
