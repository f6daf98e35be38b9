// The beam model of a zoom optic (see relight/baker/beam_profile.h).
#include "relight/baker/beam_profile.h"

#include <algorithm>
#include <cmath>

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kEndLevel = 0.01;  // the profile is cut to 0 where it falls below 1 %
constexpr int kFluxIntervals = 20000;  // Simpson intervals up to the cut-off (even)

}  // namespace

double DefaultFieldOverBeam() { return std::sqrt(std::log2(10.0)); }

double BeamProfileExponent(double field_over_beam) {
  return std::log(std::log2(10.0)) / std::log(field_over_beam);
}

double BeamProfileEnd(double exponent) {
  return std::pow(std::log2(1.0 / kEndLevel), 1.0 / exponent);
}

double BeamProfileUncut(double x, double exponent) {
  return std::exp(-std::log(2.0) * std::pow(x, exponent));
}

double BeamProfile(double x, double exponent) {
  return x > BeamProfileEnd(exponent) ? 0.0 : BeamProfileUncut(x, exponent);
}

double BeamLumensPerPeak(double beam_deg, double exponent) {
  const double h = beam_deg / 2 * kPi / 180;
  const double end = std::min(kPi, BeamProfileEnd(exponent) * h);
  const double step = end / kFluxIntervals;
  double sum = 0;
  for (int i = 0; i <= kFluxIntervals; ++i) {
    const double g = i * step;
    const double w = (i == 0 || i == kFluxIntervals) ? 1 : (i % 2 == 1 ? 4 : 2);
    sum += w * BeamProfile(g / h, exponent) * std::sin(g);
  }
  return 2 * kPi * sum * step / 3;
}

Lid ZoomedBeamLid(const Lid& beam, double beam_deg) {
  Lid out = beam;
  out.beam_deg = beam_deg;
  out.peak_cd = beam.lumens / BeamLumensPerPeak(beam_deg, beam.beam_exponent);
  return out;
}

}  // namespace relight::baker
