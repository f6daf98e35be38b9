#include "relight/hal/register_layout.h"

namespace relight::hal {
namespace {

constexpr const char* kNames[kChannelCount] = {"dimmer", "pan",  "pan_fine", "tilt",  "tilt_fine", "roll",
                                               "roll_fine", "r", "g",        "b",     "profile",   "flags",
                                               "zoom",   "x",         "y", "size"};

// The fine byte that goes with an angle's coarse one, or the coarse one itself
// for a channel that is no angle.
Channel FineOf(Channel coarse) {
  switch (coarse) {
    case Channel::kPan: return Channel::kPanFine;
    case Channel::kTilt: return Channel::kTiltFine;
    case Channel::kRoll: return Channel::kRollFine;
    default: return coarse;
  }
}

bool IsFine(Channel c) { return c == Channel::kPanFine || c == Channel::kTiltFine || c == Channel::kRollFine; }

Channel CoarseOf(Channel fine) {
  return fine == Channel::kPanFine ? Channel::kPan : fine == Channel::kTiltFine ? Channel::kTilt : Channel::kRoll;
}

uint16_t Byte(uint16_t reg) { return reg > 255 ? 255 : reg; }

}  // namespace

const char* ChannelName(Channel channel) { return kNames[static_cast<int>(channel)]; }

bool ChannelFromName(const std::string& name, Channel* out) {
  for (int c = 0; c < kChannelCount; ++c) {
    if (name == kNames[c]) {
      *out = static_cast<Channel>(c);
      return true;
    }
  }
  return false;
}

std::string ChannelNames() {
  std::string list;
  for (const char* name : kNames) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

RegisterLayout::RegisterLayout(Empty) {
  for (int8_t& o : offset_) o = -1;
}

RegisterLayout::RegisterLayout() : RegisterLayout(Empty{}) {
  const bool ok = FromChannels({Channel::kDimmer, Channel::kPan, Channel::kTilt, Channel::kRed, Channel::kGreen,
                                Channel::kBlue, Channel::kProfile, Channel::kFlags},
                               this, nullptr);
  (void)ok;  // the standard list is valid
}

bool RegisterLayout::FromChannels(const std::vector<Channel>& channels, RegisterLayout* out, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error != nullptr) *error = why;
    return false;
  };
  if (channels.empty()) return fail("needs at least one channel");
  RegisterLayout layout{Empty{}};
  layout.size_ = static_cast<int>(channels.size());
  // More than kChannelCount entries repeat one: caught before channels_ overflows.
  for (int i = 0; i < layout.size_; ++i) {
    const Channel c = channels[static_cast<size_t>(i)];
    int8_t& offset = layout.offset_[static_cast<int>(c)];
    if (offset >= 0) {
      return fail(std::string("'") + ChannelName(c) + "' is listed twice (+" + std::to_string(offset) + " and +" +
                  std::to_string(i) + "); each channel owns one register");
    }
    offset = static_cast<int8_t>(i);
    layout.channels_[i] = c;
  }
  for (int i = 0; i < layout.size_; ++i) {
    const Channel c = layout.channels_[i];
    if (IsFine(c) && !layout.Has(CoarseOf(c))) {
      return fail(std::string("'") + ChannelName(c) + "' (+" + std::to_string(i) + ") needs '" +
                  ChannelName(CoarseOf(c)) + "', its coarse byte, in the same list");
    }
  }
  if (layout.Has(Channel::kFlags) && !layout.Has(Channel::kDimmer)) {
    return fail("'flags' switches the dimmer on and off; it needs 'dimmer' in the same list");
  }
  *out = layout;
  return true;
}

bool RegisterLayout::IsByte(int offset) const {
  const Channel c = channels_[offset];
  if (c == Channel::kRed || c == Channel::kGreen || c == Channel::kBlue || IsFine(c)) return true;
  return FineOf(c) != c && Has(FineOf(c));  // the coarse half of a pair
}

uint16_t RegisterLayout::Angle16(const uint16_t* block, Channel coarse) const {
  const uint16_t first = block[OffsetOf(coarse)];
  if (!Has(FineOf(coarse))) return first;
  return static_cast<uint16_t>(Byte(first) << 8 | Byte(block[OffsetOf(FineOf(coarse))]));
}

void RegisterLayout::PutAngle16(Channel coarse, uint16_t value, uint16_t* block) const {
  if (!Has(FineOf(coarse))) {
    block[OffsetOf(coarse)] = value;
    return;
  }
  block[OffsetOf(coarse)] = static_cast<uint16_t>(value >> 8);
  block[OffsetOf(FineOf(coarse))] = static_cast<uint16_t>(value & 0xFF);
}

bool RegisterLayout::operator==(const RegisterLayout& other) const {
  if (size_ != other.size_) return false;
  for (int i = 0; i < size_; ++i) {
    if (channels_[i] != other.channels_[i]) return false;
  }
  return true;
}

}  // namespace relight::hal
