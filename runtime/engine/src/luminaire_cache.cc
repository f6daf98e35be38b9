// The per-luminaire cache (see luminaire_cache.h).
#include "luminaire_cache.h"

#include "compressed_recombine.h"
#include "direct.h"
#include "direct_aimed.h"
#include "fixture_frame.h"
#include "recombine.h"
#include "weights.h"

namespace relight {

int RecomputeLuminaireCacheQ12(const Bake& bake, const BakeLuminaire& b, CacheWorkspace* work,
                               LuminaireRuntime* lum) {
  LuminaireRuntime& l = *lum;
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
  int64_t* coef_q16 = work->coef_q16.data();
  if (l.has_table) {
    // The LID's own coefficients rotated from the fixture frame to the world.
    const int32_t r_q30[3][3] = {{frame.c0[0], frame.c90[0], -frame.axis[0]},
                                 {frame.c0[1], frame.c90[1], -frame.axis[1]},
                                 {frame.c0[2], frame.c90[2], -frame.axis[2]}};
    ShRotationMatricesQ30(*work->rotation, l.degree, r_q30, work->rotation_q30.data());
    RotateShQ16(l.degree, work->rotation_q30.data(), l.sh_local_q16.data(), coef_q16);
  } else {
    TermCoefficientsQ16(work->sh, l.degree, l.damped_weights_q16, axis_q30, work->alm_q30.data(),
                        coef_q16);  // Dobashi Eq. 18
  }
  int passes = 0;
  for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
    const BakeLightReceivers& rx = b.receivers[s];
    const uint32_t count = bake.receiver_count(s);
    SetCache& cache = l.sets[s];
    if (rx.compressed.present()) {
      passes += static_cast<int>(RecombineCompressedQ12(
          rx.compressed, terms, coef_q16, work->k.data(), work->scratch.data(),
          static_cast<uint32_t>(work->scratch.size()), work->compressed_projection.data(),
          cache.light.data()));
    } else {
      const int shift = ChannelMultipliersQ12(coef_q16, terms, rx.basis_scale.data(), work->k.data());
      passes += static_cast<int>(RecombineQ12(rx.basis.data(), static_cast<uint32_t>(terms), count,
                                              work->k.data(), shift, work->scratch.data(),
                                              static_cast<uint32_t>(work->scratch.size()),
                                              cache.light.data()));
    }
    if (b.direct_mode != DirectMode::kExactDirect) continue;
    // Vertices: luminance added to the indirect; grids: illuminance apart.
    const uint32_t* rho = s == 0 ? work->reflectance_over_pi_q32.data() : nullptr;
    const DirectStore store = s == 0 ? DirectStore::kAdd : DirectStore::kWrite;
    int32_t* out = s == 0 ? cache.light.data() : cache.direct.data();
    if (l.has_table) {
      DirectLightTableQ12(DirectReceiversOf(rx, count), frame, l.table, rho, store, out);
    } else {
      DirectLightAimedQ12(cache.direct_points, SharedGammaTable(), axis_q30, b.lid.candela.data(),
                          l.lid_m, rho, store, out);
    }
  }
  return passes;
}

}  // namespace relight
