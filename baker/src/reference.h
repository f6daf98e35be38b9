// Dobashi's "traditional method", the ground truth of every accuracy figure:
// the same mesh, form factors and factorised system as the bake, each
// luminaire lit by its exact distribution (no SH basis) at the given aim,
// scaled by dimmer x colour and summed.
#pragma once

#include <vector>

#include "baker_core.h"
#include "relight/baker/fixture_frame.h"

namespace relight::baker {

// Throws std::invalid_argument unless there is one setting per luminaire.
ReferenceResult ComputeReference(const BakerCore& core,
                                 const std::vector<FixtureSetting>& settings);

// Exact intensity (cd) of a luminaire aimed along `axis` in direction `dir`
// (an axisymmetric LID; a (C, gamma) one takes its C-average).
double ExactIntensity(const Lid& lid, const Vec3& axis, const Vec3& dir);
// Exact intensity of any LID for a fixture in `frame` (bake.h's convention).
double ExactIntensity(const Lid& lid, const FixtureFrame& frame, const Vec3& dir);
// The frame of `lum` at `setting` (the scene's yaw; the setting's roll, or the scene's).
FixtureFrame SettingFrame(const Luminaire& lum, const FixtureSetting& setting);

}  // namespace relight::baker
