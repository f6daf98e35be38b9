#include "link_brightness.h"

#include <algorithm>

namespace relight::baker {
namespace {

// Largest intensity of a distribution (cd), sampled every 0.25 degrees.
double PeakIntensity(const Lid& lid) {
  double peak = 0;
  for (int k = 0; k <= 720; ++k) peak = std::max(peak, lid.Evaluate(0.25 * k));
  return peak;
}

}  // namespace

std::vector<double> RefinementBrightness(const Scene& scene, const Mesh& mesh, const Hierarchy& h,
                                         const std::vector<LuminaireDirect>& direct) {
  const size_t n = mesh.patch_count();
  std::vector<double> e(n, 0.0);
  for (size_t l = 0; l < direct.size(); ++l) {
    const double peak = PeakIntensity(scene.luminaires[l].lid);
    const LuminaireDirect& d = direct[l];
    for (size_t i = 0; i < n; ++i) {
      for (uint32_t s = d.patch_offsets[i]; s < d.patch_offsets[i + 1]; ++s)
        e[i] += peak * d.patch_samples[s].g_m2;
    }
  }
  double flux = 0, area = 0, rho_area = 0;
  for (size_t i = 0; i < n; ++i) {
    const Patch& p = mesh.patches[i];
    flux += e[i] * p.area_m2;
    area += p.area_m2;
    rho_area += p.area_m2 * std::max({p.reflectance[0], p.reflectance[1], p.reflectance[2]});
  }
  const double rho_mean = area > 0 ? rho_area / area : 0;
  const double ambient = area > 0 ? rho_mean * flux / ((1 - rho_mean) * area) : 0;

  std::vector<double> b(h.nodes.size(), 0.0);
  if (!(flux > 0)) {
    std::fill(b.begin(), b.end(), 1.0);
    return b;
  }
  for (size_t k = 0; k < h.nodes.size(); ++k) {
    const HierarchyNode& node = h.nodes[k];
    if (!node.leaf()) continue;
    const Rgb& r = mesh.patches[node.patch].reflectance;
    b[k] = std::max({r[0], r[1], r[2]}) * (e[node.patch] + ambient);
  }
  // Children follow their parents: in reverse, every child is final first.
  for (size_t k = h.nodes.size(); k-- > 0;) {
    const HierarchyNode& node = h.nodes[k];
    if (node.leaf()) continue;
    double sum = 0;
    for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c)
      sum += h.nodes[c].area_m2 * b[c];
    b[k] = sum / node.area_m2;
  }
  return b;
}

}  // namespace relight::baker
