// IES photometric type B (floodlights, LM-63 photometric type 2) turned into
// relight's (C, gamma) table.
//
// Type B angles: the measuring planes share one horizontal axis through the
// luminaire at right angles to its beam. V (the file's "vertical angles",
// -90..90, up positive) turns a plane about that axis; H (its "horizontal
// angles", -90..90, clockwise seen from above, so positive to the right when
// looking along the beam) is the angle within a plane from the beam towards
// the shared axis. With f the beam axis, u up and l = u x f to the left:
//   d(H, V) = cos H (cos V f + sin V u) - sin H l.
// relight's frame (photometric_file.h) puts gamma 0 on f, C 0 on u and C 90
// on l (counter-clockwise seen from behind): C 0 is the way the flood's V
// angles rise, C 270 the side its positive H angles point to. Type B covers
// the front hemisphere only; everything behind is 0 cd.
#pragma once

#include <vector>

#include "relight/baker/photometric_file.h"

namespace relight::baker {

struct TypeBTable {
  std::vector<double> h_deg;    // strictly increasing in [-90, 90]; 0..90 = left-right symmetric
  std::vector<double> v_deg;    // strictly increasing in [-90, 90]
  std::vector<double> candela;  // [h * v_deg.size() + v], cd
};

// Candela at (H, V) in degrees: bilinear between the file's angles, H folded
// to |H| for a 0..90 (symmetric) file, 0 outside the angles the file covers.
double EvaluateTypeB(const TypeBTable& b, double h_deg, double v_deg);

// The same light in relight's frame, at (C, gamma) in degrees.
double TypeBAtCGamma(const TypeBTable& b, double c_deg, double gamma_deg);

// Resamples a type B table onto a uniform (C, gamma) grid (C 0..360 open,
// gamma 0..90; steps half the file's finest angle step, gamma 0.25-1 degree,
// C 0.5-2.5 degrees) and stores it in `out` as a full-circle (kNone) table.
// The caller keeps the file's other fields (path, version, flux, multiplier).
void ConvertTypeBToC(const TypeBTable& b, PhotometricTable* out);

}  // namespace relight::baker
