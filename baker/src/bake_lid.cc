#include "bake_lid.h"

#include <algorithm>
#include <cmath>

#include "quantise.h"
#include "relight/baker/beam_profile.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/photometry.h"
#include "relight/baker/sh_rotation.h"

namespace relight::baker {

namespace {

// Samples of the normalised profile over [0, x_end] (bake.h BakeZoom).
constexpr int kZoomProfileSamples = 2049;

// The zoom of a "beam" LID with a zoom range: its range, default angle,
// lumens and normalised profile f(x), sampled at the x_end the bake stores
// (Q16.16, so the runtime's positions and these samples agree).
BakeZoom MakeBakeZoom(const Lid& lid) {
  BakeZoom z;
  z.min_deg = ToQ16_16(lid.zoom_min_deg).raw();
  z.max_deg = ToQ16_16(lid.zoom_max_deg).raw();
  z.default_deg = ToQ16_16(lid.beam_deg).raw();
  z.lumens = ToQ48_16(lid.lumens).raw();
  z.profile_end = ToQ16_16(BeamProfileEnd(lid.beam_exponent)).raw();
  const double x_end = z.profile_end / 65536.0;
  for (int k = 0; k < kZoomProfileSamples; ++k) {
    const double x = std::min(x_end * k / (kZoomProfileSamples - 1), x_end);
    // Exactly at x_end: the last value before the cut, even where x_end rounded up.
    const double f = BeamProfileUncut(x, lid.beam_exponent);
    z.profile.push_back(static_cast<int32_t>(std::lround(f * (1 << 30))));
  }
  return z;
}

}  // namespace

void FillBakeLuminaireLid(const Luminaire& lum, int sh_degree, int lid_samples,
                          relight::BakeLuminaire* out) {
  switch (lum.mounting) {
    case MountingKind::kHanging: out->mounting = Mounting::kHanging; break;
    case MountingKind::kStanding: out->mounting = Mounting::kStanding; break;
    case MountingKind::kWall: out->mounting = Mounting::kWall; break;
  }
  out->yaw = ToQ16_16(lum.yaw_deg).raw();
  out->roll = ToQ16_16(lum.roll_deg).raw();
  out->pan_range = ToQ16_16(lum.pan_range_deg).raw();
  out->tilt_range = ToQ16_16(lum.tilt_range_deg).raw();
  out->lid = BakeLid();
  for (double cd : SampleLid(lum.lid, lid_samples)) out->lid.candela.push_back(ToQ48_16(cd).raw());
  if (lum.lid.zooms()) out->zoom = MakeBakeZoom(lum.lid);
  if (lum.lid.axisymmetric()) return;
  const FullCircleTable full = ExpandToFullCircle(*lum.lid.file);
  for (double c : full.c_deg) out->lid.c_deg.push_back(ToQ16_16(c).raw());
  for (double g : full.gamma_deg) out->lid.gamma_deg.push_back(ToQ16_16(g).raw());
  for (double cd : full.candela) out->lid.table.push_back(ToQ48_16(cd).raw());
  for (double c : ProjectLidSh(lum.lid, sh_degree)) out->lid.sh.push_back(ToQ48_16(c).raw());
}

}  // namespace relight::baker
