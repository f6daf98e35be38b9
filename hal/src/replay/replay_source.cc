#include "relight/hal/replay_source.h"

#include "../bounded_file.h"
#include "../timed_lines.h"
#include "relight/hal/param_text.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace relight::hal {

Status ParseReplayScript(const std::string& text, const std::string& where, const std::vector<std::string>& fixtures,
                         std::vector<ParamChange>* out) {
  std::vector<ParamChange> changes;
  TimedLines lines(text, where, kMaxReplayLineBytes);
  const auto fail = [&](const std::string& why) { return lines.Fail(why); };
  int64_t last_us = 0;
  std::istringstream words;
  Status status;
  while (lines.Next(&words, &status)) {
    std::string time_text;
    if (!(words >> time_text)) continue;  // blank or comment
    errno = 0;
    char* end = nullptr;
    const double seconds = std::strtod(time_text.c_str(), &end);
    if (errno != 0 || end != time_text.c_str() + time_text.size() || !std::isfinite(seconds) || seconds < 0 ||
        seconds > 1e7) {
      return fail("expected a time in seconds (0 or more) at the start of the line, got '" + time_text + "'");
    }
    const int64_t time_us = std::llround(seconds * 1e6);
    if (time_us < last_us) return fail("time " + time_text + " s goes backwards (times must not decrease)");
    last_us = time_us;
    std::string item;
    int items = 0;
    while (words >> item) {
      NamedChange parsed[3];
      std::string error;
      const int n = ParseParamText(item, time_us, parsed, &error);
      if (n == 0) return fail(error);
      const int index = FixtureIndex(fixtures, parsed[0].fixture);
      if (index < 0) return fail("no fixture '" + parsed[0].fixture + "' (there are: " + FixtureList(fixtures) + ")");
      for (int i = 0; i < n; ++i) {
        changes.push_back(parsed[i].change);
        changes.back().fixture = static_cast<uint16_t>(index);
      }
      ++items;
    }
    if (items == 0) return fail("a time needs at least one FIXTURE.PARAM=VALUE after it");
  }
  RELIGHT_RETURN_IF_ERROR(status);
  *out = std::move(changes);
  return Status::Ok();
}

Status ReplaySource::DoStart() {
  std::string text;
  RELIGHT_RETURN_IF_ERROR(ReadConfigFile(path_, "replay script", &text, kMaxReplayScriptBytes));
  next_ = 0;
  return ParseReplayScript(text, path_, fixtures_, &changes_);
}

size_t ReplaySource::DoPoll(int64_t now_us, ParamChange* out, size_t capacity) {
  size_t count = 0;
  while (next_ < changes_.size() && count < capacity && changes_[next_].time_us <= now_us) {
    out[count++] = changes_[next_++];
  }
  return count;
}

}  // namespace relight::hal
