// A patch with its own register layout, end to end: a console writes roll
// and coarse/fine 16-bit pan and tilt over Modbus TCP to relightd's core, and
// the engine's state must be what the engine's own 16-bit entry point
// (SetPanTilt16, over the bake's console ranges) and SetRoll give.
#include <gtest/gtest.h>

#include <modbus/modbus.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "../runtime/bake_test_bake.h"
#include "daemon_test_support.h"
#include "relight/base/console_value.h"
#include "relight/hal/modbus_tcp_server.h"

namespace relight::daemon {
namespace {

// "spot" of the test bake: not axisymmetric (a C-plane table), console
// ranges 630 (pan) and 265 (tilt) degrees; "wash" has the defaults 540, 270.
constexpr const char* kPatch = R"(
[[fixture]]
name = "spot"
modbus_base = 0
registers = ["dimmer", "pan", "pan_fine", "tilt", "tilt_fine", "roll", "r", "g", "b", "flags"]
roll_range_deg = 360

[modbus_tcp]
port = 0
)";

hal::ModbusTcpServer* TcpServerOf(const Daemon& d) {
  for (hal::InputSource* s : d.sources()) {
    if (auto* tcp = dynamic_cast<hal::ModbusTcpServer*>(s)) return tcp;
  }
  return nullptr;
}

double Degrees(Q16_16 v) { return v.raw() / 65536.0; }

// The float64 meaning of a console value over `range_deg`, wrapped to (-180, 180].
double ConsoleDegrees(uint16_t value, double range_deg) {
  double d = (value - 32768.0) / 65536.0 * range_deg;
  while (d > 180) d -= 360;
  while (d <= -180) d += 360;
  return d;
}

TEST(DaemonPatch, RollAndCoarseFinePanTiltReachTheEngineAsItsOwn16BitPath) {
  const Bake bake = bake_test::MakeBake(7);
  ASSERT_EQ(bake.luminaires[0].name, "spot");
  ASSERT_EQ(bake.luminaires[0].pan_range, 630 << 16);
  ASSERT_EQ(bake.luminaires[0].tilt_range, 265 << 16);
  const std::string bake_path = ::testing::TempDir() + "/daemon_patch_test.rlb";
  ASSERT_TRUE(WriteBake(bake, bake_path).ok());
  DaemonConfig c;  // not SmallConfig(): that bakes the Cornell box
  c.bake_path = bake_path;
  c.width = 64;
  c.height = 48;
  c.fps = 20;
  c.patch_path = testing::WriteTemp("daemon_patch_test.toml", kPatch);
  Daemon d;
  const Status opened = d.Open(c);
  ASSERT_TRUE(opened.ok()) << opened.ToString();
  ASSERT_TRUE(d.Start().ok());
  hal::ModbusTcpServer* server = TcpServerOf(d);
  ASSERT_NE(server, nullptr);
  // The unpatched wash follows the spot's 10 registers with the standard 8.
  ASSERT_EQ(d.register_map().fixture(1).modbus_base, 10);

  modbus_t* ctx = modbus_new_tcp("127.0.0.1", server->port());
  modbus_set_response_timeout(ctx, 2, 0);
  ASSERT_EQ(modbus_connect(ctx), 0);
  // At start-up the registers show the bake's defaults, roll included.
  uint16_t shown[6] = {};
  ASSERT_EQ(modbus_read_registers(ctx, 0, 6, shown), 6);
  const FixtureState start = d.engine().state(0);
  EXPECT_EQ(shown[5], DegreesToConsole(start.roll_deg, 360 << 16));
  EXPECT_EQ(shown[1] << 8 | shown[2], DegreesToConsole(start.pan_deg, 630 << 16));

  std::atomic<bool> stop{false}, reload{false};
  std::atomic<int64_t> frames{0};
  d.SetFrameObserver([&](const FrameInfo& f) { frames.store(f.frame + 1); });
  Status run_status;
  std::thread runner([&] { run_status = d.Run(stop, reload); });

  // One request writes pan coarse, pan fine, tilt coarse, tilt fine and roll,
  // as a console sends a fixture's channels together.
  const uint16_t pan16 = 0x9A3C, tilt16 = 0x6001, roll16 = 32768 + 8192;  // roll +45 degrees over 360
  const uint16_t spot[5] = {pan16 >> 8, pan16 & 0xFF, tilt16 >> 8, tilt16 & 0xFF, roll16};
  EXPECT_EQ(modbus_write_registers(ctx, 1, 5, spot), 5) << modbus_strerror(errno);
  const uint16_t wash[2] = {0x1234, 0xC000};  // the standard block: 16-bit pan and tilt in one register each
  EXPECT_EQ(modbus_write_registers(ctx, 10 + hal::kRegPan, 2, wash), 2) << modbus_strerror(errno);
  // A coarse byte above 255 is refused, and changes nothing.
  const uint16_t too_big = 256;
  EXPECT_EQ(modbus_write_register(ctx, 1, too_big), -1);
  EXPECT_EQ(errno, EMBXILVAL);
  const int64_t seen = frames.load();
  while (frames.load() < seen + 2) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  modbus_close(ctx);
  modbus_free(ctx);
  stop.store(true);
  runner.join();
  ASSERT_TRUE(run_status.ok()) << run_status.ToString();

  Engine reference;
  ASSERT_TRUE(reference.Open(bake).ok());
  ASSERT_TRUE(reference.SetPanTilt16(0, pan16, tilt16).ok());
  ASSERT_TRUE(reference.SetRoll(0, Q16_16::FromInt(45)).ok());
  ASSERT_TRUE(reference.SetPanTilt16(1, wash[0], wash[1]).ok());
  for (int lum = 0; lum < 2; ++lum) {
    const FixtureState got = d.engine().state(lum), want = reference.state(lum);
    EXPECT_EQ(got.pan_deg, want.pan_deg) << lum;
    EXPECT_EQ(got.tilt_deg, want.tilt_deg) << lum;
    EXPECT_EQ(got.roll_deg, want.roll_deg) << lum;
  }
  // Documented precision: the Q16.16 degree nearest the console value.
  const FixtureState s = d.engine().state(0);
  EXPECT_LE(std::fabs(Degrees(s.pan_deg) - ConsoleDegrees(pan16, 630)), 0.5 / 65536 + 1e-12);
  EXPECT_LE(std::fabs(Degrees(s.tilt_deg) - ConsoleDegrees(tilt16, 265)), 0.5 / 65536 + 1e-12);
  EXPECT_EQ(s.roll_deg, Q16_16::FromInt(45));
  EXPECT_LE(std::fabs(Degrees(d.engine().state(1).pan_deg) - ConsoleDegrees(wash[0], 540)), 0.5 / 65536 + 1e-12);
  EXPECT_EQ(server->counters().illegal_value, 1u);
  std::remove(bake_path.c_str());
  std::remove(c.patch_path.c_str());
}

}  // namespace
}  // namespace relight::daemon
