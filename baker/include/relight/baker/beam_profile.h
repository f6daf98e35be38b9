// The beam model of a zoom optic (scene LID type "beam", docs/scene-format.md):
// consoles' fixture types give lens beam angles, not photometry, so the
// intensity is one fixed normalised curve of the angle from the axis scaled
// by the beam angle,
//   I(gamma) = peak f(gamma / h),  h = beam angle / 2,
//   f(x) = exp(-ln 2 x^p),  0 past x_end where f = 1 %,
// a super-Gaussian: f(1) = 1/2 (the beam angle is the full angle at half
// peak) and f(r) = 1/10 for r = field angle / beam angle (the field angle is
// the full angle at a tenth of the peak), which fixes p = ln(log2 10) / ln r.
// The default r = sqrt(log2 10) = 1.8226 gives p = 2, a Gaussian. A zoom
// changes h only; the flux 2 pi int I sin(gamma) dgamma is held, so the peak
// follows the angle. Float64, for the baker and the reference.
#pragma once

#include "relight/baker/scene.h"

namespace relight::baker {

// Field angle over beam angle when the scene gives no field angle: a Gaussian.
double DefaultFieldOverBeam();
// p of f(x) = exp(-ln 2 x^p) for a field / beam ratio r > 1.
double BeamProfileExponent(double field_over_beam);
// x_end: where f falls to 1 % of the peak; the profile is 0 past it.
double BeamProfileEnd(double exponent);
// exp(-ln 2 x^p), without the cut.
double BeamProfileUncut(double x, double exponent);
// f(x) for x >= 0 (0 past BeamProfileEnd).
double BeamProfile(double x, double exponent);
// Lumens per candela of peak: 2 pi int_0^pi f(gamma / h) sin(gamma) dgamma
// (Simpson up to the cut-off, finely), for the full beam angle beam_deg.
double BeamLumensPerPeak(double beam_deg, double exponent);
// The LID of a "beam" at another beam angle, lumens held.
Lid ZoomedBeamLid(const Lid& beam, double beam_deg);

}  // namespace relight::baker
