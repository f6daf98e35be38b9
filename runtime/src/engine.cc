// The run-time engine (see relight/engine.h): fixture state -> weights
// (weights.h) -> recombination (recombine.h) + exact direct (direct.h) per
// luminaire, cached; then a mix of the caches (mix.h) per dimmer and colour.
//
// Caches, per luminaire and receiver set, computed at dimmer 1 and white:
//   vertices: one array, direct + indirect (luminance), LightQ12 cd/m^2;
//   grids:    indirect and (kExactDirect only) direct apart, LightQ12 lux,
//             because grids also report the direct part on its own.
// A kAllInSh luminaire has no direct arrays: its SH basis holds everything,
// so it adds nothing to grid_direct_illuminance().
//
// A pan/tilt change marks only that luminaire dirty. A dirty luminaire whose
// gains are all zero (dimmer or colour at 0) is rebuilt when it is next lit,
// not before: moving a fixture "in black" costs nothing until it fades up.
//
// Everything is allocated in Open(); Update() and the setters allocate
// nothing and use integers only.
#include "relight/engine.h"

#include <cstddef>
#include <utility>
#include <vector>

#include "direct.h"
#include "mix.h"
#include "recombine.h"
#include "relight/sh_eval.h"
#include "relight/sh_index.h"
#include "weights.h"

namespace relight {
namespace {

constexpr int32_t kHalfTurnQ16 = 180 << 16;
constexpr int64_t kFullTurnQ16 = int64_t{360} << 16;
// Largest accepted LID sample: 2^24 cd in Q48.16. Keeps every Legendre
// weight and per-term coefficient (<= ~1000 x the peak) far inside int64.
constexpr int64_t kMaxCandelaQ16 = int64_t{1} << 40;

// Degrees wrapped to (-180, 180].
Q16_16 WrapDegrees(Q16_16 degrees) {
  int64_t v = degrees.raw() % kFullTurnQ16;
  if (v > kHalfTurnQ16) v -= kFullTurnQ16;
  if (v <= -kHalfTurnQ16) v += kFullTurnQ16;
  return Q16_16::FromRaw(static_cast<int32_t>(v));
}

Q1_15 ClampUnit(Q1_15 v) { return v.raw() < 0 ? Q1_15::FromRaw(0) : v; }

struct SetCache {
  std::vector<int32_t> light;   // vertices: direct + indirect; grids: indirect
  std::vector<int32_t> direct;  // grids of kExactDirect luminaires
};

struct LuminaireRuntime {
  FixtureState state;
  bool dirty = true;
  int degree = 0;
  int lid_m = 0;
  int64_t damped_weights_q16[kMaxShDegree + 1] = {};
  std::vector<SetCache> sets;
};

Status Invalid(const BakeLuminaire& lum, const char* what) {
  return Status(StatusCode::kInvalidArgument,
                StrFormat("engine: luminaire '%s': %s", lum.name.c_str(), what));
}

Status ValidateBake(const Bake& bake) {
  const BakeMesh& mesh = bake.mesh;
  if (mesh.positions.size() % 3 != 0) {
    return Status(StatusCode::kInvalidArgument, "engine: mesh positions not a multiple of 3");
  }
  if (mesh.albedo.size() != mesh.positions.size()) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("engine: mesh has %zu albedo values for %u vertices",
                            mesh.albedo.size(), mesh.vertex_count()));
  }
  for (const BakeGrid& grid : bake.grids) {
    if (grid.points.size() % 3 != 0) {
      return Status(StatusCode::kInvalidArgument,
                    StrFormat("engine: grid '%s' points not a multiple of 3", grid.name.c_str()));
    }
  }
  for (const BakeLuminaire& lum : bake.luminaires) {
    if (lum.sh_degree > kMaxShDegree) return Invalid(lum, "SH degree above 16");
    if (lum.direct_mode != DirectMode::kExactDirect && lum.direct_mode != DirectMode::kAllInSh) {
      return Invalid(lum, "unknown direct mode");
    }
    if (lum.mounting != Mounting::kHanging && lum.mounting != Mounting::kStanding) {
      return Invalid(lum, "unknown mounting");
    }
    if (lum.lid.candela.size() < 3) return Invalid(lum, "LID needs at least 3 samples");
    for (int64_t cd : lum.lid.candela) {
      if (cd < 0 || cd >= kMaxCandelaQ16) return Invalid(lum, "LID sample outside [0, 2^24) cd");
    }
    if (lum.receivers.size() != bake.receiver_set_count()) {
      return Invalid(lum, "receiver set count differs from 1 + grids");
    }
    const size_t terms = static_cast<size_t>(ShTermCount(lum.sh_degree));
    for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
      const BakeLightReceivers& rx = lum.receivers[s];
      const size_t count = bake.receiver_count(s);
      if (rx.basis.size() != terms * count * 3) return Invalid(lum, "basis size mismatch");
      if (rx.basis_scale.size() != terms * 3) return Invalid(lum, "basis scale count mismatch");
      if (lum.direct_mode == DirectMode::kExactDirect &&
          (rx.direction.size() != count * 3 || rx.geometry.size() != count)) {
        return Invalid(lum, "direct term size mismatch");
      }
    }
  }
  return Status::Ok();
}

}  // namespace

struct Engine::Impl {
  Bake bake;
  ShTables sh;
  std::vector<LuminaireRuntime> lums;
  std::vector<uint32_t> reflectance_over_pi_q32;  // 3 per vertex
  std::vector<int64_t> scratch;                   // recombine / mix blocks
  std::vector<int64_t> alm_q30, coef_q16;         // per term
  std::vector<int32_t> k;                         // per term and channel
  std::vector<MixSource> mix;                     // per luminaire
  std::vector<int32_t> vertex_out;
  std::vector<std::vector<int32_t>> grid_total, grid_direct;
  bool remix = true;
  int last_luminaires = 0;
  int last_terms = 0;

  Status Allocate();
  bool Lit(const LuminaireRuntime& lum) const;
  int Recompute(int index);
  void Remix();
  void Update();
};

Status Engine::Impl::Allocate() {
  InitShTables(&sh);
  const uint32_t sets = bake.receiver_set_count();
  uint32_t max_count = 0;
  for (uint32_t s = 0; s < sets; ++s) {
    if (bake.receiver_count(s) > max_count) max_count = bake.receiver_count(s);
  }
  const uint32_t block = max_count < kRecombineBlockReceivers ? max_count : kRecombineBlockReceivers;
  scratch.assign(static_cast<size_t>(block > 0 ? block : 1) * 3, 0);
  int max_terms = 1;
  lums.resize(bake.luminaires.size());
  for (size_t i = 0; i < lums.size(); ++i) {
    const BakeLuminaire& b = bake.luminaires[i];
    LuminaireRuntime& l = lums[i];
    l.degree = b.sh_degree;
    l.lid_m = static_cast<int>(b.lid.candela.size()) - 1;
    if (ShTermCount(l.degree) > max_terms) max_terms = ShTermCount(l.degree);
    std::vector<int32_t> table(static_cast<size_t>(l.degree + 1) * (l.lid_m + 1));
    const Status st = DampedLegendreWeightsQ16(l.degree, b.use_sigma != 0, b.lid.candela.data(),
                                               l.lid_m, table.data(), l.damped_weights_q16);
    if (!st.ok()) return Invalid(b, st.message().c_str());
    l.state.pan_deg = WrapDegrees(Q16_16::FromRaw(b.default_pan));
    l.state.tilt_deg = WrapDegrees(Q16_16::FromRaw(b.default_tilt));
    l.state.dimmer = ClampUnit(Q1_15::FromRaw(b.default_dimmer));
    for (int c = 0; c < 3; ++c) l.state.rgb[c] = ClampUnit(Q1_15::FromRaw(b.default_rgb[c]));
    l.sets.resize(sets);
    for (uint32_t s = 0; s < sets; ++s) {
      const size_t n = static_cast<size_t>(bake.receiver_count(s)) * 3;
      l.sets[s].light.assign(n, 0);
      if (s > 0 && b.direct_mode == DirectMode::kExactDirect) l.sets[s].direct.assign(n, 0);
    }
  }
  alm_q30.assign(max_terms, 0);
  coef_q16.assign(max_terms, 0);
  k.assign(static_cast<size_t>(max_terms) * 3, 0);
  mix.resize(lums.size());
  reflectance_over_pi_q32.resize(bake.mesh.albedo.size());
  ReflectanceOverPiQ32(bake.mesh.albedo.data(), static_cast<uint32_t>(bake.mesh.albedo.size()),
                       reflectance_over_pi_q32.data());
  vertex_out.assign(static_cast<size_t>(bake.mesh.vertex_count()) * 3, 0);
  grid_total.resize(bake.grids.size());
  grid_direct.resize(bake.grids.size());
  for (size_t g = 0; g < bake.grids.size(); ++g) {
    grid_total[g].assign(static_cast<size_t>(bake.grids[g].point_count()) * 3, 0);
    grid_direct[g].assign(static_cast<size_t>(bake.grids[g].point_count()) * 3, 0);
  }
  return Status::Ok();
}

bool Engine::Impl::Lit(const LuminaireRuntime& lum) const {
  for (int c = 0; c < 3; ++c) {
    if (GainQ30(lum.state.dimmer.raw(), lum.state.rgb[c].raw()) != 0) return true;
  }
  return false;
}

// Rebuilds one luminaire's caches; returns the SH term passes it made.
int Engine::Impl::Recompute(int index) {
  const BakeLuminaire& b = bake.luminaires[index];
  LuminaireRuntime& l = lums[index];
  int32_t axis_q30[3];
  BeamAxisQ30(b.mounting, l.state.pan_deg, l.state.tilt_deg, axis_q30);
  const int terms = ShTermCount(l.degree);
  TermCoefficientsQ16(sh, l.degree, l.damped_weights_q16, axis_q30, alm_q30.data(),
                      coef_q16.data());  // Dobashi Eq. 18
  int passes = 0;
  for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
    const BakeLightReceivers& rx = b.receivers[s];
    const uint32_t count = bake.receiver_count(s);
    SetCache& cache = l.sets[s];
    const int shift = ChannelMultipliersQ12(coef_q16.data(), terms, rx.basis_scale.data(), k.data());
    passes += static_cast<int>(RecombineQ12(rx.basis.data(), static_cast<uint32_t>(terms), count,
                                            k.data(), shift, scratch.data(),
                                            static_cast<uint32_t>(scratch.size()),
                                            cache.light.data()));
    if (b.direct_mode != DirectMode::kExactDirect) continue;
    DirectReceivers direct;
    direct.direction_q14 = rx.direction.data();
    direct.geometry = rx.geometry.data();
    direct.geometry_scale = rx.geometry_scale;
    direct.count = count;
    if (s == 0) {
      DirectLightQ12(direct, axis_q30, b.lid.candela.data(), l.lid_m,
                     reflectance_over_pi_q32.data(), DirectStore::kAdd, cache.light.data());
    } else {
      DirectLightQ12(direct, axis_q30, b.lid.candela.data(), l.lid_m, nullptr, DirectStore::kWrite,
                     cache.direct.data());
    }
  }
  return passes;
}

void Engine::Impl::Remix() {
  const uint32_t scratch_len = static_cast<uint32_t>(scratch.size());
  const uint32_t n = static_cast<uint32_t>(lums.size());
  for (uint32_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      mix[i].gain_q30[c] = GainQ30(lums[i].state.dimmer.raw(), lums[i].state.rgb[c].raw());
    }
    mix[i].a = lums[i].sets[0].light.data();
    mix[i].b = nullptr;
  }
  MixLuminairesQ12(mix.data(), n, bake.mesh.vertex_count(), scratch.data(), scratch_len,
                   vertex_out.data());
  for (uint32_t g = 0; g < grid_total.size(); ++g) {
    const uint32_t count = bake.grids[g].point_count();
    for (uint32_t i = 0; i < n; ++i) {
      const SetCache& cache = lums[i].sets[g + 1];
      mix[i].a = cache.light.data();
      mix[i].b = cache.direct.empty() ? nullptr : cache.direct.data();
    }
    MixLuminairesQ12(mix.data(), n, count, scratch.data(), scratch_len, grid_total[g].data());
    // Direct only: the exact-direct luminaires, packed to the front.
    uint32_t direct_sources = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const SetCache& cache = lums[i].sets[g + 1];
      if (cache.direct.empty()) continue;
      MixSource& m = mix[direct_sources++];
      for (int c = 0; c < 3; ++c) {
        m.gain_q30[c] = GainQ30(lums[i].state.dimmer.raw(), lums[i].state.rgb[c].raw());
      }
      m.a = cache.direct.data();
      m.b = nullptr;
    }
    MixLuminairesQ12(mix.data(), direct_sources, count, scratch.data(), scratch_len,
                     grid_direct[g].data());
  }
}

void Engine::Impl::Update() {
  last_luminaires = 0;
  last_terms = 0;
  for (size_t i = 0; i < lums.size(); ++i) {
    if (!lums[i].dirty || !Lit(lums[i])) continue;
    last_terms += Recompute(static_cast<int>(i));
    lums[i].dirty = false;
    ++last_luminaires;
    remix = true;
  }
  if (remix) Remix();
  remix = false;
}

Engine::Engine() = default;
Engine::~Engine() = default;

Status Engine::Open(const std::string& bake_path) {
  Bake bake;
  RELIGHT_RETURN_IF_ERROR(ReadBake(bake_path, &bake));
  return Open(std::move(bake));
}

Status Engine::Open(Bake bake) {
  RELIGHT_RETURN_IF_ERROR(ValidateBake(bake));
  std::unique_ptr<Impl> impl(new Impl);
  impl->bake = std::move(bake);
  RELIGHT_RETURN_IF_ERROR(impl->Allocate());
  impl->Update();
  impl_ = std::move(impl);
  return Status::Ok();
}

bool Engine::is_open() const { return impl_ != nullptr; }

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

FixtureState Engine::state(int luminaire) const {
  if (luminaire < 0 || luminaire >= luminaire_count()) return FixtureState{};
  return impl_->lums[luminaire].state;
}

void Engine::Update() {
  if (impl_) impl_->Update();
}

const int32_t* Engine::vertex_luminance() const {
  return impl_ ? impl_->vertex_out.data() : nullptr;
}

uint32_t Engine::vertex_count() const { return impl_ ? impl_->bake.mesh.vertex_count() : 0; }

const int32_t* Engine::grid_illuminance(int grid) const {
  if (!impl_ || grid < 0 || grid >= static_cast<int>(impl_->grid_total.size())) return nullptr;
  return impl_->grid_total[grid].data();
}

const int32_t* Engine::grid_direct_illuminance(int grid) const {
  if (!impl_ || grid < 0 || grid >= static_cast<int>(impl_->grid_direct.size())) return nullptr;
  return impl_->grid_direct[grid].data();
}

int Engine::last_update_luminaires_recombined() const {
  return impl_ ? impl_->last_luminaires : 0;
}

int Engine::last_update_terms_recombined() const { return impl_ ? impl_->last_terms : 0; }

}  // namespace relight
