// Beam editing on a photometric table (Dobashi 4.1, offline side): control
// points on the distribution curve. relight-lid edit applies them and saves
// the profile; the runtime's Engine::SetLidControlPoints does the same on a
// running fixture with Eq. 21's incremental weights.
#pragma once

#include <optional>
#include <string>

#include "relight/baker/photometric_file.h"

namespace relight::baker {

struct ControlPoint {
  double gamma_deg = 0;
  double candela = 0;
  std::optional<double> c_deg;  // one stored C plane; unset: every plane
};

// "GAMMA=CD" or "C:GAMMA=CD"; throws std::invalid_argument naming the text.
ControlPoint ParseControlPoint(const std::string& text);

// The intensity at gamma becomes `candela` on the chosen plane(s); where the
// table has no such gamma a knot is inserted (every other plane keeps its
// interpolated value there, so its curve does not change). Throws
// std::invalid_argument for gamma outside [0, 180], a negative candela or a
// C that is not a stored plane.
void ApplyControlPoint(const ControlPoint& point, PhotometricTable* table);

}  // namespace relight::baker
