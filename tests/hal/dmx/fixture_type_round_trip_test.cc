// Fixture types written in the TOML form (FixtureTypeToToml) read back as the
// same type: every .qxf of QLC+'s library, every TOML type in fixtures/dmx,
// per-mode <Physical> overrides, names that need escaping, every Q16 beam
// angle near the ends of the range. And the comparer these checks rest on
// sees each field change.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {
namespace {

namespace fs = std::filesystem;

// write -> parse -> compare; the failure names the file and the first difference.
::testing::AssertionResult RoundTrips(const FixtureType& type) {
  const std::string toml = FixtureTypeToToml(type);
  FixtureType back;
  const Status st = ParseFixtureTypeToml(toml, "written", &back);
  if (!st.ok()) {
    return ::testing::AssertionFailure() << type.where << ": the written form does not parse: " << st.message()
                                         << "\n" << toml;
  }
  const std::string difference = FixtureTypeDifference(type, back);
  if (!difference.empty()) return ::testing::AssertionFailure() << type.where << ": " << difference;
  return ::testing::AssertionSuccess();
}

std::vector<fs::path> Files(const std::string& dir, const std::string& extension) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().extension() == extension) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

FixtureType TestSpot() {
  FixtureType type;
  const Status st = LoadFixtureType(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/relight-test-spot.toml", &type);
  EXPECT_TRUE(st.ok()) << st.message();
  return type;
}

TEST(DmxFixtureTypeRoundTrip, EveryLibraryQxf) {
  if (!fs::is_directory(kQlcFixtureDir)) GTEST_SKIP() << kQlcFixtureDir << " missing: apt-get install qlcplus-data";
  int files = 0, loaded = 0, round_tripped = 0, mode_overrides = 0, unused_channels = 0;
  for (const fs::path& path : Files(kQlcFixtureDir, ".qxf")) {
    ++files;
    FixtureType type;
    if (!LoadQxf(path.string(), &type).ok()) continue;  // fixture_library_test.cc checks the errors
    ++loaded;
    const ::testing::AssertionResult same = RoundTrips(type);
    EXPECT_TRUE(same);
    round_tripped += static_cast<bool>(same);
    for (const DmxMode& m : type.modes) {
      mode_overrides += m.pan_range_deg != 0 || m.tilt_range_deg != 0 || m.beam_max_q16 != 0;
    }
    for (size_t i = 0; i < type.channels.size(); ++i) {
      unused_channels += std::none_of(type.modes.begin(), type.modes.end(), [&](const DmxMode& m) {
        return std::count(m.channels.begin(), m.channels.end(), static_cast<int>(i)) > 0;
      });
    }
  }
  std::printf("qxf files %d: loaded %d, round-tripped %d; modes with their own <Physical> %d, "
              "channels no mode uses %d\n", files, loaded, round_tripped, mode_overrides, unused_channels);
  EXPECT_GT(loaded, files * 95 / 100);
  EXPECT_EQ(round_tripped, loaded);
  EXPECT_GT(mode_overrides, 0);   // the library exercises the per-mode keys
  EXPECT_GT(unused_channels, 0);  // and channels outside every mode
}

TEST(DmxFixtureTypeRoundTrip, EveryTomlTypeInFixtures) {
  int types = 0;
  for (const fs::path& path : Files(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx", ".toml")) {
    if (path.filename().string().find(".patch.") != std::string::npos) continue;  // DMX patches, not types
    FixtureType type;
    const Status st = LoadFixtureTypeToml(path.string(), &type);
    ASSERT_TRUE(st.ok()) << st.message();
    EXPECT_TRUE(RoundTrips(type));
    ++types;
  }
  EXPECT_GE(types, 3);
}

TEST(DmxFixtureTypeRoundTrip, ModeOverridesParseAndValidate) {
  const std::string head =
      "manufacturer = \"a\"\nmodel = \"b\"\nbeam_deg = [10, 40]\n"
      "[[channel]]\nname = \"x\"\nfunction = \"zoom\"\n"
      "[[mode]]\nname = \"m\"\n";  // the mode's keys start on line 9
  FixtureType type;
  Status st = ParseFixtureTypeToml(head + "pan_range_deg = 630\ntilt_range_deg = 265\nbeam_deg = [7.3, 30]\n"
                                          "channels = [\"x\"]\n", "t.toml", &type);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(type.modes.size(), 1u);
  EXPECT_EQ(type.modes[0].pan_range_deg, 630);
  EXPECT_EQ(type.modes[0].tilt_range_deg, 265);
  EXPECT_EQ(type.modes[0].beam_min_q16, 478413);  // lround(7.3 * 65536)
  EXPECT_EQ(type.modes[0].beam_max_q16, 30 << 16);
  EXPECT_EQ(type.beam_max_q16, 40 << 16);  // the type's own stay
  EXPECT_EQ(type.pan_range_deg, 0);
  EXPECT_TRUE(RoundTrips(type));
  EXPECT_NE(FixtureTypeToToml(type).find("beam_deg = [7.3, 30.0]"), std::string::npos) << FixtureTypeToToml(type);

  struct Bad {
    std::string keys;
    const char* message;
  };
  for (const Bad& bad : {Bad{"tilt_range_deg = 4000\n", "tilt_range_deg must be in 0..3600"},
                         Bad{"pan_range_deg = 1.5\n", "pan_range_deg must be an integer"},
                         Bad{"beam_deg = [30, 7]\n", "beam_deg is [narrowest, widest]"},
                         Bad{"beam_deg = [30]\n", "beam_deg is [narrowest, widest]"},
                         Bad{"beam_deg = [-1, 7]\n", "beam_deg must be in 0..3600 degrees"},
                         Bad{"pan_range = 540\n", "mode: unknown key 'pan_range'"}}) {
    st = ParseFixtureTypeToml(head + bad.keys + "channels = [\"x\"]\n", "t.toml", &type);
    ASSERT_FALSE(st.ok()) << bad.keys;
    EXPECT_EQ(st.message().rfind("t.toml:9: ", 0), 0u) << st.message();
    EXPECT_NE(st.message().find(bad.message), std::string::npos) << st.message();
  }
}

TEST(DmxFixtureTypeRoundTrip, NamesThatNeedEscaping) {
  FixtureType type = TestSpot();
  type.manufacturer = "Ac\\me \"Pro\"";
  type.channels[0].name = "Dimmer \"master\" C:\\dmx\\";
  type.channels[1].name = "Fäder – 日本\tfine\n";
  type.modes[0].name = "'16' bit # not a comment";
  const std::string toml = FixtureTypeToToml(type);
  FixtureType back;
  const Status st = ParseFixtureTypeToml(toml, "written", &back);
  ASSERT_TRUE(st.ok()) << st.message() << "\n" << toml;
  EXPECT_EQ(back.manufacturer, type.manufacturer);
  EXPECT_EQ(back.channels[0].name, type.channels[0].name);
  EXPECT_EQ(back.channels[1].name, type.channels[1].name);
  EXPECT_EQ(back.modes[0].name, type.modes[0].name);
  EXPECT_TRUE(RoundTrips(type));
}

// Degrees are written with as few decimals as read back to the same Q16.16:
// every angle within a degree of either end of the reader's 0..3600.
TEST(DmxFixtureTypeRoundTrip, EveryBeamAngleNearTheEndsOfTheRange) {
  FixtureType type;
  ASSERT_TRUE(ParseFixtureTypeToml("manufacturer = \"a\"\nmodel = \"b\"\n[[channel]]\nname = \"z\"\n"
                                   "function = \"zoom\"\n[[mode]]\nname = \"m\"\nchannels = [\"z\"]\n",
                                   "beam.toml", &type)
                  .ok());
  constexpr int32_t kTop = 3600 << 16;
  for (int32_t q = 0; q <= (1 << 16); ++q) {
    type.beam_min_q16 = q;
    type.beam_max_q16 = kTop - q;
    type.modes[0].beam_min_q16 = q;
    type.modes[0].beam_max_q16 = q;
    ASSERT_TRUE(RoundTrips(type)) << "q16 " << q;
  }
}

// The comparer sees each field, and the writer carries each: a changed field
// is a difference before writing and still one after the round trip.
TEST(DmxFixtureTypeRoundTrip, EachChangedFieldIsADifference) {
  const FixtureType original = TestSpot();
  ASSERT_EQ(original.channels[9].function, DmxFunction::kColorWheel);
  ASSERT_EQ(original.channels[10].function, DmxFunction::kZoom);
  ASSERT_EQ(original.channels[11].function, DmxFunction::kShutter);
  EXPECT_EQ(FixtureTypeDifference(original, original), "");
  const std::vector<std::pair<const char*, std::function<void(FixtureType&)>>> changes = {
      {"manufacturer", [](FixtureType& t) { t.manufacturer += "x"; }},
      {"model", [](FixtureType& t) { t.model = "Other"; }},
      {"type", [](FixtureType& t) { t.type = "Scanner"; }},
      {"pan_range_deg", [](FixtureType& t) { t.pan_range_deg = 541; }},
      {"tilt_range_deg", [](FixtureType& t) { t.tilt_range_deg = 0; }},
      {"beam_min_q16", [](FixtureType& t) { t.beam_min_q16 += 1; }},
      {"beam_max_q16", [](FixtureType& t) { t.beam_max_q16 -= 1; }},
      {"channel count", [](FixtureType& t) { t.channels.emplace_back().name = "In no mode"; }},
      {"name", [](FixtureType& t) { t.channels[12].name = "Gobo 2"; }},
      {"function", [](FixtureType& t) { t.channels[12].function = DmxFunction::kWhite; }},
      {"big_to_small", [](FixtureType& t) { t.channels[10].zoom_big_to_small = true; }},
      {"slot count", [](FixtureType& t) { t.channels[9].slots.pop_back(); }},
      {"slot 1 range", [](FixtureType& t) { t.channels[9].slots[1].range.max = 18; }},
      {"slot 2 color", [](FixtureType& t) { t.channels[9].slots[2].color.g = 1; }},
      {"closed count", [](FixtureType& t) { t.channels[11].closed.push_back(DmxRange{250, 255}); }},
      {"closed 0", [](FixtureType& t) { t.channels[11].closed[0].min = 1; }},
      {"mode count", [](FixtureType& t) { t.modes.pop_back(); }},
      {"mode 1 '8 bit': name", [](FixtureType& t) { t.modes[1].name = "8 bit b"; }},
      {"mode 0 '16 bit': pan_range_deg", [](FixtureType& t) { t.modes[0].pan_range_deg = 630; }},
      {"mode 0 '16 bit': tilt_range_deg", [](FixtureType& t) { t.modes[0].tilt_range_deg = 265; }},
      {"mode 0 '16 bit': beam_min_q16", [](FixtureType& t) { t.modes[0].beam_min_q16 = 1, t.modes[0].beam_max_q16 = 7 << 16; }},
      {"mode 0 '16 bit': beam_max_q16", [](FixtureType& t) { t.modes[0].beam_max_q16 = 7 << 16; }},
      {"mode 1 '8 bit': channel count", [](FixtureType& t) { t.modes[1].channels.pop_back(); }},
      {"channel at offset 1", [](FixtureType& t) { std::swap(t.modes[1].channels[1], t.modes[1].channels[2]); }},
  };
  for (const auto& [field, change] : changes) {
    FixtureType changed = original;
    change(changed);
    const std::string difference = FixtureTypeDifference(original, changed);
    EXPECT_NE(difference.find(field), std::string::npos) << field << ": " << difference;
    EXPECT_TRUE(RoundTrips(changed)) << field;
    FixtureType back;
    ASSERT_TRUE(ParseFixtureTypeToml(FixtureTypeToToml(changed), "written", &back).ok()) << field;
    EXPECT_NE(FixtureTypeDifference(original, back), "") << field << " was lost in the TOML form";
  }
  // What need not round-trip is no difference.
  FixtureType moved = original;
  moved.where = "elsewhere.toml";
  moved.channels[0].line = 99;
  moved.modes[0].line = 99;
  moved.channels[12].ignored_why = "preset GoboWheel";
  EXPECT_EQ(FixtureTypeDifference(original, moved), "");
}

}  // namespace
}  // namespace relight::hal
