// What BF refinement multiplies a form factor by (hierarchy_links.h): an
// estimate of every node's exitance that holds for any aim, dimmer and colour
// of the luminaires, since one set of links serves every SH term and every
// run-time setting:
//   E_i  = sum over luminaires of (peak intensity, cd) x (patch i's mean
//          cos / d^2 with visibility): the direct illuminance if every
//          luminaire shone its peak in every direction;
//   E_a  = rho_a Phi / ((1 - rho_a) A): the mean interreflected illuminance
//          of a closed room (Phi = sum E_i A_i, rho_a the area-mean
//          reflectance), so patches lit only indirectly are not ignored;
//   B_i  = max over channels of rho_i (E_i + E_a)   (lm/m^2),
// averaged by area over each node's leaves. A scene without luminaires gets
// B = 1 everywhere (plain F refinement).
#pragma once

#include <vector>

#include "direct_light.h"
#include "hierarchy.h"

namespace relight::baker {

std::vector<double> RefinementBrightness(const Scene& scene, const Mesh& mesh, const Hierarchy& h,
                                         const std::vector<LuminaireDirect>& direct);

}  // namespace relight::baker
