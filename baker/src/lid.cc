// Lid::Evaluate: the intensity of a rotationally symmetric luminous intensity
// distribution at an angle from its beam axis (scene.h).
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "relight/baker/beam_profile.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

namespace relight::baker {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double Lid::Evaluate(double gamma_in_deg) const {
  // The distribution is symmetric about the axis, so only |gamma| matters.
  const double g_deg = std::fabs(gamma_in_deg);
  switch (kind) {
    case LidKind::kIsotropic:
      return peak_cd;
    case LidKind::kCosPower: {
      // Dobashi Eq. 11; cos is clamped at 0 so a spread past 90 degrees never
      // yields a negative (or, for a fractional k, undefined) intensity.
      if (g_deg > spread_deg) return 0.0;
      const double c = std::max(0.0, std::cos(g_deg * kPi / 180.0));
      return peak_cd * std::pow(c, exponent);
    }
    case LidKind::kTable: {
      const size_t n = std::min(gamma_deg.size(), candela.size());
      if (n == 0 || g_deg > gamma_deg[n - 1] || g_deg < gamma_deg[0]) return 0.0;
      // First control point strictly above g; linear between it and the one before.
      const size_t hi = static_cast<size_t>(
          std::upper_bound(gamma_deg.begin(), gamma_deg.begin() + static_cast<std::ptrdiff_t>(n),
                           g_deg) -
          gamma_deg.begin());
      if (hi == 0) return candela[0];
      if (hi >= n) return candela[n - 1];  // g equals the last control point
      const double t = (g_deg - gamma_deg[hi - 1]) / (gamma_deg[hi] - gamma_deg[hi - 1]);
      return candela[hi - 1] + t * (candela[hi] - candela[hi - 1]);
    }
    case LidKind::kBeam:
      return beam_deg > 0 ? peak_cd * BeamProfile(g_deg / (beam_deg / 2), beam_exponent) : 0.0;
    case LidKind::kCGamma: {
      if (!file) return 0.0;
      // Mean over C, 1 degree steps: the file's planes are linear in C
      // between at most a few degrees' worth of detail per step.
      double sum = 0;
      for (int c = 0; c < 360; ++c) sum += file->Evaluate(c + 0.5, g_deg);
      return sum / 360.0;
    }
  }
  return 0.0;
}

double Lid::Evaluate(double c_deg, double gamma_in_deg) const {
  if (kind == LidKind::kCGamma) return file ? file->Evaluate(c_deg, gamma_in_deg) : 0.0;
  return Evaluate(gamma_in_deg);
}

}  // namespace relight::baker
