// relightd: the real-time daemon. Inputs (Modbus, GPIO, replay) -> engine ->
// OSMesa frames at a steady rate -> PNG files, a PPM/raw stream, a framebuffer.
//
//   relightd room.rlb --patch patch.toml --fb /dev/fb0
//   relightd room.rlb --replay show.replay --png frames/f_%04d.png --exit-when-replay-done
//   relightd stage.rlb --dmx stage_patch.toml --fb /dev/fb0          # a console through olad
//   relightd stage.rlb --dmx stage_patch.toml --dmx-replay stage.dmxrec --png f_%04d.png --exit-when-replay-done
//
// SIGINT/SIGTERM: clean shutdown. SIGHUP: re-read the bake (if its file
// changed) and the patch; on an error the running ones stay. Logs on stderr.
#include <csignal>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include <CLI/CLI.hpp>

#include "daemon.h"
#include "notify.h"
#include "relight/base/log.h"
#include "relight/base/proc_status.h"

namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_reload{false};

extern "C" void OnSignal(int sig) {
  if (sig == SIGHUP) {
    g_reload.store(true);
  } else {
    g_stop.store(true);
  }
}

void InstallSignals() {
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a signal cuts the frame-rate sleep short
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a stream reader that goes away is a write error, not a kill
}

int Fail(const relight::Status& st, int code) {
  std::fprintf(stderr, "relightd: error: %s\n", st.ToString().c_str());
  return code;
}

bool ParseVec3(const std::string& text, float out[3]) {
  return std::sscanf(text.c_str(), "%f,%f,%f", &out[0], &out[1], &out[2]) == 3;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "relightd: relight's real-time daemon. Reads fixture changes from the inputs the patch names\n"
      "(Modbus TCP/RTU server, Modbus poller, GPIO), from a replay script and from DMX (--dmx: a\n"
      "lighting console through olad, or --dmx-replay: a recorded show), relights the baked room\n"
      "and renders frames at a steady rate to the sinks given (--png, --ppm, --raw, --fb).\n"
      "SIGINT/SIGTERM stop it cleanly; SIGHUP re-reads the bake (when its file changed; a bad one is\n"
      "refused) and the patch. Register map: docs/modbus.md;\n"
      "DMX, olad and consoles: docs/dmx.md."};
  relight::daemon::DaemonConfig config;
  std::string png, ppm, raw, fb, fb_size, sheet, camera_pos, camera_target;
  double fov = 0, white_cd_m2 = 0;
  app.add_option("bake", config.bake_path, "bake file written by relight-bake (.rlb)")->required();
  app.add_option("--patch", config.patch_path, "patch file (TOML): inputs, register blocks, ranges, curves, fades");
  app.add_option("--replay", config.replay_path, "replay script of timed changes (the simulated console)");
  app.add_option("--dmx", config.dmx_patch_path,
                 "DMX patch (TOML, docs/dmx.md): take DMX from olad (sACN, Art-Net, USB) for its universes; "
                 "fixture names must be the bake's luminaires");
  app.add_option("--dmx-replay", config.dmx_replay_path,
                 "with --dmx: play this DMX recording (timestamped frames) instead of listening to olad");
  app.add_option("--modbus-port", config.modbus_port,
                 "serve Modbus TCP on 127.0.0.1:PORT even without [modbus_tcp] in the patch (0: any free port)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--threads", config.engine_threads,
                 "engine threads, 1..16 (default: RELIGHT_THREADS, else the cores, at most 2)")
      ->check(CLI::Range(1, 16));
  double table_mb = static_cast<double>(config.emitter_bounce_table_bytes) / (1 << 20);
  app.add_option("--emitter-table-mb", table_mb,
                 "with [[emitter]]s: memory for their later bounces, tabulated at start-up (a few seconds) so a "
                 "new emitter's solve starts near its answer; 0: none (faster start, slower placements)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 4096.0));
  app.add_option("--fps", config.fps, "frames per second")->capture_default_str()->check(CLI::Range(0.1, 1000.0));
  app.add_option("--width", config.width, "frame width, pixels")->capture_default_str()->check(CLI::Range(16, 8192));
  app.add_option("--height", config.height, "frame height, pixels")->capture_default_str()->check(CLI::Range(16, 8192));
  app.add_option("--png", png, "write every frame as PNG: a pattern with one %d, e.g. out/frames/f_%04d.png");
  app.add_option("--ppm", ppm, "write a PPM frame stream to PATH (a FIFO or file) or - for stdout");
  app.add_option("--raw", raw, "write raw RGB24 frames to PATH or - for stdout");
  app.add_option("--fb", fb, "write frames to a Linux framebuffer device (or a file: give --fb-size)");
  app.add_option("--fb-size", fb_size, "WxH of a framebuffer that is a plain file (32-bit XRGB)");
  app.add_option("--sheet", sheet, "also write all frames, half size, on one PNG page at the end (finite runs only)");
  app.add_option("--frames", config.max_frames, "stop after this many frames (0: run until stopped)")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 40));
  app.add_flag("--exit-when-replay-done", config.exit_when_replay_done,
               "stop after the frame showing the replay's last change (and its fade)");
  app.add_flag("--script-time", config.script_time,
               "do not wait for the clock: frame k shows script time k/fps (reproducible, as fast as it renders)");
  app.add_option("--camera-pos", camera_pos, "camera position X,Y,Z in metres (default: the scene's)");
  app.add_option("--camera-target", camera_target, "point looked at X,Y,Z in metres (default: the scene's)");
  app.add_option("--fov", fov, "vertical field of view, degrees")->check(CLI::Range(1.0, 170.0));
  app.add_option("--white", white_cd_m2, "luminance shown as display white, cd/m^2")->check(CLI::Range(0.001, 1e7));
  bool keep_startup_memory = false;
  app.add_flag("--keep-startup-memory", keep_startup_memory,
               "keep what only start-up needed resident (default: blocks of 128 KiB or more get their own "
               "mappings, so what start-up frees goes back at once; llvmpipe compiles its shaders on a stand-in "
               "triangle before the bake is read, then its compiler's pages, ~45 MB, go back to the kernel, "
               "and the heap's free pages once the bake is read; a later shader compile reads them again)");
  CLI11_PARSE(app, argc, argv);
  config.release_startup_memory = !keep_startup_memory;

  if (!sheet.empty() && config.max_frames == 0 && !config.exit_when_replay_done) {
    return Fail(relight::Status(relight::StatusCode::kInvalidArgument,
                                "--sheet needs a finite run: --frames N or --exit-when-replay-done"), 2);
  }
  for (const auto& [text, slot, name] : {std::tuple<const std::string&, std::optional<std::array<float, 3>>*, const char*>{
           camera_pos, &config.camera_pos, "--camera-pos"},
       {camera_target, &config.camera_target, "--camera-target"}}) {
    if (text.empty()) continue;
    std::array<float, 3> v{};
    if (!ParseVec3(text, v.data())) {
      return Fail(relight::Status(relight::StatusCode::kInvalidArgument, std::string(name) + " wants X,Y,Z in metres"), 2);
    }
    *slot = v;
  }
  config.fov_y_deg = static_cast<float>(fov);
  config.white_q12 = white_cd_m2 > 0 ? static_cast<int32_t>(std::lround(white_cd_m2 * 4096.0)) : 0;

  config.emitter_bounce_table_bytes = static_cast<int64_t>(table_mb * (1 << 20));
  relight::daemon::Daemon daemon;
  if (relight::Status st = daemon.Open(config); !st.ok()) return Fail(st, 2);

  std::unique_ptr<relight::daemon::FrameSink> sink;
  if (!png.empty()) {
    if (relight::Status st = relight::daemon::MakePngSequenceSink(png, &sink); !st.ok()) return Fail(st, 2);
    daemon.AddSink(std::move(sink));
  }
  for (const auto& [path, is_raw] : {std::pair<std::string, bool>{ppm, false}, {raw, true}}) {
    if (path.empty()) continue;
    if (relight::Status st = relight::daemon::MakeStreamSink(path, is_raw, &sink); !st.ok()) return Fail(st, 2);
    daemon.AddSink(std::move(sink));
  }
  if (!fb.empty()) {
    int fw = 0, fh = 0;
    if (!fb_size.empty() && std::sscanf(fb_size.c_str(), "%dx%d", &fw, &fh) != 2) {
      return Fail(relight::Status(relight::StatusCode::kInvalidArgument, "--fb-size wants WxH, e.g. 1280x720"), 2);
    }
    if (relight::Status st = relight::daemon::MakeFramebufferSink(fb, fw, fh, &sink); !st.ok()) return Fail(st, 2);
    daemon.AddSink(std::move(sink));
  }
  if (!sheet.empty()) {
    if (relight::Status st = relight::daemon::MakeContactSheetSink(sheet, &sink); !st.ok()) return Fail(st, 2);
    daemon.AddSink(std::move(sink));
  }

  InstallSignals();
  if (relight::Status st = daemon.Start(); !st.ok()) return Fail(st, 2);
  std::string inputs;
  for (relight::hal::InputSource* s : daemon.sources()) inputs += std::string(inputs.empty() ? "" : ", ") + s->Name();
  relight::Log(relight::LogLevel::kInfo, "relightd: %s, %d luminaires, %dx%d at %g frames/s; inputs: %s",
                    config.bake_path.c_str(), daemon.engine().luminaire_count(), config.width, config.height,
                    config.fps, inputs.empty() ? "none" : inputs.c_str());
  if (daemon.engine().emitter_bounce_sources() > 0) {
    relight::Log(relight::LogLevel::kInfo,
                 "relightd: surface emitters: later bounces of %d pieces of the surfaces tabulated at start-up "
                 "(%.1f MB), so a new emitter's solve starts near its answer; adaptive-refine moves within "
                 "%.2f m of where a panel was last solved are shown at once and settled on the next idle frame",
                 daemon.engine().emitter_bounce_sources(),
                 static_cast<double>(daemon.engine().emitter_bounce_table_size()) / (1 << 20),
                 daemon.engine().emitter_quick_reach_q16() / 65536.0);
  }

  // systemd: READY=1 after the first frame, WATCHDOG=1 while frames flow (notify.h).
  relight::daemon::SystemdNotifier notifier;
  daemon.SetFrameObserver([&notifier](const relight::daemon::FrameInfo& f) { notifier.OnFrame(f.out_us); });
  const relight::Status st = daemon.Run(g_stop, g_reload);
  notifier.Stopping();
  const relight::daemon::DaemonStats stats = daemon.stats();
  const auto ms = [](int64_t us) { return static_cast<double>(us) / 1e3; };
  relight::Log(relight::LogLevel::kInfo,
               "relightd: %lld frames, %lld of them drawn (the rest unchanged, sent again), %lld ticks skipped, "
               "last write-to-frame latency %.1f ms%s",
               static_cast<long long>(stats.frames), static_cast<long long>(stats.renders),
               static_cast<long long>(stats.ticks_skipped), stats.last_latency_us / 1e3,
               g_stop.load() ? " (stopped by signal)" : "");
  if (stats.renders > 0) {
    // Percentiles to 0.1 ms (duration_histogram.h).
    const relight::daemon::DurationHistogram& r = stats.render_times;
    relight::Log(relight::LogLevel::kInfo,
                 "relightd: render (engine update + tone map + draw) %.1f ms mean, p50 %.1f, p99 %.1f, max %.1f ms; "
                 "engine update p50 %.1f, p99 %.1f ms; tone map + draw p50 %.1f, p99 %.1f ms",
                 ms(stats.render_us_total) / static_cast<double>(stats.renders), ms(r.QuantileUs(500)),
                 ms(r.QuantileUs(990)), ms(r.max_us()), ms(stats.update_times.QuantileUs(500)),
                 ms(stats.update_times.QuantileUs(990)), ms(stats.draw_times.QuantileUs(500)),
                 ms(stats.draw_times.QuantileUs(990)));
    relight::Log(relight::LogLevel::kInfo,
                 "relightd: the last frame drew %u of the mesh's %u triangles (the rest hidden at its camera)%s",
                 stats.drawn_triangles, stats.mesh_triangles,
                 stats.draw_resolved ? ", resolved from the still camera's pixel table" : ", rasterised by llvmpipe");
  }
  const long rss_kb = relight::ProcStatusKb("VmRSS"), peak_kb = relight::ProcStatusKb("VmHWM");
  if (rss_kb > 0 && peak_kb > 0) {
    relight::Log(relight::LogLevel::kInfo, "relightd: memory: %.1f MiB resident at the end, peak %.1f MiB (start-up)",
                 static_cast<double>(rss_kb) / 1024.0, static_cast<double>(peak_kb) / 1024.0);
  }
  if (!st.ok()) return Fail(st, 1);
  return 0;
}
