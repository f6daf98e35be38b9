#include "relight/hal/register_map.h"

#include <cstring>

namespace relight::hal {
namespace {

// Nearest integer of num / den for den > 0.
int64_t DivRound(int64_t num, int64_t den) {
  return num >= 0 ? (num + den / 2) / den : -((-num + den / 2) / den);
}

}  // namespace

int32_t AngleQ16FromRegister(uint16_t reg, int32_t range_q16) {
  // (reg - 32768) / 65536 of the range: |product| < 2^15 * 2^27, fits int64.
  return static_cast<int32_t>(DivRound((static_cast<int64_t>(reg) - 32768) * range_q16, 65536));
}

uint16_t RegisterFromAngleQ16(int32_t deg_q16, int32_t range_q16) {
  const int64_t reg = 32768 + DivRound(static_cast<int64_t>(deg_q16) * 65536, range_q16);
  return static_cast<uint16_t>(reg < 0 ? 0 : reg > 65535 ? 65535 : reg);
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

int32_t ParamValueFromRegister(const FixturePatch& fixture, Param param, uint16_t reg) {
  switch (param) {
    case Param::kPan: return AngleQ16FromRegister(reg, fixture.pan_range_q16);
    case Param::kTilt: return AngleQ16FromRegister(reg, fixture.tilt_range_q16);
    case Param::kDimmer: return LevelQ15FromRegister16(reg);
    case Param::kRed:
    case Param::kGreen:
    case Param::kBlue: return LevelQ15FromByte(reg);
  }
  return 0;
}

Status RegisterMap::Build(const std::vector<FixturePatch>& fixtures, RegisterMap* out) {
  RegisterMap map;
  map.fixtures_ = fixtures;
  int count = 0;
  for (const FixturePatch& f : fixtures) {
    if (f.modbus_base < 0 || f.modbus_base + kRegistersPerFixture > 65536) {
      return Status(StatusCode::kInvalidArgument, "register map: fixture '" + f.name + "' has no valid modbus_base");
    }
    count = f.modbus_base + kRegistersPerFixture > count ? f.modbus_base + kRegistersPerFixture : count;
  }
  if (fixtures.size() > 32767) return Status(StatusCode::kInvalidArgument, "register map: too many fixtures");
  map.owner_.assign(static_cast<size_t>(count), -1);
  for (size_t i = 0; i < fixtures.size(); ++i) {
    for (int k = 0; k < kRegistersPerFixture; ++k) {
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
  if (FixtureAt(addr, &offset) < 0) return kExceptionIllegalAddress;
  switch (offset) {
    case kRegRed:
    case kRegGreen:
    case kRegBlue: return value > 255 ? kExceptionIllegalValue : 0;
    case kRegProfile: return value != 0 ? kExceptionIllegalValue : 0;
    case kRegFlags: return (value & ~kFlagOn) != 0 ? kExceptionIllegalValue : 0;
    default: return 0;  // dimmer, pan, tilt: every 16-bit value means something
  }
}

void RegisterMap::Encode(const FixtureState& state, int fixture, uint16_t out[kRegistersPerFixture]) const {
  const FixturePatch& f = fixtures_[static_cast<size_t>(fixture)];
  out[kRegDimmer] = Register16FromLevelQ15(state.dimmer.raw());
  out[kRegPan] = RegisterFromAngleQ16(state.pan_deg.raw(), f.pan_range_q16);
  out[kRegTilt] = RegisterFromAngleQ16(state.tilt_deg.raw(), f.tilt_range_q16);
  for (int c = 0; c < 3; ++c) out[kRegRed + c] = ByteFromLevelQ15(state.rgb[c].raw());
  out[kRegProfile] = 0;
  out[kRegFlags] = kFlagOn;
}

size_t RegisterMap::DecodeChanges(int fixture, const uint16_t before[kRegistersPerFixture],
                                  const uint16_t after[kRegistersPerFixture], int64_t time_us,
                                  ParamChange out[6]) const {
  const FixturePatch& f = fixtures_[static_cast<size_t>(fixture)];
  size_t n = 0;
  const auto emit = [&](Param param, int32_t value) {
    ParamChange& c = out[n++];
    c = ParamChange();
    c.time_us = time_us;
    const size_t len = f.name.size() < kMaxFixtureName ? f.name.size() : kMaxFixtureName;
    std::memcpy(c.fixture, f.name.data(), len);
    c.fixture[len] = '\0';
    c.param = param;
    c.value = value;
  };
  const auto dimmer = [](const uint16_t* r) { return (r[kRegFlags] & kFlagOn) ? LevelQ15FromRegister16(r[kRegDimmer]) : 0; };
  if (dimmer(before) != dimmer(after)) emit(Param::kDimmer, dimmer(after));
  if (before[kRegPan] != after[kRegPan]) emit(Param::kPan, AngleQ16FromRegister(after[kRegPan], f.pan_range_q16));
  if (before[kRegTilt] != after[kRegTilt]) emit(Param::kTilt, AngleQ16FromRegister(after[kRegTilt], f.tilt_range_q16));
  const Param colours[3] = {Param::kRed, Param::kGreen, Param::kBlue};
  for (int c = 0; c < 3; ++c) {
    if (before[kRegRed + c] != after[kRegRed + c]) emit(colours[c], LevelQ15FromByte(after[kRegRed + c]));
  }
  return n;
}

}  // namespace relight::hal
