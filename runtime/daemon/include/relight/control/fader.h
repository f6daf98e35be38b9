// Fixture parameters on their way to the engine: each new target (levels, and
// pan, tilt and roll in degrees) is reached by a linear ramp over the
// fixture's fade time (patch.h fade_ms), in integer microseconds; then the
// fixture's dimmer curve (linear or square law) maps
// the dimmer's control level to light output. Fixtures are slots, known by
// index: a change's `fixture` is the slot. Integer-only, no heap after
// construction, no name compared per change.
//
// Thread safety: none; the daemon's thread drives it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/fixture_state.h"
#include "relight/base/param.h"
#include "relight/hal/patch.h"

namespace relight::control {

// Q1.15 control level -> Q1.15 output level.
int32_t ApplyDimmerCurve(hal::DimmerCurve curve, int32_t level_q15);

class Fader {
 public:
  // One slot per fixture of a resolved patch, in the order given (the
  // daemon gives them in the engine's luminaire order: slot = luminaire).
  explicit Fader(const std::vector<hal::FixturePatch>& fixtures);

  int slot_count() const { return static_cast<int>(slots_.size()); }
  const std::string& slot_name(int slot) const { return slots_[static_cast<size_t>(slot)].patch.name; }
  // Starts slot `slot` at `state` without a ramp (its dimmer taken as the
  // control level). The next Step() reports all of its parameters.
  void Reset(int slot, const FixtureState& state);
  // The same from raw values in Param order (an emitter's levels). The next
  // Step() reports the parameters the slot has: an emitter's (IsEmitterParam)
  // or a luminaire's (the first kFixtureParamCount).
  void ResetValues(int slot, const int32_t values[kParamCount], bool emitter);
  // A new target for slot change.fixture; ramps from the value shown at
  // now_us. False if there is no such slot.
  bool SetTarget(const ParamChange& change, int64_t now_us);
  // Output values that changed since the last call (dimmer after the curve),
  // as typed changes whose `fixture` is the slot; at most kParamCount per
  // fixture. out must hold kParamCount * slot_count().
  size_t Step(int64_t now_us, ParamChange* out);
  // True when no ramp is still moving.
  bool Idle(int64_t now_us) const;
  // Takes over the ramps of the fixtures `old` also has (same name), so a
  // patch reload does not jump; the new fixture's fade time applies to the
  // next target. Reports every parameter the slot has on the next Step().
  void CopyRampsFrom(const Fader& old);

 private:
  // Values are the raw integers of the parameter's format (Q16.16 degrees
  // or Q1.15 level): a ramp between two values of one format stays in it.
  struct Ramp {
    int32_t from = 0, to = 0;
    int64_t start_us = 0, duration_us = 0;
    int32_t shown = 0;    // last value reported
    bool report = false;  // report on the next Step even if unchanged
  };
  struct Slot {
    hal::FixturePatch patch;
    Ramp ramps[kParamCount];  // indexed by Param
  };
  static int32_t ValueAt(const Ramp& ramp, int64_t now_us);

  std::vector<Slot> slots_;
};

}  // namespace relight::control
