#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "hal_test_support.h"
#include "modbus/request_check.h"
#include "register_input.h"
#include "relight/hal/register_layout.h"
#include "relight/hal/register_map.h"

namespace relight::hal {
namespace {

using testing::LayoutPatch;
using testing::MapOf;
using testing::RestRegisters;
using testing::TwoFixturePatch;

TEST(RegisterValues, AnglesMatchAFloatReferenceToHalfAnLsb) {
  for (const int32_t range_deg : {540, 360, 270, 180}) {
    for (int reg = 0; reg <= 65535; reg += 7) {
      const double ref_deg = (reg - 32768.0) / 65536.0 * range_deg;
      const int32_t q = AngleQ16FromRegister(static_cast<uint16_t>(reg), range_deg << 16);
      EXPECT_LE(std::fabs(q - ref_deg * 65536.0), 0.5) << reg << " over " << range_deg;
    }
  }
  EXPECT_EQ(AngleQ16FromRegister(32768, 540 << 16), 0);      // centre = 0 degrees
  EXPECT_EQ(AngleQ16FromRegister(0, 540 << 16), -(270 << 16));  // one end = -range / 2
}

TEST(RegisterValues, AngleEncodeDecodeRoundTripsEveryRegister) {
  for (int reg = 0; reg <= 65535; ++reg) {
    const int32_t deg = AngleQ16FromRegister(static_cast<uint16_t>(reg), 540 << 16);
    EXPECT_EQ(RegisterFromAngleQ16(deg, 540 << 16), reg);
  }
  EXPECT_EQ(RegisterFromAngleQ16(400 << 16, 540 << 16), 65535);  // beyond the range: clamped
  EXPECT_EQ(RegisterFromAngleQ16(-(400 << 16), 540 << 16), 0);
}

TEST(RegisterValues, LevelsRoundToNearestAndRoundTrip) {
  EXPECT_EQ(LevelQ15FromRegister16(0), 0);
  EXPECT_EQ(LevelQ15FromRegister16(65535), 32767);
  EXPECT_EQ(LevelQ15FromByte(255), 32767);
  EXPECT_EQ(LevelQ15FromByte(128), 16448);  // 128/255 * 32767 = 16447.9
  for (int reg = 0; reg <= 65535; reg += 3) {
    EXPECT_LE(std::fabs(LevelQ15FromRegister16(static_cast<uint16_t>(reg)) - reg * 32767.0 / 65535.0), 0.5);
  }
  // The 16-bit grid is finer than Q1.15: level -> register -> level is exact.
  for (int level = 0; level <= 32767; ++level) {
    EXPECT_EQ(LevelQ15FromRegister16(Register16FromLevelQ15(level)), level);
  }
  for (int b = 0; b <= 255; ++b) EXPECT_EQ(ByteFromLevelQ15(LevelQ15FromByte(static_cast<uint16_t>(b))), b);
}

TEST(RegisterMap, ChecksAddressesAndValues) {
  const RegisterMap map = MapOf(TwoFixturePatch());
  EXPECT_EQ(map.holding_count(), 16);
  EXPECT_EQ(map.CheckWrite(0, 65535), 0);    // dimmer: any value
  EXPECT_EQ(map.CheckWrite(9, 0), 0);        // wash pan
  EXPECT_EQ(map.CheckWrite(3, 255), 0);      // red
  EXPECT_EQ(map.CheckWrite(3, 256), kExceptionIllegalValue);
  EXPECT_EQ(map.CheckWrite(13, 1000), kExceptionIllegalValue);  // wash blue
  EXPECT_EQ(map.CheckWrite(6, 1), kExceptionIllegalValue);      // profile: only 0
  EXPECT_EQ(map.CheckWrite(7, 1), 0);                           // flags: on
  EXPECT_EQ(map.CheckWrite(7, 2), kExceptionIllegalValue);      // reserved bit
  EXPECT_EQ(map.CheckWrite(16, 0), kExceptionIllegalAddress);
  EXPECT_EQ(map.CheckWrite(-1, 0), kExceptionIllegalAddress);
}

TEST(RegisterMap, DecodesOnlyWhatChangedAndHonoursTheOnFlag) {
  const RegisterMap map = MapOf(TwoFixturePatch());
  std::vector<uint16_t> before = RestRegisters(map), after = before;
  after[8 + kRegPan] = 32768 + 16384;  // wash pan: a quarter of 360 degrees
  after[8 + kRegDimmer] = 65535;
  ParamChange out[kParamCount];
  size_t n = map.DecodeChanges(1, &before[8], &after[8], 42, out);
  ASSERT_EQ(n, 2u);
  EXPECT_EQ(out[0].fixture, testing::FixtureIndexOf("wash"));
  EXPECT_EQ(out[0].param, Param::kDimmer);
  EXPECT_EQ(testing::Raw(out[0]), 32767);
  EXPECT_EQ(out[1].param, Param::kPan);
  EXPECT_EQ(testing::Raw(out[1]), 90 << 16);
  EXPECT_EQ(out[1].time_us, 42);
  // Off: the dimmer output goes to 0 whatever the dimmer register holds.
  before = after;
  after[8 + kRegFlags] = 0;
  n = map.DecodeChanges(1, &before[8], &after[8], 0, out);
  ASSERT_EQ(n, 1u);
  EXPECT_EQ(out[0].param, Param::kDimmer);
  EXPECT_EQ(testing::Raw(out[0]), 0);
  // Dimmer moved while off: nothing to show.
  before = after;
  after[8 + kRegDimmer] = 100;
  EXPECT_EQ(map.DecodeChanges(1, &before[8], &after[8], 0, out), 0u);
}

TEST(RegisterLayout, StandardIsTheDocumentedEight) {
  const RegisterLayout standard;
  ASSERT_EQ(standard.size(), kRegistersPerFixture);
  EXPECT_EQ(standard.OffsetOf(Channel::kDimmer), kRegDimmer);
  EXPECT_EQ(standard.OffsetOf(Channel::kPan), kRegPan);
  EXPECT_EQ(standard.OffsetOf(Channel::kTilt), kRegTilt);
  EXPECT_EQ(standard.OffsetOf(Channel::kRed), kRegRed);
  EXPECT_EQ(standard.OffsetOf(Channel::kBlue), kRegBlue);
  EXPECT_EQ(standard.OffsetOf(Channel::kProfile), kRegProfile);
  EXPECT_EQ(standard.OffsetOf(Channel::kFlags), kRegFlags);
  EXPECT_FALSE(standard.Has(Channel::kRoll));
  EXPECT_FALSE(standard.IsByte(kRegPan));  // 16-bit pan in one register
  EXPECT_TRUE(standard.IsByte(kRegRed));
}

TEST(RegisterLayout, RejectsBadListsSayingWhich) {
  struct Case {
    std::vector<Channel> channels;
    const char* says;
  };
  const Case cases[] = {
      {{}, "at least one"},
      {{Channel::kDimmer, Channel::kPanFine}, "'pan_fine' (+1) needs 'pan'"},
      {{Channel::kTilt, Channel::kRollFine}, "'roll_fine' (+1) needs 'roll'"},
      {{Channel::kPan, Channel::kTilt, Channel::kPan}, "'pan' is listed twice (+0 and +2)"},
      {{Channel::kFlags, Channel::kPan}, "needs 'dimmer'"},
  };
  for (const Case& c : cases) {
    RegisterLayout layout;
    std::string error;
    EXPECT_FALSE(RegisterLayout::FromChannels(c.channels, &layout, &error)) << c.says;
    EXPECT_NE(error.find(c.says), std::string::npos) << error;
  }
  Channel ch = Channel::kDimmer;
  for (const char* name : {"dimmer", "pan", "pan_fine", "tilt", "tilt_fine", "roll", "roll_fine", "r", "g", "b",
                           "profile", "flags", "zoom"}) {
    ASSERT_TRUE(ChannelFromName(name, &ch)) << name;
    EXPECT_STREQ(ChannelName(ch), name);
  }
  EXPECT_FALSE(ChannelFromName("iris", &ch));
}

TEST(RegisterLayout, CoarseAndFineBytesMakeThe16BitValue) {
  RegisterLayout layout;
  std::string error;
  ASSERT_TRUE(RegisterLayout::FromChannels({Channel::kPanFine, Channel::kRoll, Channel::kPan}, &layout, &error))
      << error;
  uint16_t block[3] = {};
  for (int v = 0; v <= 65535; v += 257 + 3) {
    layout.PutAngle16(Channel::kPan, static_cast<uint16_t>(v), block);
    EXPECT_EQ(block[2], v >> 8);    // coarse
    EXPECT_EQ(block[0], v & 0xFF);  // fine
    EXPECT_EQ(layout.Angle16(block, Channel::kPan), v);
  }
  layout.PutAngle16(Channel::kRoll, 40000, block);  // roll alone: one 16-bit register
  EXPECT_EQ(block[1], 40000);
  EXPECT_EQ(layout.Angle16(block, Channel::kRoll), 40000);
  EXPECT_TRUE(layout.IsByte(0));
  EXPECT_TRUE(layout.IsByte(2));
  EXPECT_FALSE(layout.IsByte(1));
  // A poller's peer may hold more than a byte: it counts as 255.
  const uint16_t wide[3] = {300, 0, 1000};
  EXPECT_EQ(layout.Angle16(wide, Channel::kPan), 0xFFFF);
}

TEST(RegisterMap, ALayoutWithRollAndFineBytesChecksEncodesAndDecodes) {
  const RegisterMap map = MapOf(LayoutPatch());
  EXPECT_EQ(map.holding_count(), 18);
  EXPECT_EQ(map.CheckWrite(1, 255), 0);                       // pan coarse
  EXPECT_EQ(map.CheckWrite(1, 256), kExceptionIllegalValue);  // a byte, not a 16-bit value
  EXPECT_EQ(map.CheckWrite(2, 256), kExceptionIllegalValue);  // pan fine
  EXPECT_EQ(map.CheckWrite(5, 65535), 0);                     // roll: 16-bit
  EXPECT_EQ(map.CheckWrite(9, 2), kExceptionIllegalValue);    // flags
  EXPECT_EQ(map.CheckWrite(10 + kRegPan, 65535), 0);          // wash: the standard block
  EXPECT_EQ(map.CheckWrite(18, 0), kExceptionIllegalAddress);

  // Encode shows a state; decoding a change from it gives the same degrees
  // as the 16-bit value over the ranges (pan 630, tilt 265 from the bake).
  FixtureState state{};
  state.pan_deg = Q16_16::FromRaw(-(100 << 16) - 1234);
  state.tilt_deg = Q16_16::FromInt(30);
  state.roll_deg = Q16_16::FromInt(-90);
  state.dimmer = Q1_15::FromRaw(32767);
  uint16_t before[10] = {}, after[10] = {};
  map.Encode(state, 0, before);
  const uint16_t pan16 = RegisterFromAngleQ16(state.pan_deg.raw(), 630 << 16);
  EXPECT_EQ(before[1], pan16 >> 8);
  EXPECT_EQ(before[2], pan16 & 0xFF);
  EXPECT_EQ(before[5], 32768 - 16384);  // -90 of 360
  EXPECT_EQ(before[9], kFlagOn);
  std::copy(before, before + 10, after);
  after[2] ^= 1;  // only the pan's fine byte moves
  after[5] = 32768 + 8192;
  ParamChange out[kParamCount];
  size_t n = map.DecodeChanges(0, before, after, 7, out);
  ASSERT_EQ(n, 2u);
  EXPECT_EQ(out[0].param, Param::kPan);
  EXPECT_EQ(testing::Raw(out[0]), AngleQ16FromRegister(static_cast<uint16_t>(pan16 ^ 1), 630 << 16));
  // One console step is 630/65536 degrees = 630 Q16.16 LSBs: Encode picks
  // the nearest value (within half a step), the fine byte moves one step.
  const int32_t shown_pan = AngleQ16FromRegister(pan16, 630 << 16);
  EXPECT_LE(std::abs(shown_pan - state.pan_deg.raw()), 315 + 1);
  EXPECT_NEAR(std::abs(testing::Raw(out[0]) - shown_pan), 630, 1);
  EXPECT_EQ(out[1].param, Param::kRoll);
  EXPECT_EQ(testing::Raw(out[1]), 45 << 16);
  // Every parameter moving: dimmer, pan, tilt, roll, r, g, b, in that order.
  const uint16_t all[10] = {100, 1, 2, 3, 4, 5, 6, 7, 8, 1};
  n = map.DecodeChanges(0, before, all, 0, out);
  constexpr int kRegisterParams = kFixtureParamCount - 1;  // every fixture parameter but zoom, which this layout lacks
  ASSERT_EQ(n, static_cast<size_t>(kRegisterParams));
  const Param order[kRegisterParams] = {Param::kDimmer, Param::kPan, Param::kTilt, Param::kRoll,
                                    Param::kRed,    Param::kGreen, Param::kBlue};
  for (int i = 0; i < kRegisterParams; ++i) EXPECT_EQ(out[i].param, order[i]) << i;
  EXPECT_EQ(testing::Raw(out[1]), AngleQ16FromRegister(0x0102, 630 << 16));
  EXPECT_EQ(testing::Raw(out[2]), AngleQ16FromRegister(0x0304, 265 << 16));
}

TEST(RegisterInput, CoalescesToTheNewestValues) {
  const RegisterMap map = MapOf(TwoFixturePatch());
  RegisterInput input(map, RestRegisters(map));
  ParamChange out[16];
  EXPECT_EQ(input.Collect(out, 16), 0u);  // the initial image is not a change
  for (uint16_t v = 1; v <= 100; ++v) input.Write(kRegRed, 1, &v, v);  // 100 writes, out of range clamps later
  const uint16_t tilt = 0;
  input.Write(10, 1, &tilt, 500);
  const size_t n = input.Collect(out, 16);
  ASSERT_EQ(n, 2u);
  EXPECT_EQ(out[0].param, Param::kRed);
  EXPECT_EQ(testing::Raw(out[0]), LevelQ15FromByte(100));
  EXPECT_EQ(out[0].time_us, 100);  // the newest arrival
  EXPECT_EQ(out[1].param, Param::kTilt);
  EXPECT_EQ(testing::Raw(out[1]), -(90 << 16));
  // Changes that do not fit stay for the next call.
  const uint16_t pan[2] = {0, 0};
  input.Write(1, 2, pan, 7);
  EXPECT_EQ(input.Collect(out, 1), 1u);
  EXPECT_EQ(input.Collect(out, 1), 1u);
  EXPECT_EQ(input.Collect(out, 1), 0u);
}

std::vector<uint8_t> Pdu(std::initializer_list<int> bytes) {
  std::vector<uint8_t> v;
  for (int b : bytes) v.push_back(static_cast<uint8_t>(b));
  return v;
}

TEST(RequestCheck, VerdictsForEachFunction) {
  const RegisterMap map = MapOf(TwoFixturePatch());
  const std::vector<uint16_t> regs = RestRegisters(map);
  const auto check = [&](const std::vector<uint8_t>& pdu) {
    return CheckPdu(pdu.data(), static_cast<int>(pdu.size()), map, regs.data());
  };
  // Reads.
  EXPECT_EQ(check(Pdu({0x03, 0, 0, 0, 16})).verdict, PduVerdict::kReply);
  EXPECT_EQ(check(Pdu({0x03, 0, 0, 0, 17})).exception, kExceptionIllegalAddress);
  EXPECT_EQ(check(Pdu({0x03, 0, 0, 0, 0})).exception, kExceptionIllegalValue);
  EXPECT_EQ(check(Pdu({0x03, 0, 0, 0, 126})).exception, kExceptionIllegalValue);
  EXPECT_EQ(check(Pdu({0x04, 0, 0, 0, kStatusRegisterCount})).verdict, PduVerdict::kReply);
  EXPECT_EQ(check(Pdu({0x04, 0, 15, 0, 2})).exception, kExceptionIllegalAddress);
  // Writes: value checks, and the values handed on.
  PduCheck c = check(Pdu({0x06, 0, 3, 0, 200}));
  EXPECT_EQ(c.verdict, PduVerdict::kReply);
  EXPECT_EQ(c.write_addr, 3);
  EXPECT_EQ(c.write_values[0], 200);
  EXPECT_EQ(check(Pdu({0x06, 0, 3, 1, 0})).exception, kExceptionIllegalValue);  // red 256
  EXPECT_EQ(check(Pdu({0x06, 0, 99, 0, 0})).exception, kExceptionIllegalAddress);
  c = check(Pdu({0x10, 0, 0, 0, 3, 6, 0xFF, 0xFF, 0x80, 0x00, 0x40, 0x00}));
  EXPECT_EQ(c.verdict, PduVerdict::kReply);
  EXPECT_EQ(c.write_count, 3);
  EXPECT_EQ(c.write_values[2], 0x4000);
  EXPECT_EQ(check(Pdu({0x10, 0, 14, 0, 3, 6, 0, 0, 0, 0, 0, 0})).exception, kExceptionIllegalAddress);
  EXPECT_EQ(check(Pdu({0x10, 0, 2, 0, 2, 4, 0, 0, 1, 0})).exception, kExceptionIllegalValue);  // red 256
  EXPECT_EQ(check(Pdu({0x10, 0, 0, 0, 2, 6, 0, 0, 0, 0, 0, 0})).exception, kExceptionIllegalValue);  // count != bytes
  // Mask write: the result is checked. red = (0 AND 0) OR 0x1FF = 511.
  EXPECT_EQ(check(Pdu({0x16, 0, 3, 0, 0, 0x01, 0xFF})).exception, kExceptionIllegalValue);
  EXPECT_EQ(check(Pdu({0x16, 0, 3, 0, 0, 0x00, 0xFF})).write_values[0], 0xFF);
  // Read/write.
  EXPECT_EQ(check(Pdu({0x17, 0, 0, 0, 2, 0, 1, 0, 1, 2, 0x12, 0x34})).verdict, PduVerdict::kReply);
  EXPECT_EQ(check(Pdu({0x17, 0, 0, 0, 2, 0, 4, 0, 1, 2, 0x12, 0x34})).exception, kExceptionIllegalValue);
  // No coils; unknown functions.
  EXPECT_EQ(check(Pdu({0x01, 0, 0, 0, 1})).exception, kExceptionIllegalAddress);
  EXPECT_EQ(check(Pdu({0x2B, 0x0E, 1, 0})).exception, kExceptionIllegalFunction);
  // Lengths that do not match the function: malformed.
  EXPECT_EQ(check(Pdu({0x03, 0, 0, 0})).verdict, PduVerdict::kMalformed);
  EXPECT_EQ(check(Pdu({0x06, 0, 0, 0, 1, 9})).verdict, PduVerdict::kMalformed);
  EXPECT_EQ(check(Pdu({0x10, 0, 0, 0, 1, 200, 0, 0})).verdict, PduVerdict::kMalformed);  // byte count lies
  EXPECT_EQ(check(Pdu({0x17, 0, 0, 0, 1, 0, 1})).verdict, PduVerdict::kMalformed);
  EXPECT_EQ(check(Pdu({})).verdict, PduVerdict::kMalformed);
}

}  // namespace
}  // namespace relight::hal

namespace relight::hal {
namespace {

// Zoom (issue 12): the beam angle in 0.01 degrees, checked, shown and decoded.
TEST(RegisterMap, AZoomRegisterCarriesTheBeamAngleInHundredthsOfADegree) {
  // Every register value: Q16.16 within half an LSB of reg / 100 degrees, and back exactly.
  for (int reg = 0; reg <= kZoomRegisterMax; ++reg) {
    const int32_t q16 = ZoomQ16FromRegister(static_cast<uint16_t>(reg));
    EXPECT_LE(std::abs(static_cast<double>(q16) - reg * 65536.0 / 100.0), 0.5) << reg;
    ASSERT_EQ(RegisterFromZoomQ16(q16), reg);
  }
  EXPECT_EQ(RegisterFromZoomQ16(-(5 << 16)), 0);
  EXPECT_EQ(RegisterFromZoomQ16(200 << 16), kZoomRegisterMax);

  Patch p;
  ASSERT_TRUE(ParsePatch("[[fixture]]\nname = \"spot\"\nregisters = [\"dimmer\", \"zoom\", \"pan\"]\n", "z.toml", &p).ok());
  ASSERT_TRUE(ResolvePatch({{"spot"}}, &p).ok());
  RegisterMap map;
  ASSERT_TRUE(RegisterMap::Build(p.fixtures, &map).ok());
  EXPECT_EQ(map.CheckWrite(1, kZoomRegisterMax), 0);
  EXPECT_EQ(map.CheckWrite(1, kZoomRegisterMax + 1), kExceptionIllegalValue);
  FixtureState state{};
  state.zoom_deg = Q16_16::FromInt(24);
  uint16_t before[3] = {}, after[3] = {};
  map.Encode(state, 0, before);
  EXPECT_EQ(before[1], 2400);
  std::copy(before, before + 3, after);
  after[1] = 3650;
  ParamChange out[kParamCount];
  ASSERT_EQ(map.DecodeChanges(0, before, after, 5, out), 1u);
  EXPECT_EQ(out[0].param, Param::kZoom);
  EXPECT_EQ(out[0].degrees.raw(), 73 << 15);  // 36.5 degrees
  // A poller's peer above 180 degrees counts as 180; the same clamped value is no change.
  before[1] = kZoomRegisterMax;
  after[1] = 40000;
  EXPECT_EQ(map.DecodeChanges(0, before, after, 5, out), 0u);
}

}  // namespace
}  // namespace relight::hal
