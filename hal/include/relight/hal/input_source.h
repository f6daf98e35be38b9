// The facade every input backend sits behind. A source yields timestamped
// parameter changes; the daemon or tool polls it once per control tick.
// Public non-virtual methods call private virtual Do...() ones (STYLE.md 3).
//
// Thread safety: one thread drives a source. Errors are Status values.
#pragma once

#include <cstddef>
#include <cstdint>

#include "relight/base/param.h"
#include "relight/base/status.h"

namespace relight::hal {

// The clock of a source's Poll(now_us) and of its changes' time_us.
enum class SourceClock : uint8_t {
  kScript,     // microseconds since the source's Start() (replay scripts)
  kMonotonic,  // CLOCK_MONOTONIC microseconds (hal::MonotonicUs()); time_us is
               // the change's arrival, which the daemon turns into latency
};

class InputSource {
 public:
  virtual ~InputSource() = default;

  // Opens files, devices or sockets. A missing device or a broken script is
  // an error here, at start-up, never later.
  Status Start() { return DoStart(); }
  // Moves the changes due at or before now_us (the source's clock) into
  // out[0..capacity) in time order; returns how many. Changes that do not fit
  // stay queued for the next call.
  size_t Poll(int64_t now_us, ParamChange* out, size_t capacity) { return DoPoll(now_us, out, capacity); }
  // True once a finite source (a replay script) has nothing more to give.
  bool Finished() const { return DoFinished(); }
  const char* Name() const { return DoName(); }
  SourceClock clock() const { return DoClock(); }
  // The daemon calls this after each frame is out: the frame number and the
  // arrival-to-frame latency of the newest live change it shows (0: none).
  // Modbus servers publish them as status registers; others ignore them.
  // Thread-safe with respect to the source's own threads.
  void OnFrameOut(uint32_t frame, uint32_t latency_us) { DoOnFrameOut(frame, latency_us); }
  // Stops the source's threads and closes its devices and sockets (the
  // destructor does too); Start() may be called again afterwards.
  void Stop() { DoStop(); }

 private:
  virtual Status DoStart() = 0;
  virtual size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) = 0;
  virtual bool DoFinished() const { return false; }
  virtual const char* DoName() const = 0;
  virtual SourceClock DoClock() const { return SourceClock::kMonotonic; }
  virtual void DoOnFrameOut(uint32_t /*frame*/, uint32_t /*latency_us*/) {}
  virtual void DoStop() {}
};

}  // namespace relight::hal
