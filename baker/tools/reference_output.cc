#include "reference_output.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "set_args.h"

namespace relight::bake_cli {

using baker::FixtureSetting;
using baker::ReferenceResult;
using baker::Rgb;
using baker::Scene;

bool ApplySets(const Scene& scene, const std::vector<std::string>& sets,
               std::vector<FixtureSetting>* settings, std::string* error) {
  for (const std::string& text : sets) {
    relight::cli::SetArg arg;
    if (!relight::cli::ParseSetArg(text, &arg, error)) return false;
    size_t index = scene.luminaires.size();
    for (size_t l = 0; l < scene.luminaires.size(); ++l)
      if (scene.luminaires[l].name == arg.fixture) index = l;
    if (index == scene.luminaires.size()) {
      std::string names;
      for (const auto& l : scene.luminaires) names += (names.empty() ? "" : ", ") + l.name;
      *error = "--set '" + text + "': no luminaire '" + arg.fixture + "' in " + scene.path +
               " (it has: " + (names.empty() ? "none" : names) + ")";
      return false;
    }
    FixtureSetting& s = (*settings)[index];
    if (arg.param == "pan") s.pan_deg = arg.values[0];
    if (arg.param == "tilt") s.tilt_deg = arg.values[0];
    if (arg.param == "roll") s.roll_deg = arg.values[0];
    if (arg.param == "zoom") {
      // Only a zooming beam has a beam angle to set; past its range the angle clamps, as in the engine.
      const relight::baker::Luminaire& lum = scene.luminaires[index];
      if (!lum.lid.zooms()) {
        *error = "--set '" + text + "': luminaire '" + lum.name + "' (" + scene.path + ":" + std::to_string(lum.line) +
                 ") has no zoom: only a \"beam\" LID with a zoom range has a beam angle to set";
        return false;
      }
      const double v = arg.values[0];
      if (v < lum.lid.zoom_min_deg || v > lum.lid.zoom_max_deg) {
        std::fprintf(stderr,
                     "relight-bake: --set '%s': %g degrees is outside the zoom range %g..%g of '%s'; the reference "
                     "uses %g degrees, as the engine clamps\n",
                     text.c_str(), v, lum.lid.zoom_min_deg, lum.lid.zoom_max_deg, lum.name.c_str(),
                     v < lum.lid.zoom_min_deg ? lum.lid.zoom_min_deg : lum.lid.zoom_max_deg);
      }
      s.zoom_deg = v;
    }
    if (arg.param == "dimmer") s.dimmer = arg.values[0];
    if (arg.param == "r") s.colour[0] = arg.values[0];
    if (arg.param == "g") s.colour[1] = arg.values[0];
    if (arg.param == "b") s.colour[2] = arg.values[0];
    if (arg.param == "colour") s.colour = {arg.values[0], arg.values[1], arg.values[2]};
  }
  return true;
}

namespace {

std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

double Photometric(const Rgb& rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

}  // namespace

bool WriteFileAtomic(const std::string& path, const std::string& text, std::string* error) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    *error = path + ": cannot create (" + std::strerror(errno) + ")";
    return false;
  }
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed || std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = path + ": write failed (" + std::strerror(errno) + ")";
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

std::string VerticesCsv(const relight::baker::Mesh& mesh, const ReferenceResult& ref) {
  std::string out = "index,x_m,y_m,z_m,R,G,B\n";
  char line[256];
  for (size_t v = 0; v < ref.vertex_luminance.size(); ++v) {
    const Rgb& l = ref.vertex_luminance[v];
    const relight::baker::Vec3& p = mesh.positions[v];
    std::snprintf(line, sizeof line, "%zu,%.6f,%.6f,%.6f,%.9g,%.9g,%.9g\n", v, p[0], p[1], p[2],
                  l[0], l[1], l[2]);
    out += line;
  }
  return out;
}

std::string GridsCsv(const Scene& scene, const ReferenceResult& ref) {
  std::string out = "grid,point,x_m,y_m,z_m,E_total_lux,E_direct_lux\n";
  char line[256];
  for (size_t g = 0; g < scene.grids.size(); ++g) {
    const auto& points = scene.grids[g].points;
    for (size_t p = 0; p < points.size(); ++p) {
      std::snprintf(line, sizeof line, ",%zu,%.6f,%.6f,%.6f,%.9g,%.9g\n", p, points[p][0],
                    points[p][1], points[p][2], Photometric(ref.grid_illuminance[g][p]),
                    Photometric(ref.grid_direct_illuminance[g][p]));
      out += CsvField(scene.grids[g].name) + line;
    }
  }
  return out;
}

}  // namespace relight::bake_cli
