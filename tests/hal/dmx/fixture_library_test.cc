// Every fixture definition in QLC+'s library (Debian qlcplus-data) loads or
// fails with a clear "file:line: what"; counts of what was recognised.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "relight/hal/dmx/fixture_type.h"
#include "relight/hal/dmx/personality.h"

namespace relight::hal {
namespace {

namespace fs = std::filesystem;

TEST(DmxFixtureLibrary, EveryQxfLoadsOrFailsClearly) {
  if (!fs::is_directory(kQlcFixtureDir)) GTEST_SKIP() << kQlcFixtureDir << " missing: apt-get install qlcplus-data";
  int files = 0, loaded = 0, failed = 0, heads = 0, heads_ptd = 0, heads_ptdz = 0, heads_ptdz_lens = 0;
  int heads_16bit = 0, cmy = 0, rgb = 0, wheel = 0;
  const std::regex located(R"(^.+\.qxf:[0-9]+: .+)");
  for (const auto& entry : fs::recursive_directory_iterator(kQlcFixtureDir)) {
    if (entry.path().extension() != ".qxf") continue;
    ++files;
    FixtureType type;
    const Status st = LoadQxf(entry.path().string(), &type);
    if (!st.ok()) {
      ++failed;
      EXPECT_TRUE(std::regex_match(st.message(), located)) << st.message();
      std::printf("  not loaded: %s\n", st.message().c_str());
      continue;
    }
    ++loaded;
    bool has_ptd = false, has_ptdz = false, has_16 = false, has_cmy = false, has_rgb = false, has_wheel = false;
    for (const DmxMode& m : type.modes) {
      DmxPersonality p;
      ASSERT_TRUE(BuildPersonality(type, m.name, &p).ok());
      EXPECT_EQ(p.footprint, m.channels.size());
      const bool ptd = p.Offset(DmxFunction::kPan) >= 0 && p.Offset(DmxFunction::kTilt) >= 0 &&
                       p.Offset(DmxFunction::kDimmer) >= 0;
      has_ptd = has_ptd || ptd;
      has_ptdz = has_ptdz || (ptd && p.Offset(DmxFunction::kZoom) >= 0);
      has_16 = has_16 || (p.Offset(DmxFunction::kPanFine) >= 0 && p.Offset(DmxFunction::kTiltFine) >= 0);
      has_cmy = has_cmy || p.Offset(DmxFunction::kCyan) >= 0;
      has_rgb = has_rgb || p.Offset(DmxFunction::kRed) >= 0;
      has_wheel = has_wheel || p.has_wheel;
    }
    cmy += has_cmy;
    rgb += has_rgb;
    wheel += has_wheel;
    if (type.type == "Moving Head") {
      ++heads;
      heads_ptd += has_ptd;
      heads_ptdz += has_ptdz;
      heads_16bit += has_16;
      heads_ptdz_lens += has_ptdz && type.beam_max_q16 > 0;
    }
  }
  std::printf("qxf files %d: loaded %d, clear errors %d\n", files, loaded, failed);
  std::printf("moving heads %d: pan+tilt+dimmer %d, pan+tilt+dimmer+zoom %d (with a lens range %d), 16-bit pan+tilt %d\n",
              heads, heads_ptd, heads_ptdz, heads_ptdz_lens, heads_16bit);
  std::printf("types with CMY %d, RGB %d, a colour wheel with colours %d\n", cmy, rgb, wheel);
  EXPECT_GT(files, 1000);
  EXPECT_EQ(loaded + failed, files);
  EXPECT_GT(loaded, files * 95 / 100);
  EXPECT_GT(heads_ptdz, 0);
}

TEST(DmxFixtureLibrary, MacAuraHasWhatARendererNeeds) {
  const std::string path = std::string(kQlcFixtureDir) + "/Martin/Martin-MAC-Aura.qxf";
  if (!fs::exists(path)) GTEST_SKIP() << path << " missing";
  FixtureType type;
  ASSERT_TRUE(LoadQxf(path, &type).ok());
  EXPECT_EQ(type.manufacturer, "Martin");
  EXPECT_FALSE(type.modes.empty());
  EXPECT_GT(type.pan_range_deg, 0);
}

TEST(DmxFixtureType, XmlErrorsNameTheLine) {
  FixtureType type;
  const Status st = ParseQxf("<?xml version=\"1.0\"?>\n<FixtureDefinition>\n <Manufacturer>x</Manufacturer>\n"
                             " <Model>y</Mode>\n</FixtureDefinition>\n",
                             "bad.qxf", &type);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind("bad.qxf:4: ", 0), 0u) << st.message();
}

TEST(DmxFixtureType, UnknownModeChannelNamesTheLine) {
  FixtureType type;
  const Status st = ParseQxf(
      "<FixtureDefinition>\n<Manufacturer>x</Manufacturer><Model>y</Model>\n"
      "<Channel Name=\"Dim\" Preset=\"IntensityDimmer\"/>\n<Mode Name=\"m\">\n"
      " <Channel Number=\"0\">Dim</Channel>\n <Channel Number=\"1\">Nope</Channel>\n</Mode>\n</FixtureDefinition>\n",
      "m.qxf", &type);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind("m.qxf:6: ", 0), 0u) << st.message();
  EXPECT_NE(st.message().find("Nope"), std::string::npos);
}

TEST(DmxFixtureType, OldGroupStyleAndPresetsAgree) {
  FixtureType type;
  ASSERT_TRUE(ParseQxf("<FixtureDefinition><Manufacturer>x</Manufacturer><Model>y</Model>"
                       "<Channel Name=\"P\"><Group Byte=\"0\">Pan</Group></Channel>"
                       "<Channel Name=\"Pf\"><Group Byte=\"1\">Pan</Group></Channel>"
                       "<Channel Name=\"C\"><Group Byte=\"0\">Intensity</Group><Colour>Cyan</Colour></Channel>"
                       "<Channel Name=\"D\"><Group Byte=\"0\">Intensity</Group></Channel>"
                       "<Channel Name=\"W\"><Group Byte=\"0\">Colour</Group>"
                       "<Capability Min=\"0\" Max=\"9\" Color=\"#ff0000\">Red</Capability></Channel>"
                       "<Channel Name=\"T\" Preset=\"PositionTilt\"/>"
                       "<Channel Name=\"Z\" Preset=\"BeamZoomBigSmall\"/>"
                       "<Channel Name=\"G\" Preset=\"GoboWheel\"/>"
                       "<Mode Name=\"m\"><Channel Number=\"0\">P</Channel></Mode></FixtureDefinition>",
                       "g.qxf", &type)
                  .ok());
  ASSERT_EQ(type.channels.size(), 8u);
  EXPECT_EQ(type.channels[0].function, DmxFunction::kPan);
  EXPECT_EQ(type.channels[1].function, DmxFunction::kPanFine);
  EXPECT_EQ(type.channels[2].function, DmxFunction::kCyan);
  EXPECT_EQ(type.channels[3].function, DmxFunction::kDimmer);
  EXPECT_EQ(type.channels[4].function, DmxFunction::kColorWheel);
  ASSERT_EQ(type.channels[4].slots.size(), 1u);
  EXPECT_EQ(type.channels[4].slots[0].color.r, 255);
  EXPECT_EQ(type.channels[4].slots[0].color.g, 0);
  EXPECT_EQ(type.channels[5].function, DmxFunction::kTilt);
  EXPECT_EQ(type.channels[6].function, DmxFunction::kZoom);
  EXPECT_TRUE(type.channels[6].zoom_big_to_small);
  EXPECT_EQ(type.channels[7].function, DmxFunction::kIgnored);
  EXPECT_EQ(type.channels[7].ignored_why, "preset GoboWheel");
}

TEST(DmxFixtureType, TomlFormLoads) {
  FixtureType type;
  const Status st = LoadFixtureType(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/relight-test-spot.toml", &type);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(type.model, "Test Spot");
  ASSERT_EQ(type.modes.size(), 2u);
  EXPECT_EQ(type.modes[0].channels.size(), 13u);
  EXPECT_EQ(type.beam_max_q16, 40 << 16);
}

TEST(DmxFixtureType, TomlErrorsNameTheLine) {
  FixtureType type;
  Status st = ParseFixtureTypeToml("manufacturer = \"a\"\nmodel = \"b\"\n[[channel]]\nname = \"x\"\nfunction = \"laser\"\n",
                                   "t.toml", &type);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind("t.toml:5: ", 0), 0u) << st.message();
  st = ParseFixtureTypeToml("manufacturer = \"a\"\nmodel = \"b\"\n[[channel]]\nname = \"x\"\nfunction = \"pan\"\n"
                            "[[mode]]\nname = \"m\"\nchannels = [\"x\",\n \"y\"]\n",
                            "t.toml", &type);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind("t.toml:9: ", 0), 0u) << st.message();
}

}  // namespace
}  // namespace relight::hal
