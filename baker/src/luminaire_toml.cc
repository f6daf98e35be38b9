// A scene's [[luminaire]] table (docs/scene-format.md) into a Luminaire:
// place, mounting, aim, console ranges, defaults, SH degree and its LID
// (lid_toml.h). Errors name file:line through TomlFields.
#include "luminaire_toml.h"

#include "lid_toml.h"
#include "relight/base/sh_index.h"
#include "relight/baker/fixture_frame.h"
#include "vec3_math.h"

namespace relight::baker {

Luminaire ReadLuminaire(const toml::table& table, const std::string& path,
                        std::map<std::string, int>* luminaire_lines) {
  TomlFields f(table, path, "luminaire");
  f.NameFrom("name", "luminaire");
  f.CheckKeys({"name", "position", "mounting", "pan", "tilt", "aim_at", "dimmer", "colour",
               "sh_degree", "sigma", "lid", "yaw", "roll", "pan_range", "tilt_range"});
  Luminaire lum;
  lum.line = f.line();
  lum.name = f.Identifier("name");
  f.set_what("luminaire " + Quoted(lum.name));
  const auto [it, inserted] = luminaire_lines->emplace(lum.name, lum.line);
  if (!inserted) {
    f.Fail(f.Required("name"),
           "name already used by the luminaire at line " + std::to_string(it->second));
  }
  lum.position = f.Vector("position");
  const std::string mounting = f.String("mounting");
  if (mounting == "hanging") {
    lum.mounting = MountingKind::kHanging;
  } else if (mounting == "standing") {
    lum.mounting = MountingKind::kStanding;
  } else if (mounting == "wall") {
    lum.mounting = MountingKind::kWall;
  } else {
    f.Fail(f.Required("mounting"), "mounting must be \"hanging\", \"standing\" or \"wall\", got " +
                                       Describe(f.Required("mounting")));
  }
  lum.yaw_deg = f.Number("yaw", Closed(-360, 360), 0.0);
  lum.roll_deg = f.Number("roll", Closed(-360, 360), 0.0);
  lum.pan_range_deg = f.Number("pan_range", OpenClosed(0, 720), 540.0);
  lum.tilt_range_deg = f.Number("tilt_range", OpenClosed(0, 360), 270.0);
  if (f.Has("aim_at")) {
    if (f.Has("pan") || f.Has("tilt")) {
      f.Fail(f.Required("aim_at"), "give either aim_at or pan/tilt, not both");
    }
    const Vec3 target = f.Vector("aim_at");
    if (Length(Sub(target, lum.position)) < kMinVectorM) {
      f.Fail(f.Required("aim_at"), "aim_at must differ from position");
    }
    AimAtPose(lum.mounting, lum.yaw_deg, lum.position, target, &lum.pan_deg, &lum.tilt_deg);
  } else {
    lum.pan_deg = f.Number("pan", Closed(-360, 360), 0.0);
    lum.tilt_deg = f.Number("tilt", Closed(-180, 180), 0.0);
  }
  lum.dimmer = f.Number("dimmer", Closed(0, 1), 1.0);
  if (f.Has("colour")) {
    const toml::node& node = f.Required("colour");
    const auto* array = node.as_array();
    if (array == nullptr || array->size() != 3) {
      f.Fail(node, "colour must be [r, g, b], each in [0, 1], got " + Describe(node));
    }
    for (size_t k = 0; k < 3; ++k)
      lum.colour[k] = f.ReadNumber(*array->get(k), "colour", Closed(0, 1));
  }
  lum.sh_degree = static_cast<int>(f.Integer("sh_degree", 0, kMaxShDegree, 8));
  lum.sh_degree_given = f.Has("sh_degree");
  if (f.Has("sigma")) lum.use_sigma = f.Bool("sigma", true);
  lum.lid = ReadLid(TomlFields(f.Table("lid"), path, f.what() + " lid"));
  return lum;
}

}  // namespace relight::baker
