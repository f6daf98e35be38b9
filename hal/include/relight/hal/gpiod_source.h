// GPIO backend on libgpiod 1.6: buttons (fixture on/off, preset recall) and
// rotary encoders from the patch ([[gpio_button]], [[gpio_encoder]]).
// libgpiod delivers edge events with kernel timestamps; debounce and
// quadrature decoding are done in software (the same decoder the mock uses).
//
// A missing chip or line, or a line another program holds, is an error at
// Start() that names the chip, the line and the patch entry.
//
// Thread safety: one thread drives it (Poll reads events without blocking).
#pragma once

#include <memory>

#include "relight/hal/input_source.h"
#include "relight/hal/patch.h"

namespace relight::hal {

class GpiodSource final : public InputSource {
 public:
  explicit GpiodSource(const Patch& patch);  // uses patch.buttons and patch.encoders
  ~GpiodSource() override;

 private:
  // kNotFound: no such chip, or the chip has no such line; kIoError: the
  // line cannot be requested (busy, permissions).
  Status DoStart() override;
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) override;
  const char* DoName() const override { return "gpio"; }
  void DoStop() override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
