#include "relight/control/engine_binding.h"

namespace relight::control {
namespace {

Q1_15 Clamped(Q1_15 level) { return level.raw() < 0 ? Q1_15::FromRaw(0) : level; }

}  // namespace

Status ApplyToEngine(Engine& engine, const ParamChange& change) {
  const int index = change.fixture;
  if (index >= engine.luminaire_count()) {
    return Status(StatusCode::kInvalidArgument, "no luminaire " + std::to_string(index));
  }
  const FixtureState s = engine.state(index);
  const Q1_15 level = Clamped(change.level);
  switch (change.param) {
    case Param::kPan: return engine.SetPanTilt(index, change.degrees, s.tilt_deg);
    case Param::kTilt: return engine.SetPanTilt(index, s.pan_deg, change.degrees);
    case Param::kDimmer: return engine.SetDimmer(index, level);
    case Param::kRed: return engine.SetColour(index, level, s.rgb[1], s.rgb[2]);
    case Param::kGreen: return engine.SetColour(index, s.rgb[0], level, s.rgb[2]);
    case Param::kBlue: return engine.SetColour(index, s.rgb[0], s.rgb[1], level);
    case Param::kRoll: return engine.SetRoll(index, change.degrees);
    // A fade's first step reports every parameter: an unchanged zoom is no
    // change, even on a luminaire without one.
    case Param::kZoom: return change.degrees == s.zoom_deg ? Status::Ok() : engine.SetZoom(index, change.degrees);
    case Param::kX:
    case Param::kY:
    case Param::kSize:
      return Status(StatusCode::kInvalidArgument, "x, y and size move emitters ([[emitter]]); a luminaire has none");
  }
  return Status(StatusCode::kInvalidArgument, "unknown parameter");
}

std::vector<std::string> LuminaireNames(const Engine& engine) {
  std::vector<std::string> names;
  for (const BakeLuminaire& lum : engine.bake().luminaires) names.push_back(lum.name);
  return names;
}

Status BindNames(const Engine& engine, const std::vector<std::string>& names, const std::string& where,
                 std::vector<uint16_t>* out) {
  std::vector<uint16_t> indices;
  for (const std::string& name : names) {
    const int index = engine.FindLuminaire(name);
    if (index < 0 || index > kMaxFixtures) {
      std::string list;
      for (const std::string& n : LuminaireNames(engine)) list += (list.empty() ? "" : ", ") + n;
      return Status(StatusCode::kNotFound, where + ": no luminaire '" + name + "' in the bake (it has: " + list + ")");
    }
    indices.push_back(static_cast<uint16_t>(index));
  }
  *out = std::move(indices);
  return Status::Ok();
}

}  // namespace relight::control
