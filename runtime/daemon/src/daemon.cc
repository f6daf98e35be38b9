// Daemon's public calls (daemon.h) other than Run: Open (the bake, the
// patch, the scripts, then the renderer), sinks and sources added, Start,
// and the accessors. The state is in daemon_impl.h, Run in daemon_run.cc.
#include <memory>
#include <string>
#include <utility>

#include "bake_reload.h"
#include "daemon_impl.h"
#include "engine_registers.h"
#include "relight/hal/replay_source.h"
#include "startup_memory.h"

namespace relight::daemon {

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

Engine& Daemon::engine() { return impl_->engine; }
const hal::Patch& Daemon::patch() const { return impl_->patch; }
const hal::RegisterMap& Daemon::register_map() const { return impl_->map; }
std::vector<hal::InputSource*> Daemon::sources() const { return impl_->AllSources(); }
DaemonStats Daemon::stats() const { return impl_->stats; }
int64_t Daemon::period_us() const { return impl_->period_us; }

}  // namespace relight::daemon
