// Polar diagrams of a luminous intensity distribution against its SH
// approximations (as Dobashi's Fig. 4): the C0-C180 plane solid, C90-C270
// dashed, gamma 0 (the beam axis) pointing down, as photometric reports draw
// them. SVG text, no dependencies.
#pragma once

#include <string>
#include <vector>

#include "relight/baker/lid_error.h"
#include "relight/baker/scene.h"

namespace relight::baker {

struct PolarPlotOptions {
  std::string title;
  int degree = 8;                                // SH degree N of the approximations
  std::vector<ShWindow> windows = {ShWindow::kNone};  // one curve each
  int size_px = 640;
};

// Draws `lid` (from its file's table or analytic form) and, per window, its
// degree-N series I_N(C, gamma) = sum_l w_l sum_m c_lm Y_lm in the fixture
// frame; the legend gives each series' zonal-flux and L2 error and its lowest
// value (ringing below zero is drawn at the centre).
std::string LidPolarSvg(const Lid& lid, const PolarPlotOptions& options);

}  // namespace relight::baker
