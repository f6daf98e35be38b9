#include "surface_agreement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace relight::baker {

std::vector<SurfaceAgreement> CompareBySurface(const Scene& scene, const Mesh& mesh,
                                               const std::vector<Rgb>& got,
                                               const std::vector<Rgb>& want) {
  if (got.size() != mesh.vertex_count() || want.size() != mesh.vertex_count()) {
    throw std::invalid_argument("CompareBySurface: one value per mesh vertex expected");
  }
  const size_t surfaces = mesh.surface_grids.size();
  std::vector<SurfaceAgreement> out(surfaces);
  std::vector<double> sum_signed(surfaces, 0), sum_abs(surfaces, 0), worst(surfaces, 0);
  std::vector<size_t> count(surfaces, 0);
  for (size_t v = 0; v < want.size(); ++v) {
    const uint32_t s = mesh.vertex_surface[v];
    for (int c = 0; c < 3; ++c) {
      const double d = got[v][c] - want[v][c];
      out[s].peak = std::max(out[s].peak, std::abs(want[v][c]));
      sum_signed[s] += d;
      sum_abs[s] += std::abs(d);
      worst[s] = std::max(worst[s], std::abs(d));
    }
    count[s] += 3;
  }
  for (size_t s = 0; s < surfaces; ++s) {
    SurfaceAgreement& a = out[s];
    a.name = s < scene.surfaces.size() ? scene.surfaces[s].name : std::to_string(s);
    if (!(a.peak > 0) || count[s] == 0) continue;
    const double n = static_cast<double>(count[s]);
    a.mean_signed = sum_signed[s] / n / a.peak;
    a.mean_abs = sum_abs[s] / n / a.peak;
    a.max_abs = worst[s] / a.peak;
  }
  return out;
}

}  // namespace relight::baker
