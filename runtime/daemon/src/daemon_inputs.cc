// Daemon's input sources (see daemon_impl.h): binding them to the fader's
// slots, the DMX patch, starting them, and polling them into the fader.
#include <memory>
#include <string>
#include <utility>

#include "daemon_impl.h"
#include "relight/base/clock.h"
#include "relight/hal/dmx/dmx_replay_source.h"
#include "relight/hal/dmx/ola_source.h"
#include "relight/hal/param_text.h"

namespace relight::daemon {

std::vector<hal::InputSource*> Daemon::Impl::AllSources() const {
  std::vector<hal::InputSource*> all;
  for (const control::BoundInput& in : inputs) all.push_back(in.source);
  return all;
}

void Daemon::Impl::BindInputs() {
  inputs.clear();
  for (const auto& s : patch_sources) inputs.push_back({s.get(), path.patch_luminaires()});
  if (replay) inputs.push_back({replay.get(), {}});
  if (dmx) inputs.push_back({dmx.get(), dmx_luminaires});
  for (const auto& s : extra_sources) inputs.push_back({s.get(), path.patch_luminaires()});
}

bool Daemon::Impl::ScriptsFinished() const {
  return (!replay || replay->Finished()) && (!dmx || !dmx_is_replay || dmx->Finished());
}

Status Daemon::Impl::OpenDmx() {
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

Status Daemon::Impl::StartAll(const std::vector<hal::InputSource*>& sources) {
  for (size_t i = 0; i < sources.size(); ++i) {
    if (Status st = sources[i]->Start(); !st.ok()) {
      for (size_t k = 0; k < i; ++k) sources[k]->Stop();
      return Status(st.code(), std::string("input ") + sources[i]->Name() + ": " + st.message());
    }
  }
  return Status::Ok();
}

int64_t Daemon::Impl::PollInputs(int64_t time_us, bool live_only) {
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

size_t Daemon::Impl::ApplyFader(int64_t time_us) {
  const size_t n = path.Apply(time_us);
  stats.changes_applied += static_cast<int64_t>(n);
  return n;
}

bool Daemon::Impl::LiveOnly() const {
  for (const control::BoundInput& in : inputs) {
    if (in.source->clock() == hal::SourceClock::kScript) return false;
  }
  return true;
}

}  // namespace relight::daemon
