#include "bake_reload.h"

#include <sys/stat.h>

#include <utility>
#include <vector>

namespace relight::daemon {

BakeFileId StatBakeFile(const std::string& path) {
  BakeFileId id;
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return id;
  id.dev = st.st_dev;
  id.ino = st.st_ino;
  id.size = st.st_size;
  id.mtime_ns = int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec;
  return id;
}

Status ReloadBake(const std::string& path, Engine* engine, BakeFileId* loaded, BakeReload* result,
                  const EngineOptions& options, bool force) {
  *result = BakeReload::kUnchanged;
  // Taken before reading: a file changing while it is read gets a new id
  // and is read again at the next SIGHUP.
  const BakeFileId now = StatBakeFile(path);
  if (!force && now.size >= 0 && now == *loaded) return Status::Ok();
  Bake bake;
  if (Status st = ReadBake(path, &bake); !st.ok()) {
    // ReadBake's messages mostly name the part, not always the file.
    const std::string& msg = st.message();
    return msg.find(path) == std::string::npos ? Status(st.code(), path + ": " + msg) : st;
  }
  const std::vector<BakeLuminaire>& old = engine->bake().luminaires;
  bool same = bake.luminaires.size() == old.size();
  for (size_t i = 0; same && i < old.size(); ++i) same = bake.luminaires[i].name == old[i].name;
  if (!same) {
    return Status(StatusCode::kInvalidArgument,
                  path + ": the bake's luminaires differ from the running one's (names or order); restart relightd "
                         "to change the rig");
  }
  std::vector<FixtureState> states;
  for (int i = 0; i < engine->luminaire_count(); ++i) states.push_back(engine->state(i));
  RELIGHT_RETURN_IF_ERROR(engine->Open(std::move(bake), options));
  for (int i = 0; i < engine->luminaire_count(); ++i) {
    const FixtureState& s = states[static_cast<size_t>(i)];
    // Each setter clamps to the new bake's ranges; a luminaire that lost its
    // zoom answers kUnsupported, which leaves it at the bake's beam.
    (void)engine->SetPanTilt(i, s.pan_deg, s.tilt_deg);
    (void)engine->SetDimmer(i, s.dimmer);
    (void)engine->SetColour(i, s.rgb[0], s.rgb[1], s.rgb[2]);
    (void)engine->SetRoll(i, s.roll_deg);
    if (s.zoom_deg.raw() != 0) (void)engine->SetZoom(i, s.zoom_deg);
  }
  *loaded = now;
  *result = BakeReload::kTaken;
  return Status::Ok();
}

}  // namespace relight::daemon
