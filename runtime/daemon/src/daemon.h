// relightd's core: inputs -> fades -> engine -> renderer -> sinks at a
// steady frame rate. The main (relightd_main.cc) parses the command line and
// handles signals; tests and the latency benchmark drive this class directly.
//
// Each control tick k (period 1/fps): poll every source (replay scripts at
// script time k/fps, live sources at once), hand the changes to the fader,
// apply its outputs to the engine, render, write the frame to every sink,
// then tell every source the frame number and the write-to-frame latency
// (Modbus status registers). When rendering falls behind, ticks are
// skipped, not queued. The last state keeps being shown whatever the
// inputs do.
//
// Between ticks the live sources (Modbus, GPIO, DMX) are polled every
// millisecond: a change that arrives when the render budget allows is
// rendered at once (an early frame) instead of waiting for the tick, so
// renders stay at most one per period on average while a change is shown
// within about one render time. A tick where nothing moved sends the last
// frame again without redrawing it.
//
// With live inputs only, the ticks follow the input: the next tick is due
// one period after the last frame, and a change may be rendered up to one
// period early (a burst of one), so a console sending at the frame rate is
// rendered as each DMX frame arrives, never phase-locked a period behind.
// With a replay script the ticks stay at t0 + k/fps and early frames keep
// one period from the last render: replay scripts only act on ticks, so
// replays give the same frames in real time and in script time.
//
// Thread safety: one thread calls everything; stop/reload flags may be set
// from anywhere (signal handlers).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "duration_histogram.h"
#include "frame_pipeline.h"
#include "frame_sink.h"
#include "relight/engine/engine.h"
#include "relight/control/change_path.h"
#include "relight/hal/input_source.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::daemon {

struct DaemonConfig {
  std::string bake_path;
  std::string patch_path;     // empty: every luminaire with defaults, no live inputs
  std::string replay_path;    // empty: the patch's [replay] script, if any
  std::string dmx_patch_path;   // DMX patch (TOML): live DMX through olad, or the DMX replay below
  std::string dmx_replay_path;  // with dmx_patch_path: play this recording (dmx_replay_source.h) instead of olad
  int modbus_port = -1;       // >= 0: serve Modbus TCP on 127.0.0.1 at this port (0: any) even without [modbus_tcp]
  int width = 1280, height = 720;
  double fps = 30;
  bool script_time = false;   // no waiting: frame k shows script time k/fps (reproducible runs)
  bool fixed_ticks = false;   // live inputs only: keep the ticks at t0 + k/fps (the loop before ticks
                              // followed the input; dmx_latency_bench --compare measures both)
  bool exit_when_replay_done = false;  // after the frame that shows the replay's (or DMX replay's) last change and fade
  int64_t max_frames = 0;     // 0: no limit
  int engine_threads = 0;     // Engine::Update's threads (EngineOptions); 0: its default
  // Memory for the engine's later-bounce table of surface emitters
  // (EngineOptions::emitter_bounce_table_bytes): built at start-up when the
  // patch has an [[emitter]]; 0: none (a faster start, more sweeps a new emitter).
  int64_t emitter_bounce_table_bytes = kDefaultEmitterBounceTableBytes;
  // Camera: the bake's, with any of these replacing its part.
  std::optional<std::array<float, 3>> camera_pos, camera_target;  // metres
  float fov_y_deg = 0;        // 0: the bake's
  int32_t white_q12 = 0;      // display white, LightQ12 cd/m^2; 0: the bake's
  // Hand what only start-up needs back to the kernel (startup_memory.h):
  // the shader compiler's pages, compiled out before the bake is read, and
  // the heap's free pages after; about 50 MB less RSS on the stage, and a
  // start-up peak about as low.
  bool release_startup_memory = true;
};

// What one frame was: for logs, tests and the latency benchmark.
struct FrameInfo {
  int64_t frame = 0;          // 0, 1, 2, ...
  int64_t tick = 0;           // control tick shown (script time = tick / fps); -1: an early frame
  int64_t render_us = 0;      // engine update + tone map + draw; 0: the last frame sent again
  int64_t out_us = 0;         // MonotonicUs() when every sink had it
  int64_t newest_arrival_us = 0;  // arrival of the newest live change it shows (0: none this frame)
};

struct DaemonStats {
  int64_t frames = 0;         // written to the sinks
  int64_t renders = 0;        // drawn (a frame where nothing moved is sent again, not redrawn)
  int64_t early_frames = 0;   // rendered between ticks for a live change
  int64_t ticks_skipped = 0;  // render too slow for the frame rate
  int64_t render_us_total = 0, render_us_max = 0;  // over the renders
  // Per render: the whole (= FrameInfo::render_us), Engine::Update, tone map + draw.
  DurationHistogram render_times, update_times, draw_times;
  // The last render's triangles shown, of the mesh's (hidden-triangle
  // culling: OsMesaFrame::SetHiddenTriangleCulling), and whether that frame
  // came from the still camera's pixel table rather than llvmpipe.
  uint32_t drawn_triangles = 0, mesh_triangles = 0;
  bool draw_resolved = false;
  uint32_t last_latency_us = 0;
  int64_t changes_applied = 0;
  int reloads = 0, reload_failures = 0;
};

class Daemon {
 public:
  Daemon();
  ~Daemon();

  // Opens the bake, reads and resolves the patch, creates its input sources
  // and the renderer. Errors name the file and what is wrong.
  Status Open(const DaemonConfig& config);
  void AddSink(std::unique_ptr<FrameSink> sink);
  // An extra source (a mock in tests), kept across patch reloads.
  void AddSource(std::unique_ptr<hal::InputSource> source);
  // Called after every frame (tests, benchmark).
  void SetFrameObserver(std::function<void(const FrameInfo&)> observer);

  // Starts every source; the first failure stops the others and is returned
  // naming the source.
  Status Start();
  // Renders until `stop` is set, max_frames are out or (with
  // exit_when_replay_done) the replay is over. `reload` set: re-read the
  // bake if its file changed (bake_reload.h: a bad one is refused, the
  // running one stays), then the patch (on an error the old patch stays).
  // Returns the error that stopped it.
  Status Run(const std::atomic<bool>& stop, std::atomic<bool>& reload);

  Engine& engine();
  const hal::Patch& patch() const;
  const hal::RegisterMap& register_map() const;
  // Sources from the patch, the replay, the DMX input, then the extra ones.
  std::vector<hal::InputSource*> sources() const;
  DaemonStats stats() const;
  int64_t period_us() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::daemon
