// The relightd executable end to end: --help, bad input, SIGHUP reload,
// SIGTERM/SIGINT clean shutdown, a Modbus client writing to the process.
#include <gtest/gtest.h>

#include <modbus/modbus.h>

#include <cstdlib>

#include "relightd_process.h"

namespace relight::daemon {
namespace {

using testing::ReadAll;
using testing::Relightd;
using testing::WriteTemp;

TEST(Relightd, HelpAndBadInput) {
  {
    Relightd d({"--help"}, "relightd_help.log");
    EXPECT_EQ(d.Wait(), 0);
    EXPECT_NE(d.log().find("--exit-when-replay-done"), std::string::npos);
  }
  {
    Relightd d({"/nonexistent/room.rlb"}, "relightd_nobake.log");
    EXPECT_EQ(d.Wait(), 2);
    EXPECT_NE(d.log().find("/nonexistent/room.rlb"), std::string::npos) << d.log();
  }
  {
    Relightd d({testing::CornellBake(), "--png", "frames.png", "--frames", "1"}, "relightd_badpng.log");
    EXPECT_EQ(d.Wait(), 2);
    EXPECT_NE(d.log().find("one %d"), std::string::npos) << d.log();
  }
  {
    const std::string patch = WriteTemp("relightd_bad.toml", "[modbus_tcp]\nport = \"x\"\n");
    Relightd d({testing::CornellBake(), "--patch", patch}, "relightd_badpatch.log");
    EXPECT_EQ(d.Wait(), 2);
    EXPECT_NE(d.log().find("relightd_bad.toml:2"), std::string::npos) << d.log();
  }
}

TEST(Relightd, ServesModbusReloadsOnSighupAndStopsCleanlyOnSigterm) {
  const std::string patch = WriteTemp("relightd_live.toml", "[[fixture]]\nname = \"spot\"\n[modbus_tcp]\nport = 0\n");
  Relightd d({testing::CornellBake(), "--patch", patch, "--fps", "20", "--width", "64", "--height", "48", "--raw",
              "/dev/null"},
             "relightd_live.log");
  const int port = std::atoi(d.WaitForLog("listening on 127\\.0\\.0\\.1:([0-9]+)").c_str());
  ASSERT_GT(port, 0);
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  ASSERT_EQ(modbus_connect(ctx), 0);
  ASSERT_EQ(modbus_write_register(ctx, hal::kRegDimmer, 1234), 1);
  // The frame counter moves and the latency of that write is published.
  uint16_t status[4] = {};
  for (int i = 0; i < 500 && status[3] == 0 && status[2] == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_EQ(modbus_read_input_registers(ctx, 0, 4, status), 4);
  }
  EXPECT_GT((uint32_t{status[2]} << 16) | status[3], 0u) << "latency status register";
  modbus_close(ctx);
  modbus_free(ctx);

  d.Signal(SIGHUP);
  d.WaitForLog("patch .*relightd_live\\.toml reloaded");
  d.Signal(SIGTERM);
  EXPECT_EQ(d.Wait(), 0);
  EXPECT_NE(d.log().find("stopped by signal"), std::string::npos) << d.log();
}

TEST(Relightd, ReplayRunExitsByItselfAndSigintStopsAnEndlessOne) {
  const std::string script = WriteTemp("relightd.replay", "0 spot.dimmer=0.5\n0.2 spot.pan=30\n");
  const std::string pattern = ::testing::TempDir() + "/relightd_%02d.png";
  {
    // Script time: frames at 0, 0.1 and 0.2 s whatever the machine's load.
    Relightd d({testing::CornellBake(), "--replay", script, "--fps", "10", "--width", "64", "--height", "48", "--png",
                pattern, "--exit-when-replay-done", "--script-time"},
               "relightd_replay.log");
    EXPECT_EQ(d.Wait(), 0) << d.log();
    EXPECT_NE(d.log().find("3 frames"), std::string::npos) << d.log();
  }
  {
    // Real time exits by itself too; on a loaded machine ticks may be
    // skipped, so only the exit is checked here.
    Relightd d({testing::CornellBake(), "--replay", script, "--fps", "10", "--width", "64", "--height", "48",
                "--exit-when-replay-done"},
               "relightd_replay_realtime.log");
    EXPECT_EQ(d.Wait(), 0) << d.log();
    EXPECT_NE(d.log().find(" frames, "), std::string::npos) << d.log();
  }
  {
    Relightd d({testing::CornellBake(), "--replay", script, "--fps", "10", "--width", "64", "--height", "48"},
               "relightd_endless.log");
    d.WaitForLog("inputs: replay");
    d.Signal(SIGINT);
    EXPECT_EQ(d.Wait(), 0) << d.log();
  }
}

}  // namespace
}  // namespace relight::daemon
