// The stage fixture's DMX side (issue 12 item 5): fixtures/stage.dmx.toml
// patches 48 real QLC+ heads over two universes under the scene's luminaire
// names, and fixtures/stage.dmxrec (written by scripts/make-stage-show.py) is
// a well-formed 44 frames/s recording in which every head moves every frame.
//
// The show is parsed here with a few lines of our own (ParseShowLine), not
// with hal's replay reader, so the file is checked against the format as
// written down rather than against one reader of it; the test can switch to
// that reader once it is the one relightd uses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "relight/hal/dmx/dmx_patch.h"
#include "relight/hal/dmx/personality.h"

namespace relight::hal {
namespace {

const std::string kPatch = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/stage.dmx.toml";
const std::string kScene = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/stage.toml";
const std::string kShow = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/stage.dmxrec";
constexpr int kHeads = 48;
constexpr int kFps = 44;

bool LoadStagePatch(DmxPatch* p) {
  if (!std::filesystem::is_directory(kQlcFixtureDir)) return false;
  const Status st = LoadDmxPatch(kPatch, p);
  EXPECT_TRUE(st.ok()) << st.message();
  return st.ok();
}

bool Has(const DmxPersonality& p, DmxFunction f) { return p.Offset(f) >= 0; }

TEST(StagePatch, Loads48HeadsOverTwoUniverses) {
  DmxPatch patch;
  if (!LoadStagePatch(&patch)) GTEST_SKIP() << kQlcFixtureDir << " missing: apt-get install qlcplus-data";
  ASSERT_EQ(patch.fixtures.size(), static_cast<size_t>(kHeads));
  std::map<int, std::vector<int>> owner;  // universe -> slot owner (index + 1), 0 = free
  int spots = 0, washes = 0;
  for (size_t i = 0; i < patch.fixtures.size(); ++i) {
    const DmxFixturePatch& f = patch.fixtures[i];
    const DmxPersonality& p = f.personality;
    SCOPED_TRACE(f.name);
    std::vector<int>& slots = owner.try_emplace(f.universe, kDmxSlots, 0).first->second;
    ASSERT_LE(f.address - 1 + p.footprint, kDmxSlots);
    for (int s = f.address - 1; s < f.address - 1 + p.footprint; ++s) {
      EXPECT_EQ(slots[s], 0) << "slot " << s + 1 << " of universe " << f.universe << " patched twice";
      slots[s] = static_cast<int>(i) + 1;
    }
    // What the renderer needs from every head: 16-bit pan/tilt, dimmer, zoom with a lens range, colour.
    EXPECT_TRUE(Has(p, DmxFunction::kPan) && Has(p, DmxFunction::kPanFine));
    EXPECT_TRUE(Has(p, DmxFunction::kTilt) && Has(p, DmxFunction::kTiltFine));
    EXPECT_TRUE(Has(p, DmxFunction::kDimmer));
    EXPECT_TRUE(Has(p, DmxFunction::kZoom));
    EXPECT_GT(p.beam_max_q16, p.beam_min_q16);
    EXPECT_GT(p.pan_range_deg, 0);
    const bool cmy = Has(p, DmxFunction::kCyan) && Has(p, DmxFunction::kMagenta) && Has(p, DmxFunction::kYellow);
    const bool rgbw = Has(p, DmxFunction::kRed) && Has(p, DmxFunction::kGreen) && Has(p, DmxFunction::kBlue) &&
                      Has(p, DmxFunction::kWhite);
    EXPECT_TRUE(cmy || rgbw);
    if (cmy && p.has_wheel) ++spots;
    if (rgbw) ++washes;
  }
  ASSERT_EQ(owner.size(), 2u);
  for (const auto& [universe, slots] : owner) {
    std::set<int> heads(slots.begin(), slots.end());
    heads.erase(0);
    EXPECT_EQ(heads.size(), static_cast<size_t>(kHeads / 2)) << "universe " << universe;
  }
  EXPECT_EQ(spots, kHeads / 2);   // CMY + colour wheel
  EXPECT_EQ(washes, kHeads / 2);  // RGBW
}

TEST(StagePatch, NamesAreTheSceneLuminaires) {
  DmxPatch patch;
  if (!LoadStagePatch(&patch)) GTEST_SKIP() << kQlcFixtureDir << " missing";
  // A plain TOML read: hal does not link the baker's scene loader.
  toml::table scene;
  try {
    scene = toml::parse_file(kScene);
  } catch (const toml::parse_error& e) {
    FAIL() << kScene << ": " << e.description();
  }
  std::set<std::string> luminaires;
  const toml::array* list = scene["luminaire"].as_array();
  ASSERT_NE(list, nullptr);
  for (const toml::node& n : *list) {
    const toml::table* t = n.as_table();
    ASSERT_NE(t, nullptr);
    const std::optional<std::string> name = (*t)["name"].value<std::string>();
    ASSERT_TRUE(name.has_value());
    luminaires.insert(*name);
  }
  std::set<std::string> patched;
  for (const DmxFixturePatch& f : patch.fixtures) {
    EXPECT_EQ(luminaires.count(f.name), 1u) << f.name << " is patched but not a luminaire of " << kScene;
    patched.insert(f.name);
  }
  EXPECT_EQ(patched.size(), static_cast<size_t>(kHeads));
  for (const std::string& name : luminaires) {
    if (patched.count(name) == 0) {
      EXPECT_EQ(name.rfind("foh_", 0), 0u) << name << ": only the front washes are unpatched";
    }
  }
}

// One line of the show: "<time_us> <universe> <slot>=<hexbytes> ...".
struct ShowLine {
  int64_t time_us = 0;
  int universe = 0;
  std::vector<std::pair<int, std::vector<uint8_t>>> runs;  // first slot (1-based), bytes
};

int Hex(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// false (with *why) if the line breaks the format.
bool ParseShowLine(const std::string& line, ShowLine* out, std::string* why) {
  std::istringstream in(line);
  std::string time, universe, run;
  if (!(in >> time >> universe)) return *why = "fewer than 3 fields", false;
  char* end = nullptr;
  out->time_us = std::strtoll(time.c_str(), &end, 10);
  if (time.empty() || *end != '\0' || out->time_us < 0) return *why = "bad time '" + time + "'", false;
  out->universe = static_cast<int>(std::strtol(universe.c_str(), &end, 10));
  if (universe.empty() || *end != '\0' || out->universe < 1) return *why = "bad universe '" + universe + "'", false;
  out->runs.clear();
  while (in >> run) {
    const size_t eq = run.find('=');
    if (eq == std::string::npos || eq == 0) return *why = "no slot= in '" + run + "'", false;
    const std::string slot_text = run.substr(0, eq);  // named: strtol's end points into it below
    const long slot = std::strtol(slot_text.c_str(), &end, 10);
    const std::string hex = run.substr(eq + 1);
    if (*end != '\0' || slot < 1 || slot > kDmxSlots) return *why = "bad slot in '" + run + "'", false;
    if (hex.empty() || hex.size() % 2 != 0) return *why = "odd or empty hex in '" + run + "'", false;
    if (slot - 1 + static_cast<long>(hex.size() / 2) > kDmxSlots) return *why = "run past slot 512: " + run, false;
    std::vector<uint8_t> bytes;
    for (size_t i = 0; i < hex.size(); i += 2) {
      const int hi = Hex(hex[i]), lo = Hex(hex[i + 1]);
      if (hi < 0 || lo < 0) return *why = "not hex: '" + run + "'", false;
      bytes.push_back(static_cast<uint8_t>(hi << 4 | lo));
    }
    out->runs.emplace_back(static_cast<int>(slot), std::move(bytes));
  }
  if (out->runs.empty()) return *why = "no slots", false;
  return true;
}

TEST(StageShow, LineParserRejectsWhatTheFormatForbids) {
  ShowLine l;
  std::string why;
  EXPECT_TRUE(ParseShowLine("22727 2 1=00ff 511=0102", &l, &why)) << why;
  EXPECT_EQ(l.runs.size(), 2u);
  EXPECT_EQ(l.runs[1].second[1], 2);
  for (const char* bad : {"22727 1", "x 1 1=00", "1 0 1=00", "1 1 0=00", "1 1 513=00", "1 1 1=0", "1 1 1=zz",
                          "1 1 512=0000", "1 1 =00", "-5 1 1=00"}) {
    EXPECT_FALSE(ParseShowLine(bad, &l, &why)) << bad;
  }
}

TEST(StageShow, WellFormedAt44HzAndEveryHeadMovesEveryFrame) {
  DmxPatch patch;
  if (!LoadStagePatch(&patch)) GTEST_SKIP() << kQlcFixtureDir << " missing";
  std::ifstream in(kShow);
  ASSERT_TRUE(in) << kShow << " missing: scripts/make-stage-show.py writes it";
  std::map<int, std::vector<uint8_t>> levels;   // universe -> current 512 slots
  std::map<int, std::vector<int64_t>> times;    // universe -> frame times
  std::map<int, std::vector<bool>> patched;     // universe -> slot inside a fixture's footprint
  for (const DmxFixturePatch& f : patch.fixtures) {
    levels.try_emplace(f.universe, kDmxSlots, 0);
    std::vector<bool>& used = patched.try_emplace(f.universe, kDmxSlots, false).first->second;
    for (int s = 0; s < f.personality.footprint; ++s) used[f.address - 1 + s] = true;
  }
  std::vector<DmxFixtureValues> values(patch.fixtures.size()), before(patch.fixtures.size());
  std::vector<uint16_t> pan_before(patch.fixtures.size());
  // What the show must contain, seen through hal's decoder.
  int frames_all_dark = 0, frames_all_lit = 0;
  std::set<int32_t> beam_angles;
  bool spot_coloured = false, wash_coloured = false, wheel_used = false;
  std::string line;
  int line_no = 0;
  int64_t last_time = -1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    ShowLine l;
    std::string why;
    ASSERT_TRUE(ParseShowLine(line, &l, &why)) << kShow << ":" << line_no << ": " << why;
    ASSERT_GE(l.time_us, last_time) << kShow << ":" << line_no << ": time goes back";
    last_time = l.time_us;
    ASSERT_EQ(levels.count(l.universe), 1u) << kShow << ":" << line_no << ": universe not in the patch";
    std::vector<uint8_t>& slots = levels[l.universe];
    for (const auto& [first, bytes] : l.runs) {
      for (size_t i = 0; i < bytes.size(); ++i) {
        // A run may write through a gap between two heads, but only zeros.
        ASSERT_TRUE(patched[l.universe][first - 1 + i] || bytes[i] == 0)
            << kShow << ":" << line_no << ": slot " << first + i << " is in no fixture's footprint";
        slots[first - 1 + i] = bytes[i];
      }
    }
    times[l.universe].push_back(l.time_us);
    const size_t frame = times[l.universe].size();
    bool dark = true, lit = true;
    for (size_t i = 0; i < patch.fixtures.size(); ++i) {
      const DmxFixturePatch& f = patch.fixtures[i];
      if (f.universe != l.universe) continue;
      before[i] = values[i];
      ASSERT_TRUE(DecodeDmxFrame(f.personality, f.address, kDmxNullStartCode, slots.data(), slots.size(), &values[i]));
      if (frame > 1) {
        EXPECT_NE(values[i].pan16, before[i].pan16) << kShow << ":" << line_no << ": " << f.name << "'s pan did not move";
      }
      dark = dark && values[i].dimmer.raw() == 0;
      lit = lit && values[i].dimmer.raw() == 32767;
      beam_angles.insert(values[i].beam_angle.raw());
      const bool coloured = values[i].r.raw() != values[i].g.raw() || values[i].g.raw() != values[i].b.raw();
      const bool spot = Has(f.personality, DmxFunction::kCyan);
      spot_coloured = spot_coloured || (spot && coloured);
      wash_coloured = wash_coloured || (!spot && coloured);
      wheel_used = wheel_used || (spot && slots[f.address - 1 + f.personality.Offset(DmxFunction::kColorWheel)] != 0);
    }
    frames_all_dark += dark;
    frames_all_lit += lit;
  }
  ASSERT_EQ(times.size(), 2u);
  const size_t frames = times.begin()->second.size();
  for (const auto& [universe, t] : times) {
    SCOPED_TRACE("universe " + std::to_string(universe));
    EXPECT_EQ(t.size(), frames);
    EXPECT_GE(t.size(), static_cast<size_t>(20 * kFps));   // 20-30 s
    EXPECT_LE(t.size(), static_cast<size_t>(30 * kFps));
    for (size_t k = 1; k < t.size(); ++k) {
      // 44 frames/s: 22727.27 us apart, whole microseconds.
      ASSERT_LE(std::llabs((t[k] - t[k - 1]) * kFps - 1000000), kFps) << "frame " << k;
    }
  }
  EXPECT_GE(frames_all_dark, 2 * kFps) << "a blackout of at least a second on both universes";
  EXPECT_GT(frames_all_lit, 0) << "a restore to full";
  EXPECT_TRUE(spot_coloured) << "CMY colour changes on the spots";
  EXPECT_TRUE(wash_coloured) << "RGBW colour changes on the washes";
  EXPECT_TRUE(wheel_used);
  EXPECT_GT(beam_angles.size(), 20u) << "zoom changes";
}

}  // namespace
}  // namespace relight::hal
