// A work-plane illuminance report as a picture: each calculation grid of a
// bake drawn as a plan of false-coloured cells (lux), with the value in
// each cell where it fits, a colour bar in lux, the grid's size in metres
// and the figures lighting designers check (Emin, Eavg, Emax, U0).
// Used by relight-probe --svg. Plain SVG text: opens in any browser.
#pragma once

#include <string>
#include <vector>

namespace relight::cli {

struct GridLux {
  std::string name;
  unsigned columns = 0, rows = 0;  // a rectangle (point = row * columns + column), or 0, 0 for a list
  std::vector<double> xyz_m;       // 3 per point, metres
  std::vector<double> lux;         // 1 per point
};

struct LuxSummary {
  double min = 0, avg = 0, max = 0;
  double u0 = 0;  // Emin / Eavg (0 when Eavg is 0)
};
LuxSummary Summarise(const std::vector<double>& lux);

// The top of the colour scale: the smallest of 1, 1.2, 1.5, 2, 2.5, 3, 4, 5,
// 6, 8 x 10^k (k >= 0) that is >= max_lux.
double ScaleTop(double max_lux);
// The scale's colour of a value as "#rrggbb": dark blue at 0 through cyan,
// green and yellow to red at `top`; clamped.
std::string LuxColour(double lux, double top);

// The whole SVG document. `subtitle` says what was lit (scene, settings).
std::string LuxMapSvg(const std::vector<GridLux>& grids, const std::string& subtitle);

}  // namespace relight::cli
