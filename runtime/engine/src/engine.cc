// The run-time engine (see relight/engine.h), a facade over the data flow:
//   Open:   ValidateBake (the bake layer's one set of rules and limits) ->
//           SetUpLuminaires (luminaire.h: buffers, LIDs prepared, state);
//   setters: fixture state; pan/tilt/roll/zoom/LID edits mark a luminaire dirty;
//   Update: dirty, lit luminaires -> a pending zoom's LID samples and
//           weights (zoom.h, ApplyZoom) -> RecomputeLuminaireCacheQ12
//           (luminaire_cache.h) -> RemixQ12 (remix.h) per dimmer and colour
//           -> + run-time surface emitters (surface_emitters.h); the rebuilds
//           and the remix on the worker threads (engine_threads.h).
//
// A dirty luminaire whose gains are all zero (dimmer or colour at 0) is
// rebuilt when it is next lit, not before: moving a fixture "in black" costs
// nothing until it fades up.
//
// Everything is allocated in Open(); Update() and the setters allocate
// nothing and use integers only.
#include "relight/engine/engine.h"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "compressed_tiles.h"
#include "console_aim.h"
#include "emitter_grids.h"
#include "engine_threads.h"
#include "fixture_frame.h"
#include "luminaire.h"
#include "luminaire_cache.h"
#include "mix.h"
#include "relight/bake/bake_limits.h"
#include "relight/base/fixed_ops.h"
#include "remix.h"
#include "surface_emitters.h"
#include "zoom.h"

namespace relight {

struct Engine::Impl {
  Bake bake;
  std::vector<LuminaireRuntime> lums;
  CacheWorkspace work;
  std::vector<MixSource> mix;  // per luminaire
  EngineOutputs out;
  SurfaceEmitters emitters;  // run-time light sources on surfaces
  EmitterGrids emitter_grids;  // ... and their light on the calculation grids
  bool remix = true;
  int last_luminaires = 0;
  int last_terms = 0;
  int last_emitters = 0;
  EngineThreads threads;  // last: its workers are joined first

  Status Allocate(const EngineOptions& options) {
    for (BakeLuminaire& b : bake.luminaires) {
      for (BakeLightReceivers& rx : b.receivers) TileCompressedWeights(&rx.compressed);
    }
    RELIGHT_RETURN_IF_ERROR(SetUpLuminaires(&bake, !options.keep_direct_inputs, &lums, &work));
    SizeOutputs(bake, &out, &mix);
    RELIGHT_RETURN_IF_ERROR(emitters.Open(bake, options.emitter_refine_links, options.emitter_refine_bits));
    emitter_grids.Open(bake);
    emitters.set_observer(&emitter_grids);
    StartEngineThreads(options.threads, work, lums.size(), &threads);
    emitters.PrecomputeBounces(options.emitter_bounce_table_bytes, &threads.pool);
    emitters.set_quick_changes(options.emitter_quick_changes);
    return Status::Ok();
  }
  void ApplyPendingZoom(size_t index) {
    if (lums[index].zoom_pending) {
      ApplyZoom(&bake.luminaires[index], &lums[index], work.zoom_samples_q16.data());
    }
  }
  Status EditLidSample(int index, int sample, int64_t candela_q16) {
    ApplyPendingZoom(static_cast<size_t>(index));  // an edit changes the zoomed beam
    bool changed = false;
    RELIGHT_RETURN_IF_ERROR(relight::EditLidSample(&bake.luminaires[index], &lums[index], sample,
                                                   candela_q16, &changed));
    if (changed) remix = true;
    return Status::Ok();
  }
  void Update();
};

namespace {

// The bake as if it had no calculation grid (EngineOptions::grids): still
// one that passes ValidateBake.
void DropGrids(Bake* bake) {
  bake->grids.clear();
  bake->grids.shrink_to_fit();
  for (BakeLuminaire& b : bake->luminaires) {
    b.receivers.resize(1);
    b.receivers.shrink_to_fit();
  }
  if (bake->hierarchy) {
    bake->hierarchy->grid_link_offsets = {};
    bake->hierarchy->grid_link_node = {};
    bake->hierarchy->grid_link_f = {};
  }
}

bool Lit(const LuminaireRuntime& lum) {
  for (int c = 0; c < 3; ++c) {
    if (GainQ30(lum.state.dimmer, lum.state.rgb[c]).raw() != 0) return true;
  }
  return false;
}

}  // namespace

void Engine::Impl::Update() {
  threads.rebuild_count = 0;
  for (size_t i = 0; i < lums.size(); ++i) {
    if (lums[i].dirty && Lit(lums[i])) threads.rebuild[threads.rebuild_count++] = static_cast<uint32_t>(i);
  }
  last_luminaires = static_cast<int>(threads.rebuild_count);
  last_terms = RebuildLuminaires(&bake, &lums, &work, &threads);  // on all threads
  if (last_luminaires > 0) remix = true;
  last_emitters = emitters.SolvePending(&threads.pool);
  if (last_emitters == 0) last_emitters = emitters.Settle(&threads.pool);  // no emitter changed
  if (last_emitters > 0) remix = true;
  if (remix) {
    RemixOnThreads(bake, lums, &work, mix.data(), &threads, &out);
    emitters.AddTo(out.vertex.data());
    emitter_grids.AddTo(emitters, &out.grid_total);
  }
  remix = false;
}

Engine::Engine() = default;
Engine::~Engine() = default;

Status Engine::Open(const std::string& bake_path) { return Open(bake_path, EngineOptions{}); }

Status Engine::Open(Bake bake) { return Open(std::move(bake), EngineOptions{}); }

Status Engine::Open(const std::string& bake_path, const EngineOptions& options) {
  Bake bake;
  ReadBakeOptions read;
  read.hierarchy = options.surface_emitters;
  read.grids = options.grids;
  RELIGHT_RETURN_IF_ERROR(ReadBake(bake_path, read, &bake));
  return Open(std::move(bake), options);
}

Status Engine::Open(Bake bake, const EngineOptions& options) {
  RELIGHT_RETURN_IF_ERROR(ValidateBake(bake));
  std::unique_ptr<Impl> impl(new Impl);
  impl->bake = std::move(bake);
  if (!options.surface_emitters) impl->bake.hierarchy.reset();
  if (!options.grids) DropGrids(&impl->bake);
  RELIGHT_RETURN_IF_ERROR(impl->Allocate(options));
  impl->Update();
  impl_ = std::move(impl);
  return Status::Ok();
}

bool Engine::is_open() const { return impl_ != nullptr; }

int Engine::thread_count() const { return impl_ ? impl_->threads.pool.threads() : 0; }

const Bake& Engine::bake() const {
  static const Bake kEmpty;
  return impl_ ? impl_->bake : kEmpty;
}

int Engine::luminaire_count() const { return impl_ ? static_cast<int>(impl_->lums.size()) : 0; }

int Engine::FindLuminaire(const std::string& name) const {
  if (!impl_) return -1;
  for (size_t i = 0; i < impl_->bake.luminaires.size(); ++i) {
    if (impl_->bake.luminaires[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

namespace {

// Setters run at control rate after Open: the message stays within the
// string's small-buffer capacity (15 chars), so even this error allocates nothing.
Status BadIndex() { return Status(StatusCode::kInvalidArgument, "luminaire index"); }

}  // namespace

Status Engine::SetPanTilt(int luminaire, Q16_16 pan_deg, Q16_16 tilt_deg) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  FixtureState& s = impl_->lums[luminaire].state;
  const Q16_16 pan = WrapDegrees(pan_deg);
  const Q16_16 tilt = WrapDegrees(tilt_deg);
  if (pan != s.pan_deg || tilt != s.tilt_deg) {
    s.pan_deg = pan;
    s.tilt_deg = tilt;
    impl_->lums[luminaire].dirty = true;
    impl_->remix = true;
  }
  return Status::Ok();
}

Status Engine::SetDimmer(int luminaire, Q1_15 level) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  FixtureState& s = impl_->lums[luminaire].state;
  const Q1_15 v = ClampUnit(level);
  if (v != s.dimmer) {
    s.dimmer = v;
    impl_->remix = true;
  }
  return Status::Ok();
}

Status Engine::SetColour(int luminaire, Q1_15 r, Q1_15 g, Q1_15 b) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  FixtureState& s = impl_->lums[luminaire].state;
  const Q1_15 rgb[3] = {ClampUnit(r), ClampUnit(g), ClampUnit(b)};
  for (int c = 0; c < 3; ++c) {
    if (rgb[c] != s.rgb[c]) {
      s.rgb[c] = rgb[c];
      impl_->remix = true;
    }
  }
  return Status::Ok();
}

Status Engine::SetRoll(int luminaire, Q16_16 roll_deg) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  FixtureState& s = impl_->lums[luminaire].state;
  const Q16_16 roll = WrapDegrees(roll_deg);
  if (roll != s.roll_deg) {
    s.roll_deg = roll;
    impl_->lums[luminaire].dirty = true;
    impl_->remix = true;
  }
  return Status::Ok();
}

Status Engine::SetZoom(int luminaire, Q16_16 beam_angle_deg) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  const BakeZoom& zoom = impl_->bake.luminaires[luminaire].zoom;
  if (!zoom.present()) return Status(StatusCode::kUnsupported, "no zoom");  // fits the buffer
  LuminaireRuntime& l = impl_->lums[luminaire];
  const Q16_16 angle = ClampZoomDegrees(zoom, beam_angle_deg);
  if (angle != l.state.zoom_deg) {
    l.state.zoom_deg = angle;
    l.zoom_pending = true;
    l.dirty = true;
    impl_->remix = true;
  }
  return Status::Ok();
}

Status Engine::SetPanTilt16(int luminaire, uint16_t pan, uint16_t tilt) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  const BakeLuminaire& b = impl_->bake.luminaires[luminaire];
  return SetPanTilt(luminaire, ConsoleToDegrees(pan, b.pan_range),
                    ConsoleToDegrees(tilt, b.tilt_range));
}

Status Engine::AimAt(int luminaire, const int32_t target_q16[3]) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  const BakeLuminaire& b = impl_->bake.luminaires[luminaire];
  const FixtureState& s = impl_->lums[luminaire].state;
  Q16_16 pan, tilt, chosen_pan, chosen_tilt;
  if (!AimAtQ16(b.mounting, Q16_16::FromRaw(b.yaw), b.position, target_q16, &pan, &tilt)) {
    return Status(StatusCode::kInvalidArgument, "aim: same point");
  }
  if (!ChooseAimInRange(pan, tilt, b.pan_range, b.tilt_range, s.pan_deg, s.tilt_deg, &chosen_pan,
                        &chosen_tilt)) {
    return Status(StatusCode::kOutOfRange, "aim: no reach");  // fits the string buffer
  }
  return SetPanTilt(luminaire, chosen_pan, chosen_tilt);
}

Status Engine::SetLidSample(int luminaire, int k, Q48_16 candela) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  return impl_->EditLidSample(luminaire, k, candela.raw());
}

Status Engine::SetLidControlPoints(int luminaire, const Q16_16* gamma_deg, const Q48_16* candela,
                                   int count) {
  if (luminaire < 0 || luminaire >= luminaire_count()) return BadIndex();
  if (count < 1 || gamma_deg == nullptr || candela == nullptr || gamma_deg[0].raw() != 0) {
    return Status(StatusCode::kInvalidArgument, "control points");
  }
  for (int i = 0; i < count; ++i) {
    const bool increasing = i == 0 || gamma_deg[i] > gamma_deg[i - 1];
    if (!increasing || gamma_deg[i].raw() > (180 << 16) || candela[i].raw() < 0 ||
        candela[i].raw() > bake_format::kMaxCandelaRaw) {
      return Status(StatusCode::kInvalidArgument, "control points");
    }
  }
  const int M = impl_->lums[luminaire].lid_m;
  int seg = 0;
  for (int k = 0; k <= M; ++k) {
    // gamma_k = 180 k / M degrees in Q16.16 x M, compared without division.
    const int64_t g_times_m = int64_t{180 << 16} * k;
    while (seg + 1 < count && int64_t{gamma_deg[seg + 1].raw()} * M <= g_times_m) ++seg;
    int64_t value = 0;
    if (seg + 1 < count) {
      const int64_t a = int64_t{gamma_deg[seg].raw()} * M, b = int64_t{gamma_deg[seg + 1].raw()} * M;
      const Int128 num = static_cast<Int128>(candela[seg + 1].raw() - candela[seg].raw()) * (g_times_m - a);
      const Int128 den = b - a;
      value = candela[seg].raw() + static_cast<int64_t>((num + (num >= 0 ? den / 2 : -den / 2)) / den);
    } else if (int64_t{gamma_deg[seg].raw()} * M == g_times_m) {
      value = candela[seg].raw();  // the last control point itself; 0 past it
    }
    RELIGHT_RETURN_IF_ERROR(impl_->EditLidSample(luminaire, k, value));
  }
  return Status::Ok();
}

const int64_t* Engine::lid_samples(int luminaire, int* count) const {
  if (luminaire < 0 || luminaire >= luminaire_count()) return nullptr;
  impl_->ApplyPendingZoom(static_cast<size_t>(luminaire));  // the samples of the zoom as set
  const BakeLid& lid = impl_->bake.luminaires[luminaire].lid;
  if (count != nullptr) *count = static_cast<int>(lid.candela.size());
  return lid.candela.data();
}

FixtureState Engine::state(int luminaire) const {
  if (luminaire < 0 || luminaire >= luminaire_count()) return FixtureState{};
  return impl_->lums[luminaire].state;
}

void Engine::Update() {
  if (impl_) impl_->Update();
}

LuminanceView Engine::vertex_luminance() const {
  if (!impl_) return {};
  return LuminanceView(impl_->out.vertex.data(), impl_->bake.mesh.vertex_count());
}

uint32_t Engine::vertex_count() const { return impl_ ? impl_->bake.mesh.vertex_count() : 0; }

IlluminanceView Engine::grid_illuminance(int grid) const {
  if (!impl_ || grid < 0 || grid >= static_cast<int>(impl_->out.grid_total.size())) return {};
  return IlluminanceView(impl_->out.grid_total[grid].data(), impl_->bake.grids[grid].point_count());
}

IlluminanceView Engine::grid_direct_illuminance(int grid) const {
  if (!impl_ || grid < 0 || grid >= static_cast<int>(impl_->out.grid_direct.size())) return {};
  return IlluminanceView(impl_->out.grid_direct[grid].data(), impl_->bake.grids[grid].point_count());
}

int Engine::last_update_luminaires_recombined() const {
  return impl_ ? impl_->last_luminaires : 0;
}

int Engine::last_update_terms_recombined() const { return impl_ ? impl_->last_terms : 0; }

int Engine::last_update_emitters_solved() const { return impl_ ? impl_->last_emitters : 0; }

int Engine::emitter_bounce_sources() const {
  return impl_ ? static_cast<int>(impl_->emitters.bounces().source_count()) : 0;
}

int64_t Engine::emitter_bounce_table_size() const {
  return impl_ ? static_cast<int64_t>(impl_->emitters.bounces().bytes()) : 0;
}

int Engine::last_update_emitter_sweeps() const {
  return impl_ ? impl_->emitters.last_sweeps() : 0;
}

int32_t Engine::emitter_quick_reach_q16() const { return impl_ ? impl_->emitters.quick_reach_q16() : 0; }

int Engine::last_update_emitters_quick() const { return impl_ ? impl_->emitters.last_quick() : 0; }

bool Engine::emitters_settled() const { return impl_ ? impl_->emitters.settled() : true; }

int Engine::last_emitter_refine_links() const {
  return impl_ ? impl_->emitters.last_refine_links() : 0;
}

namespace {

Status NotOpen() { return Status(StatusCode::kInvalidArgument, "engine not open"); }

}  // namespace

Status Engine::SetSurfaceEmitter(int slot, const SurfaceEmitterShape& shape,
                                 const LightQ12 luminance[3]) {
  if (!impl_) return NotOpen();
  for (int c = 0; c < 3; ++c) {  // checked before the shape, so an error changes nothing
    if (luminance[c].raw() < 0) {
      return Status(StatusCode::kInvalidArgument, "surface emitter: luminance < 0");
    }
  }
  RELIGHT_RETURN_IF_ERROR(impl_->emitters.Place(slot, shape, &impl_->threads.pool));
  impl_->remix = true;
  return impl_->emitters.SetLuminance(slot, luminance);
}

Status Engine::SetSurfaceEmitterLuminance(int slot, const LightQ12 luminance[3]) {
  if (!impl_) return NotOpen();
  RELIGHT_RETURN_IF_ERROR(impl_->emitters.SetLuminance(slot, luminance));
  impl_->remix = true;
  return Status::Ok();
}

Status Engine::RemoveSurfaceEmitter(int slot) {
  if (!impl_) return NotOpen();
  RELIGHT_RETURN_IF_ERROR(impl_->emitters.Remove(slot));
  impl_->remix = true;
  return Status::Ok();
}

}  // namespace relight
