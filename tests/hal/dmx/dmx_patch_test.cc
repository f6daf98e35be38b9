// DMX patch files: a good one, and errors that name file:line.
#include <gtest/gtest.h>

#include "relight/hal/dmx/dmx_patch.h"

namespace relight::hal {
namespace {

// A patch "in" fixtures/dmx/, so type paths resolve there.
const std::string kWhere = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/test.patch.toml";

std::string Fixture(const char* name, const char* type, const char* mode, int universe, int address) {
  return std::string("[[dmx_fixture]]\nname = \"") + name + "\"\ntype = \"" + type + "\"\nmode = \"" + mode +
         "\"\nuniverse = " + std::to_string(universe) + "\naddress = " + std::to_string(address) + "\n";
}

TEST(DmxPatch, Good) {
  DmxPatch p;
  const std::string text = "[dmx]\nloss_of_signal = \"blackout\"\nloss_timeout_ms = 500\n" +
                           Fixture("a", "relight-test-spot.toml", "16 bit", 1, 1) +
                           Fixture("b", "relight-test-spot.toml", "8 bit", 1, 14) +
                           Fixture("c", "relight-test-rgbw.toml", "4 channel", 2, 509);
  const Status st = ParseDmxPatch(text, kWhere, &p);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(p.fixtures.size(), 3u);
  EXPECT_EQ(p.loss_policy, DmxLossPolicy::kBlackout);
  EXPECT_EQ(p.loss_timeout_ms, 500);
  EXPECT_EQ(p.fixtures[1].personality.footprint, 8);
  EXPECT_EQ(p.fixtures[2].line, 16);
}

TEST(DmxPatch, QlcLibraryTypes) {
  DmxPatch p;
  const Status st = ParseDmxPatch(Fixture("aura", "Martin/Martin-MAC-Aura.qxf", "Standard Mode", 1, 1), kWhere, &p);
  if (st.code() == StatusCode::kInvalidArgument && st.message().find("unknown fixture type") != std::string::npos) {
    GTEST_SKIP() << "qlcplus-data not installed";
  }
  ASSERT_TRUE(st.ok()) << st.message();
}

void ExpectError(const std::string& text, int line, const char* needle) {
  DmxPatch p;
  const Status st = ParseDmxPatch(text, kWhere, &p);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind(kWhere + ":" + std::to_string(line) + ": ", 0), 0u) << st.message();
  EXPECT_NE(st.message().find(needle), std::string::npos) << st.message();
}

TEST(DmxPatch, LossOfSignalFade) {
  DmxPatch p;
  const std::string fixture = Fixture("a", "relight-test-spot.toml", "16 bit", 1, 1);
  ASSERT_TRUE(ParseDmxPatch("[dmx]\nloss_of_signal = \"fade\"\nloss_fade_ms = 2500\n" + fixture, kWhere, &p).ok());
  EXPECT_EQ(p.loss_policy, DmxLossPolicy::kFade);
  EXPECT_EQ(p.loss_fade_ms, 2500);
  ExpectError("[dmx]\nloss_of_signal = \"hold\"\nloss_fade_ms = 2500\n" + fixture, 3,
              "loss_fade_ms is for loss_of_signal = \"fade\"");
  ExpectError("[dmx]\nloss_of_signal = \"fade\"\nloss_fade_ms = 0\n" + fixture, 3, "must be in 1..600000");
  ExpectError("[dmx]\nloss_of_signal = \"dim\"\n" + fixture, 2, "\"hold\", \"fade\" or \"blackout\"");
}

TEST(DmxPatch, OverlapNamesBothFixtures) {
  // a: 1..13; b at 13 overlaps; its address is on line 12.
  ExpectError(Fixture("a", "relight-test-spot.toml", "16 bit", 1, 1) +
                  Fixture("b", "relight-test-spot.toml", "8 bit", 1, 13),
              12, "overlap 'a' (1..13, line 1)");
}

TEST(DmxPatch, SameAddressOtherUniverseIsFine) {
  DmxPatch p;
  EXPECT_TRUE(ParseDmxPatch(Fixture("a", "relight-test-spot.toml", "16 bit", 1, 1) +
                                Fixture("b", "relight-test-spot.toml", "16 bit", 2, 1),
                            kWhere, &p)
                  .ok());
}

TEST(DmxPatch, FootprintPast512) {
  DmxPatch p;
  EXPECT_TRUE(ParseDmxPatch(Fixture("a", "relight-test-spot.toml", "16 bit", 1, 500), kWhere, &p).ok());  // 500..512
  ExpectError(Fixture("a", "relight-test-spot.toml", "16 bit", 1, 501), 6, "ends at 513, past 512");
}

TEST(DmxPatch, UnknownTypeAndMode) {
  ExpectError(Fixture("a", "no-such-type.toml", "16 bit", 1, 1), 3, "unknown fixture type 'no-such-type.toml'");
  ExpectError(Fixture("a", "relight-test-spot.toml", "24 bit", 1, 1), 4, "no mode '24 bit'");
}

TEST(DmxPatch, BadValuesAndKeys) {
  ExpectError(Fixture("a", "relight-test-spot.toml", "16 bit", 1, 0), 6, "'address' must be in 1..512");
  ExpectError("[dmx]\nloss_of_signal = \"fadeout\"\n", 2, "hold");
  ExpectError("[[dmx_fixture]]\nname = \"a\"\nadress = 3\n", 3, "unknown key 'adress'");
  ExpectError(Fixture("a", "relight-test-rgbw.toml", "4 channel", 1, 1) +
                  Fixture("a", "relight-test-rgbw.toml", "4 channel", 1, 10),
              7, "name already used at line 1");
}

}  // namespace
}  // namespace relight::hal
