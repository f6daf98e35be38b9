// The DMX personality decoder: 16-bit pan/tilt, CMY -> RGB, colour wheel,
// zoom -> beam angle, shutter, short frames, non-zero start codes.
#include <gtest/gtest.h>

#include <cmath>

#include "relight/hal/dmx/personality.h"

namespace relight::hal {
namespace {

class DmxDecode : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string dir = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/";
    ASSERT_TRUE(LoadFixtureType(dir + "relight-test-spot.toml", &spot_).ok());
    ASSERT_TRUE(BuildPersonality(spot_, "16 bit", &p16_).ok());
    ASSERT_TRUE(BuildPersonality(spot_, "8 bit", &p8_).ok());
    ASSERT_TRUE(LoadFixtureType(dir + "relight-test-rgbw.toml", &par_).ok());
    ASSERT_TRUE(BuildPersonality(par_, "4 channel", &rgbw_).ok());
  }
  // A 16-bit-mode frame for a fixture at `address`, open white, full.
  void Fill16(int address) {
    uint8_t* s = frame_ + address - 1;
    const uint8_t v[13] = {255, 255, 0x80, 0x00, 0x80, 0x00, 0, 0, 0, 0, 0, 255, 0};
    std::copy(v, v + 13, s);
  }
  FixtureType spot_, par_;
  DmxPersonality p16_, p8_, rgbw_;
  uint8_t frame_[512] = {};
};

// Q1.15 of an 8-bit level, the double reference.
int Ref8(int v) { return static_cast<int>(std::lround(v / 255.0 * 32767.0)); }

TEST_F(DmxDecode, FootprintAndOffsets) {
  EXPECT_EQ(p16_.footprint, 13);
  EXPECT_EQ(p16_.Offset(DmxFunction::kPanFine), 3);
  EXPECT_EQ(p8_.Offset(DmxFunction::kPanFine), -1);
  EXPECT_EQ(p16_.pan_range_deg, 540);
}

TEST_F(DmxDecode, SixteenBitPanTiltAndDimmer) {
  Fill16(100);
  frame_[99] = 0x12, frame_[100] = 0x34;                       // dimmer
  frame_[101] = 0xAB, frame_[102] = 0xCD;                      // pan
  frame_[103] = 0x01, frame_[104] = 0xFF;                      // tilt
  DmxFixtureValues v;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 100, 0x00, frame_, 512, &v));
  EXPECT_EQ(v.pan16, 0xABCD);
  EXPECT_EQ(v.tilt16, 0x01FF);
  EXPECT_NEAR(v.dimmer.raw(), std::round(0x1234 / 65535.0 * 32767.0), 1);
  frame_[99] = 255, frame_[100] = 255;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 100, 0x00, frame_, 512, &v));
  EXPECT_EQ(v.dimmer.raw(), 32767);
  EXPECT_EQ(v.frames, 2u);
}

TEST_F(DmxDecode, EightBitModeWidens) {
  // 8 bit: Dimmer, Pan, Tilt, C, M, Y, Zoom, Shutter.
  const uint8_t s[8] = {128, 128, 255, 0, 0, 0, 0, 255};
  DmxFixtureValues v;
  ASSERT_TRUE(DecodeDmxFrame(p8_, 1, 0x00, s, 8, &v));
  EXPECT_EQ(v.pan16, 32768);          // 128 << 8 = home
  EXPECT_EQ(v.tilt16, 0xFF00);
  EXPECT_EQ(v.dimmer.raw(), Ref8(128));
}

TEST_F(DmxDecode, EveryEightBitLevelWithinOneLsbOfReference) {
  DmxFixtureValues v;
  for (int level = 0; level < 256; ++level) {
    const uint8_t s[8] = {static_cast<uint8_t>(level), 0, 0, static_cast<uint8_t>(level), 0, 0, 0, 255};
    ASSERT_TRUE(DecodeDmxFrame(p8_, 1, 0x00, s, 8, &v));
    EXPECT_NEAR(v.dimmer.raw(), Ref8(level), 1) << level;
    EXPECT_NEAR(v.r.raw(), 32767 - Ref8(level), 1) << level;
  }
}

TEST_F(DmxDecode, CmyToRgb) {
  Fill16(1);
  frame_[6] = 255, frame_[7] = 0, frame_[8] = 128;  // full cyan, no magenta, half yellow
  DmxFixtureValues v;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  EXPECT_EQ(v.r.raw(), 0);
  EXPECT_EQ(v.g.raw(), 32767);
  EXPECT_NEAR(v.b.raw(), 32767 - Ref8(128), 1);
}

TEST_F(DmxDecode, ColourWheelFiltersTheMix) {
  Fill16(1);
  DmxFixtureValues v;
  frame_[9] = 15;  // red slot
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  EXPECT_EQ(v.r.raw(), 32767);
  EXPECT_EQ(v.g.raw(), 0);
  EXPECT_EQ(v.b.raw(), 0);
  frame_[9] = 25;  // blue slot, with full cyan: blue passes both
  frame_[6] = 255;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  EXPECT_EQ(v.r.raw(), 0);
  EXPECT_EQ(v.b.raw(), 32767);
  frame_[9] = 200;  // past the last slot: open
  frame_[6] = 0;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  EXPECT_EQ(v.g.raw(), 32767);
}

TEST_F(DmxDecode, ZoomMapsToTheLensRange) {
  Fill16(1);
  DmxFixtureValues v;
  for (int z : {0, 1, 77, 128, 254, 255}) {
    frame_[10] = static_cast<uint8_t>(z);
    ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
    const double ref = 10.0 + 30.0 * z / 255.0;  // small -> big between 10 and 40 degrees
    EXPECT_NEAR(v.beam_angle.raw() / 65536.0, ref, 1.0 / 65536.0) << z;
  }
}

TEST_F(DmxDecode, ShutterClosedRange) {
  Fill16(1);
  DmxFixtureValues v;
  frame_[11] = 7;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  EXPECT_FALSE(v.shutter_open);
  frame_[11] = 8;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  EXPECT_TRUE(v.shutter_open);
}

TEST_F(DmxDecode, ShortFrameKeepsSixteenBitValuesWhoseFineByteIsMissing) {
  Fill16(1);
  frame_[2] = 0x10, frame_[3] = 0x20, frame_[4] = 0x30, frame_[5] = 0x40;
  DmxFixtureValues v;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  ASSERT_EQ(v.pan16, 0x1020);
  // A frame that ends after the tilt coarse byte: pan (both bytes) moves,
  // tilt keeps its previous 16-bit value, colour and zoom are untouched.
  frame_[2] = 0x50, frame_[3] = 0x60, frame_[4] = 0x70;
  frame_[6] = 255;  // beyond the frame: must not be seen
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 5, &v));
  EXPECT_EQ(v.pan16, 0x5060);
  EXPECT_EQ(v.tilt16, 0x3040);
  EXPECT_EQ(v.r.raw(), 32767);
  // Frame ends before the fixture: nothing happens.
  const uint32_t frames = v.frames;
  EXPECT_FALSE(DecodeDmxFrame(p16_, 200, 0x00, frame_, 199, &v));
  EXPECT_EQ(v.frames, frames);
}

TEST_F(DmxDecode, NonZeroStartCodesAreNotLevels) {
  Fill16(1);
  DmxFixtureValues v;
  ASSERT_TRUE(DecodeDmxFrame(p16_, 1, 0x00, frame_, 512, &v));
  const DmxFixtureValues before = v;
  frame_[0] = 0, frame_[2] = 0xFF;
  EXPECT_FALSE(DecodeDmxFrame(p16_, 1, 0xCC, frame_, 512, &v));  // RDM
  EXPECT_FALSE(DecodeDmxFrame(p16_, 1, 0x17, frame_, 512, &v));  // text
  EXPECT_EQ(v.dimmer.raw(), before.dimmer.raw());
  EXPECT_EQ(v.pan16, before.pan16);
  EXPECT_EQ(v.frames, before.frames);
}

TEST_F(DmxDecode, RgbwWithoutDimmerChannel) {
  const uint8_t s[4] = {255, 0, 64, 128};
  DmxFixtureValues v;
  ASSERT_TRUE(DecodeDmxFrame(rgbw_, 1, 0x00, s, 4, &v));
  EXPECT_EQ(v.dimmer.raw(), 32767);                 // no dimmer: full
  EXPECT_EQ(v.r.raw(), 32767);                      // saturates
  EXPECT_NEAR(v.g.raw(), Ref8(128), 1);             // white only
  EXPECT_NEAR(v.b.raw(), Ref8(64) + Ref8(128), 2);  // blue + white
  EXPECT_EQ(v.beam_angle.raw(), 0);                 // no zoom channel
}

TEST(DmxPersonality, UnknownModeListsTheModes) {
  FixtureType t;
  ASSERT_TRUE(LoadFixtureType(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/relight-test-spot.toml", &t).ok());
  DmxPersonality p;
  const Status st = BuildPersonality(t, "Extended", &p);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("'16 bit', '8 bit'"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace relight::hal
