// relightd's Modbus benchmarks, run in-process against the real daemon loop
// (its Modbus TCP server on loopback, the engine, OSMesa at full size, a raw
// frame sink to /dev/null):
//
//   relightd_bench latency BAKE [--writes 1000] [--fps 30] [--width 1280 --height 720]
//     One libmodbus client writes pan, tilt or dimmer of a fixture, one
//     write at a time at a random phase of the frame period, and waits for
//     the first frame showing it. Latency = send -> that frame written.
//     Reports p50/p99 against one frame period + one render time measured
//     in the same run.
//
//   relightd_bench soak BAKE [--seconds 60] [--clients 8] [--rate 100]
//     N clients each write 100 times a second for the duration, with a
//     client sending garbage and one connected but silent throughout. Checks
//     that every client was served, and that the rendered state at the end
//     equals the last value written to every register.
//
// Exit status 0 if the run meets its bound, 1 if not, 2 on set-up errors.
#include <modbus/modbus.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "daemon.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/hal/modbus_tcp_server.h"
#include "relight/hal/register_map.h"

namespace relight::daemon {
namespace {

struct Args {
  std::string mode, bake;
  int writes = 1000, width = 1280, height = 720, clients = 8, rate = 100;
  double fps = 30, seconds = 60;
};

bool ParseArgs(int argc, char** argv, Args* a) {
  if (argc < 3) return false;
  a->mode = argv[1];
  a->bake = argv[2];
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (k == "--writes") a->writes = static_cast<int>(v);
    else if (k == "--fps") a->fps = v;
    else if (k == "--width") a->width = static_cast<int>(v);
    else if (k == "--height") a->height = static_cast<int>(v);
    else if (k == "--clients") a->clients = static_cast<int>(v);
    else if (k == "--rate") a->rate = static_cast<int>(v);
    else if (k == "--seconds") a->seconds = v;
    else return false;
  }
  return a->mode == "latency" || a->mode == "soak";
}

int32_t WrapQ16(int64_t v) {
  v %= int64_t{360} << 16;
  if (v > (int64_t{180} << 16)) v -= int64_t{360} << 16;
  if (v <= -(int64_t{180} << 16)) v += int64_t{360} << 16;
  return static_cast<int32_t>(v);
}

// The engine value register `offset` of fixture `f` shows (fade 0, linear curve, on).
int32_t Shown(const FixtureState& s, int offset) {
  switch (offset) {
    case hal::kRegDimmer: return s.dimmer.raw();
    case hal::kRegPan: return s.pan_deg.raw();
    case hal::kRegTilt: return s.tilt_deg.raw();
    default: return s.rgb[offset - hal::kRegRed].raw();
  }
}
int32_t Expected(const hal::FixturePatch& f, int offset, uint16_t reg) {
  switch (offset) {
    case hal::kRegDimmer: return hal::LevelQ15FromRegister16(reg);
    case hal::kRegPan: return WrapQ16(hal::AngleQ16FromRegister(reg, f.pan_range_q16));
    case hal::kRegTilt: return WrapQ16(hal::AngleQ16FromRegister(reg, f.tilt_range_q16));
    default: return hal::LevelQ15FromByte(reg);
  }
}

double Percentile(std::vector<int64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return static_cast<double>(v[i]) / 1000.0;  // ms
}

// The daemon on its own thread, with its Modbus server on 127.0.0.1, any port.
struct Rig {
  Daemon daemon;
  std::atomic<bool> stop{false}, reload{false};
  std::thread runner;
  int port = 0;
  Status run_status;

  Status Open(const Args& a) {
    DaemonConfig c;
    c.bake_path = a.bake;
    c.width = a.width;
    c.height = a.height;
    c.fps = a.fps;
    c.modbus_port = 0;
    RELIGHT_RETURN_IF_ERROR(daemon.Open(c));
    std::unique_ptr<FrameSink> sink;
    RELIGHT_RETURN_IF_ERROR(MakeStreamSink("/dev/null", true, &sink));
    daemon.AddSink(std::move(sink));
    RELIGHT_RETURN_IF_ERROR(daemon.Start());
    for (hal::InputSource* s : daemon.sources()) {
      if (auto* tcp = dynamic_cast<hal::ModbusTcpServer*>(s)) port = tcp->port();
    }
    return Status::Ok();
  }
  void Run() {
    runner = std::thread([this] { run_status = daemon.Run(stop, reload); });
  }
  void Stop() {
    stop.store(true);
    if (runner.joinable()) runner.join();
  }
};

int Latency(const Args& a) {
  Rig rig;
  if (Status st = rig.Open(a); !st.ok()) {
    std::fprintf(stderr, "relightd_bench: %s\n", st.ToString().c_str());
    return 2;
  }
  const int fixture = 0;
  const hal::FixturePatch patch_f = rig.daemon.patch().fixtures[fixture];
  const int lum = rig.daemon.engine().FindLuminaire(patch_f.name);

  // Shared with the frame observer (daemon thread).
  std::mutex mutex;
  std::condition_variable shown_cv;
  int want_offset = -1;
  int32_t want_value = 0;
  int64_t shown_out_us = 0, shown_arrival_us = 0, shown_render_us = 0;
  std::vector<int64_t> render_us;  // every frame's render time
  rig.daemon.SetFrameObserver([&](const FrameInfo& f) {
    std::lock_guard<std::mutex> lock(mutex);
    if (f.render_us > 0) render_us.push_back(f.render_us);  // 0: a frame sent again, not drawn
    if (want_offset >= 0 && shown_out_us == 0 &&
        Shown(rig.daemon.engine().state(lum), want_offset) == want_value) {
      shown_out_us = f.out_us;
      shown_arrival_us = f.newest_arrival_us;
      shown_render_us = f.render_us;
      shown_cv.notify_all();
    }
  });
  rig.Run();

  modbus_t* ctx = modbus_new_tcp("127.0.0.1", rig.port);
  if (modbus_connect(ctx) != 0) {
    std::fprintf(stderr, "relightd_bench: cannot connect: %s\n", modbus_strerror(errno));
    rig.Stop();
    return 2;
  }
  std::mt19937 rng(12345);
  const int64_t period_us = rig.daemon.period_us();
  std::uniform_int_distribution<int64_t> phase(0, period_us);
  const int offsets[3] = {hal::kRegPan, hal::kRegTilt, hal::kRegDimmer};
  uint16_t current[3] = {0, 0, 0};
  std::vector<int64_t> latency_us, server_latency_us, shown_render;
  int timeouts = 0;
  for (int i = 0; i < a.writes; ++i) {
    const int which = i % 3;
    uint16_t value;
    do {
      value = static_cast<uint16_t>(rng() & 0xFFFF);
    } while (value == current[which] ||
             Expected(patch_f, offsets[which], value) == Shown(rig.daemon.engine().state(lum), offsets[which]));
    current[which] = value;
    std::this_thread::sleep_for(std::chrono::microseconds(phase(rng)));  // a random phase of the frame period
    {
      std::lock_guard<std::mutex> lock(mutex);
      want_offset = offsets[which];
      want_value = Expected(patch_f, offsets[which], value);
      shown_out_us = 0;
    }
    const int64_t sent_us = MonotonicUs();
    if (modbus_write_register(ctx, patch_f.modbus_base + offsets[which], value) != 1) {
      std::fprintf(stderr, "relightd_bench: write failed: %s\n", modbus_strerror(errno));
      break;
    }
    std::unique_lock<std::mutex> lock(mutex);
    if (!shown_cv.wait_for(lock, std::chrono::seconds(5), [&] { return shown_out_us != 0; })) {
      ++timeouts;
      continue;
    }
    latency_us.push_back(shown_out_us - sent_us);
    server_latency_us.push_back(shown_out_us - shown_arrival_us);
    shown_render.push_back(shown_render_us);
    want_offset = -1;
  }
  modbus_close(ctx);
  modbus_free(ctx);
  rig.Stop();

  std::vector<int64_t> renders;
  {
    std::lock_guard<std::mutex> lock(mutex);
    renders = render_us;
  }
  const double period_ms = static_cast<double>(period_us) / 1000.0;
  const double render_p50 = Percentile(shown_render, 0.5), render_p99 = Percentile(shown_render, 0.99);
  const double p50 = Percentile(latency_us, 0.5), p99 = Percentile(latency_us, 0.99);
  const double bound = period_ms + render_p50;
  std::printf("relightd_bench latency: %s %dx%d at %g frames/s (period %.2f ms), %zu writes (pan/tilt/dimmer in turn), "
              "%d timeouts\n",
              a.bake.c_str(), a.width, a.height, a.fps, period_ms, latency_us.size(), timeouts);
  std::printf("  render (update + tone map + draw) of the frames showing a write: p50 %.2f ms, p99 %.2f ms; all drawn "
              "frames p50 %.2f ms\n",
              render_p50, render_p99, Percentile(renders, 0.5));
  std::printf("  write -> frame out, client side (send to frame written): p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", p50,
              p99, Percentile(latency_us, 1.0));
  std::printf("  arrival at the server -> frame out:                      p50 %.2f ms, p99 %.2f ms\n",
              Percentile(server_latency_us, 0.5), Percentile(server_latency_us, 0.99));
  std::printf("  bound: one period + one render (p50) = %.2f ms; p99 / bound = %.2f -> %s\n", bound, p99 / bound,
              p99 <= bound && timeouts == 0 ? "PASS" : "FAIL");
  const DaemonStats s = rig.daemon.stats();
  std::printf("  daemon: %lld frames, %lld ticks skipped\n", static_cast<long long>(s.frames),
              static_cast<long long>(s.ticks_skipped));
  return p99 <= bound && timeouts == 0 && rig.run_status.ok() ? 0 : 1;
}

int Soak(const Args& a) {
  Rig rig;
  if (Status st = rig.Open(a); !st.ok()) {
    std::fprintf(stderr, "relightd_bench: %s\n", st.ToString().c_str());
    return 2;
  }
  const hal::RegisterMap& map = rig.daemon.register_map();
  const int regs = map.holding_count();
  std::atomic<int64_t> frames{0};
  rig.daemon.SetFrameObserver([&](const FrameInfo& f) { frames.store(f.frame + 1); });
  rig.Run();

  // Client k writes registers k, k + N, k + 2N, ... in turn: between them the
  // clients cover every register of every fixture.
  const int n = a.clients;
  std::vector<uint16_t> last(static_cast<size_t>(regs), 0);
  std::vector<int64_t> ok(static_cast<size_t>(n), 0), failed(static_cast<size_t>(n), 0);
  std::vector<std::vector<int64_t>> response_us(static_cast<size_t>(n));
  const auto legal = [&](int addr, uint32_t r) -> uint16_t {
    int off = 0;
    map.FixtureAt(addr, &off);
    if (off >= hal::kRegRed && off <= hal::kRegBlue) return static_cast<uint16_t>(r % 256);
    if (off == hal::kRegProfile) return 0;
    if (off == hal::kRegFlags) return 1;
    return static_cast<uint16_t>(r & 0xFFFF);
  };
  std::vector<std::thread> threads;
  const int64_t end_us = MonotonicUs() + static_cast<int64_t>(a.seconds * 1e6);
  for (int k = 0; k < n; ++k) {
    threads.emplace_back([&, k] {
      modbus_t* ctx = modbus_new_tcp("127.0.0.1", rig.port);
      modbus_set_response_timeout(ctx, 1, 0);
      if (modbus_connect(ctx) != 0) {
        failed[static_cast<size_t>(k)] = 1;
        return;
      }
      std::mt19937 rng(static_cast<uint32_t>(k));
      const int64_t step_us = 1000000 / a.rate;
      int64_t next = MonotonicUs();
      for (int i = 0; MonotonicUs() < end_us; ++i) {
        const int addr = k + n * (i % ((regs - k + n - 1) / n));
        const uint16_t v = legal(addr, static_cast<uint32_t>(rng()));
        const int64_t t0 = MonotonicUs();
        if (modbus_write_register(ctx, addr, v) == 1) {
          ++ok[static_cast<size_t>(k)];
          last[static_cast<size_t>(addr)] = v;  // only this client writes addr
          response_us[static_cast<size_t>(k)].push_back(MonotonicUs() - t0);
        } else {
          ++failed[static_cast<size_t>(k)];
          modbus_flush(ctx);
        }
        next += step_us;
        const int64_t now = MonotonicUs();
        if (next > now) std::this_thread::sleep_for(std::chrono::microseconds(next - now));
      }
      modbus_close(ctx);
      modbus_free(ctx);
    });
  }
  // A silent client, connected all along; a garbage client, twice a second.
  std::atomic<int> garbage_sent{0};
  std::thread misbehaving([&] {
    modbus_t* silent = modbus_new_tcp("127.0.0.1", rig.port);
    modbus_connect(silent);
    std::mt19937 rng(99);
    while (MonotonicUs() < end_us) {
      modbus_t* g = modbus_new_tcp("127.0.0.1", rig.port);
      if (modbus_connect(g) == 0) {
        uint8_t junk[64];
        for (uint8_t& b : junk) b = static_cast<uint8_t>(rng());
        if (write(modbus_get_socket(g), junk, sizeof junk) > 0) garbage_sent.fetch_add(1);
      }
      modbus_close(g);
      modbus_free(g);
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    modbus_close(silent);
    modbus_free(silent);
  });
  for (auto& t : threads) t.join();
  misbehaving.join();
  const int64_t seen = frames.load();
  while (frames.load() < seen + 2) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  hal::ModbusServerCounters counters;
  std::vector<uint16_t> held;
  for (hal::InputSource* s : rig.daemon.sources()) {
    if (auto* tcp = dynamic_cast<hal::ModbusTcpServer*>(s)) {
      counters = tcp->counters();
      held = tcp->holding_registers();
    }
  }
  rig.Stop();

  // Registers nobody wrote keep their start value: compare those written.
  int mismatches = 0, checked = 0;
  for (int f = 0; f < map.fixture_count(); ++f) {
    const hal::FixturePatch& fp = map.fixture(f);
    const FixtureState s = rig.daemon.engine().state(rig.daemon.engine().FindLuminaire(fp.name));
    for (int off : {hal::kRegDimmer, hal::kRegPan, hal::kRegTilt, hal::kRegRed, hal::kRegGreen, hal::kRegBlue}) {
      const size_t addr = static_cast<size_t>(fp.modbus_base + off);
      if (held[addr] != last[addr]) ++mismatches;
      if (Shown(s, off) != Expected(fp, off, last[addr])) ++mismatches;
      checked += 2;
    }
  }
  int64_t total = 0, min_ok = INT64_MAX, fails = 0;
  std::vector<int64_t> all_resp;
  for (int k = 0; k < n; ++k) {
    total += ok[static_cast<size_t>(k)];
    min_ok = std::min(min_ok, ok[static_cast<size_t>(k)]);
    fails += failed[static_cast<size_t>(k)];
    all_resp.insert(all_resp.end(), response_us[static_cast<size_t>(k)].begin(), response_us[static_cast<size_t>(k)].end());
  }
  const int64_t expected_each = static_cast<int64_t>(a.seconds * a.rate);
  const bool pass = mismatches == 0 && fails == 0 && min_ok >= expected_each * 95 / 100 && rig.run_status.ok();
  const DaemonStats s = rig.daemon.stats();
  std::printf("relightd_bench soak: %s %dx%d at %g frames/s, %d clients x %d writes/s for %g s, plus a silent client and "
              "%d garbage connections\n",
              a.bake.c_str(), a.width, a.height, a.fps, n, a.rate, a.seconds, garbage_sent.load());
  std::printf("  writes answered: %lld (per client min %lld of %lld scheduled), failed %lld\n",
              static_cast<long long>(total), static_cast<long long>(min_ok), static_cast<long long>(expected_each),
              static_cast<long long>(fails));
  std::printf("  response time: p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", Percentile(all_resp, 0.5),
              Percentile(all_resp, 0.99), Percentile(all_resp, 1.0));
  std::printf("  server: bad frames %u, illegal address %u, illegal value %u, refused %u\n", counters.bad_frames,
              counters.illegal_address, counters.illegal_value, counters.refused);
  std::printf("  daemon: %lld frames, %lld drawn, %lld ticks skipped, render mean %.2f ms (over the drawn)\n",
              static_cast<long long>(s.frames), static_cast<long long>(s.renders),
              static_cast<long long>(s.ticks_skipped),
              s.renders > 0 ? static_cast<double>(s.render_us_total) / static_cast<double>(s.renders) / 1000.0 : 0.0);
  std::printf("  final state vs last written: %d of %d checks differ -> %s\n", mismatches, checked, pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}

}  // namespace
}  // namespace relight::daemon

int main(int argc, char** argv) {
  relight::daemon::Args args;
  if (!relight::daemon::ParseArgs(argc, argv, &args)) {
    std::fprintf(stderr,
                 "usage: relightd_bench latency BAKE [--writes N] [--fps F] [--width W] [--height H]\n"
                 "       relightd_bench soak BAKE [--seconds S] [--clients N] [--rate HZ] [--fps F] [--width W] [--height H]\n");
    return 2;
  }
  // The server logs every connection; the garbage client makes many.
  relight::SetLogSink([](relight::LogLevel level, const std::string& line) {
    if (level != relight::LogLevel::kInfo) std::fprintf(stderr, "%s\n", line.c_str());
  });
  return args.mode == "latency" ? relight::daemon::Latency(args) : relight::daemon::Soak(args);
}
