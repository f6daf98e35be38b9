// Fixture parameters as every input produces them: a timestamped change of
// one parameter of one fixture, in the runtime's fixed formats. Below hal,
// the control stage and the engine alike; knows nothing of radiosity.
//
// A change names its fixture by index, never by name: names are resolved
// once, when a patch, script or argument is loaded (issue 11), so nothing on
// the per-change path compares strings or allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "relight/base/fixed.h"

namespace relight {

// kX, kY and kSize belong to run-time emitters (a patch's [[emitter]]): levels
// 0..1 across the ranges the patch declares for them, so inputs treat them
// like a dimmer and only the control stage knows what they move (metres on a
// surface, a scale). Luminaires have none: kFixtureParamCount come first.
enum class Param : uint8_t { kPan, kTilt, kDimmer, kRed, kGreen, kBlue, kRoll, kZoom, kX, kY, kSize };
inline constexpr int kParamCount = 11;
inline constexpr int kFixtureParamCount = 8;
// pan, tilt, roll and zoom (the full beam angle) carry degrees; the rest Q1.15 levels.
inline constexpr bool IsAngle(Param param) {
  return param == Param::kPan || param == Param::kTilt || param == Param::kRoll ||
         param == Param::kZoom;
}
// The parameters a run-time emitter has: dimmer, colour, x, y, size.
inline constexpr bool IsEmitterParam(Param p) {
  return p == Param::kDimmer || p == Param::kRed || p == Param::kGreen || p == Param::kBlue || p == Param::kX ||
         p == Param::kY || p == Param::kSize;
}

inline constexpr size_t kMaxFixtureName = 47;
inline constexpr int kMaxFixtures = 65535;  // a fixture index fits uint16_t

struct ParamChange {
  int64_t time_us = 0;    // when the change applies, microseconds on the source's clock
  // Index of the fixture in the list the source was built from (for sources
  // made from a patch, the patch's fixtures; the daemon maps it once to an
  // engine luminaire).
  uint16_t fixture = 0;
  Param param = Param::kDimmer;
  // The value, typed by the parameter: `degrees` for pan, tilt, roll and
  // zoom (IsAngle), `level` (0 .. 1) for dimmer, red, green and blue. The
  // other member stays 0.
  Q16_16 degrees;
  Q1_15 level;

  static constexpr ParamChange Angle(int64_t time_us, uint16_t fixture, Param param, Q16_16 degrees) {
    ParamChange c;
    c.time_us = time_us;
    c.fixture = fixture;
    c.param = param;
    c.degrees = degrees;
    return c;
  }
  static constexpr ParamChange Level(int64_t time_us, uint16_t fixture, Param param, Q1_15 level) {
    ParamChange c;
    c.time_us = time_us;
    c.fixture = fixture;
    c.param = param;
    c.level = level;
    return c;
  }
};

const char* ParamName(Param param);
// "pan", "tilt", "roll", "dimmer", "r", "g", "b", "zoom", "x", "y", "size" -> Param; false for anything else.
bool ParamFromName(const std::string& name, Param* out);

}  // namespace relight
