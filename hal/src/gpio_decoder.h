// GPIO lines -> parameter changes, shared by the libgpiod backend and the
// mock: buttons with software debounce (libgpiod 1.6 has none) and rotary
// encoders decoded with a quadrature state table.
//
// Buttons: a level counts once it has been stable for debounce_ms; a press
// (the line going to its active level) toggles the fixture (first press on at
// on_level, next off) or recalls the preset. Encoders: every valid Gray-code
// step moves the parameter by +-step; invalid (skipped) steps are ignored;
// contact bounce cancels out (+1 -1). Angles stay in -720..720 degrees, a
// zoom (a beam angle, from the patch's start) in (0, 180), levels in 0..1.
//
// Thread safety: none.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "change_ring.h"
#include "relight/hal/param_text.h"
#include "relight/hal/patch.h"

namespace relight::hal {

struct GpioLineUse {
  std::string chip;
  int line = 0;
  std::string role;  // "gpio_button 1", "gpio_encoder 2 A", ... for messages
};

class GpioDecoder {
 public:
  // From a resolved patch: fixture names become indices into patch.fixtures
  // here, once (a name the patch lacks yields no changes).
  explicit GpioDecoder(const Patch& patch);

  // Every line used: button i is line i; encoder j's A and B follow the buttons.
  const std::vector<GpioLineUse>& lines() const { return lines_; }
  // Index in lines() of (chip, line), or -1.
  int Find(const std::string& chip, int line) const;
  // The level a line has when watching starts (no action).
  void SetInitial(int index, bool level);
  // Line `index` changed to `level` (raw, before active_low) at time_us.
  void OnEdge(int index, bool level, int64_t time_us, ChangeRing* out);
  // Settles debounced buttons up to now_us.
  void Tick(int64_t now_us, ChangeRing* out);

 private:
  struct Button {
    GpioButtonConfig config;
    int fixture = -1;                  // kToggle: index in the patch
    std::vector<ParamChange> preset;   // kPreset: resolved once
    bool raw = false, stable = false;  // levels as read (true = high)
    int64_t changed_us = 0;
    bool on = false;                   // kToggle state
  };
  struct Encoder {
    GpioEncoderConfig config;
    int fixture = -1;
    int state = 0;  // A << 1 | B
    int32_t value = 0;
  };
  void Settle(Button& b, int64_t now_us, ChangeRing* out);
  void Step(Encoder& e, int new_state, int64_t time_us, ChangeRing* out);

  std::vector<GpioLineUse> lines_;
  std::vector<Button> buttons_;
  std::vector<Encoder> encoders_;
};

}  // namespace relight::hal
