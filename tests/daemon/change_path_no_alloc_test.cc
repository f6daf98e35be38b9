// Issue 11: the per-change path allocates nothing after start-up. A Modbus
// register write decoded by hal (MockSource decodes through the same
// RegisterMap and register input as the TCP/RTU servers) goes through
// control::ChangePath (index mapping, fader, typed engine setters) to the
// engine's state and Update(); heap allocations are counted from the first
// write to the last Update. The patch lists the luminaires in another order
// than the bake, so the mapping is exercised too, and the engine state is
// checked against the values written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <vector>

#include "relight/control/change_path.h"
#include "relight/control/engine_binding.h"
#include "relight/engine/engine.h"
#include "relight/base/console_value.h"
#include "relight/hal/dmx/dmx_replay_source.h"
#include "relight/hal/mock_source.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

#include "../runtime/count_allocations.h"

namespace relight::control {
namespace {

// These check the change path's allocations, not emitter placement cost:
// the engine's later-bounce table (~2.5 s of Open, 30 s under ASan) stays off.
EngineOptions NoBounceTable() {
  EngineOptions o;
  o.emitter_bounce_table_bytes = 0;
  return o;
}

// The engine keeps angles in (-180, 180] degrees.
Q16_16 Wrapped(Q16_16 deg) {
  int64_t v = deg.raw() % (int64_t{360} << 16);
  if (v > (int64_t{180} << 16)) v -= int64_t{360} << 16;
  if (v <= -(int64_t{180} << 16)) v += int64_t{360} << 16;
  return Q16_16::FromRaw(static_cast<int32_t>(v));
}

bool FileExists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

TEST(ChangePath, ARegisterWriteReachesTheEngineWithoutAllocating) {
  const std::string bake = RELIGHT_TEST_HIER_BAKE;
  if (!FileExists(bake)) GTEST_SKIP() << "no bake at " << bake << " (ctest's MakeLivingRoomHierBake makes it)";
  Engine engine;
  ASSERT_TRUE(engine.Open(bake, NoBounceTable()).ok());
  ASSERT_EQ(engine.luminaire_count(), 3);

  // The bake's luminaires in reverse: patch index i is luminaire 2 - i.
  hal::Patch patch;
  std::string text;
  std::vector<hal::LuminaireConsole> luminaires;
  for (int l = 2; l >= 0; --l) text += "[[fixture]]\nname = \"" + engine.bake().luminaires[l].name + "\"\n";
  text += "fade_ms = 50\n";  // the last one fades: ramps run while counting
  for (const BakeLuminaire& l : engine.bake().luminaires) luminaires.push_back({l.name, l.pan_range, l.tilt_range});
  ASSERT_TRUE(hal::ParsePatch(text, "alloc.toml", &patch).ok());
  ASSERT_TRUE(hal::ResolvePatch(luminaires, &patch).ok());
  hal::RegisterMap map;
  ASSERT_TRUE(hal::RegisterMap::Build(patch.fixtures, &map).ok());
  std::vector<uint16_t> initial(static_cast<size_t>(map.holding_count()), 0);
  for (int f = 0; f < map.fixture_count(); ++f) {
    map.Encode(engine.state(2 - f), f, &initial[static_cast<size_t>(map.fixture(f).modbus_base)]);
  }
  hal::MockSource mock(patch, initial);
  ASSERT_TRUE(mock.Start().ok());

  ChangePath path;
  ASSERT_TRUE(path.Bind(&engine, patch.fixtures, nullptr).ok());
  ASSERT_EQ(path.patch_luminaires(), (std::vector<uint16_t>{2, 1, 0}));
  const BoundInput input{&mock, path.patch_luminaires()};
  (void)path.Apply(0);
  engine.Update();

  // Start-up is over: count from here.
  g_allocations = 0;
  g_count_allocations = true;
  int64_t t_us = 1000;
  size_t applied = 0;
  for (int i = 0; i < 3000; ++i, t_us += 1000) {
    const int f = i % 3;
    const int base = map.fixture(f).modbus_base;
    EXPECT_EQ(mock.SetHoldingRegister(base + hal::kRegPan, static_cast<uint16_t>(1000 + 37 * i), t_us), 0);
    EXPECT_EQ(mock.SetHoldingRegister(base + hal::kRegTilt, static_cast<uint16_t>(60000 - 11 * i), t_us), 0);
    EXPECT_EQ(mock.SetHoldingRegister(base + hal::kRegDimmer, static_cast<uint16_t>(i * 21), t_us), 0);
    EXPECT_EQ(mock.SetHoldingRegister(base + hal::kRegGreen, static_cast<uint16_t>(i % 256), t_us), 0);
    (void)path.Poll(input, t_us, t_us);
    applied += path.Apply(t_us);
    engine.Update();
  }
  t_us += 100000;  // past every fade
  applied += path.Apply(t_us);
  engine.Update();
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0) << "heap allocations on the per-change path";
  EXPECT_GT(applied, 9000u);
  EXPECT_EQ(path.dropped(), 0);
  EXPECT_EQ(path.rejected(), 0);

  // The engine shows the last write of each patch fixture, on its own luminaire.
  for (int f = 0; f < 3; ++f) {
    const int last = 2999 - ((2999 - f) % 3);  // the last i with i % 3 == f
    const hal::FixturePatch& fp = map.fixture(f);
    const FixtureState s = engine.state(2 - f);
    EXPECT_EQ(s.pan_deg.raw(), hal::AngleQ16FromRegister(static_cast<uint16_t>(1000 + 37 * last), fp.pan_range_q16));
    EXPECT_EQ(s.tilt_deg.raw(), hal::AngleQ16FromRegister(static_cast<uint16_t>(60000 - 11 * last), fp.tilt_range_q16));
    EXPECT_EQ(s.dimmer.raw(), hal::LevelQ15FromRegister16(static_cast<uint16_t>(last * 21)));
    EXPECT_EQ(s.rgb[1].raw(), hal::LevelQ15FromByte(static_cast<uint16_t>(last % 256)));
  }
}

// The same for DMX: frames of a recording decoded by the DMX decoder
// (DmxReplaySource, which shares its frame -> change core with the OLA
// source), three 16-bit moving spots patched to the bake's luminaires.
TEST(ChangePath, ADmxFrameReachesTheEngineWithoutAllocating) {
  const std::string bake = RELIGHT_TEST_HIER_BAKE;
  if (!FileExists(bake)) GTEST_SKIP() << "no bake at " << bake << " (ctest's MakeLivingRoomHierBake makes it)";
  Engine engine;
  ASSERT_TRUE(engine.Open(bake, NoBounceTable()).ok());
  ASSERT_EQ(engine.luminaire_count(), 3);
  // DMX fixture d (address 1 + 20 d) is luminaire 2 - d.
  std::string patch_text;
  for (int d = 0; d < 3; ++d) {
    patch_text += "[[dmx_fixture]]\nname = \"" + engine.bake().luminaires[2 - d].name + "\"\ntype = \"" +
                  RELIGHT_SOURCE_DIR "/fixtures/dmx/relight-test-spot.toml\"\nmode = \"16 bit\"\nuniverse = 1\n" +
                  "address = " + std::to_string(1 + 20 * d) + "\n";
  }
  hal::DmxPatch dmx;
  const Status parsed = hal::ParseDmxPatch(patch_text, "alloc_dmx.toml", &dmx);
  ASSERT_TRUE(parsed.ok()) << parsed.message();
  std::vector<std::string> names;
  for (const hal::DmxFixturePatch& f : dmx.fixtures) names.push_back(f.name);
  // Frame k: every spot moves (pan, tilt, dimmer, cyan), 44 frames/s.
  const int kFrames = 2000;
  const std::string rec_path = ::testing::TempDir() + "/alloc.dmxrec";
  {
    std::ofstream rec(rec_path);
    for (int k = 0; k < kFrames; ++k) {
      rec << (int64_t{k} * 22727) << " 1";
      for (int d = 0; d < 3; ++d) {
        char run[64];
        const unsigned pan = (1000u + 97u * static_cast<unsigned>(k) + 5000u * d) & 0xFFFF;
        const unsigned tilt = (60000u - 31u * static_cast<unsigned>(k)) & 0xFFFF;
        std::snprintf(run, sizeof run, " %d=%04x%04x%04x%02x0000001fff", 1 + 20 * d, (k * 33) & 0xFFFF, pan, tilt,
                      k % 256);
        rec << run;
      }
      rec << "\n";
    }
  }
  hal::DmxReplaySource source(std::move(dmx), rec_path);
  ASSERT_TRUE(source.Start().ok());
  hal::Patch none;  // no Modbus patch: every luminaire with defaults
  ChangePath path;
  ASSERT_TRUE(path.Bind(&engine, none.fixtures, nullptr).ok());
  BoundInput input{&source, {}};
  ASSERT_TRUE(BindNames(engine, names, "alloc_dmx.toml", &input.luminaire_of).ok());
  EXPECT_EQ(input.luminaire_of, (std::vector<uint16_t>{2, 1, 0}));
  (void)path.Poll(input, 0, 0);  // the first frame (its zoom: SetZoom's kUnsupported, these luminaires have none)
  (void)path.Apply(0);
  engine.Update();

  g_allocations = 0;
  g_count_allocations = true;
  size_t applied = 0;
  for (int k = 1; k < kFrames; ++k) {
    const int64_t t_us = int64_t{k} * 22727;
    (void)path.Poll(input, t_us, t_us);
    applied += path.Apply(t_us);
    engine.Update();
  }
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0) << "heap allocations on the DMX per-change path";
  EXPECT_GT(applied, size_t{kFrames} * 3 * 3);
  EXPECT_TRUE(source.Finished());
  const int k = kFrames - 1;
  for (int d = 0; d < 3; ++d) {
    const FixtureState s = engine.state(2 - d);
    const unsigned pan = (1000u + 97u * static_cast<unsigned>(k) + 5000u * d) & 0xFFFF;
    EXPECT_EQ(s.pan_deg, Wrapped(ConsoleToDegrees(static_cast<uint16_t>(pan), 540 << 16))) << d;
    EXPECT_EQ(s.tilt_deg, Wrapped(ConsoleToDegrees(static_cast<uint16_t>((60000u - 31u * k) & 0xFFFF), 270 << 16)))
        << d;
    EXPECT_EQ(s.dimmer.raw(), static_cast<int>(((k * 33 & 0xFFFF) * 32767 + 32767) / 65535)) << d;
    EXPECT_EQ(s.rgb[0].raw(), 32767 - static_cast<int>(((k % 256) * 257 * 32767 + 32767) / 65535)) << d;
  }
  std::remove(rec_path.c_str());
}


// Issue 15: an emitter patched like a fixture ([[emitter]]), moved,
// switched, dimmed and re-coloured 1,000 times by register writes through
// the same path: the coalesced engine calls (a clip, a solve at Update, a
// rescale or a removal) allocate nothing either. Off at the end, the vertex
// luminance is the one before it was ever placed, bit for bit.
TEST(ChangePath, EmitterChangesReachTheEngineWithoutAllocating) {
  const std::string bake = RELIGHT_TEST_HIER_BAKE;
  if (!FileExists(bake)) GTEST_SKIP() << "no bake at " << bake << " (ctest's MakeLivingRoomHierBake makes it)";
  Engine engine;
  ASSERT_TRUE(engine.Open(bake, NoBounceTable()).ok());
  hal::Patch patch;
  const std::string text =
      "[[emitter]]\nname = \"panel\"\nsurface = \"room/+x\"\ncentre = [6.0, 2.2, 1.5]\nwidth = 1.2\n"
      "height = 0.9\nluminance = [2500, 2400, 2200]\nx_range_m = [-1.4, 1.4]\ny_range_m = [-0.4, 0.4]\n"
      "size_range = [0.4, 1.0]\ndimmer = 0\nmodbus_base = 100\n";
  ASSERT_TRUE(hal::ParsePatch(text, "emitter_alloc.toml", &patch).ok());
  std::vector<hal::LuminaireConsole> luminaires;
  for (const BakeLuminaire& l : engine.bake().luminaires) luminaires.push_back({l.name, l.pan_range, l.tilt_range});
  ASSERT_TRUE(hal::ResolvePatch(luminaires, &patch).ok());
  hal::RegisterMap map;
  ASSERT_TRUE(hal::RegisterMap::Build(patch.fixtures, &map).ok());
  hal::MockSource mock(patch, std::vector<uint16_t>(static_cast<size_t>(map.holding_count()), 0));
  ASSERT_TRUE(mock.Start().ok());
  ChangePath path;
  const Status bound = path.Bind(&engine, patch.fixtures, nullptr, patch.emitters, "emitter_alloc.toml");
  ASSERT_TRUE(bound.ok()) << bound.ToString();
  ASSERT_EQ(path.emitters().count(), 1);
  const BoundInput input{&mock, path.patch_luminaires()};
  (void)path.Apply(0);
  engine.Update();
  const LuminanceView view = engine.vertex_luminance();
  const std::vector<int32_t> before(view.begin(), view.end());

  // Registers from 100: dimmer, x, y, size, r, g, b (the emitter layout).
  g_allocations = 0;
  g_count_allocations = true;
  int64_t t_us = 1000;
  int solves = 0;
  constexpr int kChanges = 1000;
  for (int i = 0; i < kChanges; ++i, t_us += 1000) {
    switch (i % 5) {
      case 0: EXPECT_EQ(mock.SetHoldingRegister(100, static_cast<uint16_t>(20000 + 40 * i), t_us), 0); break;  // on/dim
      case 1:  // a move: x and y in one frame, one solve
        EXPECT_EQ(mock.SetHoldingRegister(101, static_cast<uint16_t>(65 * i), t_us), 0);
        EXPECT_EQ(mock.SetHoldingRegister(102, static_cast<uint16_t>(65535 - 60 * i), t_us), 0);
        break;
      case 2: EXPECT_EQ(mock.SetHoldingRegister(103, static_cast<uint16_t>(64 * i), t_us), 0); break;  // size
      case 3: EXPECT_EQ(mock.SetHoldingRegister(105, static_cast<uint16_t>(i % 256), t_us), 0); break;  // green
      default: EXPECT_EQ(mock.SetHoldingRegister(100, 0, t_us), 0); break;  // off
    }
    (void)path.Poll(input, t_us, t_us);
    (void)path.Apply(t_us);
    engine.Update();
    solves += engine.last_update_emitters_solved();
  }
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0) << "heap allocations on the emitter path";
  EXPECT_EQ(path.rejected(), 0);
  // Moved at i % 5 == 1 and resized at 2 (a solve each), re-coloured at 3 (a
  // rescale), off at 4; on at 0 places it back where it went off, so the
  // engine restores the slot's stored solution (no solve) except the first time.
  EXPECT_EQ(solves, 2 * kChanges / 5 + 1);
  EXPECT_EQ(path.emitters().engine_calls(), kChanges);
  EXPECT_FALSE(path.emitters().on(0));
  const LuminanceView after = engine.vertex_luminance();
  EXPECT_TRUE(std::equal(before.begin(), before.end(), after.begin())) << "off is not the state before";
}

}  // namespace
}  // namespace relight::control
