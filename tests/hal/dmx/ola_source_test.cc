// DmxOlaSource against a real olad: olad runs as `nobody` (it refuses root)
// in a private network namespace of this test process, with every plugin
// disabled, so nothing leaves the machine and port 9010 is our own. OLA's
// own ola_streaming_client sends frames through olad; the source must decode
// exactly what was sent, survive olad restarting, and say clearly when olad
// is not there. Skips without olad or without the right to unshare.
#include <gtest/gtest.h>

#include "common/child_output.h"
#include "common/required_or_skip.h"
#include <sched.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "relight/base/clock.h"
#include "relight/hal/dmx/ola_source.h"

namespace relight::hal {
namespace {

const char* const kPlugins[] = {"artnet", "dummy", "e131", "espnet", "ftdidmx", "gpio", "karate",
                                "kinet", "milinst", "opendmx", "openpixelcontrol", "osc", "pathport", "renard",
                                "sandnet", "shownet", "spi", "stageprofi", "uartdmx", "usbdmx", "usbserial"};

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
    kill(pid_, SIGTERM);
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

void Send(const std::string& csv, int universe = 1) {
  const std::string cmd = "ola_streaming_client -u " + std::to_string(universe) + " -d " + csv + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

TEST(DmxOlaSource, EndToEndThroughOlad) {
  if (!Exists("/usr/bin/olad") || !Exists("/usr/bin/ola_streaming_client") || !Exists("/usr/bin/setpriv")) {
    RELIGHT_SKIP_UNLESS_REQUIRED("olad not installed (apt-get install ola)");
  }
  if (unshare(CLONE_NEWNET) != 0) RELIGHT_SKIP_UNLESS_REQUIRED("cannot unshare a network namespace (needs root)");
  ASSERT_EQ(std::system("ip link set lo up"), 0);

  char tmpl[] = "/tmp/relight-olad-XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl;
  for (const char* p : kPlugins) std::ofstream(dir + "/ola-" + p + ".conf") << "enabled = false\n";
  ASSERT_EQ(std::system(("chown -R nobody:nogroup " + dir).c_str()), 0);

  DmxPatch patch;
  const std::string where = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/e2e.patch.toml";
  const Status parsed = ParseDmxPatch(
      "[[dmx_fixture]]\nname = \"spot\"\ntype = \"relight-test-spot.toml\"\nmode = \"16 bit\"\nuniverse = 1\n"
      "address = 10\n[[dmx_fixture]]\nname = \"par\"\ntype = \"relight-test-rgbw.toml\"\nmode = \"4 channel\"\n"
      "universe = 2\naddress = 30\n",
      where, &patch);
  ASSERT_TRUE(parsed.ok()) << parsed.message();
  DmxOlaSource source(std::move(patch), DmxOlaConfig{200});

  // No olad yet: a clear error.
  const Status missing = source.Start();
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("olad is not running"), std::string::npos) << missing.message();

  OlaDaemon olad(dir);
  olad.Launch();
  ASSERT_TRUE(WaitFor([&] { Status st = source.Start(); return st.ok(); }, 10000)) << "olad did not come up";
  ASSERT_TRUE(WaitFor([&] { return source.connected(); }, 2000));

  // Slots 1..9 zero; spot at 10: dimmer 0x1234, pan 0xABCD, tilt 0x01FF,
  // C 255 M 0 Y 128, wheel 0 (open), zoom 255, shutter 255, gobo 0. The par
  // is on universe 2: universe 1's slots 30..33 (green) are not its.
  std::string csv = "0,0,0,0,0,0,0,0,0,18,52,171,205,1,255,255,0,128,0,255,255,0";
  for (int slot = 23; slot < 30; ++slot) csv += ",0";
  csv += ",0,255,0,0";
  std::string zeros;  // slots 1..29
  for (int slot = 1; slot < 30; ++slot) zeros += "0,";
  // A console sends continuously; resend until the registration is through.
  DmxFixtureValues spot, par;
  ASSERT_TRUE(WaitFor([&] { Send(csv); return WaitFor([&] { return source.frames_received() > 0; }, 200); }, 8000))
      << "no frame from olad";
  // Universe 2: the par, red; universe 3 (not patched): blue at the same slots, ignored.
  ASSERT_TRUE(WaitFor([&] {
    Send(zeros + "255,0,64,0", 2);
    return WaitFor([&] { return source.LatestValues(1, MonotonicUs(), &par) && par.g.raw() == 0; }, 200);
  }, 8000)) << "no frame of universe 2 from olad";
  Send(zeros + "0,0,255,0", 3);
  Send(csv, 1);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_TRUE(source.LatestValues(0, MonotonicUs(), &spot));
  ASSERT_TRUE(source.LatestValues(1, MonotonicUs(), &par));
  EXPECT_EQ(spot.pan16, 0xABCD);
  EXPECT_EQ(spot.tilt16, 0x01FF);
  EXPECT_EQ(spot.dimmer.raw(), (0x1234 * 32767 + 32767) / 65535);
  EXPECT_EQ(spot.r.raw(), 0);                 // full cyan
  EXPECT_EQ(spot.g.raw(), 32767);
  EXPECT_EQ(spot.b.raw(), 32767 - (128 * 257 * 32767 + 32767) / 65535);
  EXPECT_EQ(spot.beam_angle.raw(), 40 << 16);
  EXPECT_TRUE(spot.shutter_open);
  EXPECT_EQ(par.r.raw(), 32767);
  EXPECT_EQ(par.g.raw(), 0) << "universe 1's slots reached the par of universe 2";
  EXPECT_EQ(par.b.raw(), (64 * 257 * 32767 + 32767) / 65535) << "universe 3 (not patched) reached the par";

  // olad goes away: the look is held; it comes back: the source reconnects.
  olad.Kill();
  ASSERT_TRUE(WaitFor([&] { return !source.connected(); }, 3000));
  DmxFixtureValues held;
  ASSERT_TRUE(source.LatestValues(0, MonotonicUs() + 10'000'000, &held));  // long past the loss timeout
  EXPECT_EQ(held.pan16, 0xABCD);
  EXPECT_EQ(held.dimmer.raw(), spot.dimmer.raw());                          // "hold" is the default
  olad.Launch();
  ASSERT_TRUE(WaitFor([&] { return source.connected(); }, 10000)) << "no reconnection";
  ASSERT_TRUE(WaitFor([&] {
    Send("0,0,0,0,0,0,0,0,0,255,255,128,0,128,0");  // a short frame: ends at tilt fine
    DmxFixtureValues v;
    return WaitFor([&] { return source.LatestValues(0, MonotonicUs(), &v) && v.pan16 == 0x8000; }, 200);
  }, 8000));
  ASSERT_TRUE(source.LatestValues(0, MonotonicUs(), &spot));
  EXPECT_EQ(spot.tilt16, 0x8000);
  EXPECT_EQ(spot.dimmer.raw(), 32767);
  EXPECT_EQ(spot.r.raw(), 0);                 // colour not in the frame: kept
  source.Stop();
  olad.Kill();
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace relight::hal
