#include "relight/hal/param_text.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace relight::hal {
namespace {

bool ParseNumber(const std::string& s, double* out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (errno != 0 || end != s.c_str() + s.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

// Callers check the ranges first: 0..1 and -720..720 fit the formats.
Q1_15 LevelQ15(double level) { return Q1_15::FromRaw(static_cast<int16_t>(std::lround(level * 32767.0))); }
Q16_16 DegreesQ16(double degrees) { return Q16_16::FromRaw(static_cast<int32_t>(std::llround(degrees * 65536.0))); }

bool ValidFixtureName(const std::string& name) {
  if (name.empty() || name.size() > kMaxFixtureName) return false;
  for (char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
                    ch == '_' || ch == '-';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

int FixtureIndex(const std::vector<std::string>& fixtures, const std::string& name) {
  for (size_t i = 0; i < fixtures.size() && i <= static_cast<size_t>(kMaxFixtures); ++i) {
    if (fixtures[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::string FixtureList(const std::vector<std::string>& fixtures) {
  std::string list;
  for (const std::string& f : fixtures) list += (list.empty() ? "" : ", ") + f;
  return list.empty() ? "none" : list;
}

int ParseParamText(const std::string& text, int64_t time_us, NamedChange out[3], std::string* error) {
  const auto fail = [&](const std::string& why) {
    *error = "'" + text + "': " + why;
    return 0;
  };
  const size_t eq = text.find('=');
  const size_t dot = eq == std::string::npos ? std::string::npos : text.rfind('.', eq);
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= eq) {
    return fail("expected FIXTURE.PARAM=VALUE, e.g. spot1.pan=30");
  }
  const std::string fixture = text.substr(0, dot);
  const std::string param = text.substr(dot + 1, eq - dot - 1);
  std::string value = text.substr(eq + 1);
  if (!ValidFixtureName(fixture)) {
    return fail("fixture name must be 1.." + std::to_string(kMaxFixtureName) + " of A-Z a-z 0-9 _ -");
  }
  NamedChange base;
  base.fixture = fixture;
  base.change.time_us = time_us;

  if (param == "colour" || param == "color") {
    double rgb[3];
    size_t start = 0;
    for (int i = 0; i < 3; ++i) {
      const size_t comma = value.find(',', start);
      if ((i < 2) != (comma != std::string::npos)) return fail("colour wants exactly three numbers R,G,B");
      const std::string part = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!ParseNumber(part, &rgb[i]) || rgb[i] < 0 || rgb[i] > 1) {
        return fail("colour wants R,G,B with each in 0..1");
      }
      start = comma + 1;
    }
    const Param params[3] = {Param::kRed, Param::kGreen, Param::kBlue};
    for (int i = 0; i < 3; ++i) {
      out[i] = base;
      out[i].change.param = params[i];
      out[i].change.level = LevelQ15(rgb[i]);
    }
    return 3;
  }

  Param kind = Param::kDimmer;
  if (!ParamFromName(param, &kind)) {
    return fail("unknown parameter '" + param + "' (pan, tilt, roll, zoom, dimmer, r, g, b, colour; emitters also x, y, size)");
  }
  bool percent = false;
  if (param == "dimmer" && !value.empty() && value.back() == '%') {
    percent = true;
    value.pop_back();
  }
  double v = 0;
  if (!ParseNumber(value, &v)) return fail("'" + value + "' is not a number");
  if (percent) v /= 100.0;
  out[0] = base;
  out[0].change.param = kind;
  if (kind == Param::kZoom && !(v > 0 && v < 180)) {
    return fail("zoom (the full beam angle) must be in (0, 180) degrees");
  }
  if (IsAngle(kind)) {
    if (v < -720 || v > 720) return fail(param + " must be in -720..720 degrees");
    out[0].change.degrees = DegreesQ16(v);
  } else {
    if (v < 0 || v > 1) return fail(param + " must be in 0..1" + (param == "dimmer" ? " (or 0..100%)" : ""));
    out[0].change.level = LevelQ15(v);
  }
  return 1;
}

}  // namespace relight::hal
