#include "replay_step.h"

#include <cstdio>

#include "set_args.h"

namespace relight::cli {

bool ApplyDueReplayChanges(hal::ReplaySource& source, const std::string& script_path, int64_t now_us,
                           Engine& engine, std::vector<ParamChange>* buffer, std::string* error) {
  size_t n;
  while ((n = source.Poll(now_us, buffer->data(), buffer->size())) > 0) {
    for (size_t k = 0; k < n; ++k) {
      std::string why;
      if (!ApplyChange(engine, (*buffer)[k], &why)) {
        char at[32];
        std::snprintf(at, sizeof at, "%.3f", static_cast<double>((*buffer)[k].time_us) / 1e6);
        *error = script_path + " at " + at + " s: " + why;
        return false;
      }
    }
  }
  return true;
}

}  // namespace relight::cli
