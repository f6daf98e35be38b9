// DMX over the network through OLA: relightd registers with olad (the Open
// Lighting Architecture daemon, which speaks E1.31/sACN, Art-Net and USB
// interfaces) for every universe of the DMX patch, and decodes each frame
// for the fixtures patched there (personality.h). docs/dmx.md shows how to
// start olad and point a console at it.
//
// One receive thread runs OLA's client and select loop; frames are decoded
// there into fixed per-fixture storage sized at construction (no heap per
// frame). OLA hands clients only null-start-code (level) data; the decoder
// would drop others too. If olad goes away the thread reconnects every
// reconnect_ms and the current look is kept meanwhile.
//
// Poll() yields the typed changes of what changed since the last poll
// (dmx_changes.h, shared with DmxReplaySource): fixtures are named by their
// index in the DMX patch, time_us is the arrival of the fixture's latest
// frame (CLOCK_MONOTONIC). LatestValues() gives what the DMX says.
//
// Thread safety: Start/Poll/Stop from one thread; LatestValues(),
// connected(), frames_received() from any.
#pragma once

#include <cstdint>
#include <memory>

#include "relight/hal/dmx/dmx_patch.h"
#include "relight/hal/input_source.h"

namespace relight::hal {

struct DmxOlaConfig {
  int reconnect_ms = 1000;             // between attempts while olad is away
  // Start() without olad: false = an error; true = a warning, and the
  // receive thread keeps trying (relightd: a console setup may start olad later).
  bool wait_for_olad = false;
};

class DmxOlaSource final : public InputSource {
 public:
  DmxOlaSource(DmxPatch patch, DmxOlaConfig config = {});
  ~DmxOlaSource() override;

  // The latest values of patch fixture `index` with the loss-of-signal
  // policy applied at now_us (MonotonicUs()). False if there is no such
  // fixture. Before any frame: DmxFixtureValues{} (dark, home, white).
  bool LatestValues(size_t index, int64_t now_us, DmxFixtureValues* out) const;
  // Connected to olad now.
  bool connected() const;
  // Frames received from olad, all universes.
  uint32_t frames_received() const;

 private:
  // Start: kIoError "olad is not running ..." if olad does
  // not answer on 127.0.0.1:9010 (unless config.wait_for_olad) (it is never auto-started: it must run as
  // its own user with its own config, docs/dmx.md); kInvalidArgument for an
  // empty patch.
  Status DoStart() override;
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) override;
  const char* DoName() const override { return "dmx-ola"; }
  void DoStop() override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
