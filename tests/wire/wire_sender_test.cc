// An independent sender on the wire (issue 12): the npm packages `sacn`
// (E1.31) and `artnet`, written by others, send unicast to 127.0.0.1; olad
// (as nobody, in a private network namespace with a tap device nothing
// reads, so no packet or multicast join leaves the machine) receives them on
// its E1.31 and Art-Net input ports; relightd's DmxOlaSource -> change path
// -> engine must show exactly what was sent: 16-bit dimmer, pan and tilt,
// CMY -> RGB. Junk at the Art-Net port must not get through or stall it.
// Skips (saying why) without olad, node and the installed npm packages
// (the WireNpmInstall fixture), or a network namespace.
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
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <regex>
#include <thread>

#include "daemon_test_support.h"
#include "relight/base/console_value.h"

namespace relight::daemon {
namespace {

using testing::SmallConfig;
using testing::WriteTemp;

const std::string kNodeDir = RELIGHT_WIRE_NODE_DIR;

bool Exists(const std::string& path, int mode = X_OK) { return access(path.c_str(), mode) == 0; }

// The values one frame carries for the Cornell spot, a relight-test-spot
// ("16 bit") at universe 1, address 10: dimmer, dimmer fine, pan, pan fine,
// tilt, tilt fine, C, M, Y, wheel (0: open), zoom, shutter (255: open), gobo.
struct Look {
  uint16_t dimmer16, pan16, tilt16;
  uint8_t c, m, y;
  std::string Csv() const {
    std::string csv = "0,0,0,0,0,0,0,0,0";  // slots 1..9
    for (int v : {dimmer16 >> 8, dimmer16 & 0xFF, pan16 >> 8, pan16 & 0xFF, tilt16 >> 8, tilt16 & 0xFF, int{c},
                  int{m}, int{y}, 0, 255, 255, 0}) {
      csv += "," + std::to_string(v);
    }
    return csv;
  }
};

// Exactly what the engine must hold (the type's ranges: 540 / 270 degrees).
void ExpectShown(const FixtureState& s, const Look& look) {
  const auto level = [](int32_t v16) { return (v16 * 32767 + 32767) / 65535; };
  EXPECT_EQ(s.dimmer.raw(), level(look.dimmer16));
  EXPECT_EQ(s.pan_deg, ConsoleToDegrees(look.pan16, 540 << 16));
  EXPECT_EQ(s.tilt_deg, ConsoleToDegrees(look.tilt16, 270 << 16));
  EXPECT_EQ(s.rgb[0].raw(), 32767 - level(look.c * 257));  // subtractive: R = 1 - C
  EXPECT_EQ(s.rgb[1].raw(), 32767 - level(look.m * 257));
  EXPECT_EQ(s.rgb[2].raw(), 32767 - level(look.y * 257));
}

// Runs a shell command; its standard output.
std::string Output(const std::string& command) {
  std::string out;
  if (FILE* p = popen(command.c_str(), "r")) {
    char buf[512];
    while (fgets(buf, sizeof buf, p) != nullptr) out += buf;
    pclose(p);
  }
  return out;
}

// olad's device id for a plugin, from `ola_dev_info` ("Device 2: E1.31 (DMX over ACN) [...]"); -1: none yet.
int DeviceId(const std::string& name_start) {
  const std::string info = Output("ola_dev_info 2>/dev/null");
  const std::regex line("Device ([0-9]+): " + name_start);
  std::smatch m;
  return std::regex_search(info, m, line) ? std::stoi(m[1]) : -1;
}

template <typename Pred>
bool WaitFor(Pred pred, int timeout_ms) {
  for (int waited = 0; waited < timeout_ms; waited += 20) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return pred();
}

// The npm sender: `repeats` copies of one frame, 25 ms apart (Art-Net: 30), to
// 127.0.0.1; a sender that hangs is killed after 20 s.
int NodeSend(const char* protocol, int universe, const Look& look, int repeats = 4) {
  return std::system(("cd " + kNodeDir + " && timeout 20 node send.js " + protocol + " " + std::to_string(universe) +
                      " 127.0.0.1 " + look.Csv() + " " + std::to_string(repeats) + " 25 > /dev/null")
                         .c_str());
}

// Junk at the Art-Net port: random bytes, ArtDmx with a wrong protocol
// version, one claiming 512 slots in a 20-byte packet, one for another universe.
void SendArtnetJunk() {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(6454);
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  const auto send = [&](const uint8_t* p, size_t n) {
    (void)sendto(fd, p, n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  };
  unsigned seed = 4242;
  uint8_t junk[600];
  for (int i = 0; i < 200; ++i) {
    const size_t n = static_cast<size_t>(rand_r(&seed)) % sizeof junk;
    for (size_t k = 0; k < n; ++k) junk[k] = static_cast<uint8_t>(rand_r(&seed));
    if (i % 2 == 0 && n > 18) std::memcpy(junk, "Art-Net\0\0\x50", 10);  // ArtDmx opcode, random rest
    send(junk, n);
  }
  uint8_t dmx[18 + 512] = {'A', 'r', 't', '-', 'N', 'e', 't', 0, 0x00, 0x50, 0, 13, 0, 0, 1, 0, 2, 0};
  std::memset(dmx + 18, 0x55, 512);
  send(dmx, sizeof dmx);  // version 13
  dmx[11] = 14;
  send(dmx, 20);          // says 512 slots, carries 2
  dmx[14] = 7;
  send(dmx, sizeof dmx);  // universe 7: nobody listens
  close(fd);
}

TEST(WireSender, NpmSacnAndArtnetThroughOladReachTheEngineExactly) {
  for (const char* tool : {"/usr/bin/olad", "/usr/bin/ola_patch", "/usr/bin/ola_dev_info", "/usr/bin/setpriv"}) {
    if (!Exists(tool)) RELIGHT_SKIP_UNLESS_REQUIRED(tool << " missing (apt-get install ola)");
  }
  if (std::system("node --version > /dev/null 2>&1") != 0) RELIGHT_SKIP_UNLESS_REQUIRED("node missing (scripts/setup.sh)");
  if (!Exists(kNodeDir + "/node_modules/sacn/package.json", R_OK) ||
      !Exists(kNodeDir + "/node_modules/artnet/package.json", R_OK)) {
    RELIGHT_SKIP_UNLESS_REQUIRED("the npm senders are not installed in "
                                 << kNodeDir
                                 << " (the WireNpmInstall test installs them; it could not reach the npm "
                                    "registry or its cache)");
  }
  if (unshare(CLONE_NEWNET) != 0) RELIGHT_SKIP_UNLESS_REQUIRED("cannot unshare a network namespace (needs root)");
  ASSERT_EQ(std::system("ip link set lo up"), 0);
  // A tap nothing reads: the plugins bind their devices to it, so their multicast joins and Art-Net
  // polls go nowhere (PITFALLS.md); both still listen on 0.0.0.0, so unicast to 127.0.0.1 arrives.
  ASSERT_EQ(std::system("ip tuntap add dev t0 mode tap && ip addr add 198.18.0.1/24 dev t0 && ip link set t0 up"), 0);

  char tmpl[] = "/tmp/relight-wire-XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl;
  for (const char* p : {"dummy", "espnet", "ftdidmx", "gpio", "karate", "kinet", "milinst", "opendmx",
                        "openpixelcontrol", "osc", "pathport", "renard", "sandnet", "shownet", "spi", "stageprofi",
                        "uartdmx", "usbdmx", "usbserial"}) {
    std::ofstream(dir + "/ola-" + p + ".conf") << "enabled = false\n";
  }
  std::ofstream(dir + "/ola-e131.conf") << "enabled = true\n";
  std::ofstream(dir + "/ola-artnet.conf") << "enabled = true\nip = 198.18.0.1\n";  // net 0, subnet 0
  ASSERT_EQ(std::system(("chown -R nobody:nogroup " + dir).c_str()), 0);
  const pid_t olad = fork();
  if (olad == 0) {
    relight::testing::SendOutputTo(dir + "/olad.log");
    execl("/usr/bin/setpriv", "setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "/usr/bin/olad", "-c",
          dir.c_str(), "--no-http", "--no-register-with-dns-sd", "-l", "1", static_cast<char*>(nullptr));
    _exit(127);
  }
  struct Cleanup {
    pid_t pid;
    std::string dir;
    ~Cleanup() {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
      std::system(("rm -rf " + dir).c_str());
    }
  } cleanup{olad, dir};

  int e131 = -1, artnet = -1;
  ASSERT_TRUE(WaitFor([&] { return (e131 = DeviceId("E1.31")) > 0 && (artnet = DeviceId("ArtNet")) > 0; }, 15000))
      << "olad did not come up with its E1.31 and Art-Net devices:\n" << Output("ola_dev_info 2>&1");

  DaemonConfig c = SmallConfig();
  c.fps = 44;
  c.dmx_patch_path = WriteTemp("wire_patch.toml", "[[dmx_fixture]]\nname = \"spot\"\ntype = \"" RELIGHT_SOURCE_DIR
                                                  "/fixtures/dmx/relight-test-spot.toml\"\nmode = \"16 bit\"\n"
                                                  "universe = 1\naddress = 10\n");
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
  const auto shows = [&](const Look& look) {
    const FixtureState s = snapshot().first;
    return s.pan_deg == ConsoleToDegrees(look.pan16, 540 << 16) && s.tilt_deg == ConsoleToDegrees(look.tilt16, 270 << 16);
  };
  // A console sends continuously: resend until relightd is registered and the frame is through.
  const auto send_until_shown = [&](const char* protocol, const Look& look) {
    return WaitFor([&] { NodeSend(protocol, 1, look); return WaitFor([&] { return shows(look); }, 200); }, 15000);
  };

  // sACN: E1.31 input port 0 -> OLA universe 1 (the E1.31 universe number is the same).
  ASSERT_EQ(std::system(("ola_patch -d " + std::to_string(e131) + " -p 0 -i -u 1").c_str()), 0);
  const Look sacn{0x1234, 0xABCD, 0x01FF, 255, 0, 128};
  ASSERT_TRUE(send_until_shown("sacn", sacn)) << "sACN from the npm sender never reached the engine";
  ExpectShown(snapshot().first, sacn);

  // Art-Net: E1.31 off universe 1, Art-Net input port 0 on it. OLA universe 1 is Art-Net port-address
  // net 0, subnet 0, universe 1 (ola-artnet.conf's net and subnet, the OLA universe mod 16).
  ASSERT_EQ(std::system(("ola_patch -r -d " + std::to_string(e131) + " -p 0 -i -u 1").c_str()), 0);
  ASSERT_EQ(std::system(("ola_patch -d " + std::to_string(artnet) + " -p 0 -i -u 1").c_str()), 0);
  const Look art{0xFEDC, 0x4321, 0xC0DE, 0, 200, 40};
  ASSERT_TRUE(send_until_shown("artnet", art)) << "Art-Net from the npm sender never reached the engine";
  ExpectShown(snapshot().first, art);

  // Junk at the Art-Net port: nothing of it shows, the loop keeps going, the next real frame shows.
  const int64_t before = snapshot().second;
  SendArtnetJunk();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_GT(snapshot().second, before + 5) << "the frame loop stalled";
  ExpectShown(snapshot().first, art);
  const Look after{0x8000, 0x7000, 0x9000, 10, 20, 30};
  ASSERT_TRUE(send_until_shown("artnet", after)) << "Art-Net stopped getting through after the junk";
  ExpectShown(snapshot().first, after);

  stop = true;
  runner.join();
  EXPECT_TRUE(run_status.ok()) << run_status.ToString();
}

}  // namespace
}  // namespace relight::daemon
