// What a fixture is set to: the parameters a console, a replay or a Modbus
// client moves and the engine renders. Plain values in the runtime's fixed
// formats; shared by hal (which reads and reports them) and the engine.
#pragma once

#include "relight/base/fixed.h"

namespace relight {

struct FixtureState {
  Q16_16 pan_deg;
  Q16_16 tilt_deg;
  Q1_15 dimmer;      // 0 .. 1
  Q1_15 rgb[3];      // 0 .. 1 each
  Q16_16 roll_deg;   // about the beam axis (bake.h); moves only LIDs that are not axisymmetric
  Q16_16 zoom_deg;   // full beam angle at half peak (bake.h BakeZoom); 0: the LID has no zoom
};

}  // namespace relight
