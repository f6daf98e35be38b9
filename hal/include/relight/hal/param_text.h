// The text syntax of a parameter change ("spot.pan=30"), for --set, replay
// scripts and patch presets. The change itself is relight/base/param.h.
#pragma once

#include <cstdint>
#include <string>

#include "relight/base/param.h"

namespace relight::hal {

// Parses "FIXTURE.PARAM=VALUE", the syntax of --set and replay scripts:
//   pan, tilt, roll   degrees in -720..720   dimmer   0..1, or 0..100%
//   r, g, b           0..1                   colour   R,G,B, each 0..1 (three changes)
//   zoom              the full beam angle at half peak, degrees in (0, 180)
// (roll: the fixture turned about its beam axis, engine.h SetRoll; zoom: engine.h SetZoom)
// Fills out[0..n) and returns n (1, or 3 for colour); on error returns 0 and
// writes a message that quotes the text and says what was expected.
int ParseParamText(const std::string& text, int64_t time_us, ParamChange out[3], std::string* error);

}  // namespace relight::hal
