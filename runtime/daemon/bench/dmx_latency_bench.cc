// DMX frame in -> frame out, relightd's loop in-process (issue 12):
//
//   dmx_latency_bench BAKE [--seconds 20] [--fps 44] [--width 1280 --height 720]   (at most 60 s)
//                          [--dmx-patch PATCH.toml]
//
// olad runs as nobody in a private network namespace with every plugin off
// (needs root, like tests/daemon/dmx_daemon_test.cc). A sender thread, an
// OLA client of its own, sends universe 1 to olad at 44 frames/s like a
// console, each frame moving one moving head's 16-bit pan to a new value; the
// daemon (--dmx, the bake's first luminaire patched as a 16-bit spot, frames
// to /dev/null) renders at --fps. With --dmx-patch (the stage's 48 heads:
// fixtures/stage.dmx.toml) every fixture of that patch with pan and tilt
// moves in every DMX frame, on all its universes. For each DMX frame the
// first rendered frame showing its pan (on every moving fixture) gives the
// latency: send to olad -> frame written.
// Reported as p50/p99 against one frame period + one render (p50) measured
// in the same run. Exit 0 if p99 <= that bound, 1 if not, 2 on set-up errors.
#include <ola/DmxBuffer.h>
#include <ola/Logging.h>
#include <ola/client/StreamingClient.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "daemon.h"
#include "relight/base/clock.h"
#include "relight/base/console_value.h"
#include "relight/base/log.h"
#include "relight/hal/dmx/dmx_patch.h"

namespace relight::daemon {
namespace {

struct Args {
  std::string bake;
  std::string dmx_patch;  // empty: the bake's first luminaire as a 16-bit test spot
  double seconds = 20, fps = 44;
  int width = 1280, height = 720;
};

double PercentileMs(std::vector<int64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return static_cast<double>(v[static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5)]) / 1000.0;
}

// olad as nobody with its own config directory, every plugin off: port 9010 of this namespace only.
pid_t StartOlad(const std::string& dir) {
  for (const char* p : {"artnet", "dummy", "e131", "espnet", "ftdidmx", "gpio", "karate", "kinet", "milinst",
                        "opendmx", "openpixelcontrol", "osc", "pathport", "renard", "sandnet", "shownet", "spi",
                        "stageprofi", "uartdmx", "usbdmx", "usbserial"}) {
    std::ofstream(dir + "/ola-" + p + ".conf") << "enabled = false\n";
  }
  if (std::system(("chown -R nobody:nogroup " + dir).c_str()) != 0) return -1;
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/usr/bin/setpriv", "setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "/usr/bin/olad", "-c",
          dir.c_str(), "--no-http", "--no-register-with-dns-sd", "-l", "1", static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

int Run(const Args& a) {
  if (unshare(CLONE_NEWNET) != 0 || std::system("ip link set lo up") != 0) {
    std::fprintf(stderr, "dmx_latency_bench: needs root (a private network namespace for olad)\n");
    return 2;
  }
  char tmpl[] = "/tmp/relight-dmxbench-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return 2;
  const std::string dir = tmpl;
  const pid_t olad = StartOlad(dir);
  if (olad < 0) return 2;

  Daemon daemon;
  std::string patch_path = a.dmx_patch;
  if (patch_path.empty()) {
    Engine probe;
    if (Status st = probe.Open(a.bake); !st.ok()) {
      std::fprintf(stderr, "dmx_latency_bench: %s\n", st.ToString().c_str());
      return 2;
    }
    patch_path = dir + "/patch.toml";
    std::ofstream(patch_path) << "[[dmx_fixture]]\nname = \"" << probe.bake().luminaires[0].name
                              << "\"\ntype = \"" RELIGHT_SOURCE_DIR
                                 "/fixtures/dmx/relight-test-spot.toml\"\nmode = \"16 bit\"\n"
                                 "universe = 1\naddress = 1\n";
  }
  hal::DmxPatch patch;
  if (Status st = hal::LoadDmxPatch(patch_path, &patch); !st.ok()) {
    std::fprintf(stderr, "dmx_latency_bench: %s\n", st.ToString().c_str());
    return 2;
  }
  DaemonConfig c;
  c.bake_path = a.bake;
  c.width = a.width;
  c.height = a.height;
  c.fps = a.fps;
  c.dmx_patch_path = patch_path;
  if (Status st = daemon.Open(c); !st.ok()) {
    std::fprintf(stderr, "dmx_latency_bench: %s\n", st.ToString().c_str());
    return 2;
  }
  std::unique_ptr<FrameSink> sink;
  if (!MakeStreamSink("/dev/null", true, &sink).ok()) return 2;
  daemon.AddSink(std::move(sink));
  // The fixtures that move: every one with pan and tilt, with its luminaire and pan range.
  struct Mover {
    const hal::DmxFixturePatch* patch;
    int lum;
    int32_t pan_range_q16;
  };
  std::vector<Mover> movers;
  std::vector<int> universes;
  for (const hal::DmxFixturePatch& f : patch.fixtures) {
    if (f.personality.Offset(hal::DmxFunction::kPan) < 0 || f.personality.Offset(hal::DmxFunction::kTilt) < 0) continue;
    const int range = f.personality.pan_range_deg > 0 ? f.personality.pan_range_deg : 540;
    movers.push_back({&f, daemon.engine().FindLuminaire(f.name), range << 16});
    if (std::find(universes.begin(), universes.end(), f.universe) == universes.end()) universes.push_back(f.universe);
  }
  if (movers.empty()) {
    std::fprintf(stderr, "dmx_latency_bench: no fixture of %s has pan and tilt\n", patch_path.c_str());
    return 2;
  }

  // pan16 of DMX frame k, the same on every mover: 12000 + 13 k (mod 40000): inside +-180 degrees (the
  // engine wraps angles, the value must come back from its state), distinct over any run shorter than
  // ~70 s at 44 Hz. A frame counts as shown when every mover shows it.
  constexpr int kRing = 1 << 16;
  std::vector<int64_t> sent_us(kRing, 0);  // by pan16
  std::mutex mu;
  std::vector<int64_t> latency_us, arrival_us, shown_render_us, render_us;
  uint16_t last_shown = 0;
  daemon.SetFrameObserver([&](const FrameInfo& f) {
    const uint16_t pan16 = DegreesToConsole(daemon.engine().state(movers[0].lum).pan_deg, movers[0].pan_range_q16);
    bool all = true;
    for (const Mover& m : movers) {
      all = all && DegreesToConsole(daemon.engine().state(m.lum).pan_deg, m.pan_range_q16) == pan16;
    }
    std::lock_guard<std::mutex> lock(mu);
    if (f.render_us > 0) render_us.push_back(f.render_us);
    if (!all || pan16 == last_shown || sent_us[pan16] == 0) return;
    last_shown = pan16;
    latency_us.push_back(f.out_us - sent_us[pan16]);
    if (f.newest_arrival_us > 0) arrival_us.push_back(f.out_us - f.newest_arrival_us);
    shown_render_us.push_back(f.render_us);
  });
  if (!daemon.Start().ok()) return 2;
  std::atomic<bool> stop{false}, reload{false};
  std::thread runner([&] { (void)daemon.Run(stop, reload); });

  ola::InitLogging(ola::OLA_LOG_WARN, ola::OLA_LOG_STDERR);
  ola::client::StreamingClient sender((ola::client::StreamingClient::Options()));
  bool up = false;
  for (int i = 0; i < 200 && !(up = sender.Setup()); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (!up) {
    std::fprintf(stderr, "dmx_latency_bench: olad did not come up\n");
    return 2;
  }
  // Give the daemon's source time to connect and register (it retries every second).
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  {
    std::lock_guard<std::mutex> lock(mu);
    latency_us.clear();
    arrival_us.clear();
    shown_render_us.clear();
    render_us.clear();
  }
  const int64_t frame_us = 22727;  // 44 frames/s
  const int64_t frames = static_cast<int64_t>(std::min(a.seconds, 60.0) * 44);
  // Every mover: dimmer full, shutter open (its first open value), the frame's pan, a tilt that moves too.
  std::vector<std::vector<uint8_t>> slots(universes.size(), std::vector<uint8_t>(hal::kDmxSlots, 0));
  auto put = [](std::vector<uint8_t>& u, const hal::DmxFixturePatch& f, hal::DmxFunction fn, uint8_t v) {
    const int off = f.personality.Offset(fn);
    if (off >= 0) u[static_cast<size_t>(f.address - 1 + off)] = v;
  };
  auto universe_index = [&](int universe) {
    return static_cast<size_t>(std::find(universes.begin(), universes.end(), universe) - universes.begin());
  };
  for (const Mover& m : movers) {
    std::vector<uint8_t>& u = slots[universe_index(m.patch->universe)];
    put(u, *m.patch, hal::DmxFunction::kDimmer, 255);
    put(u, *m.patch, hal::DmxFunction::kDimmerFine, 255);
    int open = 255;
    while (m.patch->personality.has_shutter_ranges && open > 0 && !m.patch->personality.shutter_open[static_cast<size_t>(open)]) --open;
    put(u, *m.patch, hal::DmxFunction::kShutter, static_cast<uint8_t>(open));
  }
  ola::DmxBuffer buffer;
  const int64_t t0 = MonotonicUs();
  for (int64_t k = 0; k < frames; ++k) {
    const int64_t due = t0 + k * frame_us;
    while (MonotonicUs() < due) std::this_thread::sleep_for(std::chrono::microseconds(200));
    const uint16_t pan16 = static_cast<uint16_t>(12000 + (13 * k) % 40000);
    const uint16_t tilt16 = static_cast<uint16_t>(20000 + (7 * k) % 20000);
    for (const Mover& m : movers) {
      std::vector<uint8_t>& u = slots[universe_index(m.patch->universe)];
      put(u, *m.patch, hal::DmxFunction::kPan, static_cast<uint8_t>(pan16 >> 8));
      put(u, *m.patch, hal::DmxFunction::kPanFine, static_cast<uint8_t>(pan16 & 0xFF));
      put(u, *m.patch, hal::DmxFunction::kTilt, static_cast<uint8_t>(tilt16 >> 8));
      put(u, *m.patch, hal::DmxFunction::kTiltFine, static_cast<uint8_t>(tilt16 & 0xFF));
    }
    {
      std::lock_guard<std::mutex> lock(mu);
      sent_us[pan16] = MonotonicUs();
    }
    bool ok = true;
    for (size_t i = 0; i < universes.size() && ok; ++i) {
      buffer.Set(slots[i].data(), static_cast<unsigned int>(slots[i].size()));
      ok = sender.SendDmx(static_cast<unsigned int>(universes[i]), buffer);
    }
    if (!ok) {
      std::fprintf(stderr, "dmx_latency_bench: send failed\n");
      break;
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  stop = true;
  runner.join();
  sender.Stop();
  kill(olad, SIGTERM);
  waitpid(olad, nullptr, 0);
  std::system(("rm -rf " + dir).c_str());

  std::lock_guard<std::mutex> lock(mu);
  const double period_ms = 1000.0 / a.fps;
  const double render_p50 = PercentileMs(shown_render_us, 0.5);
  const double p50 = PercentileMs(latency_us, 0.5), p99 = PercentileMs(latency_us, 0.99);
  const double bound = period_ms + render_p50;
  std::printf("dmx_latency_bench: %s %dx%d, relightd at %g frames/s (period %.2f ms); %lld DMX frames "
              "at 44 frames/s, %zu of them shown\n",
              a.bake.c_str(), a.width, a.height, a.fps, period_ms, static_cast<long long>(frames), latency_us.size());
  std::printf("  %zu moving fixture(s) on %zu universe(s), every one's pan and tilt new in every DMX frame\n",
              movers.size(), universes.size());
  std::printf("  render of the frames showing a DMX frame: p50 %.2f ms, p99 %.2f ms\n", render_p50,
              PercentileMs(shown_render_us, 0.99));
  std::printf("  DMX frame sent to olad -> frame out: p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", p50, p99,
              PercentileMs(latency_us, 1.0));
  std::printf("  arrival at relightd's OLA client -> frame out: p50 %.2f ms, p99 %.2f ms\n", PercentileMs(arrival_us, 0.5),
              PercentileMs(arrival_us, 0.99));
  std::printf("  bound: one period + one render (p50) = %.2f ms; p99 / bound = %.2f -> %s\n", bound, p99 / bound,
              p99 <= bound ? "PASS" : "FAIL");
  const DaemonStats s = daemon.stats();
  std::printf("  daemon: %lld frames, %lld renders, %lld early, %lld ticks skipped\n", static_cast<long long>(s.frames),
              static_cast<long long>(s.renders), static_cast<long long>(s.early_frames),
              static_cast<long long>(s.ticks_skipped));
  return p99 <= bound && !latency_us.empty() ? 0 : 1;
}

}  // namespace
}  // namespace relight::daemon

int main(int argc, char** argv) {
  relight::daemon::Args a;
  if (argc < 2) {
    std::fprintf(stderr, "usage: dmx_latency_bench BAKE [--seconds S] [--fps F] [--width W] [--height H] [--dmx-patch PATCH.toml]\n");
    return 2;
  }
  a.bake = argv[1];
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (k == "--seconds") a.seconds = v;
    else if (k == "--fps") a.fps = v;
    else if (k == "--width") a.width = static_cast<int>(v);
    else if (k == "--height") a.height = static_cast<int>(v);
    else if (k == "--dmx-patch") a.dmx_patch = argv[i + 1];
    else return 2;
  }
  relight::SetLogSink([](relight::LogLevel level, const std::string& line) {
    if (level != relight::LogLevel::kInfo) std::fprintf(stderr, "%s\n", line.c_str());
  });
  return relight::daemon::Run(a);
}
