// The relightd executable end to end: --help, bad input, SIGHUP reload,
// SIGTERM/SIGINT clean shutdown, a Modbus client writing to the process.
#include <gtest/gtest.h>

#include <modbus/modbus.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <chrono>
#include <cstdlib>
#include <regex>
#include <thread>

#include "daemon_test_support.h"

extern char** environ;

namespace relight::daemon {
namespace {

using testing::ReadAll;
using testing::WriteTemp;

class Relightd {
 public:
  // Starts relightd with `args`, stderr and stdout to a log file.
  explicit Relightd(std::vector<std::string> args, const std::string& log_name)
      : log_(::testing::TempDir() + "/" + log_name) {
    args.insert(args.begin(), RELIGHTD_PATH);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    EXPECT_EQ(posix_spawn(&pid_, RELIGHTD_PATH, &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Relightd() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      Wait();
    }
  }
  // Waits (up to 60 s) until the log matches `pattern`; returns the first group.
  std::string WaitForLog(const std::string& pattern) {
    const std::regex re(pattern);
    for (int i = 0; i < 6000; ++i) {
      std::smatch m;
      const std::string text = ReadAll(log_);
      if (std::regex_search(text, m, re)) return m.size() > 1 ? m[1].str() : m[0].str();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "no '" << pattern << "' in the log:\n" << ReadAll(log_);
    return "";
  }
  void Signal(int sig) { kill(pid_, sig); }
  int Wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::string log() const { return ReadAll(log_); }

 private:
  std::string log_;
  pid_t pid_ = -1;
};

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
