// A timestamped change of one fixture parameter: what every input backend
// (Modbus, GPIO, replay, mock, the command line) produces. hal/ knows
// fixtures by name and parameters by kind; it knows nothing of radiosity.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace relight::hal {

enum class Param : uint8_t { kPan, kTilt, kDimmer, kRed, kGreen, kBlue, kRoll };
inline constexpr int kParamCount = 7;
// pan, tilt and roll carry degrees; the rest Q1.15 levels.
inline constexpr bool IsAngle(Param param) {
  return param == Param::kPan || param == Param::kTilt || param == Param::kRoll;
}

inline constexpr size_t kMaxFixtureName = 47;

struct ParamChange {
  int64_t time_us = 0;  // when the change applies, microseconds on the source's clock
  char fixture[kMaxFixtureName + 1] = {};
  Param param = Param::kDimmer;
  // pan, tilt, roll: degrees in Q16.16 (65536 = 1 degree);
  // dimmer, red, green, blue: Q1.15 level, 0 .. 32767 = 0 .. 1.
  int32_t value = 0;
};

const char* ParamName(Param param);
// "pan", "tilt", "roll", "dimmer", "r", "g", "b" -> Param; false for anything else.
bool ParamFromName(const std::string& name, Param* out);

// Parses "FIXTURE.PARAM=VALUE", the syntax of --set and replay scripts:
//   pan, tilt, roll   degrees in -720..720   dimmer   0..1, or 0..100%
//   r, g, b           0..1                   colour   R,G,B, each 0..1 (three changes)
// (roll: the fixture turned about its beam axis, engine.h SetRoll)
// Fills out[0..n) and returns n (1, or 3 for colour); on error returns 0 and
// writes a message that quotes the text and says what was expected.
int ParseParamText(const std::string& text, int64_t time_us, ParamChange out[3], std::string* error);

}  // namespace relight::hal
