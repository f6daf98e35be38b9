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
#include "hierarchy_solve.h"

namespace relight::baker {

// Per mesh patch, E_i above (lux).
std::vector<double> PeakDirectIlluminance(const Mesh& mesh, const Scene& scene,
                                          const std::vector<LuminaireDirect>& direct);

std::vector<double> RefinementBrightness(const Scene& scene, const Mesh& mesh, const Hierarchy& h,
                                         const std::vector<LuminaireDirect>& direct);


// Receiver-relative refinement (docs/hierarchy.md). An absolute bound
// (epsilon of the scene's mean exitance) leaves surfaces 30-1000x dimmer
// than the room with errors large against their own light. A first solve
// over the absolute bound's links spreads the peak direct light E_i; from it
//   brightness[n] = max over channels of the solved exitance, area mean over
//                   n's leaves, + kSourceSpread x the mean |B_leaf - B_n|
//                   (a link takes its source as uniform plus a linear
//                   moment; a source whose exitance varies more errs more);
//   bound[n]      = min(absolute, kReceiverRelative x link_epsilon x E_n),
//                   E_n the least total illuminance (direct + interreflected)
//                   of n's leaves, at least kDarkFloor x its surface's peak;
//                   never below kAbsoluteFloor x absolute (an unlit surface
//                   would otherwise link leaf to leaf with everything).
// The least, not the mean: dim parts of bright surfaces (the wall in the
// 5 cm behind the sofa) light dim surfaces, whose error is then theirs.
constexpr double kReceiverRelative = 0.3;
constexpr double kDarkFloor = 0.01;
constexpr double kAbsoluteFloor = 0.01;
// With kQuadratureError = 0.1 a link in full view counts F x the spread.
constexpr double kSourceSpread = 10.0;

struct RefinementEstimate {
  std::vector<double> brightness, bound;  // per node
};
RefinementEstimate ReceiverRelativeEstimate(const Mesh& mesh, const Hierarchy& h,
                                            const HierarchicalSolver& first,
                                            const std::vector<double>& peak_direct,
                                            double link_epsilon, double absolute_bound);

}  // namespace relight::baker
