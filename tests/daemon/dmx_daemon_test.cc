// DMX into relightd (issue 12): a DMX patch bound to the bake's luminaires,
// a DMX replay played in script time, and — over the wire — an independent
// sender (OLA's ola_streaming_client) -> olad -> DmxOlaSource -> the change
// path -> the engine, whose state must equal the values sent, exactly,
// including 16-bit pan/tilt and CMY -> RGB. olad runs as nobody in a
// private network namespace (E1.31 plugin on a tap device nothing reads, so
// no multicast join leaves the machine); garbage UDP on the E1.31 port,
// short frames, a sender that stops and olad killed and restarted must not
// crash or stall the daemon. Skips where olad or namespaces are unavailable.
#include <arpa/inet.h>
#include <gtest/gtest.h>

#include "common/child_output.h"
#include "common/required_or_skip.h"
#include <netinet/in.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include "daemon_test_support.h"
#include "relight/base/console_value.h"

namespace relight::daemon {
namespace {

using testing::CornellBake;
using testing::SmallConfig;
using testing::WriteTemp;

// The Cornell box's one luminaire as a relight-test-spot ("16 bit") at
// universe 1, address 10: dimmer, dimmer fine, pan, pan fine, tilt, tilt
// fine, C, M, Y, wheel, zoom, shutter, gobo.
std::string SpotPatch(const std::string& file, const std::string& dmx_section = "") {
  return WriteTemp(file, dmx_section +
                                                "[[dmx_fixture]]\nname = \"spot\"\ntype = \"" RELIGHT_SOURCE_DIR
                                                "/fixtures/dmx/relight-test-spot.toml\"\nmode = \"16 bit\"\n"
                                                "universe = 1\naddress = 10\n");
}

// What the engine must show for dimmer 0x1234, pan 0xABCD, tilt 0x01FF,
// C 255 M 0 Y 128 (the type's ranges: 540 / 270 degrees; 92.4 and -132.9
// degrees, inside the engine's wrap to -180..180).
void ExpectSent(const FixtureState& s) {
  EXPECT_EQ(s.dimmer.raw(), (0x1234 * 32767 + 32767) / 65535);
  EXPECT_EQ(s.pan_deg, ConsoleToDegrees(0xABCD, 540 << 16));
  EXPECT_EQ(s.tilt_deg, ConsoleToDegrees(0x01FF, 270 << 16));
  EXPECT_EQ(s.rgb[0].raw(), 0);
  EXPECT_EQ(s.rgb[1].raw(), 32767);
  EXPECT_EQ(s.rgb[2].raw(), 32767 - (128 * 257 * 32767 + 32767) / 65535);
}

TEST(DmxDaemon, AMissingLuminaireIsAnErrorNamingThePatchLine) {
  DaemonConfig c = SmallConfig();
  c.dmx_patch_path = WriteTemp("dmx_daemon_bad.toml",
                               "[[dmx_fixture]]\nname = \"spot\"\ntype = \"" RELIGHT_SOURCE_DIR
                               "/fixtures/dmx/relight-test-spot.toml\"\nmode = \"16 bit\"\nuniverse = 1\naddress = 1\n"
                               "[[dmx_fixture]]\nname = \"wash\"\ntype = \"" RELIGHT_SOURCE_DIR
                               "/fixtures/dmx/relight-test-rgbw.toml\"\nmode = \"4 channel\"\nuniverse = 1\n"
                               "address = 20\n");
  c.dmx_replay_path = WriteTemp("dmx_daemon_unused.dmxrec", "0 1 1=00\n");
  Daemon d;
  const Status st = d.Open(c);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find(c.dmx_patch_path + ":7: dmx_fixture: no luminaire 'wash' in the bake (it has: spot)"),
            std::string::npos)
      << st.message();
  DaemonConfig replay_only = SmallConfig();
  replay_only.dmx_replay_path = c.dmx_replay_path;
  EXPECT_NE(Daemon().Open(replay_only).message().find("--dmx-replay needs the DMX patch"), std::string::npos);
}

TEST(DmxDaemon, ADmxReplayDrivesTheEngineInScriptTime) {
  DaemonConfig c = SmallConfig();
  c.fps = 44;
  c.script_time = true;
  c.exit_when_replay_done = true;
  c.dmx_patch_path = SpotPatch("dmx_daemon_replay_patch.toml");
  c.dmx_replay_path = WriteTemp("dmx_daemon.dmxrec",
                                "0 1 10=1234abcd01ffff0080 19=00ffff00\n"
                                "45454 1 12=80 13=00\n");  // frame 2: pan home
  Daemon d;
  ASSERT_TRUE(d.Open(c).ok());
  std::vector<FixtureState> seen;
  d.SetFrameObserver([&](const FrameInfo&) { seen.push_back(d.engine().state(0)); });
  ASSERT_TRUE(testing::RunToEnd(d).ok());
  ASSERT_EQ(seen.size(), 3u);  // frames at 0, 22.7 and 45.5 ms: the last one shows the last frame
  ExpectSent(seen[0]);
  EXPECT_EQ(seen[2].pan_deg.raw(), 0);
  EXPECT_EQ(seen[2].tilt_deg, seen[0].tilt_deg);
}

bool Exists(const char* path) { return access(path, X_OK) == 0; }

class OlaDaemon {
 public:
  explicit OlaDaemon(std::string dir) : dir_(std::move(dir)) {}
  ~OlaDaemon() { Kill(); }
  void Launch() {
    pid_ = fork();
    if (pid_ == 0) {
      relight::testing::SendOutputTo(dir_ + "/olad.log");
      execl("/usr/bin/setpriv", "setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "/usr/bin/olad",
            "-c", dir_.c_str(), "--no-http", "--no-register-with-dns-sd", "-l", "1", static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  void Kill() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);  // as a crash would: no goodbye to the client
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  std::string dir_;
  pid_t pid_ = -1;
};

template <typename Pred>
bool WaitFor(Pred pred, int timeout_ms) {
  for (int waited = 0; waited < timeout_ms; waited += 20) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return pred();
}

int Send(const std::string& csv) {
  return std::system(("ola_streaming_client -u 1 -d " + csv + " > /dev/null 2>&1").c_str());
}

// Junk at olad's E1.31 port: random bytes, a truncated root layer, an
// sACN-looking packet with a bad vector.
void SendGarbage(const char* ip) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(5568);
  inet_pton(AF_INET, ip, &to.sin_addr);
  unsigned seed = 12345;
  uint8_t junk[638];
  for (int i = 0; i < 200; ++i) {
    const size_t n = static_cast<size_t>(rand_r(&seed)) % sizeof junk;
    for (size_t k = 0; k < n; ++k) junk[k] = static_cast<uint8_t>(rand_r(&seed));
    if (i % 3 == 0 && n > 16) std::memcpy(junk + 4, "ASC-E1.17\0\0\0", 12);  // a plausible preamble
    (void)sendto(fd, junk, n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  }
  close(fd);
}

TEST(DmxDaemon, EndToEndOverTheWireThroughOlad) {
  if (!Exists("/usr/bin/olad") || !Exists("/usr/bin/ola_streaming_client") || !Exists("/usr/bin/setpriv")) {
    RELIGHT_SKIP_UNLESS_REQUIRED("olad not installed (apt-get install ola)");
  }
  if (unshare(CLONE_NEWNET) != 0) RELIGHT_SKIP_UNLESS_REQUIRED("cannot unshare a network namespace (needs root)");
  ASSERT_EQ(std::system("ip link set lo up"), 0);
  // A tap nothing reads: the E1.31 plugin binds to it, its multicast joins go nowhere (PITFALLS.md).
  const bool tap = std::system("ip tuntap add dev t0 mode tap 2>/dev/null && ip addr add 198.18.0.1/24 dev t0 && "
                               "ip link set t0 up") == 0;

  char tmpl[] = "/tmp/relight-dmxd-XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl;
  for (const char* p : {"artnet", "dummy", "e131", "espnet", "ftdidmx", "gpio", "karate", "kinet", "milinst",
                        "opendmx", "openpixelcontrol", "osc", "pathport", "renard", "sandnet", "shownet", "spi",
                        "stageprofi", "uartdmx", "usbdmx", "usbserial"}) {
    const bool on = tap && std::string(p) == "e131";
    std::ofstream(dir + "/ola-" + p + ".conf") << "enabled = " << (on ? "true" : "false") << "\n";
  }
  ASSERT_EQ(std::system(("chown -R nobody:nogroup " + dir).c_str()), 0);

  DaemonConfig c = SmallConfig();
  c.fps = 44;
  c.dmx_patch_path = SpotPatch("dmx_daemon_wire_patch.toml", "[dmx]\nloss_timeout_ms = 200\n");  // hold (the default)
  Daemon d;
  ASSERT_TRUE(d.Open(c).ok());
  std::mutex mu;
  FixtureState shown{};
  int64_t frames = 0;
  d.SetFrameObserver([&](const FrameInfo&) {
    std::lock_guard<std::mutex> lock(mu);
    shown = d.engine().state(0);
    ++frames;
  });
  const auto snapshot = [&] {
    std::lock_guard<std::mutex> lock(mu);
    return std::make_pair(shown, frames);
  };
  // No olad yet: relightd starts anyway (a warning) and keeps trying.
  ASSERT_TRUE(d.Start().ok());
  std::atomic<bool> stop{false}, reload{false};
  Status run_status;
  std::thread runner([&] { run_status = d.Run(stop, reload); });
  struct Join {  // a failed ASSERT returns early: stop the loop first
    std::atomic<bool>& stop;
    std::thread& t;
    ~Join() {
      stop = true;
      if (t.joinable()) t.join();
    }
  } join{stop, runner};

  OlaDaemon olad(dir);
  olad.Launch();
  const std::string full = "0,0,0,0,0,0,0,0,0,18,52,171,205,1,255,255,0,128,0,255,255,0";
  const auto shows = [&](uint16_t pan16) {
    return snapshot().first.pan_deg == ConsoleToDegrees(pan16, 540 << 16);
  };
  // A console sends continuously; resend until olad is up and the registration is through.
  ASSERT_TRUE(WaitFor([&] { Send(full); return WaitFor([&] { return shows(0xABCD); }, 200); }, 15000))
      << "the frame never reached the engine";
  ExpectSent(snapshot().first);

  // Bad input: garbage at the E1.31 port, then a short frame (ending at pan fine): pan applied, the rest kept.
  if (tap) {
    SendGarbage("127.0.0.1");
    SendGarbage("198.18.0.1");
  }
  ASSERT_TRUE(WaitFor([&] { Send("0,0,0,0,0,0,0,0,0,18,52,112,0"); return WaitFor([&] { return shows(0x7000); }, 200); },
                      8000));
  FixtureState s = snapshot().first;
  EXPECT_EQ(s.tilt_deg, ConsoleToDegrees(0x01FF, 270 << 16));
  EXPECT_EQ(s.rgb[0].raw(), 0);
  // A frame ending between pan and pan fine: the 16-bit pan needs both bytes, so it stays.
  ASSERT_EQ(Send("0,0,0,0,0,0,0,0,0,18,52,200"), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_TRUE(shows(0x7000));

  // The sender stops, then olad dies: the look is held and frames keep coming.
  const int64_t before = snapshot().second;
  olad.Kill();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_GT(snapshot().second, before + 5) << "the frame loop stalled without olad";
  EXPECT_TRUE(shows(0x7000));
  EXPECT_EQ(snapshot().first.dimmer.raw(), (0x1234 * 32767 + 32767) / 65535);
  // olad comes back: relightd reconnects by itself and the next frame shows.
  olad.Launch();
  ASSERT_TRUE(WaitFor([&] { Send(full); return WaitFor([&] { return shows(0xABCD); }, 200); }, 15000))
      << "no reconnection";
  ExpectSent(snapshot().first);

  stop = true;
  runner.join();
  EXPECT_TRUE(run_status.ok()) << run_status.ToString();
  olad.Kill();
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace relight::daemon
