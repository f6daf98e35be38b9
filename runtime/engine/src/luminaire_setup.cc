// Luminaire set-up at Engine::Open and beam edits (see luminaire.h).
#include <cstddef>
#include <utility>

#include "compressed_recombine.h"
#include "direct.h"
#include "gamma_table.h"
#include "luminaire.h"
#include "recombine.h"
#include "relight/bake/bake_limits.h"
#include "relight/engine/legendre_weights.h"
#include "weights.h"
#include "zoom.h"

namespace relight {
namespace {

constexpr int32_t kHalfTurnQ16 = 180 << 16;
constexpr int64_t kFullTurnQ16 = int64_t{360} << 16;

Status Invalid(const BakeLuminaire& lum, const char* what) {
  return Status(StatusCode::kInvalidArgument,
                StrFormat("engine: luminaire '%s': %s", lum.name.c_str(), what));
}

// The LID in the kernels' forms: Legendre table and weights always (the
// direct term of an axisymmetric LID, beam edits); for a (C, gamma) LID also
// its table view and sigma-damped SH coefficients.
Status PrepareLid(const BakeLuminaire& b, LuminaireRuntime* l) {
  l->degree = b.sh_degree;
  l->lid_m = static_cast<int>(b.lid.candela.size()) - 1;
  std::vector<int32_t> table(static_cast<size_t>(l->degree + 1) * (l->lid_m + 1));
  const Status st = DampedLegendreWeightsQ16(l->degree, b.use_sigma != 0, b.lid.candela.data(),
                                             l->lid_m, table.data(), l->damped_weights_q16);
  if (!st.ok()) return Invalid(b, st.message().c_str());
  LegendreWeightsQ16(table.data(), l->degree, l->lid_m, b.lid.candela.data(), l->weights_q16);
  l->legendre_table_q30 = std::move(table);
  if (b.lid.axisymmetric()) return Status::Ok();
  l->has_table = true;
  l->table.c_deg_q16 = b.lid.c_deg.data();
  l->table.planes = static_cast<uint32_t>(b.lid.c_deg.size());
  l->table.gamma_deg_q16 = b.lid.gamma_deg.data();
  l->table.gammas = static_cast<uint32_t>(b.lid.gamma_deg.size());
  l->table.candela_q16 = b.lid.table.data();
  l->sh_local_q16 = b.lid.sh;
  if (b.use_sigma != 0) {
    for (int t = 0; t < ShTermCount(l->degree); ++t) {
      l->sh_local_q16[t] = SigmaDampedQ16(l->degree, ShDegreeOf(t), l->sh_local_q16[t]);
    }
  }
  return Status::Ok();
}

// The weights the kernels use: sigma-damped when the bake says so (Eq. 13).
void DampWeights(const BakeLuminaire& b, LuminaireRuntime* l) {
  for (int d = 0; d <= l->degree; ++d) {
    l->damped_weights_q16[d] =
        b.use_sigma != 0 ? SigmaDampedQ16(l->degree, d, l->weights_q16[d]) : l->weights_q16[d];
  }
}

void SetDefaultState(const BakeLuminaire& b, FixtureState* s) {
  s->roll_deg = WrapDegrees(Q16_16::FromRaw(b.roll));
  s->pan_deg = WrapDegrees(Q16_16::FromRaw(b.default_pan));
  s->tilt_deg = WrapDegrees(Q16_16::FromRaw(b.default_tilt));
  s->dimmer = ClampUnit(Q1_15::FromRaw(b.default_dimmer));
  for (int c = 0; c < 3; ++c) s->rgb[c] = ClampUnit(Q1_15::FromRaw(b.default_rgb[c]));
  s->zoom_deg = Q16_16::FromRaw(b.zoom.present() ? b.zoom.default_deg : 0);
}

}  // namespace

Q16_16 WrapDegrees(Q16_16 degrees) {
  int64_t v = degrees.raw() % kFullTurnQ16;
  if (v > kHalfTurnQ16) v -= kFullTurnQ16;
  if (v <= -kHalfTurnQ16) v += kFullTurnQ16;
  return Q16_16::FromRaw(static_cast<int32_t>(v));
}

Q1_15 ClampUnit(Q1_15 v) { return v.raw() < 0 ? Q1_15::FromRaw(0) : v; }

// The largest projection scratch any compressed basis needs (at least 1).
static size_t MaxCompressedProjection(const Bake& bake) {
  uint64_t most = 1;
  for (const BakeLuminaire& b : bake.luminaires) {
    for (const BakeLightReceivers& rx : b.receivers) {
      const uint64_t n = CompressedProjectionValues(rx.compressed);
      if (n > most) most = n;
    }
  }
  return static_cast<size_t>(most);
}

Status SetUpLuminaires(Bake* bake_in, bool release_direct_inputs, std::vector<LuminaireRuntime>* lums,
                       CacheWorkspace* work) {
  const Bake& bake = *bake_in;
  InitShTables(&work->sh);
  (void)SharedGammaTable();  // built here, not in an Update()
  const uint32_t sets = bake.receiver_set_count();
  uint32_t max_count = 0;
  for (uint32_t s = 0; s < sets; ++s) {
    if (bake.receiver_count(s) > max_count) max_count = bake.receiver_count(s);
  }
  const uint32_t block = max_count < kRecombineBlockReceivers ? max_count : kRecombineBlockReceivers;
  work->scratch.assign(static_cast<size_t>(block > 0 ? block : 1) * 3, 0);
  int max_terms = 1;
  size_t max_zoom_samples = 0;
  lums->resize(bake.luminaires.size());
  for (size_t i = 0; i < lums->size(); ++i) {
    const BakeLuminaire& b = bake.luminaires[i];
    LuminaireRuntime& l = (*lums)[i];
    RELIGHT_RETURN_IF_ERROR(PrepareLid(b, &l));
    if (ShTermCount(l.degree) > max_terms) max_terms = ShTermCount(l.degree);
    if (l.has_table && !work->rotation) {
      work->rotation.reset(new ShRotationTables);
      InitShRotationTables(work->rotation.get());
      work->rotation_q30.assign(kShRotationValues, 0);
    }
    SetDefaultState(b, &l.state);
    if (b.zoom.present() && b.lid.candela.size() > max_zoom_samples) {
      max_zoom_samples = b.lid.candela.size();
    }
    l.sets.resize(sets);
    for (uint32_t s = 0; s < sets; ++s) {
      const size_t n = static_cast<size_t>(bake.receiver_count(s)) * 3;
      l.sets[s].light.assign(n, 0);
      if (s > 0 && b.direct_mode == DirectMode::kExactDirect) l.sets[s].direct.assign(n, 0);
      if (b.direct_mode == DirectMode::kExactDirect && !l.has_table) {
        PrepareDirectPoints(DirectReceiversOf(b.receivers[s], bake.receiver_count(s)),
                            &l.sets[s].direct_points);
      }
    }
    // Luminaire by luminaire, so the next one's points can take the freed room.
    if (release_direct_inputs) ReleasePreparedDirectInputs(&bake_in->luminaires[i], l);
  }
  work->compressed_projection.assign(MaxCompressedProjection(bake), 0);
  work->zoom_samples_q16.assign(max_zoom_samples, 0);
  work->alm_q30.assign(max_terms, 0);
  work->coef_q16.assign(max_terms, 0);
  work->k.assign(static_cast<size_t>(max_terms) * 3, 0);
  work->reflectance_over_pi_q32.resize(bake.mesh.albedo.size());
  ReflectanceOverPiQ32(bake.mesh.albedo.data(), static_cast<uint32_t>(bake.mesh.albedo.size()),
                       work->reflectance_over_pi_q32.data());
  return Status::Ok();
}

void ReleasePreparedDirectInputs(BakeLuminaire* b, const LuminaireRuntime& l) {
  if (b->direct_mode != DirectMode::kExactDirect || l.has_table) return;
  for (BakeLightReceivers& rx : b->receivers) {
    std::vector<int16_t>().swap(rx.direction);
    std::vector<uint32_t>().swap(rx.geometry);
  }
}

void ApplyZoom(BakeLuminaire* b, LuminaireRuntime* l, int64_t* samples) {
  const int M = l->lid_m;
  ZoomedLidSamplesQ16(b->zoom, l->state.zoom_deg, l->legendre_table_q30.data(), M, samples);
  for (int k = 0; k <= M; ++k) b->lid.candela[k] = samples[k];
  LegendreWeightsQ16(l->legendre_table_q30.data(), l->degree, M, samples, l->weights_q16);  // Eq. 19
  DampWeights(*b, l);
  l->zoom_pending = false;
  l->dirty = true;
}

Status EditLidSample(BakeLuminaire* b, LuminaireRuntime* l, int sample, int64_t candela_q16,
                     bool* changed) {
  *changed = false;
  if (l->has_table) return Status(StatusCode::kUnsupported, "LID has planes");
  if (sample < 0 || sample > l->lid_m) {
    return Status(StatusCode::kInvalidArgument, "LID sample idx");
  }
  if (candela_q16 < 0 || candela_q16 > bake_format::kMaxCandelaRaw) {
    return Status(StatusCode::kOutOfRange, "LID candela");
  }
  const int64_t old = b->lid.candela[sample];
  if (old == candela_q16) return Status::Ok();
  UpdateLegendreWeightsQ16(l->legendre_table_q30.data(), l->degree, l->lid_m, sample, old,
                           candela_q16, l->weights_q16);  // Eq. 21
  b->lid.candela[sample] = candela_q16;
  DampWeights(*b, l);
  l->dirty = true;
  *changed = true;
  return Status::Ok();
}

}  // namespace relight
