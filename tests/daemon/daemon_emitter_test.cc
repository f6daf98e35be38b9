// Issue 15: relightd drives a run-time emitter ([[emitter]] in the patch)
// from its inputs. A replay script and Modbus TCP writes switch a panel on
// the living room's wall on, move it and switch it off; the vertex luminance
// rises where the panel is (and nowhere near as much elsewhere), follows it
// when it moves, and is the state before, bit for bit, once it is off.
// Runs on the living room's hierarchical bake (MakeLivingRoomHierBake).
#include <gtest/gtest.h>

#include <modbus/modbus.h>

#include <sys/stat.h>

#include <chrono>
#include <cstdint>
#include <array>
#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "daemon.h"
#include "relight/hal/modbus_tcp_server.h"

namespace relight::daemon {
namespace {

// The panel on the wall x = 6 m (u = +y, v = +z): 1.2 x 0.9 m about (2.2, 1.5),
// x moves it -1.4..+1.4 m along y, y -0.4..+0.4 m along z, size scales 0.4..1.
const char* kPatch = R"([[emitter]]
name = "panel"
surface = "room/+x"
centre = [6.0, 2.2, 1.5]
width = 1.2
height = 0.9
luminance = [2500, 2400, 2200]
x_range_m = [-1.4, 1.4]
y_range_m = [-0.4, 0.4]
size_range = [0.4, 1.0]
dimmer = 0
modbus_base = 100
)";

bool FileExists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// Named after the test too: ctest runs these tests in parallel processes.
std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path =
      ::testing::TempDir() + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

DaemonConfig Config(const std::string& patch_text) {
  DaemonConfig c;
  c.bake_path = RELIGHT_TEST_HIER_BAKE;
  c.patch_path = WriteTemp("emitter_patch.toml", patch_text);
  c.width = 96;
  c.height = 72;
  c.fps = 2;
  // The engine's later-bounce table changes how many sweeps a placement
  // takes, not what these tests check, and costs ~2.5 s of start-up (40 s
  // under ASan); AReplaySwitchesAndMovesAPanel keeps it, as relightd does.
  c.emitter_bounce_table_bytes = 0;
  return c;
}

using Luminance = std::vector<int32_t>;

Luminance Snapshot(const Engine& engine) {
  const LuminanceView v = engine.vertex_luminance();
  return Luminance(v.begin(), v.end());
}

// Where the light rose most from `base` to `lit`: that vertex's position (metres).
std::array<double, 3> Brightest(const Engine& engine, const Luminance& base, const Luminance& lit) {
  const std::vector<int32_t>& pos = engine.bake().mesh.positions;
  int64_t best = -1;
  size_t at = 0;
  for (size_t v = 0; v < lit.size() / 3; ++v) {
    const int64_t rise = int64_t{lit[3 * v + 1]} - base[3 * v + 1];
    if (rise > best) best = rise, at = v;
  }
  return {pos[3 * at] / 65536.0, pos[3 * at + 1] / 65536.0, pos[3 * at + 2] / 65536.0};
}

// The panel's rectangle on the wall: y and z extents for levels x, y, size.
void ExpectInside(const std::array<double, 3>& p, double x_level, double y_level, double size_level) {
  const double cy = 2.2 + (-1.4 + 2.8 * x_level), cz = 1.5 + (-0.4 + 0.8 * y_level);
  const double scale = 0.4 + 0.6 * size_level;
  EXPECT_NEAR(p[0], 6.0, 1e-3) << "the brightest vertex is not on the wall";
  EXPECT_LE(std::abs(p[1] - cy), 0.6 * scale + 0.25) << "y " << p[1] << " vs panel centre " << cy;
  EXPECT_LE(std::abs(p[2] - cz), 0.45 * scale + 0.25) << "z " << p[2] << " vs panel centre " << cz;
}

TEST(DaemonEmitter, AReplaySwitchesAndMovesAPanel) {
  if (!FileExists(RELIGHT_TEST_HIER_BAKE)) GTEST_SKIP() << "no bake (ctest's MakeLivingRoomHierBake makes it)";
  DaemonConfig c = Config(kPatch);
  c.emitter_bounce_table_bytes = kDefaultEmitterBounceTableBytes;  // as relightd runs
  c.replay_path = WriteTemp("emitter.replay",
                            "0.0 ceiling_wide.dimmer=0.3\n"
                            "1.0 panel.dimmer=1\n"
                            "2.0 panel.x=0.1 panel.y=0.8   # one move: one solve\n"
                            "3.0 panel.colour=1,0.5,0.25\n"
                            "4.0 panel.dimmer=0\n");
  c.script_time = true;
  c.exit_when_replay_done = true;
  Daemon d;
  const Status opened = d.Open(c);
  ASSERT_TRUE(opened.ok()) << opened.ToString();
  std::map<int64_t, Luminance> at_tick;  // tick (0.5 s each) -> vertex luminance
  std::map<int64_t, int> solved;
  d.SetFrameObserver([&](const FrameInfo& f) {
    at_tick[f.tick] = Snapshot(d.engine());
    solved[f.tick] = f.render_us > 0 ? d.engine().last_update_emitters_solved() : 0;
  });
  std::atomic<bool> stop{false}, reload{false};
  ASSERT_TRUE(d.Start().ok());
  const Status ran = d.Run(stop, reload);
  ASSERT_TRUE(ran.ok()) << ran.ToString();
  ASSERT_GE(at_tick.size(), 9u);

  const Luminance& off = at_tick[0];
  EXPECT_EQ(at_tick[1], off);
  EXPECT_NE(at_tick[2], off) << "switched on at 1 s: no change";
  ExpectInside(Brightest(d.engine(), off, at_tick[2]), 0.5, 0.5, 1.0);  // starts at offset 0
  EXPECT_NE(at_tick[4], at_tick[2]) << "moved at 2 s: no change";
  ExpectInside(Brightest(d.engine(), off, at_tick[4]), 0.1, 0.8, 1.0);
  EXPECT_EQ(solved[4], 1) << "x and y in one frame: one solve";
  EXPECT_EQ(solved[6], 0) << "a colour change rescales, no solve";
  EXPECT_NE(at_tick[6], at_tick[4]);
  EXPECT_EQ(at_tick[8], off) << "switched off: not the light before, bit for bit";
}

// DMX: the panel patched as a DMX fixture (fixtures/dmx/relight-light-panel.toml:
// dimmer, dimmer fine, x, y, size, r, g, b) under the emitter's name, played
// from a recording through the same decoder as live DMX.
TEST(DaemonEmitter, ADmxRecordingSwitchesAndMovesAPanel) {
  if (!FileExists(RELIGHT_TEST_HIER_BAKE)) GTEST_SKIP() << "no bake (ctest's MakeLivingRoomHierBake makes it)";
  DaemonConfig c = Config(kPatch);
  c.dmx_patch_path = WriteTemp("emitter_dmx.toml", "[[dmx_fixture]]\nname = \"panel\"\ntype = \"" RELIGHT_SOURCE_DIR
                                                   "/fixtures/dmx/relight-light-panel.toml\"\nmode = \"8 channel\"\n"
                                                   "universe = 1\naddress = 1\n");
  c.dmx_replay_path = WriteTemp("emitter.dmxrec",
                                "0       1 1=0000808000ffffff\n"  // off; x, y middle, size 0
                                "1000000 1 1=ffff\n"              // on at 1 s
                                "2000000 1 3=1acc\n"              // x 0.1, y 0.8 at 2 s
                                "3000000 1 1=0000\n");            // off at 3 s
  c.script_time = true;
  c.exit_when_replay_done = true;
  Daemon d;
  const Status opened = d.Open(c);
  ASSERT_TRUE(opened.ok()) << opened.ToString();
  std::map<int64_t, Luminance> at_tick;
  d.SetFrameObserver([&](const FrameInfo& f) { at_tick[f.tick] = Snapshot(d.engine()); });
  std::atomic<bool> stop{false}, reload{false};
  ASSERT_TRUE(d.Start().ok());
  const Status ran = d.Run(stop, reload);
  ASSERT_TRUE(ran.ok()) << ran.ToString();
  ASSERT_GE(at_tick.size(), 7u);
  const Luminance& off = at_tick[0];
  EXPECT_NE(at_tick[2], off) << "switched on at 1 s: no change";
  ExpectInside(Brightest(d.engine(), off, at_tick[2]), 0.5, 0.5, 0.0);
  EXPECT_NE(at_tick[4], at_tick[2]) << "moved at 2 s: no change";
  ExpectInside(Brightest(d.engine(), off, at_tick[4]), 0x1a / 255.0, 0xcc / 255.0, 0.0);
  EXPECT_EQ(at_tick[6], off) << "switched off: not the light before, bit for bit";
}

hal::ModbusTcpServer* TcpServerOf(const Daemon& d) {
  for (hal::InputSource* s : d.sources()) {
    if (auto* tcp = dynamic_cast<hal::ModbusTcpServer*>(s)) return tcp;
  }
  return nullptr;
}

TEST(DaemonEmitter, ModbusWritesSwitchAndMoveAPanel) {
  if (!FileExists(RELIGHT_TEST_HIER_BAKE)) GTEST_SKIP() << "no bake (ctest's MakeLivingRoomHierBake makes it)";
  DaemonConfig c = Config(kPatch);
  c.fps = 20;
  c.modbus_port = 0;
  Daemon d;
  const Status opened = d.Open(c);
  ASSERT_TRUE(opened.ok()) << opened.ToString();
  ASSERT_TRUE(d.Start().ok());
  hal::ModbusTcpServer* server = TcpServerOf(d);
  ASSERT_NE(server, nullptr);
  // The panel's block, as the Modbus server starts it: dimmer 0, x at offset 0, y middle, size 1, white.
  const std::vector<uint16_t> regs = server->holding_registers();
  ASSERT_GE(regs.size(), 107u);
  EXPECT_EQ(regs[100], 0);
  EXPECT_EQ(regs[103], 65535);
  EXPECT_EQ(regs[104], 255);

  std::mutex mu;
  Luminance shown;
  int64_t frames = 0;
  d.SetFrameObserver([&](const FrameInfo&) {
    std::lock_guard<std::mutex> lock(mu);
    shown = Snapshot(d.engine());
    ++frames;
  });
  std::atomic<bool> stop{false}, reload{false};
  Status run_status;
  std::thread runner([&] { run_status = d.Run(stop, reload); });
  // The frame after `n` more frames are out.
  const auto after_frames = [&](int n) {
    int64_t seen;
    {
      std::lock_guard<std::mutex> lock(mu);
      seen = frames;
    }
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      std::lock_guard<std::mutex> lock(mu);
      if (frames >= seen + n) return shown;
    }
  };
  const Luminance before = after_frames(2);
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", server->port());
  ASSERT_EQ(modbus_connect(ctx), 0);
  const uint16_t on[4] = {65535, 6554, 52428, 65535};  // dimmer 1, x 0.1, y 0.8, size 1
  ASSERT_EQ(modbus_write_registers(ctx, 100, 4, on), 4);
  const Luminance lit = after_frames(3);
  const uint16_t off = 0;
  ASSERT_EQ(modbus_write_registers(ctx, 100, 1, &off), 1);
  const Luminance dark = after_frames(3);
  modbus_close(ctx);
  modbus_free(ctx);
  stop.store(true);
  runner.join();
  ASSERT_TRUE(run_status.ok()) << run_status.ToString();

  EXPECT_NE(lit, before);
  ExpectInside(Brightest(d.engine(), before, lit), 6554 / 65535.0, 52428 / 65535.0, 1.0);
  EXPECT_EQ(dark, before) << "off again: not the light before, bit for bit";
}

// A patch without [[emitter]] leaves the bake's hierarchy unread (it is most
// of a hierarchical bake's memory); a SIGHUP with a patch that adds one reads
// it, the fixtures keeping their state, and the panel then lights the wall.
TEST(DaemonEmitter, TheHierarchyIsReadOnlyWhenThePatchHasAnEmitter) {
  if (!FileExists(RELIGHT_TEST_HIER_BAKE)) GTEST_SKIP() << "no bake (ctest's MakeLivingRoomHierBake makes it)";
  DaemonConfig c = Config("[[fixture]]\nname = \"ceiling_spot\"\n");
  c.fps = 20;
  Daemon d;
  const Status opened = d.Open(c);
  ASSERT_TRUE(opened.ok()) << opened.ToString();
  EXPECT_FALSE(d.engine().bake().hierarchy.has_value()) << "no emitter in the patch: the hierarchy was read";
  const LightQ12 lum[3] = {LightQ12::FromRaw(1 << 20), LightQ12::FromRaw(1 << 20), LightQ12::FromRaw(1 << 20)};
  SurfaceEmitterShape shape;
  EXPECT_EQ(d.engine().SetSurfaceEmitter(0, shape, lum).code(), StatusCode::kUnsupported);

  ASSERT_TRUE(d.Start().ok());
  std::atomic<int64_t> frames{0};
  std::atomic<bool> hierarchy{false};
  std::mutex mu;
  FixtureState shown;  // fixture 0 as last drawn
  d.SetFrameObserver([&](const FrameInfo& f) {  // on the daemon's thread
    {
      std::lock_guard<std::mutex> lock(mu);
      shown = d.engine().state(0);
    }
    hierarchy.store(d.engine().bake().hierarchy.has_value());
    frames.store(f.frame + 1);
  });
  // Run on this thread, as relightd does: the reload makes a new OSMesa
  // context there, and the Daemon destroys it here.
  std::atomic<bool> stop{false}, reload{false};
  FixtureState before;
  std::thread console([&] {
    while (frames.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    {
      std::lock_guard<std::mutex> lock(mu);
      before = shown;
    }
    std::ofstream(c.patch_path, std::ios::binary | std::ios::trunc)
        << "[[fixture]]\nname = \"ceiling_spot\"\n\n" << kPatch;
    reload.store(true);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!hierarchy.load() && std::chrono::steady_clock::now() < give_up) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    stop.store(true);  // (no input moves: after the reload's frame the loop waits for one)
  });
  const Status run_status = d.Run(stop, reload);
  console.join();
  ASSERT_TRUE(run_status.ok()) << run_status.ToString();
  EXPECT_EQ(d.stats().reload_failures, 0);
  ASSERT_TRUE(d.engine().bake().hierarchy.has_value()) << "the patch's emitter did not bring the hierarchy";
  EXPECT_EQ(d.patch().emitters.size(), 1u);
  const FixtureState after = d.engine().state(0);
  EXPECT_EQ(after.dimmer, before.dimmer) << "the fixture lost its state when the bake was read again";
  EXPECT_EQ(after.pan_deg, before.pan_deg);
  EXPECT_EQ(after.tilt_deg, before.tilt_deg);

  // The panel now works: the same engine lights the wall through it.
  const Luminance off = Snapshot(d.engine());
  SurfaceEmitterShape panel;
  panel.surface = "room/+x";
  const double corners[4][3] = {{6.0, 1.6, 1.05}, {6.0, 2.8, 1.05}, {6.0, 2.8, 1.95}, {6.0, 1.6, 1.95}};
  for (int k = 0; k < 4; ++k) {
    for (int i = 0; i < 3; ++i) panel.corners_q16[k][i] = static_cast<int32_t>(std::lround(corners[k][i] * 65536));
  }
  panel.corner_count = 4;
  const Status placed = d.engine().SetSurfaceEmitter(0, panel, lum);
  ASSERT_TRUE(placed.ok()) << placed.ToString();
  d.engine().Update();
  EXPECT_NE(Snapshot(d.engine()), off);
}

TEST(DaemonEmitter, AShapeOffItsSurfaceIsAnErrorAtOpenNamingFileLine) {
  if (!FileExists(RELIGHT_TEST_HIER_BAKE)) GTEST_SKIP() << "no bake (ctest's MakeLivingRoomHierBake makes it)";
  // Moved 5 m along y from 2.2, the panel is past the 4.5 m wall (partly past
  // its edge, it would be clipped to it).
  std::string patch = "[[fixture]]\nname = \"ceiling_spot\"\n\n" + std::string(kPatch);
  patch.replace(patch.find("x_range_m = [-1.4, 1.4]"), 23, "x_range_m = [-1.4, 5.0]");
  Daemon d;
  Status st = d.Open(Config(patch));
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("emitter_patch.toml:4: emitter 'panel' at x = 1, y = 0"), std::string::npos)
      << st.message();
  // An unknown surface lists the bake's.
  patch = kPatch;
  patch.replace(patch.find("room/+x"), 7, "room/+w");
  Daemon d2;
  st = d2.Open(Config(patch));
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("emitter_patch.toml:1: emitter 'panel': no surface 'room/+w' in the bake (it has: "),
            std::string::npos)
      << st.message();
}

}  // namespace
}  // namespace relight::daemon
