#include "set_args.h"

namespace relight::cli {

bool ParseSetArg(const std::string& text, SetArg* out, std::string* error) {
  ParamChange changes[3];
  const int n = hal::ParseParamText(text, 0, changes, error);
  if (n == 0) {
    *error = "--set " + *error;
    return false;
  }
  SetArg arg;
  arg.fixture = changes[0].fixture;
  if (n == 3) {
    arg.param = "colour";
  } else {
    arg.param = ParamName(changes[0].param);
  }
  for (int i = 0; i < n; ++i) {
    arg.values.push_back(IsAngle(changes[i].param) ? changes[i].value / 65536.0 : changes[i].value / 32767.0);
  }
  *out = std::move(arg);
  return true;
}

bool ApplyChange(Engine& engine, const ParamChange& change, std::string* error) {
  const int index = engine.FindLuminaire(change.fixture);
  if (index < 0) {
    std::string names;
    for (const auto& lum : engine.bake().luminaires) names += (names.empty() ? "" : ", ") + lum.name;
    *error = std::string("no luminaire '") + change.fixture + "' in the bake (it has: " + names + ")";
    return false;
  }
  const FixtureState s = engine.state(index);
  const Q16_16 angle = Q16_16::FromRaw(change.value);
  const Q1_15 level = Q1_15::FromRaw(static_cast<int16_t>(change.value < 0 ? 0 : (change.value > 32767 ? 32767 : change.value)));
  Status st;
  switch (change.param) {
    case Param::kPan: st = engine.SetPanTilt(index, angle, s.tilt_deg); break;
    case Param::kTilt: st = engine.SetPanTilt(index, s.pan_deg, angle); break;
    case Param::kDimmer: st = engine.SetDimmer(index, level); break;
    case Param::kRed: st = engine.SetColour(index, level, s.rgb[1], s.rgb[2]); break;
    case Param::kGreen: st = engine.SetColour(index, s.rgb[0], level, s.rgb[2]); break;
    case Param::kBlue: st = engine.SetColour(index, s.rgb[0], s.rgb[1], level); break;
    case Param::kRoll: st = engine.SetRoll(index, angle); break;
    // A fade's first step reports every parameter: an unchanged zoom is no
    // change, even on a luminaire without one.
    case Param::kZoom: st = angle == s.zoom_deg ? Status::Ok() : engine.SetZoom(index, angle); break;
  }
  if (!st.ok()) {
    *error = std::string(change.fixture) + "." + ParamName(change.param) + ": " + st.ToString();
    return false;
  }
  return true;
}

bool ApplySetText(Engine& engine, const std::string& text, std::string* error) {
  ParamChange changes[3];
  const int n = hal::ParseParamText(text, 0, changes, error);
  if (n == 0) {
    *error = "--set " + *error;
    return false;
  }
  for (int i = 0; i < n; ++i) {
    if (!ApplyChange(engine, changes[i], error)) {
      *error = "--set '" + text + "': " + *error;
      return false;
    }
  }
  return true;
}

}  // namespace relight::cli
