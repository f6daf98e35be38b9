// Dobashi's "traditional method", the ground truth of every accuracy figure:
// the same mesh, form factors and factorised system as the bake, each
// luminaire lit by its exact distribution (no SH basis) at the given aim,
// scaled by dimmer x colour and summed.
#pragma once

#include <vector>

#include "baker_core.h"

namespace relight::baker {

// Throws std::invalid_argument unless there is one setting per luminaire.
ReferenceResult ComputeReference(const BakerCore& core,
                                 const std::vector<FixtureSetting>& settings);

// Exact intensity (cd) of a luminaire aimed along `axis` in direction `dir`.
double ExactIntensity(const Lid& lid, const Vec3& axis, const Vec3& dir);

}  // namespace relight::baker
