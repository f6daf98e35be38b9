// relight-probe: illuminance (lux) at every calculation-grid point of a bake
// for the given fixture settings, as a lighting designer's work-plane check:
// a CSV of every point plus min / average / max and uniformity per grid, and
// a false-colour plan of each grid (lux_map_svg.h).
//
//   relight-probe room.rlb --set ceiling_spot.tilt=30 -o grid.csv --svg grid.svg
//   relight-probe room.rlb --emitter "room/+z:3000:2.5,1.5,2.7;3.5,1.5,2.7;3.5,2.5,2.7;2.5,2.5,2.7"
// (a light panel on a surface: its light and interreflections on the grids,
// with a bake that stores the hierarchy and its grid links; docs/hierarchy.md).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lux_map_svg.h"
#include "relight/engine/engine.h"
#include "emitter_args.h"
#include "relight/engine/surface_emitter.h"
#include "set_args.h"

namespace {

// Photometric illuminance from the RGB channels (Rec. 709 luminance weights):
// with white light the three channels are equal for direct light and differ
// only by the colour of interreflected light.
double PhotometricLux(const int32_t* rgb_q12) {
  return (0.2126 * rgb_q12[0] + 0.7152 * rgb_q12[1] + 0.0722 * rgb_q12[2]) / 4096.0;
}

// Writes `text` to `path` through a temporary file, so a failed write never
// leaves half a file behind.
bool WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "relight-probe: illuminance in lux at the calculation-grid points of a bake.\n"
      "Writes one CSV row per point (grid, point, x_m, y_m, z_m, E_total_lux, E_direct_lux) and\n"
      "prints per grid: Emin, Eavg, Emax (lux) and uniformity U0 = Emin / Eavg.\n"
      "--svg draws each grid as a false-colour plan in lux with those figures (opens in a browser).\n"
      "Settings: --set FIXTURE.PARAM=VALUE as for relight-render; --emitter SURFACE:L:x,y,z;... puts a\n"
      "light panel (L cd/m^2, or R,G,B) on a surface, as relight-render's --emitter."};
  std::string bake_path, out_path, svg_path;
  std::vector<std::string> sets, emitters;
  app.add_option("bake", bake_path, "bake file written by relight-bake (.rlb)")->required();
  app.add_option("--set", sets, "fixture setting FIXTURE.PARAM=VALUE (repeatable)");
  app.add_option("--emitter", emitters,
                 "run-time light source SURFACE:L:x,y,z;x,y,z;x,y,z[;...] (L in cd/m^2 or R,G,B; "
                 "repeatable)");
  app.add_option("-o,--output", out_path, "CSV file to write (default: summary only)");
  app.add_option("--svg", svg_path, "false-colour lux plan of every grid to write (SVG)");
  CLI11_PARSE(app, argc, argv);

  relight::Engine engine;
  relight::EngineOptions options;
  // One placement per emitter: solving it from the emission costs less than
  // the later-bounce table a long-running engine builds at Open.
  options.emitter_bounce_table_bytes = 0;
  if (relight::Status st = engine.Open(bake_path, options); !st.ok()) {
    std::fprintf(stderr, "relight-probe: error: %s\n", st.ToString().c_str());
    return 2;
  }
  for (const std::string& text : sets) {
    std::string error;
    if (!relight::cli::ApplySetText(engine, text, &error)) {
      std::fprintf(stderr, "relight-probe: error: %s\n", error.c_str());
      return 2;
    }
  }
  if (emitters.size() > static_cast<size_t>(relight::kMaxSurfaceEmitters)) {
    std::fprintf(stderr, "relight-probe: error: at most %d --emitter\n", relight::kMaxSurfaceEmitters);
    return 2;
  }
  for (size_t i = 0; i < emitters.size(); ++i) {
    std::string error;
    if (!relight::cli::ApplyEmitterText(engine, static_cast<int>(i), emitters[i], &error)) {
      std::fprintf(stderr, "relight-probe: error: %s\n", error.c_str());
      return 2;
    }
  }
  engine.Update();

  const relight::Bake& bake = engine.bake();
  if (!emitters.empty() && !bake.grids.empty() &&
      !(bake.hierarchy && bake.hierarchy->has_grid_links())) {
    std::fprintf(stderr,
                 "relight-probe: error: the bake has no links from its hierarchy to the grids, so "
                 "emitters cannot light them (re-bake with relight-bake, format version 6)\n");
    return 2;
  }
  if (bake.grids.empty()) {
    std::fprintf(stderr, "relight-probe: the bake has no calculation grids (add [[grid]] to the scene)\n");
    return 1;
  }
  std::FILE* csv = nullptr;
  const std::string tmp_path = out_path + ".tmp";
  if (!out_path.empty()) {
    csv = std::fopen(tmp_path.c_str(), "w");
    if (csv == nullptr) {
      std::fprintf(stderr, "relight-probe: error: cannot write '%s'\n", tmp_path.c_str());
      return 1;
    }
    std::fprintf(csv, "grid,point,x_m,y_m,z_m,E_total_lux,E_direct_lux\n");
  }
  std::printf("%-16s %8s %10s %10s %10s %8s\n", "grid", "points", "Emin_lux", "Eavg_lux", "Emax_lux", "U0");
  std::vector<relight::cli::GridLux> plans;
  for (size_t g = 0; g < bake.grids.size(); ++g) {
    const relight::BakeGrid& grid = bake.grids[g];
    const int32_t* total = engine.grid_illuminance(static_cast<int>(g)).raw();
    const int32_t* direct = engine.grid_direct_illuminance(static_cast<int>(g)).raw();
    relight::cli::GridLux plan{grid.name, grid.columns, grid.rows, {}, {}};
    for (uint32_t p = 0; p < grid.point_count(); ++p) {
      const double e = PhotometricLux(total + 3 * p);
      plan.lux.push_back(e);
      for (int k = 0; k < 3; ++k) plan.xyz_m.push_back(grid.points[3 * p + k] / 65536.0);
      if (csv != nullptr) {
        std::fprintf(csv, "%s,%u,%.4f,%.4f,%.4f,%.3f,%.3f\n", grid.name.c_str(), p, grid.points[3 * p] / 65536.0,
                     grid.points[3 * p + 1] / 65536.0, grid.points[3 * p + 2] / 65536.0, e,
                     PhotometricLux(direct + 3 * p));
      }
    }
    const relight::cli::LuxSummary sum = relight::cli::Summarise(plan.lux);
    std::printf("%-16s %8u %10.2f %10.2f %10.2f %8.3f\n", grid.name.c_str(), grid.point_count(), sum.min, sum.avg,
                sum.max, sum.u0);
    plans.push_back(std::move(plan));
  }
  if (!svg_path.empty()) {
    std::string settings;
    for (const std::string& text : sets) settings += (settings.empty() ? "" : ", ") + text;
    for (const std::string& text : emitters) settings += (settings.empty() ? "emitter " : ", emitter ") + text;
    const std::string subtitle = "relight-probe " + bake_path + " (scene '" + bake.scene_name + "'), " +
                                 (settings.empty() ? std::string("scene defaults") : settings);
    if (!WriteFileAtomically(svg_path, relight::cli::LuxMapSvg(plans, subtitle))) {
      std::fprintf(stderr, "relight-probe: error: cannot write '%s'\n", svg_path.c_str());
      return 1;
    }
    std::printf("relight-probe: wrote %s\n", svg_path.c_str());
  }
  if (csv != nullptr) {
    const bool ok = std::fclose(csv) == 0 && std::rename(tmp_path.c_str(), out_path.c_str()) == 0;
    if (!ok) {
      std::remove(tmp_path.c_str());
      std::fprintf(stderr, "relight-probe: error: cannot write '%s'\n", out_path.c_str());
      return 1;
    }
    std::printf("relight-probe: wrote %s\n", out_path.c_str());
  }
  return 0;
}
