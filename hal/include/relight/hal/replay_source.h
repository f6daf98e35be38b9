// Replay backend: a timed text script of parameter changes, the simulated
// hardware for demos, integration tests and integrators without a console.
//
//   # seconds  changes (FIXTURE.PARAM=VALUE, as --set)
//   0.0   ceiling_spot.pan=0  ceiling_spot.tilt=20
//   1.5   ceiling_spot.pan=35 corner_uplight.colour=1,0.55,0.25
//   2.0   ceiling_spot.roll=90   # degrees about the beam axis
//   3.0   panel.dimmer=1  panel.x=0.4  panel.size=0.5   # a patch [[emitter]]: x, y, size 0..1 of its ranges
//
// Times are seconds from the start of the script, non-decreasing. The whole
// script is read and checked at Start(), and its fixture names resolved to
// indices into the list the source was given; an error (a name the list
// lacks among them) names file:line.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "relight/hal/input_source.h"

namespace relight::hal {

class ReplaySource final : public InputSource {
 public:
  // Changes name fixtures by their index in `fixtures` (e.g. the bake's
  // luminaires, in order).
  ReplaySource(std::string path, std::vector<std::string> fixtures)
      : path_(std::move(path)), fixtures_(std::move(fixtures)) {}
  // Script time of the last change, microseconds (valid after Start()).
  int64_t duration_us() const { return changes_.empty() ? 0 : changes_.back().time_us; }

 private:
  Status DoStart() override;
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) override;
  bool DoFinished() const override { return next_ >= changes_.size(); }
  const char* DoName() const override { return "replay"; }
  SourceClock DoClock() const override { return SourceClock::kScript; }

  std::string path_;
  std::vector<std::string> fixtures_;
  std::vector<ParamChange> changes_;
  size_t next_ = 0;
};

// A script line longer than this is an error, not a megabyte of items to parse.
inline constexpr std::size_t kMaxReplayLineBytes = 4096;

// Parses script text (for tests and for Start()), resolving fixture names
// to indices in `fixtures`. `where` names the source in errors.
Status ParseReplayScript(const std::string& text, const std::string& where, const std::vector<std::string>& fixtures,
                         std::vector<ParamChange>* out);

}  // namespace relight::hal
