// Daemon's patch and bake (see daemon_impl.h): the patch read, resolved and
// adopted (at Open and on SIGHUP), the camera, and SIGHUP's reload of the
// bake, then the patch, each falling back to what ran before on an error.
#include <string>
#include <utility>

#include "daemon_impl.h"
#include "engine_registers.h"
#include "relight/base/log.h"
#include "relight/hal/source_factory.h"

namespace relight::daemon {

Status Daemon::Impl::Adopt(hal::Patch p) {
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

Status Daemon::Impl::LoadPatchFile(hal::Patch* out) const {
  hal::Patch p;
  if (!config.patch_path.empty()) RELIGHT_RETURN_IF_ERROR(hal::LoadPatch(config.patch_path, &p));
  if (config.modbus_port >= 0) {
    p.modbus_tcp.enabled = true;
    p.modbus_tcp.port = config.modbus_port;
  }
  *out = std::move(p);
  return Status::Ok();
}

Status Daemon::Impl::LoadResolved(hal::Patch* out) {
  hal::Patch p;
  RELIGHT_RETURN_IF_ERROR(LoadPatchFile(&p));
  RELIGHT_RETURN_IF_ERROR(hal::ResolvePatch(Luminaires(engine), &p));
  *out = std::move(p);
  return Status::Ok();
}

CameraView Daemon::Impl::View() const {
  CameraView view = cli::CameraFromBake(engine.bake().camera);
  for (int i = 0; i < 3; ++i) {
    if (config.camera_pos) view.position[i] = (*config.camera_pos)[static_cast<size_t>(i)];
    if (config.camera_target) view.target[i] = (*config.camera_target)[static_cast<size_t>(i)];
  }
  if (config.fov_y_deg > 0) view.fov_y_deg = config.fov_y_deg;
  return view;
}

bool Daemon::Impl::ReloadBakeFile(bool force) {
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

bool Daemon::Impl::EnableSurfaceEmitters() {
  engine_options.surface_emitters = true;
  if (ReloadBakeFile(/*force=*/true) && fatal.ok()) return true;
  engine_options.surface_emitters = false;
  return false;
}

void Daemon::Impl::Reload() {
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

}  // namespace relight::daemon
