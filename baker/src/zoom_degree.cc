// The SH degree of a zooming beam: what its narrowest angle needs (see
// relight/baker/lid_error.h ChooseZoomDegrees), the way `relight-lid degree`
// picks one for an error target.
#include "relight/baker/beam_profile.h"
#include "relight/baker/lid_error.h"

namespace relight::baker {

Lid NarrowestLid(const Lid& lid) {
  return lid.zooms() ? ZoomedBeamLid(lid, lid.zoom_min_deg) : lid;
}

std::vector<LuminaireDegree> ChooseZoomDegrees(Scene* scene, DirectModeKind mode) {
  std::vector<LuminaireDegree> out;
  for (Luminaire& lum : scene->luminaires) {
    if (!lum.lid.zooms() || lum.sh_degree_given) continue;
    out.push_back(ChooseLuminaireDegree(&lum, kZoomDegreeTarget, mode));
  }
  return out;
}

}  // namespace relight::baker
