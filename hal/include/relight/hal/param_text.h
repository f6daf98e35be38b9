// The text syntax of a parameter change ("spot.pan=30"), for --set, replay
// scripts and patch presets. Text names fixtures; a ParamChange
// (relight/base/param.h) carries an index: the name is resolved once, when
// the text is loaded (FixtureIndex), never per change.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/param.h"

namespace relight::hal {

// A change as text gives it: the fixture's name beside the change, whose
// `fixture` index is set when the name is resolved.
struct NamedChange {
  std::string fixture;
  ParamChange change;
  int line = 0;  // where it was read (0: not from a file)
};

// Parses "FIXTURE.PARAM=VALUE", the syntax of --set and replay scripts:
//   pan, tilt, roll   degrees in -720..720   dimmer   0..1, or 0..100%
//   r, g, b           0..1                   colour   R,G,B, each 0..1 (three changes)
//   zoom              the full beam angle at half peak, degrees in (0, 180)
//   x, y, size        an emitter's position and size, 0..1 across the ranges its patch entry declares
// (roll: the fixture turned about its beam axis, engine.h SetRoll; zoom: engine.h SetZoom)
// Fills out[0..n) and returns n (1, or 3 for colour); on error returns 0 and
// writes a message that quotes the text and says what was expected.
int ParseParamText(const std::string& text, int64_t time_us, NamedChange out[3], std::string* error);

// Index of `name` in `fixtures`, or -1 (also past kMaxFixtures).
int FixtureIndex(const std::vector<std::string>& fixtures, const std::string& name);
// "a, b, c": the fixtures a message lists.
std::string FixtureList(const std::vector<std::string>& fixtures);

}  // namespace relight::hal
