// relight-probe: illuminance (lux) at every calculation-grid point of a bake
// for the given fixture settings, as a lighting designer's work-plane check:
// a CSV of every point plus min / average / max and uniformity per grid.
//
//   relight-probe room.rlb --set ceiling_spot.tilt=30 -o grid.csv
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "relight/engine.h"
#include "set_args.h"

namespace {

// Photometric illuminance from the RGB channels (Rec. 709 luminance weights):
// with white light the three channels are equal for direct light and differ
// only by the colour of interreflected light.
double PhotometricLux(const int32_t* rgb_q12) {
  return (0.2126 * rgb_q12[0] + 0.7152 * rgb_q12[1] + 0.0722 * rgb_q12[2]) / 4096.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "relight-probe: illuminance in lux at the calculation-grid points of a bake.\n"
      "Writes one CSV row per point (grid, point, x_m, y_m, z_m, E_total_lux, E_direct_lux) and\n"
      "prints per grid: Emin, Eavg, Emax (lux) and uniformity U0 = Emin / Eavg.\n"
      "Settings: --set FIXTURE.PARAM=VALUE as for relight-render."};
  std::string bake_path, out_path;
  std::vector<std::string> sets;
  app.add_option("bake", bake_path, "bake file written by relight-bake (.rlb)")->required();
  app.add_option("--set", sets, "fixture setting FIXTURE.PARAM=VALUE (repeatable)");
  app.add_option("-o,--output", out_path, "CSV file to write (default: summary only)");
  CLI11_PARSE(app, argc, argv);

  relight::Engine engine;
  if (relight::Status st = engine.Open(bake_path); !st.ok()) {
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
  engine.Update();

  const relight::Bake& bake = engine.bake();
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
  for (size_t g = 0; g < bake.grids.size(); ++g) {
    const relight::BakeGrid& grid = bake.grids[g];
    const int32_t* total = engine.grid_illuminance(static_cast<int>(g));
    const int32_t* direct = engine.grid_direct_illuminance(static_cast<int>(g));
    double lo = 1e300, hi = 0, sum = 0;
    for (uint32_t p = 0; p < grid.point_count(); ++p) {
      const double e = PhotometricLux(total + 3 * p);
      lo = std::min(lo, e);
      hi = std::max(hi, e);
      sum += e;
      if (csv != nullptr) {
        std::fprintf(csv, "%s,%u,%.4f,%.4f,%.4f,%.3f,%.3f\n", grid.name.c_str(), p, grid.points[3 * p] / 65536.0,
                     grid.points[3 * p + 1] / 65536.0, grid.points[3 * p + 2] / 65536.0, e,
                     PhotometricLux(direct + 3 * p));
      }
    }
    const double avg = grid.point_count() > 0 ? sum / grid.point_count() : 0;
    std::printf("%-16s %8u %10.2f %10.2f %10.2f %8.3f\n", grid.name.c_str(), grid.point_count(), lo, avg, hi,
                avg > 0 ? lo / avg : 0.0);
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
