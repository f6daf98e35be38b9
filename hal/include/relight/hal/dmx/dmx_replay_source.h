// DMX replay: a recorded console show as timestamped DMX frames, played
// through the same decoder and change logic as live DMX (dmx_changes.h), no
// olad needed. The format (fixtures/stage.dmxrec is one):
//
//   # comments start with '#'
//   <time_us> <universe> <slot>=<hex bytes>[ <slot>=<hex bytes> ...]
//   0      1 1=ff8000 10=00
//   22727  1 2=81
//
// One frame per line. Slots are 1-based; each hex run sets consecutive
// slots from its slot on. Slots a line does not list keep their value from
// the previous frame of that universe (all 0 at the start); a frame is as
// long as the highest slot set so far in its universe. Times are script
// microseconds and must not decrease. Universes the DMX patch does not use
// are read and ignored. The whole file is read and checked at Start();
// every error names file:line.
//
// Changes name fixtures by their index in the DMX patch; time_us is the
// frame's script time. Thread safety: one thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "relight/hal/dmx/dmx_patch.h"
#include "relight/hal/input_source.h"

namespace relight::hal {

// One parsed frame: its runs are runs[first_run .. first_run + run_count).
struct DmxReplayRun {
  uint16_t slot = 1;         // 1-based first slot
  uint16_t count = 0;
  uint32_t offset = 0;       // into DmxRecording::bytes
};
struct DmxReplayFrame {
  int64_t time_us = 0;
  unsigned universe = 0;
  uint32_t first_run = 0, run_count = 0;
};
struct DmxRecording {
  std::vector<DmxReplayFrame> frames;
  std::vector<DmxReplayRun> runs;
  std::vector<uint8_t> bytes;
};

inline constexpr size_t kMaxDmxReplayLineBytes = 16384;  // a full universe in hex is ~1 KiB

// Parses recording text; `where` names it in errors ("where:line: what").
Status ParseDmxRecording(const std::string& text, const std::string& where, DmxRecording* out);

class DmxReplaySource final : public InputSource {
 public:
  DmxReplaySource(DmxPatch patch, std::string path);
  ~DmxReplaySource() override;
  // Script time of the last frame (valid after Start()).
  int64_t duration_us() const;

 private:
  Status DoStart() override;
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) override;
  bool DoFinished() const override;
  const char* DoName() const override { return "dmx-replay"; }
  SourceClock DoClock() const override { return SourceClock::kScript; }

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
