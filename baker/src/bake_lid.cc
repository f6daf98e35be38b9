#include "bake_lid.h"

#include "quantise.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/photometry.h"
#include "relight/baker/sh_rotation.h"

namespace relight::baker {

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
  if (lum.lid.axisymmetric()) return;
  const FullCircleTable full = ExpandToFullCircle(*lum.lid.file);
  for (double c : full.c_deg) out->lid.c_deg.push_back(ToQ16_16(c).raw());
  for (double g : full.gamma_deg) out->lid.gamma_deg.push_back(ToQ16_16(g).raw());
  for (double cd : full.candela) out->lid.table.push_back(ToQ48_16(cd).raw());
  for (double c : ProjectLidSh(lum.lid, sh_degree)) out->lid.sh.push_back(ToQ48_16(c).raw());
}

}  // namespace relight::baker
