// relightd's per-change path: changes polled from the inputs -> the fader
// -> the engine's typed setters. Everything is mapped and sized when it is
// built (Bind), so a change travels as {fixture index, parameter, typed
// value} with no name lookup, no string and no allocation (issue 11;
// tests/daemon/change_path_no_alloc_test.cc counts).
//
// Index spaces: an input's changes name fixtures by their index in the list
// that input was built from (the patch's fixtures for Modbus, GPIO and
// mocks; the DMX patch's for DMX; the slots' for replays, SlotNames()).
// Each BoundInput carries the table from that index to the fader slot, made
// once from names. The fader's slots are the engine's luminaires, then the
// patch's emitters (emitter_binding.h): an emitter's changes are gathered
// per frame and reach the engine as one call each (Apply).
//
// Thread safety: none; the daemon's thread drives it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "relight/base/param.h"
#include "relight/base/status.h"
#include "relight/control/emitter_binding.h"
#include "relight/control/fader.h"
#include "relight/engine/engine.h"
#include "relight/hal/input_source.h"
#include "relight/hal/patch.h"

namespace relight::control {

struct BoundInput {
  hal::InputSource* source = nullptr;
  // luminaire_of[i]: the engine luminaire of the source's fixture i; empty:
  // the source's indices are luminaire indices already.
  std::vector<uint16_t> luminaire_of;
};

class ChangePath {
 public:
  // Fader slots for every luminaire of `engine`, set up from the resolved
  // patch `fixtures` (which names each luminaire once) and started at the
  // engine's state, then one per entry of `emitters` (whose entries
  // `fixtures` lists last, as ResolvePatch appends them) started at its
  // patch levels; ramps running in `previous` (a patch reload) go on.
  // kNotFound for a patch fixture the bake lacks, naming it; the emitters'
  // errors (EmitterBinding::Bind) name `where`:line.
  Status Bind(Engine* engine, const std::vector<hal::FixturePatch>& fixtures, const ChangePath* previous,
              const std::vector<hal::EmitterPatch>& emitters = {}, const std::string& where = "patch");

  // The table for inputs built from the patch given to Bind.
  const std::vector<uint16_t>& patch_luminaires() const { return patch_luminaires_; }
  // Every slot's name, in slot order (the luminaires', then the emitters'):
  // what a replay script's names resolve against.
  std::vector<std::string> SlotNames() const;
  const EmitterBinding& emitters() const { return emitters_; }

  // Drains `input` (its Poll at source time `source_now_us`) into the fader
  // at daemon time `time_us`. Returns the newest time_us among its changes
  // (the arrival, for live sources; 0: none). Changes naming no fixture of
  // the input's table are dropped and counted.
  int64_t Poll(const BoundInput& input, int64_t source_now_us, int64_t time_us);
  // Hands what the fader moved at `time_us` to the engine (the emitters'
  // changes coalesced: one engine call per emitter); returns how many
  // parameters changed.
  size_t Apply(int64_t time_us);
  bool Idle(int64_t time_us) const { return fader_->Idle(time_us); }

  int64_t dropped() const { return dropped_; }          // changes naming an unknown fixture
  int64_t rejected() const { return rejected_; }        // the engine refused (e.g. zoom before SetZoom)

 private:
  Engine* engine_ = nullptr;
  std::unique_ptr<Fader> fader_;
  std::vector<uint16_t> patch_luminaires_;
  EmitterBinding emitters_;
  std::vector<ParamChange> batch_;    // one Poll's worth
  std::vector<ParamChange> outputs_;  // kParamCount per slot
  int64_t dropped_ = 0, rejected_ = 0;
};

}  // namespace relight::control
