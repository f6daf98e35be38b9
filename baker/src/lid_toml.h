// A luminaire's `lid` table (docs/scene-format.md) into a Lid:
//   { type = "isotropic", peak_cd }
//   { type = "cos", exponent, spread, peak_cd }        (Dobashi Eq. 11)
//   { type = "table", gamma = [0, ...], candela = [...] }
//   { type = "file", path = "luminaire.ies" }        (IES LM-63 or EULUMDAT .ldt)
//   { type = "beam", beam_angle, field_angle, lumens | peak_cd, zoom = [min, max] }
//                                                    (a zoom optic, beam_profile.h)
#pragma once

#include "relight/baker/scene.h"
#include "toml_fields.h"

namespace relight::baker {

// Throws SceneError (file:line, what was expected) on any bad field.
Lid ReadLid(const TomlFields& lid_table);

}  // namespace relight::baker
