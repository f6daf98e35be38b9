// The engine's outputs as types: RGB light per receiver in LightQ12
// (fixed.h, 1 LSB = 1/4096), tagged with the quantity it measures, so a
// luminance buffer (cd/m^2, on vertices) cannot be handed to code that
// reads illuminance (lux, on calculation grids) or the other way round.
//
// A view borrows the engine's buffer: it stays valid until the engine is
// closed or reopened, and Update() rewrites the values in place.
#pragma once

#include <cstddef>
#include <cstdint>

#include "relight/base/fixed.h"

namespace relight {

enum class LightQuantity {
  kLuminance,    // cd/m^2
  kIlluminance,  // lux
};

template <LightQuantity Q>
class RgbLightView {
 public:
  static constexpr LightQuantity kQuantity = Q;
  static constexpr uint32_t kChannels = 3;

  constexpr RgbLightView() = default;
  // `q12`: kChannels values (r, g, b) per receiver.
  constexpr RgbLightView(const int32_t* q12, uint32_t receivers)
      : q12_(q12), receivers_(q12 != nullptr ? receivers : 0) {}

  constexpr uint32_t receivers() const { return receivers_; }
  constexpr bool empty() const { return receivers_ == 0; }
  // Channel 0, 1, 2 = r, g, b; no bounds check (the hot path reads these).
  constexpr LightQ12 at(uint32_t receiver, uint32_t channel) const {
    return LightQ12::FromRaw(q12_[static_cast<size_t>(receiver) * kChannels + channel]);
  }
  // The raw LightQ12 values, kChannels per receiver: for kernels that take
  // the buffer whole (tone mapping, hashing, comparing two results).
  constexpr const int32_t* raw() const { return q12_; }
  constexpr size_t raw_size() const { return static_cast<size_t>(receivers_) * kChannels; }
  constexpr const int32_t* begin() const { return q12_; }
  constexpr const int32_t* end() const { return q12_ + raw_size(); }

 private:
  const int32_t* q12_ = nullptr;
  uint32_t receivers_ = 0;
};

using LuminanceView = RgbLightView<LightQuantity::kLuminance>;
using IlluminanceView = RgbLightView<LightQuantity::kIlluminance>;

}  // namespace relight
