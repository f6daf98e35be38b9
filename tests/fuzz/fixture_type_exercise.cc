#include "fixture_type_exercise.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "relight/hal/dmx/personality.h"

namespace relight::fuzz {
namespace {

// Well-formed UTF-8 (no overlong forms, surrogates or code points past
// U+10FFFF): only such names can come back from TOML unchanged.
bool Utf8(const std::string& s) {
  size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    uint32_t cp = 0;
    if (c < 0x80) extra = 0, cp = c;
    else if ((c & 0xE0) == 0xC0) extra = 1, cp = c & 0x1F;
    else if ((c & 0xF0) == 0xE0) extra = 2, cp = c & 0x0F;
    else if ((c & 0xF8) == 0xF0) extra = 3, cp = c & 0x07;
    else return false;
    if (static_cast<size_t>(extra) >= s.size() - i) return false;  // cut short
    for (int k = 1; k <= extra; ++k) {
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      cp = cp << 6 | (d & 0x3F);
    }
    static const uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += static_cast<size_t>(extra) + 1;
  }
  return true;
}

bool AllNamesUtf8(const hal::FixtureType& type) {
  if (!Utf8(type.manufacturer) || !Utf8(type.model) || !Utf8(type.type)) return false;
  for (const hal::DmxChannel& c : type.channels) {
    if (!Utf8(c.name) || !Utf8(c.ignored_why)) return false;
  }
  for (const hal::DmxMode& m : type.modes) {
    if (!Utf8(m.name)) return false;
  }
  return true;
}

}  // namespace

void ExerciseFixtureType(const hal::FixtureType& type) {
  static uint8_t zeros[512] = {};
  static uint8_t ramp[512];
  for (int i = 0; i < 512; ++i) ramp[i] = static_cast<uint8_t>(i * 7);
  for (const hal::DmxMode& mode : type.modes) {
    hal::DmxPersonality p;
    if (!hal::BuildPersonality(type, mode.name, &p).ok()) continue;
    hal::DmxFixtureValues values;
    (void)hal::DecodeDmxFrame(p, 1, 0, zeros, sizeof zeros, &values);
    (void)hal::DecodeDmxFrame(p, 1, 0, ramp, sizeof ramp, &values);
  }
  // The TOML form (relight-fixture-type): what reads back must be the same
  // type. A type the TOML reader refuses is a clear error there, not a finding.
  const std::string text = hal::FixtureTypeToToml(type);
  hal::FixtureType back;
  if (AllNamesUtf8(type) && hal::ParseFixtureTypeToml(text, "(written form)", &back).ok()) {
    const std::string difference = hal::FixtureTypeDifference(type, back);
    if (!difference.empty()) {
      std::fprintf(stderr, "fixture type round trip: %s\n%s\n", difference.c_str(), text.c_str());
      std::abort();
    }
  }
}

}  // namespace relight::fuzz
