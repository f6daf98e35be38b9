// What moving a run-time emitter costs relightd (issue 15), against a pan
// change in the same run: the real daemon loop in-process (Modbus TCP on
// loopback, the engine, OSMesa, a raw sink to /dev/null), a patch with an
// [[emitter]] that is switched on first. One libmodbus client writes, in
// turn, the pan register of the patch's first luminaire and the x register
// of its first emitter (each a new random value, at a random phase of the
// frame period) and waits for the first frame that shows it: for the pan,
// the engine's state; for the emitter, the first frame whose update solved
// it. Reports the render time (update + tone map + draw) and write -> frame
// out of each kind, p50 and p99, and their ratios.
//
//   relightd_emitter_bench BAKE PATCH [--writes 200] [--fps 30] [--width 1280 --height 720]
#include <modbus/modbus.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "daemon.h"
#include "relight/base/clock.h"
#include "relight/base/console_value.h"
#include "relight/hal/modbus_tcp_server.h"
#include "relight/hal/register_map.h"

namespace relight::daemon {
namespace {

double Percentile(std::vector<int64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return static_cast<double>(v[static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5)]) / 1000.0;
}

int Run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: relightd_emitter_bench BAKE PATCH [--writes N] [--fps F] [--width W] [--height H]\n");
    return 2;
  }
  DaemonConfig c;
  c.bake_path = argv[1];
  c.patch_path = argv[2];
  c.modbus_port = 0;
  c.fps = 30;
  int writes = 200;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (k == "--writes") writes = static_cast<int>(v);
    else if (k == "--fps") c.fps = v;
    else if (k == "--width") c.width = static_cast<int>(v);
    else if (k == "--height") c.height = static_cast<int>(v);
  }
  Daemon d;
  std::unique_ptr<FrameSink> sink;
  Status st = d.Open(c);
  if (st.ok()) st = MakeStreamSink("/dev/null", true, &sink);
  if (st.ok()) d.AddSink(std::move(sink)), st = d.Start();
  if (!st.ok()) {
    std::fprintf(stderr, "relightd_emitter_bench: %s\n", st.ToString().c_str());
    return 2;
  }
  int port = 0;
  for (hal::InputSource* s : d.sources()) {
    if (auto* tcp = dynamic_cast<hal::ModbusTcpServer*>(s)) port = tcp->port();
  }
  const hal::FixturePatch* lum_f = nullptr;
  const hal::FixturePatch* emit_f = nullptr;
  for (const hal::FixturePatch& f : d.patch().fixtures) {
    if (f.emitter < 0 && lum_f == nullptr) lum_f = &f;
    if (f.emitter >= 0 && emit_f == nullptr) emit_f = &f;
  }
  if (lum_f == nullptr || emit_f == nullptr || !emit_f->layout.Has(hal::Channel::kX)) {
    std::fprintf(stderr, "relightd_emitter_bench: the patch needs a luminaire and an emitter with an x register\n");
    return 2;
  }
  const int lum = d.engine().FindLuminaire(lum_f->name);

  std::mutex mu;
  std::condition_variable cv;
  int want = -1;  // 0: the pan, 1: the emitter's move
  int32_t want_pan = 0;
  int64_t out_us = 0, render_us = 0;
  d.SetFrameObserver([&](const FrameInfo& f) {
    std::lock_guard<std::mutex> lock(mu);
    if (want < 0 || out_us != 0 || f.render_us == 0) return;
    const bool shown = want == 0 ? d.engine().state(lum).pan_deg.raw() == want_pan
                                 : d.engine().last_update_emitters_solved() > 0;
    if (!shown) return;
    out_us = f.out_us;
    render_us = f.render_us;
    cv.notify_all();
  });
  std::atomic<bool> stop{false}, reload{false};
  Status run_status;
  std::thread runner([&] { run_status = d.Run(stop, reload); });
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  if (modbus_connect(ctx) != 0) {
    std::fprintf(stderr, "relightd_emitter_bench: cannot connect\n");
    stop.store(true);
    runner.join();
    return 2;
  }
  const int dimmer_at = emit_f->modbus_base + emit_f->layout.OffsetOf(hal::Channel::kDimmer);
  const int x_at = emit_f->modbus_base + emit_f->layout.OffsetOf(hal::Channel::kX);
  const int pan_at = lum_f->modbus_base + lum_f->layout.OffsetOf(hal::Channel::kPan);
  (void)modbus_write_register(ctx, dimmer_at, 65535);  // the emitter on before timing
  std::this_thread::sleep_for(std::chrono::milliseconds(500));

  std::mt19937 rng(12345);
  std::uniform_int_distribution<int64_t> phase(0, d.period_us());
  std::vector<int64_t> render[2], latency[2];
  int timeouts = 0;
  uint16_t last[2] = {0, 0};
  for (int i = 0; i < writes; ++i) {
    const int kind = i % 2;
    uint16_t value;
    do {
      value = static_cast<uint16_t>(rng() & 0xFFFF);
    } while (value == last[kind] || (kind == 0 && hal::AngleQ16FromRegister(value, lum_f->pan_range_q16) ==
                                                      d.engine().state(lum).pan_deg.raw()));
    last[kind] = value;
    std::this_thread::sleep_for(std::chrono::microseconds(phase(rng)));
    {
      std::lock_guard<std::mutex> lock(mu);
      want = kind;
      // The engine keeps pan in (-180, 180]: as relightd_bench, the bake's ranges keep writes within it.
      want_pan = hal::AngleQ16FromRegister(value, lum_f->pan_range_q16);
      if (want_pan > (180 << 16)) want_pan -= 360 << 16;
      if (want_pan <= -(180 << 16)) want_pan += 360 << 16;
      out_us = 0;
    }
    const int64_t sent_us = MonotonicUs();
    if (modbus_write_register(ctx, kind == 0 ? pan_at : x_at, value) != 1) break;
    std::unique_lock<std::mutex> lock(mu);
    if (!cv.wait_for(lock, std::chrono::seconds(5), [&] { return out_us != 0; })) {
      ++timeouts;
      want = -1;
      continue;
    }
    render[kind].push_back(render_us);
    latency[kind].push_back(out_us - sent_us);
    want = -1;
  }
  modbus_close(ctx);
  modbus_free(ctx);
  stop.store(true);
  runner.join();
  const char* names[2] = {"pan change (baseline)", "emitter move (x)"};
  std::printf("relightd_emitter_bench: %s %dx%d at %g frames/s, %d writes, %d timeouts\n", c.bake_path.c_str(), c.width,
              c.height, c.fps, writes, timeouts);
  for (int k = 0; k < 2; ++k) {
    std::printf("  %-22s render p50 %7.2f ms p99 %7.2f ms   write -> frame out p50 %7.2f ms p99 %7.2f ms  (%zu)\n",
                names[k], Percentile(render[k], 0.5), Percentile(render[k], 0.99), Percentile(latency[k], 0.5),
                Percentile(latency[k], 0.99), render[k].size());
  }
  std::printf("  ratio move / pan: render p50 %.2f, p99 %.2f; write -> frame out p50 %.2f, p99 %.2f\n",
              Percentile(render[1], 0.5) / Percentile(render[0], 0.5),
              Percentile(render[1], 0.99) / Percentile(render[0], 0.99),
              Percentile(latency[1], 0.5) / Percentile(latency[0], 0.5),
              Percentile(latency[1], 0.99) / Percentile(latency[0], 0.99));
  return timeouts == 0 && run_status.ok() ? 0 : 1;
}

}  // namespace
}  // namespace relight::daemon

int main(int argc, char** argv) { return relight::daemon::Run(argc, argv); }
