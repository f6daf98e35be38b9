// What each holding register of a fixture's block means, in order from its
// modbus_base, as a DMX personality lists a fixture's channels from its start
// address. Every unpatched fixture has the standard 8 (docs/modbus.md); a
// patch may give a fixture its own list (`registers = [...]`).
//
// Angles (pan, tilt, roll) are 16-bit console values, 32768 = 0 degrees:
//   "pan" alone          one register holds the whole value (coarse << 8 | fine)
//   "pan" + "pan_fine"   two registers, the coarse and the fine byte, 0..255 each
//
// Zoom is the full beam angle itself, in hundredths of a degree (2400 =
// 24 degrees, 0..18000), not a console value: a luminaire's zoom range is
// the bake's, and the engine clamps the angle to it.
//
// Thread safety: a value type, immutable once built.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace relight::hal {

enum class Channel : uint8_t {
  kDimmer, kPan, kPanFine, kTilt, kTiltFine, kRoll, kRollFine, kRed, kGreen, kBlue, kProfile, kFlags, kZoom,
  kX, kY, kSize,  // an emitter's position and size: 0..65535 = 0..1 of its declared ranges, as the dimmer
};
inline constexpr int kChannelCount = 16;
inline constexpr int kMaxRegistersPerFixture = kChannelCount;  // each channel at most once

const char* ChannelName(Channel channel);
// "dimmer", "pan", "pan_fine", ... -> Channel; false for anything else.
bool ChannelFromName(const std::string& name, Channel* out);
// "dimmer, pan, pan_fine, ..." for messages.
std::string ChannelNames();

class RegisterLayout {
 public:
  // The standard 8: dimmer, pan, tilt, red, green, blue, profile, flags.
  RegisterLayout();
  // `channels` in register order. False, with a message saying which entry
  // and why, for an empty list, a channel listed twice, a fine byte without
  // its coarse one, or flags without a dimmer (flags switch the dimmer).
  static bool FromChannels(const std::vector<Channel>& channels, RegisterLayout* out, std::string* error);

  int size() const { return size_; }
  Channel at(int offset) const { return channels_[offset]; }
  int OffsetOf(Channel channel) const { return offset_[static_cast<int>(channel)]; }  // -1: not in the layout
  bool Has(Channel channel) const { return OffsetOf(channel) >= 0; }
  // True for a register that carries a byte: red, green, blue and both
  // halves of a coarse/fine pair.
  bool IsByte(int offset) const;
  // The 16-bit value of angle channel `coarse` (kPan, kTilt or kRoll) from a
  // block of registers; bytes above 255 (a poller's peer) count as 255.
  uint16_t Angle16(const uint16_t* block, Channel coarse) const;
  // Writes a 16-bit angle value into the block's register(s) for `coarse`.
  void PutAngle16(Channel coarse, uint16_t value, uint16_t* block) const;
  bool operator==(const RegisterLayout& other) const;

 private:
  struct Empty {};
  explicit RegisterLayout(Empty);

  int size_ = 0;
  Channel channels_[kChannelCount] = {};
  int8_t offset_[kChannelCount] = {};
};

}  // namespace relight::hal
