#include "relight/hal/register_map.h"

#include <algorithm>

#include "relight/base/console_value.h"

namespace relight::hal {
namespace {

// Nearest integer of num / den for den > 0.
int64_t DivRound(int64_t num, int64_t den) {
  return num >= 0 ? (num + den / 2) / den : -((-num + den / 2) / den);
}

}  // namespace

int32_t AngleQ16FromRegister(uint16_t reg, int32_t range_q16) { return ConsoleToDegrees(reg, range_q16).raw(); }

uint16_t RegisterFromAngleQ16(int32_t deg_q16, int32_t range_q16) {
  return DegreesToConsole(Q16_16::FromRaw(deg_q16), range_q16);
}

int32_t LevelQ15FromRegister16(uint16_t reg) { return static_cast<int32_t>(DivRound(int64_t{reg} * 32767, 65535)); }

uint16_t Register16FromLevelQ15(int32_t level_q15) {
  const int32_t level = level_q15 < 0 ? 0 : level_q15 > 32767 ? 32767 : level_q15;
  return static_cast<uint16_t>(DivRound(int64_t{level} * 65535, 32767));
}

int32_t LevelQ15FromByte(uint16_t reg) {
  const int64_t v = reg > 255 ? 255 : reg;
  return static_cast<int32_t>(DivRound(v * 32767, 255));
}

uint16_t ByteFromLevelQ15(int32_t level_q15) {
  const int32_t level = level_q15 < 0 ? 0 : level_q15 > 32767 ? 32767 : level_q15;
  return static_cast<uint16_t>(DivRound(int64_t{level} * 255, 32767));
}

int32_t ZoomQ16FromRegister(uint16_t reg) { return static_cast<int32_t>(DivRound(int64_t{reg} * 65536, 100)); }

uint16_t RegisterFromZoomQ16(int32_t deg_q16) {
  const int64_t reg = DivRound(int64_t{deg_q16} * 100, 65536);
  return static_cast<uint16_t>(reg < 0 ? 0 : reg > kZoomRegisterMax ? kZoomRegisterMax : reg);
}

Status RegisterMap::Build(const std::vector<FixturePatch>& fixtures, RegisterMap* out) {
  RegisterMap map;
  map.fixtures_ = fixtures;
  int count = 0;
  for (const FixturePatch& f : fixtures) {
    const int end = f.modbus_base + f.layout.size();
    if (f.modbus_base < 0 || end > 65536) {
      return Status(StatusCode::kInvalidArgument, "register map: fixture '" + f.name + "' has no valid modbus_base");
    }
    if (f.pan_range_q16 <= 0 || f.tilt_range_q16 <= 0 || f.roll_range_q16 <= 0) {
      return Status(StatusCode::kInvalidArgument,
                    "register map: fixture '" + f.name + "' has no console ranges (resolve the patch first)");
    }
    count = end > count ? end : count;
  }
  if (fixtures.size() > 32767) return Status(StatusCode::kInvalidArgument, "register map: too many fixtures");
  map.owner_.assign(static_cast<size_t>(count), -1);
  for (size_t i = 0; i < fixtures.size(); ++i) {
    for (int k = 0; k < fixtures[i].layout.size(); ++k) {
      int16_t& owner = map.owner_[static_cast<size_t>(fixtures[i].modbus_base + k)];
      if (owner >= 0) {
        return Status(StatusCode::kInvalidArgument, "register map: fixtures '" + fixtures[owner].name + "' and '" +
                                                        fixtures[i].name + "' overlap");
      }
      owner = static_cast<int16_t>(i);
    }
  }
  *out = std::move(map);
  return Status::Ok();
}

int RegisterMap::FixtureAt(int addr, int* offset) const {
  if (addr < 0 || addr >= holding_count() || owner_[static_cast<size_t>(addr)] < 0) return -1;
  const int index = owner_[static_cast<size_t>(addr)];
  *offset = addr - fixtures_[static_cast<size_t>(index)].modbus_base;
  return index;
}

uint8_t RegisterMap::CheckWrite(int addr, uint16_t value) const {
  int offset = 0;
  const int fixture = FixtureAt(addr, &offset);
  if (fixture < 0) return kExceptionIllegalAddress;
  const RegisterLayout& layout = fixtures_[static_cast<size_t>(fixture)].layout;
  if (layout.IsByte(offset)) return value > 255 ? kExceptionIllegalValue : 0;
  switch (layout.at(offset)) {
    case Channel::kProfile: return value != 0 ? kExceptionIllegalValue : 0;
    case Channel::kFlags: return (value & ~kFlagOn) != 0 ? kExceptionIllegalValue : 0;
    case Channel::kZoom: return value > kZoomRegisterMax ? kExceptionIllegalValue : 0;
    default: return 0;  // dimmer and whole 16-bit angles: every value means something
  }
}

void RegisterMap::Encode(const FixtureState& state, int fixture, uint16_t* out) const {
  const FixturePatch& f = fixtures_[static_cast<size_t>(fixture)];
  const RegisterLayout& layout = f.layout;
  uint16_t block[kMaxRegistersPerFixture] = {};
  const auto put = [&](Channel c, uint16_t value) {
    if (layout.Has(c)) block[layout.OffsetOf(c)] = value;
  };
  const auto put_angle = [&](Channel c, Q16_16 deg, int32_t range_q16) {
    if (layout.Has(c)) layout.PutAngle16(c, DegreesToConsole(deg, range_q16), block);
  };
  put(Channel::kDimmer, Register16FromLevelQ15(state.dimmer.raw()));
  put_angle(Channel::kPan, state.pan_deg, f.pan_range_q16);
  put_angle(Channel::kTilt, state.tilt_deg, f.tilt_range_q16);
  put_angle(Channel::kRoll, state.roll_deg, f.roll_range_q16);
  put(Channel::kRed, ByteFromLevelQ15(state.rgb[0].raw()));
  put(Channel::kGreen, ByteFromLevelQ15(state.rgb[1].raw()));
  put(Channel::kBlue, ByteFromLevelQ15(state.rgb[2].raw()));
  put(Channel::kProfile, 0);
  put(Channel::kFlags, kFlagOn);
  put(Channel::kZoom, RegisterFromZoomQ16(state.zoom_deg.raw()));  // 0: the luminaire has no zoom
  std::copy(block, block + layout.size(), out);
}

size_t RegisterMap::DecodeChanges(int fixture, const uint16_t* before, const uint16_t* after, int64_t time_us,
                                  ParamChange out[kParamCount]) const {
  const FixturePatch& f = fixtures_[static_cast<size_t>(fixture)];
  const RegisterLayout& layout = f.layout;
  size_t n = 0;
  const uint16_t index = static_cast<uint16_t>(fixture);  // Build() keeps fixture_count() <= 32767
  const auto emit = [&](Param param, int32_t value) {
    out[n++] = IsAngle(param) ? ParamChange::Angle(time_us, index, param, Q16_16::FromRaw(value))
                              : ParamChange::Level(time_us, index, param, Q1_15::FromRaw(static_cast<int16_t>(value)));
  };
  const int dimmer_at = layout.OffsetOf(Channel::kDimmer), flags_at = layout.OffsetOf(Channel::kFlags);
  const auto dimmer = [&](const uint16_t* r) {
    const bool on = flags_at < 0 || (r[flags_at] & kFlagOn) != 0;
    return on ? LevelQ15FromRegister16(r[dimmer_at]) : 0;
  };
  if (dimmer_at >= 0 && dimmer(before) != dimmer(after)) emit(Param::kDimmer, dimmer(after));
  const auto angle = [&](Channel c, Param param, int32_t range_q16) {
    if (!layout.Has(c)) return;
    const uint16_t was = layout.Angle16(before, c), now = layout.Angle16(after, c);
    if (was != now) emit(param, AngleQ16FromRegister(now, range_q16));
  };
  angle(Channel::kPan, Param::kPan, f.pan_range_q16);
  angle(Channel::kTilt, Param::kTilt, f.tilt_range_q16);
  angle(Channel::kRoll, Param::kRoll, f.roll_range_q16);
  const Channel colours[3] = {Channel::kRed, Channel::kGreen, Channel::kBlue};
  const Param params[3] = {Param::kRed, Param::kGreen, Param::kBlue};
  for (int c = 0; c < 3; ++c) {
    const int at = layout.OffsetOf(colours[c]);
    if (at >= 0 && before[at] != after[at]) emit(params[c], LevelQ15FromByte(after[at]));
  }
  // A peer's value above 180 degrees (the poller) clamps like a byte does.
  const int zoom_at = layout.OffsetOf(Channel::kZoom);
  const auto zoom = [](uint16_t reg) { return reg > kZoomRegisterMax ? kZoomRegisterMax : reg; };
  if (zoom_at >= 0 && zoom(before[zoom_at]) != zoom(after[zoom_at])) {
    emit(Param::kZoom, ZoomQ16FromRegister(zoom(after[zoom_at])));
  }
  // An emitter's position and size: 16-bit levels, as the dimmer.
  const Channel places[3] = {Channel::kX, Channel::kY, Channel::kSize};
  const Param place_params[3] = {Param::kX, Param::kY, Param::kSize};
  for (int c = 0; c < 3; ++c) {
    const int at = layout.OffsetOf(places[c]);
    if (at >= 0 && before[at] != after[at]) emit(place_params[c], LevelQ15FromRegister16(after[at]));
  }
  return n;
}

}  // namespace relight::hal
