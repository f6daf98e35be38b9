// Fixture parameters as every input produces them: a timestamped change of
// one parameter of one fixture, in the runtime's fixed formats. Below hal,
// the control stage and the engine alike; knows nothing of radiosity.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace relight {

enum class Param : uint8_t { kPan, kTilt, kDimmer, kRed, kGreen, kBlue, kRoll, kZoom };
inline constexpr int kParamCount = 8;
// pan, tilt, roll and zoom (the full beam angle) carry degrees; the rest Q1.15 levels.
inline constexpr bool IsAngle(Param param) {
  return param == Param::kPan || param == Param::kTilt || param == Param::kRoll ||
         param == Param::kZoom;
}

inline constexpr size_t kMaxFixtureName = 47;

struct ParamChange {
  int64_t time_us = 0;  // when the change applies, microseconds on the source's clock
  char fixture[kMaxFixtureName + 1] = {};
  Param param = Param::kDimmer;
  // pan, tilt, roll, zoom: degrees in Q16.16 (65536 = 1 degree; zoom: the full
  // beam angle at half peak);
  // dimmer, red, green, blue: Q1.15 level, 0 .. 32767 = 0 .. 1.
  int32_t value = 0;
};

const char* ParamName(Param param);
// "pan", "tilt", "roll", "dimmer", "r", "g", "b", "zoom" -> Param; false for anything else.
bool ParamFromName(const std::string& name, Param* out);

}  // namespace relight
