// Issue 17 faults through the relightd process.
// - The bake file under a running relightd is truncated, replaced by garbage,
//   then by another valid bake, with a SIGHUP after each. What must survive:
//   the process, its Modbus server and the look it shows (the raw frame
//   stream) through both bad files; the valid bake is taken.
// - A replay script and a DMX recording with a line a megabyte long: relightd
//   refuses to start with the file:line and the length, and exits cleanly.
#include <gtest/gtest.h>
#include <modbus/modbus.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <regex>

#include "bake_reload.h"
#include "relight/bake/bake.h"
#include "relight/hal/register_map.h"
#include "relightd_process.h"

namespace relight::daemon {
namespace {

using testing::ReadAll;
using testing::Relightd;
using testing::WriteTemp;

constexpr int kWidth = 64, kHeight = 48;
constexpr size_t kFrameBytes = size_t{kWidth} * kHeight * 3;

// The raw stream's frames so far and the last whole one.
struct Frames {
  size_t count = 0;
  std::string last;
};
Frames ReadFrames(const std::string& path) {
  const std::string all = ReadAll(path);
  Frames f;
  f.count = all.size() / kFrameBytes;
  if (f.count > 0) f.last = all.substr((f.count - 1) * kFrameBytes, kFrameBytes);
  return f;
}

// Waits until at least `more` frames past `after` are out; the last one.
std::string FrameAfter(const std::string& path, size_t after, size_t more) {
  for (int i = 0; i < 3000; ++i) {
    const Frames f = ReadFrames(path);
    if (f.count >= after + more) return f.last;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ADD_FAILURE() << "the frame stream stopped at " << ReadFrames(path).count << " frames";
  return "";
}

// Waits until the last frame differs from `old` (a change was drawn).
std::string ChangedFrame(const std::string& path, const std::string& old) {
  for (int i = 0; i < 3000; ++i) {
    const Frames f = ReadFrames(path);
    if (f.count > 0 && f.last != old) return f.last;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ADD_FAILURE() << "the frame never changed";
  return old;
}

// The port of the newest Modbus server in the log: a SIGHUP re-reads the
// patch, which restarts its server (on a new port when the patch says 0).
int LatestPort(const std::string& log) {
  static const std::regex re("listening on 127\\.0\\.0\\.1:([0-9]+)");
  int port = 0;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), re); it != std::sregex_iterator(); ++it) {
    port = std::atoi((*it)[1].str().c_str());
  }
  return port;
}

modbus_t* Connect(int port) {
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  modbus_set_response_timeout(ctx, 2, 0);
  EXPECT_EQ(modbus_connect(ctx), 0) << "port " << port;
  return ctx;
}

void Disconnect(modbus_t* ctx) {
  modbus_close(ctx);
  modbus_free(ctx);
}

TEST(RelightdFaults, BadBakesOnSighupAreRefusedAndTheOldLookStays) {
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir();
  const std::string bake = dir + "/fault_room.rlb";
  const std::string frames = dir + "/fault_frames.raw";
  fs::copy_file(testing::CornellBake(), bake, fs::copy_options::overwrite_existing);
  const std::string good = ReadAll(bake);
  // No fades: a write shows at the next frame.
  const std::string patch = WriteTemp("fault_live.toml", "[[fixture]]\nname = \"spot\"\n[modbus_tcp]\nport = 0\n");
  Relightd d({bake, "--patch", patch, "--fps", "20", "--width", std::to_string(kWidth), "--height",
              std::to_string(kHeight), "--raw", frames},
             "relightd_bake_fault.log");
  ASSERT_GT(std::atoi(d.WaitForLog("listening on 127\\.0\\.0\\.1:([0-9]+)").c_str()), 0);
  const std::string look = FrameAfter(frames, 0, 3);
  ASSERT_EQ(look.size(), kFrameBytes);

  // 1. Truncated in place (a copy cut short).
  ASSERT_EQ(truncate(bake.c_str(), static_cast<off_t>(good.size() / 2)), 0);
  d.Signal(SIGHUP);
  ASSERT_TRUE(d.WaitForLogCount("bake reload refused, keeping the running bake: .*fault_room\\.rlb", 1));
  // 2. Replaced by garbage of the same size (renamed over it, as a copy tool does).
  std::string garbage(good.size(), '\0');
  std::mt19937 rng(17);
  for (char& c : garbage) c = static_cast<char>(rng());
  WriteTemp("fault_garbage.tmp", garbage);
  fs::rename(dir + "/fault_garbage.tmp", bake);
  d.Signal(SIGHUP);
  ASSERT_TRUE(d.WaitForLogCount("bake reload refused, keeping the running bake: .*fault_room\\.rlb", 2));
  ASSERT_TRUE(d.WaitForLogCount("patch .*fault_live\\.toml reloaded", 2));
  EXPECT_NE(d.log().find("header: the file has"), std::string::npos) << "the truncation is named";
  EXPECT_NE(d.log().find("bad magic"), std::string::npos) << "the garbage is named";

  // Still running, still drawing the same look, still serving Modbus.
  EXPECT_TRUE(d.Running());
  const size_t before = ReadFrames(frames).count;
  EXPECT_EQ(FrameAfter(frames, before, 3), look) << "the look changed after refused bakes";
  modbus_t* ctx = Connect(LatestPort(d.log()));
  uint16_t regs[hal::kRegistersPerFixture] = {};
  ASSERT_EQ(modbus_read_registers(ctx, 0, hal::kRegistersPerFixture, regs), hal::kRegistersPerFixture);
  ASSERT_EQ(modbus_write_register(ctx, hal::kRegDimmer, 20000), 1);
  const std::string dimmed = ChangedFrame(frames, look);
  EXPECT_NE(dimmed, look);

  // 3. A valid bake with the same luminaire, its display white 4x higher
  // (so it looks darker): taken, and the dimmer written before stays.
  Bake next;
  ASSERT_TRUE(ReadBake(testing::CornellBake(), &next).ok());
  next.white_luminance *= 4;
  ASSERT_TRUE(WriteBake(next, dir + "/fault_next.rlb").ok());
  fs::rename(dir + "/fault_next.rlb", bake);
  Disconnect(ctx);
  d.Signal(SIGHUP);
  d.WaitForLog("bake .*fault_room\\.rlb reloaded");
  ASSERT_TRUE(d.WaitForLogCount("patch .*fault_live\\.toml reloaded", 3));
  ctx = Connect(LatestPort(d.log()));
  const std::string taken = ChangedFrame(frames, dimmed);
  EXPECT_NE(taken, dimmed);
  EXPECT_NE(taken, std::string(kFrameBytes, '\0')) << "a black frame after the reload";
  long sum_dimmed = 0, sum_taken = 0;
  for (size_t i = 0; i < kFrameBytes; ++i) {
    sum_dimmed += static_cast<unsigned char>(dimmed[i]);
    sum_taken += static_cast<unsigned char>(taken[i]);
  }
  EXPECT_LT(sum_taken, sum_dimmed) << "a higher display white must darken the frame";
  ASSERT_EQ(modbus_read_registers(ctx, hal::kRegDimmer, 1, regs), 1);
  EXPECT_EQ(regs[0], 20000) << "the dimmer written before the reload";
  EXPECT_TRUE(d.Running());

  Disconnect(ctx);
  d.Signal(SIGTERM);
  EXPECT_EQ(d.Wait(), 0) << d.log();
  std::printf("%s", d.log().c_str());
}

// ReloadBake itself: unchanged files are not read again, another rig is
// refused naming the file, the engine keeps its bake and state on any error.
TEST(BakeReload, RefusesAnotherRigAndKeepsTheEngineOnErrors) {
  namespace fs = std::filesystem;
  const std::string path = ::testing::TempDir() + "/reload_unit.rlb";
  fs::copy_file(testing::CornellBake(), path, fs::copy_options::overwrite_existing);
  BakeFileId id = StatBakeFile(path);
  Engine engine;
  ASSERT_TRUE(engine.Open(path).ok());
  ASSERT_TRUE(engine.SetDimmer(0, Q1_15::FromRatio(1, 4)).ok());
  BakeReload result = BakeReload::kTaken;
  ASSERT_TRUE(ReloadBake(path, &engine, &id, &result).ok());
  EXPECT_EQ(result, BakeReload::kUnchanged);

  Bake other;
  ASSERT_TRUE(ReadBake(path, &other).ok());
  other.luminaires[0].name = "another_spot";
  ASSERT_TRUE(WriteBake(other, path).ok());
  const BakeFileId before = id;
  Status st = ReloadBake(path, &engine, &id, &result);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find(path + ": the bake's luminaires differ"), std::string::npos) << st.message();
  EXPECT_TRUE(id == before) << "a refused file must be read again at the next SIGHUP";
  EXPECT_EQ(engine.bake().luminaires[0].name, "spot");

  fs::remove(path);
  st = ReloadBake(path, &engine, &id, &result);
  EXPECT_EQ(st.code(), StatusCode::kNotFound) << st.ToString();
  EXPECT_NE(st.message().find(path), std::string::npos) << st.message();

  // The same rig again, brighter white: taken, the dimmer kept.
  other.luminaires[0].name = "spot";
  other.white_luminance *= 2;
  ASSERT_TRUE(WriteBake(other, path).ok());
  ASSERT_TRUE(ReloadBake(path, &engine, &id, &result).ok());
  EXPECT_EQ(result, BakeReload::kTaken);
  EXPECT_EQ(engine.bake().white_luminance, other.white_luminance);
  EXPECT_EQ(engine.state(0).dimmer.raw(), Q1_15::FromRatio(1, 4).raw());
  EXPECT_TRUE(id == StatBakeFile(path));
}

std::string MegabyteLine(const std::string& item) {
  std::string line = "0";
  while (line.size() < (1u << 20)) line += " " + item;
  return line;
}

TEST(RelightdFaults, ReplayScriptWithAMegabyteLineIsRefusedNamingFileAndLine) {
  const std::string script = WriteTemp("fault_long.replay", "0 spot.dimmer=0.5\n" + MegabyteLine("spot.pan=1") + "\n");
  Relightd d({testing::CornellBake(), "--replay", script, "--fps", "10", "--width", "64", "--height", "48",
              "--exit-when-replay-done", "--script-time"},
             "relightd_long_replay.log");
  const int code = d.Wait();
  EXPECT_GT(code, 0) << d.log();
  EXPECT_LT(code, 128) << "killed by a signal:\n" << d.log();
  EXPECT_NE(d.log().find("fault_long.replay:2: line is"), std::string::npos) << d.log();
  EXPECT_NE(d.log().find("more than the limit"), std::string::npos) << d.log();
}

TEST(RelightdFaults, DmxRecordingWithAMegabyteLineIsRefusedNamingFileAndLine) {
  const std::string patch = WriteTemp("fault_dmx.toml", std::string("[[dmx_fixture]]\nname = \"spot\"\ntype = \"") +
                                                            RELIGHT_SOURCE_DIR +
                                                            "/fixtures/dmx/relight-test-spot.toml\"\n"
                                                            "mode = \"16 bit\"\nuniverse = 1\naddress = 10\n");
  const std::string recording = WriteTemp("fault_long.dmxrec", "0 1 10=ff\n" + MegabyteLine("10=ff") + "\n");
  Relightd d({testing::CornellBake(), "--dmx", patch, "--dmx-replay", recording, "--fps", "10", "--width", "64",
              "--height", "48", "--exit-when-replay-done", "--script-time"},
             "relightd_long_dmxrec.log");
  const int code = d.Wait();
  EXPECT_GT(code, 0) << d.log();
  EXPECT_LT(code, 128) << "killed by a signal:\n" << d.log();
  EXPECT_NE(d.log().find("fault_long.dmxrec:2: line is"), std::string::npos) << d.log();
  // The same patch with a good recording plays: only the bad line was at fault.
  const std::string good = WriteTemp("fault_good.dmxrec", "0 1 10=ff\n100000 1 10=80\n");
  Relightd ok({testing::CornellBake(), "--dmx", patch, "--dmx-replay", good, "--fps", "10", "--width", "64",
               "--height", "48", "--exit-when-replay-done", "--script-time"},
              "relightd_good_dmxrec.log");
  EXPECT_EQ(ok.Wait(), 0) << ok.log();
}

}  // namespace
}  // namespace relight::daemon
