#include "daemon.h"

#include <algorithm>

#include "bake_reload.h"
#include "engine_registers.h"
#include "frame_pacing.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/control/engine_binding.h"
#include "relight/hal/dmx/dmx_replay_source.h"
#include "relight/hal/dmx/ola_source.h"
#include "relight/hal/param_text.h"
#include "relight/hal/replay_source.h"
#include "relight/hal/source_factory.h"
#include "startup_memory.h"

namespace relight::daemon {

struct Daemon::Impl {
  DaemonConfig config;
  Engine engine;
  hal::Patch patch;
  hal::RegisterMap map;
  control::ChangePath path;
  std::vector<std::unique_ptr<hal::InputSource>> patch_sources;  // replaced on reload
  std::unique_ptr<hal::ReplaySource> replay;
  std::unique_ptr<hal::InputSource> dmx;      // DMX through olad, or a DMX replay; kept across patch reloads
  std::vector<uint16_t> dmx_luminaires;       // DMX patch fixture -> engine luminaire
  bool dmx_is_replay = false;
  std::vector<std::unique_ptr<hal::InputSource>> extra_sources;
  std::vector<control::BoundInput> inputs;  // every source with its index table; rebuilt when sources change
  std::vector<std::unique_ptr<FrameSink>> sinks;
  cli::FramePipeline pipeline;
  std::function<void(const FrameInfo&)> observer;
  DaemonStats stats;
  int64_t period_us = 33333;
  BakeFileId bake_id;      // the bake file as loaded: SIGHUP re-reads it when it changed
  // How the engine opens its bake; surface_emitters only while the patch has
  // an [[emitter]] (the hierarchy is most of a hierarchical bake's memory).
  EngineOptions engine_options;
  bool force_render = false;  // a new bake: draw the next frame even if no input moved
  Status fatal;            // the renderer could not take a new bake: Run stops with this

  std::vector<hal::InputSource*> AllSources() const {
    std::vector<hal::InputSource*> all;
    for (const control::BoundInput& in : inputs) all.push_back(in.source);
    return all;
  }

  // Patch sources and extra ones (mocks made from the patch) index the
  // patch's fixtures; the replay indexes the bake's luminaires.
  void BindInputs() {
    inputs.clear();
    for (const auto& s : patch_sources) inputs.push_back({s.get(), path.patch_luminaires()});
    if (replay) inputs.push_back({replay.get(), {}});
    if (dmx) inputs.push_back({dmx.get(), dmx_luminaires});
    for (const auto& s : extra_sources) inputs.push_back({s.get(), path.patch_luminaires()});
  }

  // The finite scripts (replay, DMX replay) are all played out.
  bool ScriptsFinished() const {
    return (!replay || replay->Finished()) && (!dmx || !dmx_is_replay || dmx->Finished());
  }

  // The DMX patch: its fixture names bound to the bake's luminaires once,
  // here; a name the bake lacks is an error naming the patch's file:line.
  Status OpenDmx() {
    hal::DmxPatch dmx_patch;
    RELIGHT_RETURN_IF_ERROR(hal::LoadDmxPatch(config.dmx_patch_path, &dmx_patch));
    if (dmx_patch.fixtures.size() > static_cast<size_t>(kMaxFixtures)) {
      return Status(StatusCode::kInvalidArgument, config.dmx_patch_path + ": more than 65535 fixtures");
    }
    // A DMX fixture drives a luminaire or one of the patch's emitters (its slot after the luminaires).
    const std::vector<std::string> slots = path.SlotNames();
    std::vector<uint16_t> luminaires;
    for (const hal::DmxFixturePatch& f : dmx_patch.fixtures) {
      const int slot = hal::FixtureIndex(slots, f.name);
      if (slot < 0) {
        return Status(StatusCode::kNotFound, config.dmx_patch_path + ":" + std::to_string(f.line) +
                                                 ": dmx_fixture: no luminaire '" + f.name +
                                                 "' in the bake (it has: " + hal::FixtureList(slots) +
                                                 ") nor among the --patch's emitters");
      }
      luminaires.push_back(static_cast<uint16_t>(slot));
    }
    dmx_luminaires = std::move(luminaires);
    dmx_is_replay = !config.dmx_replay_path.empty();
    if (dmx_is_replay) {
      dmx = std::make_unique<hal::DmxReplaySource>(std::move(dmx_patch), config.dmx_replay_path);
    } else {
      hal::DmxOlaConfig ola;
      ola.wait_for_olad = true;  // say so and keep trying: the console's olad may come later
      dmx = std::make_unique<hal::DmxOlaSource>(std::move(dmx_patch), ola);
    }
    BindInputs();
    return Status::Ok();
  }

  // Builds the map, fader and live sources of `p` (resolved). Does not start them.
  Status Adopt(hal::Patch p) {
    hal::RegisterMap new_map;
    RELIGHT_RETURN_IF_ERROR(hal::RegisterMap::Build(p.fixtures, &new_map));
    hal::Patch live = p;
    live.replay_script.clear();  // the replay belongs to the daemon, not to reloads
    std::vector<std::unique_ptr<hal::InputSource>> sources;
    RELIGHT_RETURN_IF_ERROR(hal::MakeInputSources(live, new_map, RegistersFor(engine, p, new_map), "", &sources));
    control::ChangePath new_path;
    RELIGHT_RETURN_IF_ERROR(new_path.Bind(&engine, p.fixtures, &path, p.emitters, p.where.empty() ? "patch" : p.where));
    patch = std::move(p);
    map = std::move(new_map);
    path = std::move(new_path);
    patch_sources = std::move(sources);
    BindInputs();
    return Status::Ok();
  }

  static Status StartAll(const std::vector<hal::InputSource*>& sources) {
    for (size_t i = 0; i < sources.size(); ++i) {
      if (Status st = sources[i]->Start(); !st.ok()) {
        for (size_t k = 0; k < i; ++k) sources[k]->Stop();
        return Status(st.code(), std::string("input ") + sources[i]->Name() + ": " + st.message());
      }
    }
    return Status::Ok();
  }

  // The patch file (and --modbus-port) as read, not yet bound to the bake.
  Status LoadPatchFile(hal::Patch* out) const {
    hal::Patch p;
    if (!config.patch_path.empty()) RELIGHT_RETURN_IF_ERROR(hal::LoadPatch(config.patch_path, &p));
    if (config.modbus_port >= 0) {
      p.modbus_tcp.enabled = true;
      p.modbus_tcp.port = config.modbus_port;
    }
    *out = std::move(p);
    return Status::Ok();
  }

  Status LoadResolved(hal::Patch* out) {
    hal::Patch p;
    RELIGHT_RETURN_IF_ERROR(LoadPatchFile(&p));
    RELIGHT_RETURN_IF_ERROR(hal::ResolvePatch(Luminaires(engine), &p));
    *out = std::move(p);
    return Status::Ok();
  }

  // The bake's camera with the command line's changes.
  CameraView View() const {
    CameraView view = cli::CameraFromBake(engine.bake().camera);
    for (int i = 0; i < 3; ++i) {
      if (config.camera_pos) view.position[i] = (*config.camera_pos)[static_cast<size_t>(i)];
      if (config.camera_target) view.target[i] = (*config.camera_target)[static_cast<size_t>(i)];
    }
    if (config.fov_y_deg > 0) view.fov_y_deg = config.fov_y_deg;
    return view;
  }

  // SIGHUP, first step: a changed bake file is read and, if valid, taken
  // (bake_reload.h); a bad one is refused and the running bake stays.
  // `force`: read it again even if the file is the one loaded (the engine
  // options changed). False when the new bake was refused.
  bool ReloadBakeFile(bool force = false) {
    BakeReload result = BakeReload::kUnchanged;
    if (Status st = ReloadBake(config.bake_path, &engine, &bake_id, &result, engine_options, force); !st.ok()) {
      ++stats.reload_failures;
      Log(LogLevel::kError, "relightd: bake reload refused, keeping the running bake: %s", st.ToString().c_str());
      return false;
    }
    if (result == BakeReload::kUnchanged) return true;
    fatal = pipeline.Init(engine, config.width, config.height, View(), config.white_q12);
    if (!fatal.ok()) return true;
    force_render = true;
    Log(LogLevel::kInfo, "relightd: bake %s reloaded (%u vertices, %d luminaires%s)", config.bake_path.c_str(),
        engine.vertex_count(), engine.luminaire_count(),
        engine_options.surface_emitters ? ", with its hierarchy for surface emitters" : "");
    return true;
  }

  // A reloaded patch that brings the first [[emitter]] needs the bake's
  // hierarchy, which was not loaded: the bake is opened again with it (the
  // fixtures keep their state). False (and the engine as it was) on error.
  bool EnableSurfaceEmitters() {
    engine_options.surface_emitters = true;
    if (ReloadBakeFile(/*force=*/true) && fatal.ok()) return true;
    engine_options.surface_emitters = false;
    return false;
  }

  void Reload() {
    ++stats.reloads;
    ReloadBakeFile();
    if (!fatal.ok()) return;
    hal::Patch p;
    if (Status st = LoadResolved(&p); !st.ok()) {
      ++stats.reload_failures;
      Log(LogLevel::kError, "relightd: patch reload failed, keeping the old patch: %s", st.ToString().c_str());
      return;
    }
    if (!p.emitters.empty() && !engine_options.surface_emitters) {
      Log(LogLevel::kInfo, "relightd: the patch now has emitters: reading the bake's hierarchy");
      if (!EnableSurfaceEmitters()) {
        Log(LogLevel::kError, "relightd: patch reload failed, keeping the old patch: its [[emitter]] entries need "
                              "the bake's hierarchy, which could not be read");
        return;
      }
    }
    hal::Patch old = patch;
    for (auto& s : patch_sources) s->Stop();  // frees ports and devices for the new sources
    std::vector<hal::InputSource*> started;
    Status st = Adopt(std::move(p));
    if (st.ok()) {
      for (auto& s : patch_sources) started.push_back(s.get());
      st = StartAll(started);
    }
    if (st.ok()) {
      Log(LogLevel::kInfo, "relightd: patch %s reloaded (%d fixtures, %zu live inputs)", config.patch_path.c_str(),
          map.fixture_count(), patch_sources.size());
      return;
    }
    ++stats.reload_failures;
    Log(LogLevel::kError, "relightd: new patch cannot start (%s); going back to the old one", st.ToString().c_str());
    started.clear();
    if (Status back = Adopt(std::move(old)); back.ok()) {
      for (auto& s : patch_sources) started.push_back(s.get());
      back = StartAll(started);
      if (!back.ok()) Log(LogLevel::kError, "relightd: the old patch cannot restart either: %s", back.ToString().c_str());
    }
  }

  // Polls the sources (only the live ones if `live_only`), handing their
  // changes to the fader at daemon time `time_us`; returns the newest
  // arrival among live changes (0: none).
  int64_t PollInputs(int64_t time_us, bool live_only) {
    int64_t newest_arrival = 0;
    for (const control::BoundInput& input : inputs) {
      const hal::SourceClock clock = input.source->clock();
      if (live_only && clock != hal::SourceClock::kMonotonic) continue;
      const int64_t now = clock == hal::SourceClock::kScript ? time_us : MonotonicUs();
      const int64_t newest = path.Poll(input, now, time_us);
      if (clock == hal::SourceClock::kMonotonic && newest > newest_arrival) newest_arrival = newest;
    }
    return newest_arrival;
  }

  // Applies what the fader moved; returns how many parameters changed.
  size_t ApplyFader(int64_t time_us) {
    const size_t n = path.Apply(time_us);
    stats.changes_applied += static_cast<int64_t>(n);
    return n;
  }

  // True when no source plays a script: then ticks follow live input (Run).
  bool LiveOnly() const {
    for (const control::BoundInput& in : inputs) {
      if (in.source->clock() == hal::SourceClock::kScript) return false;
    }
    return true;
  }

  // Real time: waits for the tick due at `deadline_us`, meanwhile polling the
  // live sources every millisecond. Returns true to render early: a live
  // change came and `budget` allows a render now.
  bool WaitForTick(int64_t t0_us, int64_t deadline_us, const RenderBudget& budget, const std::atomic<bool>& stop,
                   const std::atomic<bool>& reload, int64_t* pending_arrival_us) {
    for (;;) {
      const int64_t now = MonotonicUs();
      if (stop.load() || reload.load() || now >= deadline_us) return false;
      const int64_t arrival = PollInputs(now - t0_us, true);
      if (arrival > *pending_arrival_us) *pending_arrival_us = arrival;
      if (*pending_arrival_us > 0 && budget.Allows(now)) return true;
      SleepUntil(std::min(deadline_us, now + 1000));
    }
  }

  // Writes the frame everywhere. A sink failing on the first frame is an
  // error; later the sink is dropped with a log line and the rest go on.
  Status WriteSinks(int64_t frame) {
    for (size_t i = 0; i < sinks.size();) {
      const Status st = sinks[i]->Write(pipeline.pixels(), pipeline.width(), pipeline.height(), frame);
      if (!st.ok()) {
        if (frame == 0) return st;
        Log(LogLevel::kError, "relightd: %s: %s; no more frames go there", sinks[i]->Describe().c_str(),
            st.ToString().c_str());
        sinks.erase(sinks.begin() + static_cast<long>(i));
        continue;
      }
      ++i;
    }
    return Status::Ok();
  }
};

Daemon::Daemon() : impl_(std::make_unique<Impl>()) {}
Daemon::~Daemon() {
  for (hal::InputSource* s : impl_->AllSources()) s->Stop();
}

Status Daemon::Open(const DaemonConfig& config) {
  Impl& m = *impl_;
  m.config = config;
  if (!(config.fps >= 0.1 && config.fps <= 1000)) {
    return Status(StatusCode::kInvalidArgument, "frame rate must be in 0.1..1000 frames/s");
  }
  m.period_us = static_cast<int64_t>(1e6 / config.fps + 0.5);
  m.bake_id = StatBakeFile(config.bake_path);  // before reading: a change meanwhile is read again on SIGHUP
  hal::Patch p;
  RELIGHT_RETURN_IF_ERROR(m.LoadPatchFile(&p));
  m.engine_options.threads = config.engine_threads;
  m.engine_options.surface_emitters = !p.emitters.empty();
  m.engine_options.emitter_bounce_table_bytes = config.emitter_bounce_table_bytes;
  m.engine_options.keep_direct_inputs = false;  // nothing here reads them after Open
  m.engine_options.grids = false;               // nor the grids: frames show the surfaces
  if (config.release_startup_memory) RELIGHT_RETURN_IF_ERROR(CompileShadersThenReleaseCompiler(config, &m.pipeline));
  RELIGHT_RETURN_IF_ERROR(m.engine.Open(config.bake_path, m.engine_options));
  if (config.release_startup_memory) ReleaseFreeHeapPages();  // reading the bake left some
  RELIGHT_RETURN_IF_ERROR(hal::ResolvePatch(Luminaires(m.engine), &p));
  const std::string script = config.replay_path.empty() ? p.replay_script : config.replay_path;
  RELIGHT_RETURN_IF_ERROR(m.Adopt(std::move(p)));
  if (!script.empty()) {
    m.replay = std::make_unique<hal::ReplaySource>(script, m.path.SlotNames());  // luminaires, then emitters
    m.BindInputs();
  }
  if (!config.dmx_replay_path.empty() && config.dmx_patch_path.empty()) {
    return Status(StatusCode::kInvalidArgument, "--dmx-replay needs the DMX patch (--dmx PATCH.toml)");
  }
  if (!config.dmx_patch_path.empty()) RELIGHT_RETURN_IF_ERROR(m.OpenDmx());
  if (config.exit_when_replay_done && !m.replay && !m.dmx_is_replay) {
    return Status(StatusCode::kInvalidArgument,
                  "--exit-when-replay-done needs a replay script (--replay, [replay] or --dmx-replay)");
  }
  RELIGHT_RETURN_IF_ERROR(m.pipeline.Init(m.engine, config.width, config.height, m.View(), config.white_q12));
  if (config.release_startup_memory) ReleaseFreeHeapPages();  // and the mesh's upload
  return Status::Ok();
}

void Daemon::AddSink(std::unique_ptr<FrameSink> sink) { impl_->sinks.push_back(std::move(sink)); }
void Daemon::AddSource(std::unique_ptr<hal::InputSource> source) {
  impl_->extra_sources.push_back(std::move(source));
  impl_->BindInputs();
}
void Daemon::SetFrameObserver(std::function<void(const FrameInfo&)> observer) { impl_->observer = std::move(observer); }

Status Daemon::Start() { return Impl::StartAll(impl_->AllSources()); }

Status Daemon::Run(const std::atomic<bool>& stop, std::atomic<bool>& reload) {
  Impl& m = *impl_;
  const int64_t t0_us = MonotonicUs();
  // Live input only (no script plays): the ticks follow the input. A frame
  // rendered early for a live change moves the next tick to one period after
  // it, and the budget lets a change that comes a little before that render
  // at once, so a console sending at the frame rate is shown about one render
  // after each DMX frame instead of waiting for a tick of its own phase.
  // Scripts keep the fixed ticks t0 + k/fps: a replay's frames stay the same.
  const bool follow_input = !m.config.script_time && !m.config.fixed_ticks && m.LiveOnly();
  RenderBudget budget(m.period_us, follow_input);
  int64_t tick = 0;                         // the next tick: script time tick * period
  int64_t next_tick_us = t0_us;             // following live input: when the next tick is due
  int64_t pending_arrival_us = 0;           // newest live change not yet shown
  bool have_frame = false;
  for (int64_t frame = 0; !stop.load(); ++frame) {
    bool early = false;
    // Following live input, ticks keep to the budget too: renders stay at most --fps on average.
    const int64_t deadline_us =
        follow_input ? std::max(next_tick_us, budget.EarliestUs()) : t0_us + tick * m.period_us;
    if (!m.config.script_time) {
      early = m.WaitForTick(t0_us, deadline_us, budget, stop, reload, &pending_arrival_us);
      if (stop.load()) break;
      if (!early && MonotonicUs() < deadline_us) {
        --frame;  // woken for a reload only
        if (reload.exchange(false)) m.Reload();
        RELIGHT_RETURN_IF_ERROR(m.fatal);
        continue;
      }
    }
    if (reload.exchange(false)) m.Reload();
    RELIGHT_RETURN_IF_ERROR(m.fatal);
    // Daemon time: the tick's script time, or now for an early frame or a tick following live input.
    const int64_t start_us = MonotonicUs();
    const int64_t time_us = early || follow_input ? start_us - t0_us : tick * m.period_us;
    if (!early) {
      const int64_t arrival = m.PollInputs(time_us, false);
      if (arrival > pending_arrival_us) pending_arrival_us = arrival;
    }
    // Nothing moved since the last frame: send it again instead of redrawing it.
    const bool render = m.ApplyFader(time_us) > 0 || !have_frame || m.force_render;
    m.force_render = false;
    int64_t render_us = 0;
    if (render) {
      const int64_t render_start_us = MonotonicUs();
      budget.Spend(render_start_us);
      RELIGHT_RETURN_IF_ERROR(m.pipeline.Render(m.engine));
      render_us = MonotonicUs() - render_start_us;
      have_frame = true;
      ++m.stats.renders;
      m.stats.render_times.Add(render_us);
      m.stats.update_times.Add(m.pipeline.last_update_us());
      m.stats.draw_times.Add(m.pipeline.last_draw_us());
      m.stats.drawn_triangles = m.pipeline.last_drawn_triangles();
      m.stats.draw_resolved = m.pipeline.last_draw_resolved();
      m.stats.mesh_triangles = m.engine.bake().mesh.triangle_count();
    }
    RELIGHT_RETURN_IF_ERROR(m.WriteSinks(frame));
    const int64_t out_us = MonotonicUs();
    if (render && m.stats.renders == 2 && m.config.release_startup_memory) ReleaseFreeHeapPages();  // frames' leftovers

    const int64_t shown_arrival_us = render ? pending_arrival_us : 0;
    if (shown_arrival_us > 0) {
      const int64_t latency = out_us - shown_arrival_us;
      m.stats.last_latency_us = static_cast<uint32_t>(latency < 0 ? 0 : latency > 0xFFFFFFFF ? 0xFFFFFFFF : latency);
      pending_arrival_us = 0;
    }
    for (const control::BoundInput& in : m.inputs) in.source->OnFrameOut(static_cast<uint32_t>(frame + 1), m.stats.last_latency_us);
    ++m.stats.frames;
    if (early) ++m.stats.early_frames;
    m.stats.render_us_total += render_us;
    if (render_us > m.stats.render_us_max) m.stats.render_us_max = render_us;
    if (m.observer) m.observer({frame, early ? -1 : tick, render_us, out_us, shown_arrival_us});

    if (m.config.max_frames > 0 && frame + 1 >= m.config.max_frames) break;
    if (!early && m.config.exit_when_replay_done && m.ScriptsFinished() && m.path.Idle(time_us)) break;
    if (!early) ++tick;
    if (follow_input) {
      // The next tick one period after this frame; behind schedule: skip, don't queue.
      next_tick_us = start_us + m.period_us;
      if (out_us >= next_tick_us) {
        const int64_t behind = (out_us - next_tick_us) / m.period_us + 1;
        m.stats.ticks_skipped += behind;
        next_tick_us += behind * m.period_us;
      }
    } else if (!early && !m.config.script_time) {
      // Behind schedule: skip to the next tick still ahead rather than queue frames.
      const int64_t due = (out_us - t0_us) / m.period_us + 1;
      if (due > tick) {
        m.stats.ticks_skipped += due - tick;
        tick = due;
      }
    }
  }
  for (const auto& sink : m.sinks) RELIGHT_RETURN_IF_ERROR(sink->Finish());
  return Status::Ok();
}

Engine& Daemon::engine() { return impl_->engine; }
const hal::Patch& Daemon::patch() const { return impl_->patch; }
const hal::RegisterMap& Daemon::register_map() const { return impl_->map; }
std::vector<hal::InputSource*> Daemon::sources() const { return impl_->AllSources(); }
DaemonStats Daemon::stats() const { return impl_->stats; }
int64_t Daemon::period_us() const { return impl_->period_us; }

}  // namespace relight::daemon
