// Daemon's private state (daemon.h), shared by the files that work on it:
// daemon.cc (Open and the public calls), daemon_inputs.cc (the sources and
// their polling), daemon_reload.cc (the patch adopted, SIGHUP's bake and
// patch reload) and daemon_run.cc (the frame loop and the sinks).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "bake_reload.h"
#include "daemon.h"
#include "frame_pacing.h"
#include "relight/hal/replay_source.h"

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

  // --- The sources (daemon_inputs.cc).

  std::vector<hal::InputSource*> AllSources() const;

  // Patch sources and extra ones (mocks made from the patch) index the
  // patch's fixtures; the replay indexes the bake's luminaires.
  void BindInputs();

  // The finite scripts (replay, DMX replay) are all played out.
  bool ScriptsFinished() const;

  // The DMX patch: its fixture names bound to the bake's luminaires once,
  // here; a name the bake lacks is an error naming the patch's file:line.
  Status OpenDmx();

  static Status StartAll(const std::vector<hal::InputSource*>& sources);

  // Polls the sources (only the live ones if `live_only`), handing their
  // changes to the fader at daemon time `time_us`; returns the newest
  // arrival among live changes (0: none).
  int64_t PollInputs(int64_t time_us, bool live_only);

  // Applies what the fader moved; returns how many parameters changed.
  size_t ApplyFader(int64_t time_us);

  // True when no source plays a script: then ticks follow live input (Run).
  bool LiveOnly() const;

  // --- The patch and the bake, at Open and on SIGHUP (daemon_reload.cc).

  // Builds the map, fader and live sources of `p` (resolved). Does not start them.
  Status Adopt(hal::Patch p);

  // The patch file (and --modbus-port) as read, not yet bound to the bake.
  Status LoadPatchFile(hal::Patch* out) const;

  Status LoadResolved(hal::Patch* out);

  // The bake's camera with the command line's changes.
  CameraView View() const;

  // SIGHUP, first step: a changed bake file is read and, if valid, taken
  // (bake_reload.h); a bad one is refused and the running bake stays.
  // `force`: read it again even if the file is the one loaded (the engine
  // options changed). False when the new bake was refused.
  bool ReloadBakeFile(bool force = false);

  // A reloaded patch that brings the first [[emitter]] needs the bake's
  // hierarchy, which was not loaded: the bake is opened again with it (the
  // fixtures keep their state). False (and the engine as it was) on error.
  bool EnableSurfaceEmitters();

  void Reload();

  // --- The frame loop's steps (daemon_run.cc).

  // Real time: waits for the tick due at `deadline_us`, meanwhile polling the
  // live sources every millisecond. Returns true to render early: a live
  // change came and `budget` allows a render now.
  bool WaitForTick(int64_t t0_us, int64_t deadline_us, const RenderBudget& budget, const std::atomic<bool>& stop,
                   const std::atomic<bool>& reload, int64_t* pending_arrival_us);

  // Writes the frame everywhere. A sink failing on the first frame is an
  // error; later the sink is dropped with a log line and the rest go on.
  Status WriteSinks(int64_t frame);
};

}  // namespace relight::daemon
