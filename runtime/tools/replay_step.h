// One step of a replay in script time, shared by relight-render --replay and
// relight-replay-hash: every change of the script due by `now_us` reaches the
// engine through the control stage's binding (set_args.h ApplyChange).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/param.h"
#include "relight/engine/engine.h"
#include "relight/hal/replay_source.h"

namespace relight::cli {

// Polls `source` until nothing more is due at `now_us` (microseconds of
// script time) and applies each change; `buffer` is the poll batch (its
// size is the batch size, > 0). False on the first change the engine
// refuses, with *error = "SCRIPT at T s: fixture.param: why".
bool ApplyDueReplayChanges(hal::ReplaySource& source, const std::string& script_path, int64_t now_us,
                           Engine& engine, std::vector<ParamChange>* buffer, std::string* error);

}  // namespace relight::cli
