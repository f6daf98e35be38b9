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
#include "relight/engine/engine.h"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "relight/bake/bake_check.h"
#include "console_aim.h"
#include "direct.h"
#include "fixture_frame.h"
#include "lid_table.h"
#include "mix.h"
#include "recombine.h"
#include "relight/engine/legendre_weights.h"
#include "relight/engine/sh_eval.h"
#include "relight/base/sh_index.h"
#include "relight/engine/sh_rotation.h"
#include "relight/base/fixed_ops.h"
#include "surface_emitters.h"
#include "weights.h"

namespace relight {
namespace {

constexpr int32_t kHalfTurnQ16 = 180 << 16;
constexpr int64_t kFullTurnQ16 = int64_t{360} << 16;
// Largest accepted LID sample: 2^24 cd in Q48.16. Keeps every Legendre
// weight and per-term coefficient (<= ~1000 x the peak) far inside int64.
constexpr int64_t kMaxCandelaQ16 = int64_t{1} << 40;
// Largest SH coefficient of a (C, gamma) LID: 2^30 cd (a coefficient is at
// most sqrt(4 pi) x the peak), so rotated coefficients stay far inside int64.
constexpr int64_t kMaxShCoefficientQ16 = int64_t{1} << 46;

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
  // Beam editing (Dobashi 4.1): the undamped weights w_l and the f_l table
  // of Eq. 20 that Eq. 21 updates them with.
  int64_t weights_q16[kMaxShDegree + 1] = {};
  std::vector<int32_t> legendre_table_q30;
  // A LID that is not axisymmetric: its (C, gamma) table for the direct term
  // and its SH coefficients in the fixture frame, sigma applied (Q48.16).
  bool has_table = false;
  LidTableView table;
  std::vector<int64_t> sh_local_q16;
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
    if (lum.mounting != Mounting::kHanging && lum.mounting != Mounting::kStanding &&
        lum.mounting != Mounting::kWall) {
      return Invalid(lum, "unknown mounting");
    }
    if (lum.lid.candela.size() < 3) return Invalid(lum, "LID needs at least 3 samples");
    for (int64_t cd : lum.lid.candela) {
      if (cd < 0 || cd >= kMaxCandelaQ16) return Invalid(lum, "LID sample outside [0, 2^24) cd");
    }
    if (!lum.lid.axisymmetric()) {
      const BakeLid& lid = lum.lid;
      const size_t planes = lid.c_deg.size(), gammas = lid.gamma_deg.size();
      if (planes < 2 || gammas < 1 || lid.table.size() != planes * gammas ||
          lid.c_deg.front() != 0 || lid.c_deg.back() != (360 << 16) ||
          lid.sh.size() != static_cast<size_t>(ShTermCount(lum.sh_degree))) {
        return Invalid(lum, "LID table sizes or angles inconsistent");
      }
      for (size_t i = 1; i < planes; ++i) {
        if (lid.c_deg[i] <= lid.c_deg[i - 1]) return Invalid(lum, "LID C angles must increase");
      }
      for (size_t i = 0; i < gammas; ++i) {
        if (lid.gamma_deg[i] < 0 || lid.gamma_deg[i] > (180 << 16) ||
            (i > 0 && lid.gamma_deg[i] <= lid.gamma_deg[i - 1])) {
          return Invalid(lum, "LID gamma angles must increase within [0, 180]");
        }
      }
      for (int64_t cd : lid.table) {
        if (cd < 0 || cd >= kMaxCandelaQ16) return Invalid(lum, "LID table value outside [0, 2^24) cd");
      }
      for (int64_t c : lid.sh) {
        if (c <= -kMaxShCoefficientQ16 || c >= kMaxShCoefficientQ16) {
          return Invalid(lum, "LID SH coefficient outside +-2^30 cd");
        }
      }
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
  if (bake.hierarchy) {  // the surface emitters index mesh and nodes by it
    std::string error = bake_format::CheckHierarchyNodes(*bake.hierarchy, bake.mesh);
    if (error.empty()) error = bake_format::CheckHierarchyLinks(*bake.hierarchy);
    if (!error.empty()) return Status(StatusCode::kInvalidArgument, "engine: hierarchy: " + error);
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
  std::unique_ptr<ShRotationTables> rotation;     // only with a (C, gamma) LID
  std::vector<int32_t> rotation_q30;              // band matrices, kShRotationValues
  std::vector<int32_t> k;                         // per term and channel
  std::vector<MixSource> mix;                     // per luminaire
  std::vector<int32_t> vertex_out;
  std::vector<std::vector<int32_t>> grid_total, grid_direct;
  SurfaceEmitters emitters;  // run-time light sources on surfaces
  bool remix = true;
  int last_luminaires = 0;
  int last_terms = 0;
  int last_emitters = 0;

  Status Allocate();
  Status EditLidSample(int index, int sample, int64_t candela_q16);
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
    LegendreWeightsQ16(table.data(), l.degree, l.lid_m, b.lid.candela.data(), l.weights_q16);
    l.legendre_table_q30 = std::move(table);
    if (!b.lid.axisymmetric()) {
      l.has_table = true;
      l.table.c_deg_q16 = b.lid.c_deg.data();
      l.table.planes = static_cast<uint32_t>(b.lid.c_deg.size());
      l.table.gamma_deg_q16 = b.lid.gamma_deg.data();
      l.table.gammas = static_cast<uint32_t>(b.lid.gamma_deg.size());
      l.table.candela_q16 = b.lid.table.data();
      l.sh_local_q16 = b.lid.sh;
      if (b.use_sigma != 0) {
        for (int t = 0; t < ShTermCount(l.degree); ++t) {  // Dobashi Eq. 12-13, per band
          const Int128 p = static_cast<Int128>(l.sh_local_q16[t]) *
                           SigmaQ30(l.degree, ShDegreeOf(t)).raw();
          l.sh_local_q16[t] = static_cast<int64_t>((p + (static_cast<Int128>(1) << 29)) >> 30);
        }
      }
      if (!rotation) {
        rotation.reset(new ShRotationTables);
        InitShRotationTables(rotation.get());
        rotation_q30.assign(kShRotationValues, 0);
      }
    }
    l.state.roll_deg = WrapDegrees(Q16_16::FromRaw(b.roll));
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
  return emitters.Open(bake);
}

// Dobashi 4.1: one control point (= LID sample, the paper's simplification)
// moves; Eq. 21 updates the weights by its increment alone, O(N).
Status Engine::Impl::EditLidSample(int index, int sample, int64_t candela_q16) {
  BakeLuminaire& b = bake.luminaires[index];
  LuminaireRuntime& l = lums[index];
  if (l.has_table) return Status(StatusCode::kUnsupported, "LID has planes");
  if (sample < 0 || sample > l.lid_m) return Status(StatusCode::kInvalidArgument, "LID sample idx");
  if (candela_q16 < 0 || candela_q16 >= kMaxCandelaQ16) {
    return Status(StatusCode::kOutOfRange, "LID candela");
  }
  const int64_t old = b.lid.candela[sample];
  if (old == candela_q16) return Status::Ok();
  UpdateLegendreWeightsQ16(l.legendre_table_q30.data(), l.degree, l.lid_m, sample, old, candela_q16,
                           l.weights_q16);  // Eq. 21
  b.lid.candela[sample] = candela_q16;
  for (int d = 0; d <= l.degree; ++d) {  // Dobashi Eq. 12-13, as DampedLegendreWeightsQ16 does
    if (b.use_sigma != 0) {
      const Int128 p = static_cast<Int128>(l.weights_q16[d]) * SigmaQ30(l.degree, d).raw();
      l.damped_weights_q16[d] = RoundShiftSat64(p, -30);
    } else {
      l.damped_weights_q16[d] = l.weights_q16[d];
    }
  }
  l.dirty = true;
  remix = true;
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
  FixturePoseQ16 pose;
  pose.mounting = b.mounting;
  pose.yaw_deg = Q16_16::FromRaw(b.yaw);
  pose.pan_deg = l.state.pan_deg;
  pose.tilt_deg = l.state.tilt_deg;
  pose.roll_deg = l.state.roll_deg;
  FixtureFrameQ30 frame;
  MakeFixtureFrameQ30(pose, &frame);  // axis = BeamAxisQ30 for hanging/standing at yaw 0
  const int32_t* axis_q30 = frame.axis;
  const int terms = ShTermCount(l.degree);
  if (l.has_table) {
    // The LID's own coefficients rotated from the fixture frame to the world.
    const int32_t r_q30[3][3] = {{frame.c0[0], frame.c90[0], -frame.axis[0]},
                                 {frame.c0[1], frame.c90[1], -frame.axis[1]},
                                 {frame.c0[2], frame.c90[2], -frame.axis[2]}};
    ShRotationMatricesQ30(*rotation, l.degree, r_q30, rotation_q30.data());
    RotateShQ16(l.degree, rotation_q30.data(), l.sh_local_q16.data(), coef_q16.data());
  } else {
    TermCoefficientsQ16(sh, l.degree, l.damped_weights_q16, axis_q30, alm_q30.data(),
                        coef_q16.data());  // Dobashi Eq. 18
  }
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
    const uint32_t* rho = s == 0 ? reflectance_over_pi_q32.data() : nullptr;
    const DirectStore store = s == 0 ? DirectStore::kAdd : DirectStore::kWrite;
    int32_t* out = s == 0 ? cache.light.data() : cache.direct.data();
    if (l.has_table) {
      DirectLightTableQ12(direct, frame, l.table, rho, store, out);
    } else {
      DirectLightQ12(direct, axis_q30, b.lid.candela.data(), l.lid_m, rho, store, out);
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
  emitters.AddTo(vertex_out.data());
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
  last_emitters = emitters.SolvePending();
  if (last_emitters > 0) remix = true;
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
        candela[i].raw() >= kMaxCandelaQ16) {
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

int Engine::last_update_emitters_solved() const { return impl_ ? impl_->last_emitters : 0; }

int Engine::last_update_emitter_sweeps() const {
  return impl_ ? impl_->emitters.last_sweeps() : 0;
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
  RELIGHT_RETURN_IF_ERROR(impl_->emitters.Place(slot, shape));
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
