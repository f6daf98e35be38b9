// Shared set-up for hal tests: resolved patches and their maps.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal::testing {

// spot: holding registers 0..7, pan over 540 deg, tilt over 270 deg
// wash: holding registers 8..15, pan over 360 deg, tilt over 180 deg
inline Patch TwoFixturePatch() {
  Patch patch;
  const Status st = ParsePatch(
      "[[fixture]]\nname = \"spot\"\n"
      "[[fixture]]\nname = \"wash\"\npan_range_deg = 360\ntilt_range_deg = 180\n",
      "test.toml", &patch);
  EXPECT_TRUE(st.ok()) << st.ToString();
  EXPECT_TRUE(ResolvePatch({{"spot"}, {"wash"}}, &patch).ok());
  return patch;
}

// spot: registers 0..9 = dimmer, pan coarse, pan fine, tilt coarse, tilt
// fine, roll (over 360 deg), r, g, b, flags; its luminaire's console ranges
// are pan 630 and tilt 265 deg. wash: the standard 8 at 10..17, 540 / 270 deg.
inline Patch LayoutPatch() {
  Patch patch;
  const Status st = ParsePatch(
      "[[fixture]]\nname = \"spot\"\nmodbus_base = 0\nroll_range_deg = 360\n"
      "registers = [\"dimmer\", \"pan\", \"pan_fine\", \"tilt\", \"tilt_fine\", \"roll\", \"r\", \"g\", \"b\", "
      "\"flags\"]\n",
      "layout.toml", &patch);
  EXPECT_TRUE(st.ok()) << st.ToString();
  const Status resolved = ResolvePatch({{"spot", 630 << 16, 265 << 16}, {"wash"}}, &patch);
  EXPECT_TRUE(resolved.ok()) << resolved.ToString();
  return patch;
}

// The test patches above list spot, then wash: their fixture indices.
inline uint16_t FixtureIndexOf(const char* name) { return std::string(name) == "spot" ? 0 : 1; }

// A change's value as the raw integer of its format (Q16.16 degrees or Q1.15 level).
inline int32_t Raw(const ParamChange& c) { return IsAngle(c.param) ? c.degrees.raw() : c.level.raw(); }

inline RegisterMap MapOf(const Patch& patch) {
  RegisterMap map;
  const Status st = RegisterMap::Build(patch.fixtures, &map);
  EXPECT_TRUE(st.ok()) << st.ToString();
  return map;
}

// Registers at rest: dimmer 0, pan/tilt centred (0 deg), colour 0, on.
inline std::vector<uint16_t> RestRegisters(const RegisterMap& map) {
  std::vector<uint16_t> regs(static_cast<size_t>(map.holding_count()), 0);
  for (int f = 0; f < map.fixture_count(); ++f) {
    const int base = map.fixture(f).modbus_base;
    regs[static_cast<size_t>(base + kRegPan)] = 32768;
    regs[static_cast<size_t>(base + kRegTilt)] = 32768;
    regs[static_cast<size_t>(base + kRegFlags)] = kFlagOn;
  }
  return regs;
}

}  // namespace relight::hal::testing
