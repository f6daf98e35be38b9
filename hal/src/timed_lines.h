// The line loop of hal's timed text formats (replay scripts, DMX
// recordings): lines numbered from 1, each at most `max_line_bytes` long,
// '#' starts a comment, every error "WHERE:LINE: why".
#pragma once

#include <cstddef>
#include <sstream>
#include <string>

#include "relight/base/status.h"

namespace relight::hal {

class TimedLines {
 public:
  TimedLines(const std::string& text, const std::string& where, size_t max_line_bytes)
      : lines_(text), where_(where), max_line_bytes_(max_line_bytes) {}

  // The next line, comment removed, as a word stream (it may have no words). False
  // at the end (*status ok) or for a line over the limit (*status says so).
  bool Next(std::istringstream* words, Status* status) {
    std::string line;
    while (std::getline(lines_, line)) {
      ++line_no_;
      if (line.size() > max_line_bytes_) {
        *status = Fail("line is " + std::to_string(line.size()) + " bytes, more than the limit of " +
                       std::to_string(max_line_bytes_));
        return false;
      }
      if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
      words->clear();
      words->str(line);
      return true;
    }
    *status = Status::Ok();
    return false;
  }

  // kInvalidArgument "WHERE:LINE: why" for the current line.
  Status Fail(const std::string& why) const {
    return Status(StatusCode::kInvalidArgument, where_ + ":" + std::to_string(line_no_) + ": " + why);
  }

 private:
  std::istringstream lines_;
  const std::string& where_;
  size_t max_line_bytes_;
  int line_no_ = 0;
};

}  // namespace relight::hal
