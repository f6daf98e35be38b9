// DMX frame in -> frame out, relightd's loop in-process (issue 12):
//
//   dmx_latency_bench BAKE [--seconds 20] [--fps 44] [--width 1280 --height 720]   (at most 60 s)
//                          [--dmx-patch PATCH.toml] [--compare 1]
//
// olad runs as nobody in a private network namespace with every plugin off
// (needs root, like tests/daemon/dmx_daemon_test.cc). A sender thread, an
// OLA client of its own, sends to olad at 44 frames/s like a console, each
// frame moving one moving head's 16-bit pan to a new value; the daemon
// (--dmx, the bake's first luminaire patched as a 16-bit spot, frames to
// /dev/null) renders at --fps. With --dmx-patch (the stage's 48 heads:
// fixtures/stage.dmx.toml) every fixture of that patch with pan and tilt
// moves in every DMX frame, on all its universes. For each DMX frame the
// first rendered frame showing its pan (on every moving fixture) gives the
// latency: send to olad -> frame written.
// Reported as p50/p99 against one frame period + one render (p50) measured
// in the same run. Exit 0 if p99 <= that bound, 1 if not, 2 on set-up errors.
//
// --compare 1: the same run alternates 5 s segments of the daemon with its
// ticks following live input (relightd's loop) and with fixed ticks
// (DaemonConfig::fixed_ticks, the loop before), --seconds of each, and
// reports both: a before/after under the same machine load.
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
  bool compare = false;
};

// What one mode measured.
struct Results {
  std::vector<int64_t> latency_us, arrival_us, shown_render_us;
  int64_t frames_sent = 0;
  DaemonStats stats;
};

// The fixtures that move: every one with pan and tilt, with its pan range.
struct Mover {
  const hal::DmxFixturePatch* patch;
  int32_t pan_range_q16;
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

// Every mover: dimmer full, shutter open (its first open value), pan16 and a moving tilt.
class Frames {
 public:
  Frames(const std::vector<Mover>& movers, const std::vector<int>& universes)
      : movers_(movers), universes_(universes), slots_(universes.size(), std::vector<uint8_t>(hal::kDmxSlots, 0)) {
    for (const Mover& m : movers_) {
      int open = 255;
      while (m.patch->personality.has_shutter_ranges && open > 0 &&
             !m.patch->personality.shutter_open[static_cast<size_t>(open)]) {
        --open;
      }
      Put(m, hal::DmxFunction::kDimmer, 255);
      Put(m, hal::DmxFunction::kDimmerFine, 255);
      Put(m, hal::DmxFunction::kShutter, static_cast<uint8_t>(open));
    }
  }
  // Frame k's values in every universe; its pan16.
  uint16_t Set(int64_t k) {
    const uint16_t pan16 = static_cast<uint16_t>(12000 + (13 * k) % 40000);
    const uint16_t tilt16 = static_cast<uint16_t>(20000 + (7 * k) % 20000);
    for (const Mover& m : movers_) {
      Put(m, hal::DmxFunction::kPan, static_cast<uint8_t>(pan16 >> 8));
      Put(m, hal::DmxFunction::kPanFine, static_cast<uint8_t>(pan16 & 0xFF));
      Put(m, hal::DmxFunction::kTilt, static_cast<uint8_t>(tilt16 >> 8));
      Put(m, hal::DmxFunction::kTiltFine, static_cast<uint8_t>(tilt16 & 0xFF));
    }
    return pan16;
  }
  bool Send(ola::client::StreamingClient& sender) {
    ola::DmxBuffer buffer;
    for (size_t i = 0; i < universes_.size(); ++i) {
      buffer.Set(slots_[i].data(), static_cast<unsigned int>(slots_[i].size()));
      if (!sender.SendDmx(static_cast<unsigned int>(universes_[i]), buffer)) return false;
    }
    return true;
  }

 private:
  void Put(const Mover& m, hal::DmxFunction fn, uint8_t v) {
    const int off = m.patch->personality.Offset(fn);
    if (off < 0) return;
    const size_t u = static_cast<size_t>(std::find(universes_.begin(), universes_.end(), m.patch->universe) -
                                         universes_.begin());
    slots_[u][static_cast<size_t>(m.patch->address - 1 + off)] = v;
  }
  const std::vector<Mover>& movers_;
  const std::vector<int>& universes_;
  std::vector<std::vector<uint8_t>> slots_;
};

// One segment: a daemon (ticks following the input, or fixed) shown DMX
// frames first_k .. first_k + frames - 1 at 44 frames/s. pan16 of frame k is
// the same on every mover, 12000 + 13 k (mod 40000): inside +-180 degrees (the
// engine wraps angles, the value must come back from its state), distinct
// over 40000 frames (15 min). A frame counts as shown when every mover shows it.
bool Segment(const DaemonConfig& c, bool fixed_ticks, const std::vector<Mover>& movers, Frames& frames_out,
             ola::client::StreamingClient& sender, int64_t first_k, int64_t frames, Results* out) {
  DaemonConfig config = c;
  config.fixed_ticks = fixed_ticks;
  Daemon daemon;
  if (Status st = daemon.Open(config); !st.ok()) {
    std::fprintf(stderr, "dmx_latency_bench: %s\n", st.ToString().c_str());
    return false;
  }
  std::unique_ptr<FrameSink> sink;
  if (!MakeStreamSink("/dev/null", true, &sink).ok()) return false;
  daemon.AddSink(std::move(sink));
  std::vector<int> lums;
  for (const Mover& m : movers) lums.push_back(daemon.engine().FindLuminaire(m.patch->name));
  std::vector<int64_t> sent_us(1 << 16, 0);  // by pan16
  std::mutex mu;
  bool measuring = false;
  uint16_t last_shown = 0, warm_shown = 0;
  daemon.SetFrameObserver([&](const FrameInfo& f) {
    const uint16_t pan16 = DegreesToConsole(daemon.engine().state(lums[0]).pan_deg, movers[0].pan_range_q16);
    bool all = true;
    for (size_t i = 0; i < movers.size(); ++i) {
      all = all && DegreesToConsole(daemon.engine().state(lums[i]).pan_deg, movers[i].pan_range_q16) == pan16;
    }
    std::lock_guard<std::mutex> lock(mu);
    if (!measuring) {
      if (all) warm_shown = pan16;
      return;
    }
    if (!all || pan16 == last_shown || sent_us[pan16] == 0) return;
    last_shown = pan16;
    out->latency_us.push_back(f.out_us - sent_us[pan16]);
    if (f.newest_arrival_us > 0) out->arrival_us.push_back(f.out_us - f.newest_arrival_us);
    out->shown_render_us.push_back(f.render_us);
  });
  if (!daemon.Start().ok()) return false;
  std::atomic<bool> stop{false}, reload{false};
  std::thread runner([&] { (void)daemon.Run(stop, reload); });
  // Warm-up: frame first_k until the daemon shows it (its source connects and registers, retrying every
  // second), so no measured frame waits for the registration: olad hands a new client the last frame.
  const int64_t frame_us = 22727;  // 44 frames/s
  const uint16_t warm = frames_out.Set(first_k);
  bool ok = false;
  for (int i = 0; i < 10 * 44 && !ok; ++i) {
    if (!frames_out.Send(sender)) break;
    std::this_thread::sleep_for(std::chrono::microseconds(frame_us));
    std::lock_guard<std::mutex> lock(mu);
    ok = warm_shown == warm;
  }
  if (!ok) {
    std::fprintf(stderr, "dmx_latency_bench: the daemon never showed a DMX frame\n");
    stop = true;
    runner.join();
    return false;
  }
  const DaemonStats before = daemon.stats();
  {
    std::lock_guard<std::mutex> lock(mu);
    measuring = true;
  }
  const int64_t t0 = MonotonicUs();
  for (int64_t k = first_k + 1; k < first_k + frames && ok; ++k) {
    const int64_t due = t0 + (k - first_k - 1) * frame_us;
    while (MonotonicUs() < due) std::this_thread::sleep_for(std::chrono::microseconds(200));
    const uint16_t pan16 = frames_out.Set(k);
    {
      std::lock_guard<std::mutex> lock(mu);
      sent_us[pan16] = MonotonicUs();
    }
    ok = frames_out.Send(sender);
    if (!ok) std::fprintf(stderr, "dmx_latency_bench: send failed\n");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  stop = true;
  runner.join();
  const DaemonStats after = daemon.stats();
  out->frames_sent += frames - 1;
  out->stats.frames += after.frames - before.frames;
  out->stats.renders += after.renders - before.renders;
  out->stats.early_frames += after.early_frames - before.early_frames;
  out->stats.ticks_skipped += after.ticks_skipped - before.ticks_skipped;
  return ok;
}

// Prints one mode's figures; true if p99 <= one period + one render (p50).
bool Report(const char* mode, const Args& a, const Results& r) {
  const double period_ms = 1000.0 / a.fps;
  const double render_p50 = PercentileMs(r.shown_render_us, 0.5);
  const double p50 = PercentileMs(r.latency_us, 0.5), p99 = PercentileMs(r.latency_us, 0.99);
  const double bound = period_ms + render_p50;
  std::printf("  %s: %lld DMX frames, %zu of them shown\n", mode, static_cast<long long>(r.frames_sent),
              r.latency_us.size());
  std::printf("    render of the frames showing a DMX frame: p50 %.2f ms, p99 %.2f ms\n", render_p50,
              PercentileMs(r.shown_render_us, 0.99));
  std::printf("    DMX frame sent to olad -> frame out: p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", p50, p99,
              PercentileMs(r.latency_us, 1.0));
  std::printf("    arrival at relightd's OLA client -> frame out: p50 %.2f ms, p99 %.2f ms\n",
              PercentileMs(r.arrival_us, 0.5), PercentileMs(r.arrival_us, 0.99));
  std::printf("    bound: one period + one render (p50) = %.2f ms; p99 / bound = %.2f -> %s\n", bound, p99 / bound,
              p99 <= bound ? "PASS" : "FAIL");
  std::printf("    daemon: %lld frames, %lld renders, %lld early, %lld ticks skipped\n",
              static_cast<long long>(r.stats.frames), static_cast<long long>(r.stats.renders),
              static_cast<long long>(r.stats.early_frames), static_cast<long long>(r.stats.ticks_skipped));
  return p99 <= bound && !r.latency_us.empty();
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
  struct Cleanup {
    pid_t olad;
    std::string dir;
    ~Cleanup() {
      kill(olad, SIGTERM);
      waitpid(olad, nullptr, 0);
      std::system(("rm -rf " + dir).c_str());
    }
  } cleanup{olad, dir};

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
  std::vector<Mover> movers;
  std::vector<int> universes;
  for (const hal::DmxFixturePatch& f : patch.fixtures) {
    if (f.personality.Offset(hal::DmxFunction::kPan) < 0 || f.personality.Offset(hal::DmxFunction::kTilt) < 0) continue;
    const int range = f.personality.pan_range_deg > 0 ? f.personality.pan_range_deg : 540;
    movers.push_back({&f, range << 16});
    if (std::find(universes.begin(), universes.end(), f.universe) == universes.end()) universes.push_back(f.universe);
  }
  if (movers.empty()) {
    std::fprintf(stderr, "dmx_latency_bench: no fixture of %s has pan and tilt\n", patch_path.c_str());
    return 2;
  }
  DaemonConfig c;
  c.bake_path = a.bake;
  c.width = a.width;
  c.height = a.height;
  c.fps = a.fps;
  c.dmx_patch_path = patch_path;

  ola::InitLogging(ola::OLA_LOG_WARN, ola::OLA_LOG_STDERR);
  ola::client::StreamingClient sender((ola::client::StreamingClient::Options()));
  bool up = false;
  for (int i = 0; i < 200 && !(up = sender.Setup()); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (!up) {
    std::fprintf(stderr, "dmx_latency_bench: olad did not come up\n");
    return 2;
  }
  Frames frames(movers, universes);
  const int64_t total = static_cast<int64_t>(std::min(a.seconds, 60.0) * 44);
  Results follow, fixed;
  int64_t k = 0;
  if (!a.compare) {
    if (!Segment(c, false, movers, frames, sender, 0, total, &follow)) return 2;
  } else {
    // Alternate 5 s segments so both modes see the same machine load.
    constexpr int64_t kSegment = 5 * 44;
    for (int64_t done = 0; done < total; done += kSegment) {
      const int64_t n = std::min(kSegment, total - done);
      if (!Segment(c, true, movers, frames, sender, k, n, &fixed)) return 2;
      k += n;
      if (!Segment(c, false, movers, frames, sender, k, n, &follow)) return 2;
      k += n;
    }
  }
  sender.Stop();

  std::printf("dmx_latency_bench: %s %dx%d, relightd at %g frames/s (period %.2f ms); DMX at 44 frames/s; "
              "%zu moving fixture(s) on %zu universe(s), every one's pan and tilt new in every DMX frame\n",
              a.bake.c_str(), a.width, a.height, a.fps, 1000.0 / a.fps, movers.size(), universes.size());
  const bool pass = Report("ticks following live input (relightd)", a, follow);
  if (a.compare) {
    (void)Report("fixed ticks (the loop before)", a, fixed);
    const double f99 = PercentileMs(follow.latency_us, 0.99), x99 = PercentileMs(fixed.latency_us, 0.99);
    const double f50 = PercentileMs(follow.latency_us, 0.5), x50 = PercentileMs(fixed.latency_us, 0.5);
    std::printf("  following / fixed, same run: p50 %.2f, p99 %.2f\n", x50 > 0 ? f50 / x50 : 0, x99 > 0 ? f99 / x99 : 0);
  }
  return pass ? 0 : 1;
}

}  // namespace
}  // namespace relight::daemon

int main(int argc, char** argv) {
  relight::daemon::Args a;
  if (argc < 2) {
    std::fprintf(stderr, "usage: dmx_latency_bench BAKE [--seconds S] [--fps F] [--width W] [--height H] [--dmx-patch PATCH.toml] [--compare 1]\n");
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
    else if (k == "--compare") a.compare = v != 0;
    else return 2;
  }
  relight::SetLogSink([](relight::LogLevel level, const std::string& line) {
    if (level != relight::LogLevel::kInfo) std::fprintf(stderr, "%s\n", line.c_str());
  });
  return relight::daemon::Run(a);
}
