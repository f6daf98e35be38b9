// DMX universes -> per-fixture values -> parameter changes: the one core
// the OLA source and the DMX replay source share. Frames are decoded per
// fixture as they come (DecodeDmxFrame: 16-bit values only when both bytes
// are in the frame, short frames keep what they do not reach); Collect()
// then yields, per fixture, the parameters whose rendered value differs
// from the one last reported:
//   dimmer   Q1.15, 0 while the shutter is closed or (loss policy
//            "blackout") once no frame came for loss_timeout_ms
//   pan/tilt the 16-bit console value over the type's pan/tilt range
//            (ConsoleToDegrees; 540 / 270 degrees when the type gives none)
//   r, g, b  Q1.15 (CMY and wheels already mixed by the decoder)
//   zoom     the beam angle, Q16.16 degrees (types with a lens range only)
// Pan, tilt and colour only for types with channels for them (a fixed par
// keeps the bake's aim). A fixture's first decoded frame reports all of
// them; nothing is reported for a fixture no frame has reached. Changes name the
// fixture by its index in the DMX patch and carry the arrival time of its
// latest frame.
//
// Storage is sized at construction: no heap per frame or per Collect.
// Thread safety: OnFrame and Collect may run on different threads (the OLA
// receive thread and the daemon's); each takes the internal lock briefly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "relight/base/param.h"
#include "relight/hal/dmx/dmx_patch.h"

namespace relight::hal {

class DmxChanges {
 public:
  explicit DmxChanges(const DmxPatch& patch);

  // A level frame (start code 0) of `universe`: `count` data slots, slot 1
  // first. Fixtures of other universes are untouched.
  void OnFrame(unsigned universe, const uint8_t* slots, size_t count, int64_t arrival_us);
  // Changes since the last call, loss of signal judged at now_us (same clock
  // as arrival_us); at most capacity, the rest on the next call.
  size_t Collect(int64_t now_us, ParamChange* out, size_t capacity);
  // Patch fixture `index`'s values with the loss policy applied at now_us;
  // false for no such fixture. Before any frame: DmxFixtureValues{}.
  bool LatestValues(size_t index, int64_t now_us, DmxFixtureValues* out) const;

 private:
  struct Fixture {
    DmxFixtureValues values;      // decoded so far
    int64_t last_frame_us = 0;    // arrival of the latest frame that reached it
    bool received = false;        // a frame has reached it (script time 0 is a real time)
    bool reported = false;        // the first full report went out
    int32_t shown[kParamCount] = {};  // last reported raw value per Param
  };
  bool Lost(const Fixture& f, int64_t now_us) const;
  // What the loss-of-signal policy leaves of f's dimmer at now_us, Q15
  // (32768 = all of it; 0 = dark).
  int32_t LossDimmerScaleQ15(const Fixture& f, int64_t now_us) const;
  // Appends the parameters of `f` (values and last frame copied in) that
  // differ from what f.shown says was reported, and records them there.
  size_t Report(size_t index, int32_t dimmer_scale_q15, Fixture& f, ParamChange* out) const;

  const DmxPatch& patch_;
  mutable std::mutex mu_;
  std::vector<Fixture> fixtures_;   // guarded by mu_
  std::vector<Fixture> snapshot_;   // Collect's copy, outside the lock; its shown[] is what was reported
  std::vector<ParamChange> pending_;  // kParamCount per fixture
  size_t pending_count_ = 0, pending_next_ = 0;
};

}  // namespace relight::hal
